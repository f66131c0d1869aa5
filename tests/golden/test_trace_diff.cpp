// gmotion diff and the trace reader on hand-made traces: exact first divergence, tolerance,
// CSV against its binary twin, row-count and header mismatches.
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"
#include "support/trace_rows.hpp"
#include "trace/trace_reader.hpp"
#include "trace/trace_writer.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

gm::TraceMeta meta(const std::string& profile = "linear") {
  gm::TraceMeta m;
  m.program = "p.nc";
  m.machine_name = "paper";
  m.machine_source = "paper.toml";
  m.profile = profile;
  m.taps = 41;
  m.tau_s = 0.164;
  m.period_s = 0.004;
  m.blu_mm = gm::AxisVec::Constant(0.001);
  return m;
}

// A trace of `rows` samples; sample `bump_at` gets y_enc + `bump` (when bump_at >= 0).
std::string write(const fs::path& p, int rows, int bump_at = -1, int bump = 0,
                  gm::TraceFormat format = gm::TraceFormat::Csv,
                  const std::string& profile = "linear") {
  gm::TraceWriter w(p.string(), format, meta(profile));
  for (int k = 0; k < rows; ++k) {
    gm::SampleRecord s;
    s.k = k;
    s.t_s = k * 0.004;
    s.line = 3 + k / 10;
    s.cmd_blu = gm::blu3(10 * k, -5 * k, 1);
    s.ref_blu = gm::blu3(9 * k, -4 * k, 1);
    s.enc_blu = gm::blu3(8 * k, -3 * k + (k == bump_at ? bump : 0), 1);
    s.ferr_blu = s.ref_blu - s.enc_blu;
    s.contour_err_blu = 0.125 * k;
    gmtest::write_record(w, s);
  }
  w.finish();
  return p.string();
}

fs::path dir() {
  return gmtest::scratch_dir("diff-test");
}

}  // namespace

TEST_CASE("the reader returns the rows the writer wrote, from CSV and binary alike") {
  const std::string csv = write(dir() / "r.csv", 5),
                    bin = write(dir() / "r.bin", 5, -1, 0, gm::TraceFormat::Binary);
  for (const std::string& path : {csv, bin}) {
    INFO(path);
    gm::TraceReader r(path);
    CHECK(r.header_value("machine") == "paper (paper.toml)");
    CHECK(r.columns().size() == 2 + 4 * 3 + 2);
    std::vector<double> v;
    int n = 0;
    while (r.next(v)) {
      CHECK(v[1] == 3);
      CHECK(v[2] == 10 * n);              // x_cmd
      CHECK(v[8] == -3 * n);              // y_enc
      CHECK(v[14] == Approx(0.125 * n));  // contour_err
      CHECK(v[15] == 100);                // override %
      ++n;
    }
    CHECK(n == 5);
  }
}

TEST_CASE("gmotion diff names the first divergence exactly and honours --tol") {
  const std::string a = write(dir() / "a.csv", 50), b = write(dir() / "b.csv", 50, 23, 2);
  auto r = gmtest::run_gmotion("diff " + a + " " + b);
  CHECK(r.code == 1);
  CHECK_THAT(
      r.out,
      Catch::Contains(
          "first divergence: row 24 (t = 0.092000 s, line 5): column y_enc: -69 in A, -67 in B"));
  CHECK_THAT(r.out, Catch::Contains("y_enc=2 y_ferr=2"));
  CHECK(gmtest::run_gmotion("diff --tol 2 " + a + " " + b).code == 0);
  CHECK(gmtest::run_gmotion("diff --tol 1 " + a + " " + b).code == 1);
  CHECK(gmtest::run_gmotion("diff --columns x_cmd,x_enc " + a + " " + b).code == 0);
  CHECK(gmtest::run_gmotion("diff --columns nope " + a + " " + b).code == 1);
}

TEST_CASE("a CSV trace and its binary twin compare equal, different lengths do not") {
  const std::string csv = write(dir() / "t.csv", 40),
                    bin = write(dir() / "t.bin", 40, -1, 0, gm::TraceFormat::Binary);
  CHECK(gmtest::run_gmotion("diff " + csv + " " + bin).code == 0);
  const std::string shorter = write(dir() / "s.csv", 30);
  const auto r = gmtest::run_gmotion("diff " + csv + " " + shorter);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains(shorter + " ends after 30 rows; " + csv + " has 10 more"));
}

TEST_CASE("gmotion diff refuses traces of different set-ups, naming the header line") {
  const std::string a = write(dir() / "p1.csv", 5),
                    b = write(dir() / "p2.csv", 5, -1, 0, gm::TraceFormat::Csv, "blackman");
  const auto r = gmtest::run_gmotion("diff " + a + " " + b);
  CHECK(r.code == 1);
  CHECK_THAT(r.out,
             Catch::Contains(
                 "traces are of different set-ups: 'profile' is 'linear taps=41 tau_s=0.164'"));
  const auto n = gmtest::run_gmotion("diff " + a + " /etc/hostname");
  CHECK(n.code == 1);
  CHECK_THAT(n.out, Catch::Contains("not a gmotion trace"));
}
