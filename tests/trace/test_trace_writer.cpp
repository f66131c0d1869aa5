// Trace files: header, CSV rows, binary layout, decimation, and the temp-file-then-rename rule.
#include "common/status.hpp"
#include "trace/trace_writer.hpp"

#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {
gm::TraceMeta meta() {
  gm::TraceMeta m;
  m.program = "p.nc";
  m.machine_name = "paper";
  m.machine_source = "paper.toml";
  m.profile = "linear";
  m.taps = 41;
  m.tau_s = 0.164;
  m.period_s = 0.004;
  m.blu_mm = gm::AxisVec::Constant(0.001);
  return m;
}
gm::SampleRecord sample(std::int64_t k) {
  gm::SampleRecord s;
  s.k = k;
  s.t_s = static_cast<double>(k) * 0.004;
  s.line = 7;
  s.cmd_blu = gm::AxisBlu(10, -20, 3);
  s.ref_blu = gm::AxisBlu(9, -19, 3);
  s.enc_blu = gm::AxisBlu(8, -18, 3);
  s.ferr_blu = s.ref_blu - s.enc_blu;
  s.contour_err_blu = -1.25;
  s.feed_scale = 1.5;
  return s;
}
std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
fs::path temp_dir() { return gmtest::scratch_dir("trace-test"); }
}  // namespace

TEST_CASE("CSV trace: header then one row per sample, renamed into place by finish()") {
  const fs::path p = temp_dir() / "t.csv";
  {
    gm::TraceWriter w(p.string(), gm::TraceFormat::Csv, meta());
    w.write(sample(0));
    w.write(sample(1));
    CHECK_FALSE(fs::exists(p));  // only the .partial exists until finish()
    CHECK(fs::exists(p.string() + ".partial"));
    w.finish();
  }
  const std::string text = slurp(p);
  CHECK(text.rfind("# gmotion ", 0) == 0);
  CHECK(text.find("\nt_s,line,x_cmd,x_ref,x_enc,x_ferr,y_cmd,y_ref,y_enc,y_ferr,z_cmd,z_ref,z_enc,z_ferr,"
                  "contour_err,override\n") != std::string::npos);
  CHECK(text.find("\n0.004000,7,10,9,8,1,-20,-19,-18,-1,3,3,3,0,-1.250,150\n") != std::string::npos);
  CHECK_FALSE(fs::exists(p.string() + ".partial"));
}

TEST_CASE("a writer destroyed without finish() leaves no file behind") {
  const fs::path p = temp_dir() / "abandoned.csv";
  { gm::TraceWriter w(p.string(), gm::TraceFormat::Csv, meta()); w.write(sample(0)); }
  CHECK_FALSE(fs::exists(p));
  CHECK_FALSE(fs::exists(p.string() + ".partial"));
}

TEST_CASE("decimation keeps every K-th sample") {
  const fs::path p = temp_dir() / "dec.csv";
  auto m = meta();
  m.decimate = 3;
  gm::TraceWriter w(p.string(), gm::TraceFormat::Csv, m);
  for (int k = 0; k < 10; ++k) w.write(sample(k));
  w.finish();
  CHECK(w.rows() == 4);  // k = 0, 3, 6, 9
}

TEST_CASE("binary trace: magic, header length, fixed little-endian records") {
  const fs::path p = temp_dir() / "t.bin";
  gm::TraceWriter w(p.string(), gm::TraceFormat::Binary, meta());
  w.write(sample(5));
  w.finish();
  const std::string b = slurp(p);
  REQUIRE(b.substr(0, 8) == "GMTRACE1");
  std::uint32_t hlen = 0;
  std::memcpy(&hlen, b.data() + 8, 4);
  CHECK(hlen == gm::trace_header(meta()).size());
  const std::size_t rec = 8 + 4 + 4 * 8 * gm::kAxes + 8 + 8;
  REQUIRE(b.size() == 12 + hlen + rec);
  const char* r = b.data() + 12 + hlen;
  std::int64_t k = 0, y_enc = 0;
  double contour = 0;
  std::memcpy(&k, r, 8);
  std::memcpy(&y_enc, r + 12 + (4 + 2) * 8, 8);
  std::memcpy(&contour, r + 12 + 12 * 8, 8);
  CHECK(k == 5);
  CHECK(y_enc == -18);
  CHECK(contour == -1.25);
}

TEST_CASE("an unwritable trace path is a clear input error") {
  CHECK_THROWS_AS(gm::TraceWriter("/nonexistent-dir/x.csv", gm::TraceFormat::Csv, meta()), gm::InputError);
}
