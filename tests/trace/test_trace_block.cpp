// TraceWriter::write_block: the same bytes as write() of each row's record, CSV and binary.
#include "motion/sample_block.hpp"
#include "trace/trace_reader.hpp"
#include "trace/trace_writer.hpp"

#include "support/read_file.hpp"
#include "support/scratch_dir.hpp"
#include "support/trace_rows.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>

namespace {

constexpr double kPeriodS = 0.004;

gm::TraceMeta meta(const std::string& axes, int decimate) {
  gm::TraceMeta m;
  m.program = "p.nc";
  m.machine_name = "m";
  m.machine_source = "m.toml";
  m.profile = "linear";
  m.taps = 41;
  m.tau_s = 0.164;
  m.period_s = kPeriodS;
  m.axes = axes;
  m.blu_mm = gm::AxisVec::Constant(0.001);
  m.decimate = decimate;
  return m;
}

/// A block of rows whose values reach every path of the formatter: zeros, one digit, signs,
/// counts of 8, 9, 16 and 19 digits, INT64 extremes, contour errors of -0, near halves,
/// 1e8 and more, NaN and infinity, override changes, times past 10^8 s.
void fill(gm::SampleBlock& b, std::int64_t k0, int axes, std::mt19937_64& rng) {
  b.reset(k0);
  b.count = gm::kBlockSamples;
  const std::int64_t special[] = {0,
                                  9,
                                  -9,
                                  10,
                                  99999999,
                                  -99999999,
                                  100000000,
                                  -100000000,
                                  9999999999999999,
                                  10000000000000000,
                                  std::numeric_limits<std::int64_t>::max(),
                                  std::numeric_limits<std::int64_t>::min() + 1};
  const double contour[] = {0.0,
                            -0.0,
                            -0.0004,
                            0.0005,
                            0.0015,
                            2.5,
                            -1234.5675,
                            99999999.9995,
                            123456789.125,
                            -1e15,
                            std::numeric_limits<double>::quiet_NaN(),
                            std::numeric_limits<double>::infinity()};
  for (int i = 0; i < b.count; ++i) {
    b.line[i] = static_cast<int>(rng() % 100000);
    for (int a = 0; a < axes; ++a) {
      const auto pick = [&]() -> std::int64_t {
        const std::uint64_t r = rng();
        if (r % 8 == 0) return special[(r >> 8) % std::size(special)];
        const auto digits = static_cast<int>((r >> 8) % 9);
        std::int64_t bound = 1;
        for (int d = 0; d < digits; ++d) bound *= 10;
        const auto v = static_cast<std::int64_t>((r >> 16) % static_cast<std::uint64_t>(bound));
        return (r >> 12) % 2 == 0 ? v : -v;
      };
      b.cmd_blu.v[a][i] = pick();
      b.ref_blu.v[a][i] = pick() / 2;  // ref − enc must not overflow
      b.enc_blu.v[a][i] = pick() / 2;
      b.table_blu.v[a][i] = 0.0;
    }
    const std::uint64_t r = rng();
    b.contour_err_blu[i] = r % 4 == 0 ? contour[(r >> 8) % std::size(contour)]
                                      : (static_cast<double>(r >> 11) / 9007199254740992.0 - 0.5) *
                                            std::pow(10.0, static_cast<double>((r >> 3) % 10));
    b.feed_scale[i] = i < 100 ? 1.0 : i < 200 ? 0.375 : 1.0 / 3.0;
    b.arc_ref_dev_blu[i] = 0.0;
    b.arc_enc_dev_blu[i] = 0.0;
    b.events[i] = 0;
    b.settling[i] = false;
  }
}

std::string written(const std::string& name, gm::TraceFormat format, const std::string& axes,
                    int decimate, bool by_block) {
  const auto path = (gmtest::scratch_dir("trace-block") / name).string();
  {
    gm::TraceWriter w(path, format, meta(axes, decimate));
    auto b = std::make_unique<gm::SampleBlock>();
    std::mt19937_64 rng(20261126);
    // Three blocks: the first from row 17 on (as after a partial consume), the third at a time
    // past 10^8 s.
    const std::int64_t starts[] = {0, gm::kBlockSamples, std::int64_t{30000000000}};
    for (int n = 0; n < 3; ++n) {
      fill(*b, starts[n], static_cast<int>(axes.size()), rng);
      const int first = n == 0 ? 17 : 0;
      if (by_block) {
        w.write_block(*b, first, kPeriodS);
        continue;
      }
      gm::with_axis_count(static_cast<int>(axes.size()), [&](auto count) {
        gm::SampleRecord r;
        for (int i = first; i < b->count; ++i) {
          b->record<decltype(count)::value>(i, kPeriodS, r);
          r.contour_err_blu = b->contour_err_blu[i];
          gmtest::write_record(w, r, static_cast<int>(axes.size()));
        }
      });
    }
    w.finish();
  }
  return gmtest::slurp(path);
}

}  // namespace

TEST_CASE("write_block writes the bytes write() writes for each row's record") {
  for (const std::string axes : {"XYZ", "X", "XYZABCUVW"}) {
    for (const int decimate : {1, 3}) {
      for (const auto format : {gm::TraceFormat::Csv, gm::TraceFormat::Binary}) {
        const std::string tag = axes + "-" + std::to_string(decimate) +
                                (format == gm::TraceFormat::Csv ? ".csv" : ".bin");
        INFO(tag);
        const std::string rows = written("rows-" + tag, format, axes, decimate, false);
        const std::string block = written("block-" + tag, format, axes, decimate, true);
        CHECK(rows.size() > 20000u / static_cast<unsigned>(decimate));
        CHECK(block == rows);
      }
    }
  }
}

TEST_CASE("write_block: the CSV text of known rows") {
  const auto path = (gmtest::scratch_dir("trace-block") / "known.csv").string();
  {
    gm::TraceWriter w(path, gm::TraceFormat::Csv, meta("XY", 1));
    auto b = std::make_unique<gm::SampleBlock>();
    b->reset(250);
    b->count = 2;
    b->line[0] = 12;
    b->line[1] = 12;
    const std::int64_t cmd[2][2] = {{123456789, -7}, {0, 100000000}};
    const std::int64_t ref[2][2] = {{-5, 10}, {99999999, -3}};
    const std::int64_t enc[2][2] = {{4, 10}, {-1, -3}};
    for (int a = 0; a < 2; ++a)
      for (int i = 0; i < 2; ++i) {
        b->cmd_blu.v[a][i] = cmd[a][i];
        b->ref_blu.v[a][i] = ref[a][i];
        b->enc_blu.v[a][i] = enc[a][i];
      }
    b->contour_err_blu[0] = -0.0004;  // rounds to "-0.000", as printf does
    b->contour_err_blu[1] = 1234.5675;
    b->feed_scale[0] = 1.0;
    b->feed_scale[1] = 0.375;
    w.write_block(*b, 0, kPeriodS);
    w.finish();
  }
  const std::string text = gmtest::slurp(path);
  const std::string rows = text.substr(text.rfind("t_s,"));
  CHECK(rows ==
        "t_s,line,x_cmd,x_ref,x_enc,x_ferr,y_cmd,y_ref,y_enc,y_ferr,contour_err,override\n"
        "1.000000,12,123456789,-5,4,-9,0,99999999,-1,100000000,-0.000,100\n"
        "1.004000,12,-7,10,10,0,100000000,-3,-3,0,1234.568,37.5\n");
}

TEST_CASE("the tool tip columns: written with the modes' column set only, read back by name",
          "[trace][tip]") {
  // The same two rows with and without kTraceModes: with it each axis block gains `tip`
  // (fixed3) after `ferr` and the units line its unit; without it the trace is the one above.
  for (const bool modes : {false, true}) {
    for (const auto format : {gm::TraceFormat::Csv, gm::TraceFormat::Binary}) {
      const std::string name = std::string(modes ? "tip" : "no-tip") +
                               (format == gm::TraceFormat::Csv ? ".csv" : ".bin");
      INFO(name);
      const auto path = (gmtest::scratch_dir("trace-block") / name).string();
      {
        gm::TraceMeta m = meta("XY", 1);
        if (modes) m.columns = gm::kTraceModes;
        gm::TraceWriter w(path, format, m);
        auto b = std::make_unique<gm::SampleBlock>();
        b->reset(250);
        b->count = 2;
        for (int i = 0; i < 2; ++i) {
          b->line[i] = 7;
          b->feed_scale[i] = 1.0;
          b->contour_err_blu[i] = 0.5 * i;
          for (int a = 0; a < 2; ++a) {
            b->cmd_blu.v[a][i] = 100 * (a + 1) + i;
            b->ref_blu.v[a][i] = 90 * (a + 1) + i;
            b->enc_blu.v[a][i] = 80 * (a + 1) + i;
            b->table_blu.v[a][i] = 80.25 * (a + 1) - 3.0625 * i;  // exact in binary
          }
        }
        w.write_block(*b, 0, kPeriodS);
        w.finish();
      }
      gm::TraceReader r(path);
      const std::vector<std::string> want =
          modes ? std::vector<std::string>{"t_s",    "line",  "x_cmd",       "x_ref",   "x_enc",
                                           "x_ferr", "x_tip", "y_cmd",       "y_ref",   "y_enc",
                                           "y_ferr", "y_tip", "contour_err", "override"}
                : std::vector<std::string>{"t_s",   "line",   "x_cmd",       "x_ref",
                                           "x_enc", "x_ferr", "y_cmd",       "y_ref",
                                           "y_enc", "y_ferr", "contour_err", "override"};
      CHECK(r.columns() == want);
      const std::string units = r.header_value("units");
      CHECK((units.find("*_tip tool tip BLU") != std::string::npos) == modes);
      std::vector<double> v;
      REQUIRE(r.next(v));
      REQUIRE(v.size() == want.size());
      CHECK(v[2] == 100.0);
      CHECK(v[5] == 10.0);  // x_ferr = 90 − 80
      if (modes) {
        CHECK(v[6] == 80.25);
        CHECK(v[11] == 160.5);
      }
      REQUIRE(r.next(v));
      if (modes) {
        CHECK(v[6] == Approx(77.1875).margin(1e-3));  // CSV "77.188": fixed3
        CHECK(v[11] == Approx(157.4375).margin(1e-3));
      }
      CHECK(v[v.size() - 2] == 0.5);
      CHECK_FALSE(r.next(v));
    }
  }
}
