// ReportCollector: per-axis velocity, acceleration and jerk of the Acc/Dec output, kept per column.
#include "report/report_collector.hpp"

#include <catch2/catch.hpp>

using gm::report::kFirstAxisSeries;
using gm::report::ReportCollector;

namespace {

// X moves 5 BLU a sample for samples 1..9, then 10 BLU a sample: at the default 1 µm and 4 ms,
// v = 5e-3/0.004 = 1.25 mm/s, then 2.5 mm/s; at k = 10 a = 1.25/0.004 = 312.5 mm/s² and
// j = 312.5/0.004 = 78125 mm/s³, at k = 11 a = 0 and j = -78125 mm/s³.
void feed(ReportCollector& c) {
  gm::SampleRecord s;
  std::int64_t x = 0;
  for (int k = 0; k < 20; ++k) {
    if (k > 0) x += k < 10 ? 5 : 10;
    s.k = k;
    s.t_s = k * 0.004;
    s.line = k < 10 ? 3 : 4;
    s.ref_blu[0] = x;
    s.table_blu[0] = static_cast<double>(x);
    s.contour_err_blu = k == 12 ? -7.5 : 0.25;
    c.add(s, {});
  }
}

}  // namespace

TEST_CASE("collector: velocity, acceleration and jerk per sample", "[report]") {
  const gm::Machine m;
  REQUIRE(m.axes[0].blu_mm == 0.001);
  REQUIRE(m.period_s == 0.004);
  ReportCollector c(m);
  feed(c);
  const auto& b = c.series().bins();
  REQUIRE(b.size() == 20);
  const std::size_t v = kFirstAxisSeries, a = v + 1, j = v + 2;
  CHECK(b[0].hi[v] == 0.0);
  CHECK(b[5].hi[v] == Approx(1.25));
  CHECK(b[5].hi[a] == Approx(0.0).margin(1e-9));
  CHECK(b[10].hi[v] == Approx(2.5));
  CHECK(b[10].hi[a] == Approx(312.5));
  CHECK(b[10].hi[j] == Approx(78125.0));
  CHECK(b[11].lo[a] == Approx(0.0).margin(1e-9));
  CHECK(b[11].lo[j] == Approx(-78125.0));
  CHECK(b[12].lo[gm::report::kContourSeries] == -7.5);
  CHECK(c.max_abs_contour_blu() == 7.5);
  CHECK(c.lines() == std::vector<int>{3, 4});
}

TEST_CASE("collector: decimated columns keep the peaks and the worst sample's line", "[report]") {
  ReportCollector c(gm::Machine{}, 4, 4, 100);
  feed(c);
  // 20 samples under a cap of 4: width 8 (3 columns: 0-7, 8-15, 16-19).
  REQUIRE(c.series().width() == 8);
  const auto& b = c.series().bins();
  REQUIRE(b.size() == 3);
  const std::size_t v = kFirstAxisSeries, a = v + 1, j = v + 2;
  CHECK(b[1].lo[v] == Approx(1.25));
  CHECK(b[1].hi[v] == Approx(2.5));
  CHECK(b[1].hi[a] == Approx(312.5));
  CHECK(b[1].lo[j] == Approx(-78125.0));
  CHECK(b[1].lo[gm::report::kContourSeries] == -7.5);
  CHECK(b[1].line == 4);  // sample 12, the column's largest |contour error|
  CHECK(b[0].line == 3);
  // The XY path columns: first sample and worst sample of each.
  const auto& p = c.path().bins();
  REQUIRE(p.size() == 3);
  CHECK(p[1].k0 == 8);
  CHECK(p[1].k_worst == 12);
  CHECK(p[1].x0_mm == Approx(0.040));  // x(8) = 8·5 = 40 BLU
  CHECK(p[1].xw_mm == Approx(0.075));  // x(12) = 9·5 + 3·10 = 75 BLU
}
