// Hostile inputs end with a clear located error or a correct run, in bounded time and memory
// (every command runs under `timeout`, so a hang fails instead of blocking the suite).
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

fs::path scratch() {
  return gmtest::scratch_dir("hostile");
}

// Writes `text` to a scratch program and runs `gmotion ARGS FILE EXTRA` under a 60 s timeout.
gmtest::CommandResult on(const std::string& text, const std::string& args = "check",
                         const std::string& extra = "") {
  const std::string path = (scratch() / "h.nc").string();
  std::ofstream(path, std::ios::binary) << text;
  return gmtest::sh("timeout 60 " + std::string(GMOTION_BIN) + " " + args + " " + path + " " +
                    extra + " 2>&1");
}

}  // namespace

TEST_CASE("numbers: 1e400, NaN, inf and 10^5 digits are located errors") {
  // 1e400 needs 401 digits (E is a word letter): LinuxCNC refuses the line's length first; the
  // fanuc dialect has no length limit, so the number itself is the error there.
  const std::string huge = "G1 X1" + std::string(400, '0') + " F100\nM2\n";
  auto r = on(huge);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:1:253: error: command too long: 411 bytes"));
  r = on(huge, "check", "--dialect fanuc");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:1:5: error: number out of range"));
  r = on("G1 XNaN F100\nM2\n");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:1:5: error: expected a number after 'X'"));
  r = on("G1 Xinf F100\nM2\n");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:1:5: error"));
  r = on("G1 X" + std::string(100000, '7') + " F100\nM2\n", "check", "--dialect fanuc");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:1:5: error: number out of range"));
  CHECK(r.out.size() < 2000);  // the message abbreviates the number
}

TEST_CASE(
    "a line of megabytes is refused with its location, binary garbage gives errors, no crash") {
  auto r = on("G1 X1 F100 (" + std::string(3'000'000, 'a') + ")\nM2\n");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:1:1: error: line longer than 1048576 bytes"));
  std::string garbage;
  std::uint32_t x = 12345;
  for (int i = 0; i < 200000; ++i)
    garbage += static_cast<char>((x = x * 1664525u + 1013904223u) >> 24);
  r = on(garbage);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("errors"));
}

TEST_CASE("arcs: a million turns checks fast and --max-time ends its run, tiny and huge radii") {
  auto r = on("G0 X1\nG2 X1 Y0 I-1 J0 P1000000 F1000\nM2\n");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Catch::Contains("path 6283186.307 mm"));  // 1 mm + 10^6 · 2π mm
  r = on("G0 X1\nG2 X1 Y0 I-1 J0 P1000000 F1000\nM2\n", "run", "--max-time 1");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("run stopped at --max-time 1 s (line 2"));
  r = on("G2 X0.000000002 Y0 I0.000000001 J0 F100\nM2\n");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:1:20: error: zero radius arc: r1 = 1e-09 mm"));
  r = on("G0 X1000000000\nG2 X1000000000 Y0 I-1000000000 J0 F100\nM2\n", "run", "--max-time 0.5");
  CHECK(r.code == 1);  // 6.3e9 mm at 100 mm/min: stopped by --max-time, not hung
  CHECK_THAT(r.out, Catch::Contains("run stopped at --max-time"));
}

TEST_CASE("degenerate motion: zero-length moves run, F1e-12 is bounded by --max-time") {
  auto r = on("G1 X0 Y0 F100\nG0 X0\nM2\n", "run");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Catch::Contains("final ref/enc err"));
  r = on("G1 X1 F0.000000000001\nM2\n", "run", "--max-time 2");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("run stopped at --max-time 2 s"));
}

TEST_CASE("files: empty, a directory, a missing file") {
  auto r = on("");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("missing program end"));
  r = gmtest::run_gmotion("run " + scratch().string());
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("it is a directory"));
  r = gmtest::run_gmotion("check " + (scratch() / "no-such.nc").string());
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("No such file or directory"));
}

TEST_CASE("unsupported syntax and axes are named at their location") {
  auto r = on("#1=5\nG1 X[#1/0] F100\nG1 A10\nG1 Y#<_nope>\nM2\n");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("h.nc:2:8: error: division by zero: 5 / 0"));
  CHECK_THAT(r.out, Catch::Contains("h.nc:4:5: error: named parameter #<_nope> is not defined"));
  CHECK_THAT(r.out, Catch::Contains("h.nc:3:4: error: axis A is not available"));
}

TEST_CASE("machine files with zero or negative BLU, T or tau are refused by key and line") {
  const fs::path repo = fs::path(GMOTION_TESTS_DIR).parent_path();
  std::ifstream src(repo / "programs" / "machines" / "default.toml");
  const std::string base((std::istreambuf_iterator<char>(src)), std::istreambuf_iterator<char>());
  const std::string prog = (repo / "programs" / "square.nc").string();
  for (const auto& [key, bad] : {std::pair{std::string("period_s"), std::string("0")},
                                 std::pair{std::string("tau_s"), std::string("-0.1")},
                                 std::pair{std::string("blu_mm"), std::string("0")}}) {
    INFO(key << " = " << bad);
    std::string text = base;
    const std::size_t at = text.find("\n" + key + " = ");
    REQUIRE(at != std::string::npos);
    const std::size_t end = text.find('\n', at + 1);
    text.replace(at + 1, end - at - 1, key + " = " + bad);
    const std::string path = (scratch() / "m.toml").string();
    std::ofstream(path) << text;
    const auto r = gmtest::run_gmotion("run " + prog + " --machine " + path);
    CHECK(r.code == 1);
    CHECK_THAT(r.out, Catch::Contains(path + ":"));
    CHECK_THAT(r.out, Catch::Contains(key));
  }
  for (const char* flag : {"--blu 0", "--period -1", "--tau 0"}) {
    INFO(flag);
    const auto r = gmtest::run_gmotion("run " + prog + " " + flag);
    CHECK(r.code == 1);
    CHECK_THAT(r.out, Catch::Contains("must be a positive number"));
  }
  const auto fine = gmtest::run_gmotion("run " + prog + " --blu 1e-20");
  CHECK(fine.code == 1);
  CHECK_THAT(fine.out, Catch::Contains("--blu 1e-20 is finer than 1e-6 mm (1 nm)"));
}

TEST_CASE("Acc/Dec flags asking for millions of taps or endless cascades are refused at once") {
  const std::string prog =
      fs::path(GMOTION_TESTS_DIR).parent_path().string() + "/programs/square.nc";
  const auto huge = gmtest::sh("timeout 20 " + std::string(GMOTION_BIN) + " run " + prog +
                               " --tau 1000 --period 0.0001 2>&1");
  CHECK(huge.code == 1);
  CHECK_THAT(huge.out, Catch::Contains("tau = 1000 s is 1e+07 periods"));
  CHECK_THAT(huge.out, Catch::Contains("at most 100000 taps"));
  // 17 stages (one too many), and one stage longer than the tap limit.
  const auto stages =
      gmtest::sh("timeout 20 " + std::string(GMOTION_BIN) + " run " + prog +
                 " --profile cascade:2,2,2,2,2,2,2,2,2,2,2,2,2,2,2,2,2 --tau 0.072 2>&1");
  CHECK(stages.code == 1);
  CHECK_THAT(stages.out, Catch::Contains("more than 16 cascade stages"));
  const auto longest = gmtest::sh("timeout 20 " + std::string(GMOTION_BIN) + " run " + prog +
                                  " --profile cascade:1000000,3 --tau 4000.008 2>&1");
  CHECK(longest.code == 1);
  CHECK_THAT(longest.out, Catch::Contains("is more than 100000 taps"));
}
