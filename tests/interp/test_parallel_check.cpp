// check_program with reading and parsing on a second thread gives exactly the serial result:
// the same diagnostics in the same order and the same summary, across batch boundaries.
#include "gcode_helpers.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

struct CheckResult {
  gm::CheckSummary sum;
  std::vector<gm::Diagnostic> diags;
};

CheckResult check(const std::string& text, gm::CheckThreads threads) {
  std::istringstream in(text);
  gm::Machine m;
  CheckResult r;
  r.sum = gm::check_program_diagnostics(in, "p.nc", gm::InterpreterOptions{&m, false}, r.diags,
                                        threads);
  return r;
}

void require_same(const std::string& text) {
  const CheckResult a = check(text, gm::CheckThreads::Single);
  const CheckResult b = check(text, gm::CheckThreads::Auto);
  REQUIRE(a.sum.blocks == b.sum.blocks);
  REQUIRE(a.sum.moves == b.sum.moves);
  REQUIRE(a.sum.errors == b.sum.errors);
  REQUIRE(a.sum.path_length_mm == b.sum.path_length_mm);  // same additions in the same order
  REQUIRE(a.sum.time_at_feed_s == b.sum.time_at_feed_s);
  REQUIRE(a.diags.size() == b.diags.size());
  for (std::size_t i = 0; i < a.diags.size(); ++i) {
    INFO("diagnostic " << i);
    REQUIRE(a.diags[i].code == b.diags[i].code);
    REQUIRE(a.diags[i].loc.line == b.diags[i].loc.line);
    REQUIRE(a.diags[i].loc.column == b.diags[i].loc.column);
    REQUIRE(a.diags[i].message == b.diags[i].message);
    REQUIRE(a.diags[i].source_line == b.diags[i].source_line);
  }
}

// Every .nc of programs/ and tests/bad/: its path and its text.
std::vector<std::pair<std::string, std::string>> bundled_programs() {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, std::string>> out;
  for (const char* sub : {"../programs", "bad"})
    for (const auto& e : fs::directory_iterator(fs::path(GMOTION_TESTS_DIR) / sub)) {
      if (e.path().extension() != ".nc") continue;
      std::ifstream f(e.path(), std::ios::binary);
      std::stringstream ss;
      ss << f.rdbuf();
      out.emplace_back(e.path().string(), ss.str());
    }
  return out;
}

}  // namespace

TEST_CASE("parallel check equals serial check on the bundled and bad programs") {
  int files = 0;
  for (const auto& [path, text] : bundled_programs()) {
    INFO(path);
    require_same(text);
    ++files;
  }
  CHECK(files >= 30);
}

TEST_CASE("parallel check equals serial check across batch boundaries (seeded)") {
  const std::uint64_t seed = 5150;
  std::mt19937_64 rng(seed);
  CAPTURE(seed);
  for (int round = 0; round < 6; ++round) {
    // Several thousand lines (batches close at 1024 lines): moves, arcs, errors sprinkled at
    // random, and an ending that varies: M2 then junk, a missing end, a closing '%'.
    std::string p = round == 5 ? "%\nG21 G90 F1000\n" : "G21 G90 F1000\n";
    const int lines = 1000 + static_cast<int>(rng() % 4000);
    double x = 0;
    for (int i = 0; i < lines; ++i) {
      switch (rng() % 10) {
        case 0:
          p += "G1 X#1\n";
          break;  // parameters: unsupported
        case 1:
          p += fmt::format("G2 X{} Y0 R0.1\n", x + 5);
          x += 5;
          break;  // R too small
        case 2:
          p += "(a comment only)\n";
          break;
        case 3:
          p += fmt::format("G3 X{} Y0 I-2 J0\n", x);
          break;  // full circle
        case 4:
          p += std::string(static_cast<std::size_t>(rng() % 3000), ' ') + "G0 Z1\n";
          break;
        default:
          x += 1.25;
          p += fmt::format("G1 X{} Y{}\n", x, (i % 7) * 0.5);
          break;
      }
    }
    if (round % 3 == 0)
      p += "M2\nG1 X(junk after the end\n";
    else if (round == 5)
      p += "%\n";
    // round 1, 2, 4: no end at all (a missing-end diagnostic on the last line)
    INFO("round " << round << ", " << lines << " lines");
    require_same(p);
  }
}

TEST_CASE("parallel check handles an empty program and a program of one huge line") {
  require_same("");
  require_same(std::string(3u << 20, 'G'));  // longer than the line limit and a batch
  require_same("G1 X1 F100\n" + std::string(2u << 20, ' ') + "\nM2\n");
}

TEST_CASE("count_program_errors prints what check_program prints and counts its errors") {
  int files = 0, with_errors = 0;
  for (const auto& [path, text] : bundled_programs()) {
    INFO(path);
    gm::Machine m;
    std::istringstream in1(text), in2(text);
    std::ostringstream out1, out2;
    const gm::CheckSummary s =
        gm::check_program(in1, "p.nc", gm::InterpreterOptions{&m, false}, out1);
    const int errors =
        gm::count_program_errors(in2, "p.nc", gm::InterpreterOptions{&m, false}, out2);
    REQUIRE(errors == s.errors);
    REQUIRE(out2.str() == out1.str());
    ++files;
    if (errors > 0) ++with_errors;
  }
  CHECK(files >= 30);
  CHECK(with_errors >= 10);  // the bad corpus: the diagnostics themselves are compared
}

TEST_CASE("the missing-end diagnostic echoes the program's last line wherever a batch ends") {
  // Batches close at 1,024 lines: the last line is the last of a batch, the first of one, or
  // inside one; its text is only copied when its batch is handed back.
  for (const int lines : {1, 1023, 1024, 1025, 2048, 3000}) {
    std::string p = "G21 G90 F1000\n";
    for (int i = 1; i < lines; ++i) p += fmt::format("G1 X{} Y0\n", i % 50);
    p += "G1 X7.5 Y2 (the last line)\n";
    for (const auto threads : {gm::CheckThreads::Single, gm::CheckThreads::Auto}) {
      INFO(lines << " lines, threads " << static_cast<int>(threads));
      const CheckResult r = check(p, threads);
      REQUIRE(r.diags.size() == 1);
      CHECK(r.diags[0].loc.line == lines + 1);
      CHECK(r.diags[0].source_line == "G1 X7.5 Y2 (the last line)");
      CHECK(r.diags[0].message == "missing program end: the program must end with M2 or M30");
    }
  }
}

TEST_CASE("parallel check equals serial check on blocks imported on the read-ahead thread") {
  // Import errors (a code, a letter, an axis the machine lacks, two motion codes, a repeated
  // word), G7's halved X words (the imported words copied to halve X) and light blocks.
  const std::string text =
      "G21 G90 G17 G94\nG1 X1 Y2 F100\nG1.5 X2\nG1 Q3 X1\nG0 A5\nG1 G0 X1\nG1 X1 X2\n"
      "G18 G7\nG1 X10 Z1\nX20 Z2\nG8\nG1 X10\nG2 X12 Z2 I1 K0\nG17 G2 X1 Y1 R5\nM2\n";
  const CheckResult r = check(text, gm::CheckThreads::Auto);
  CHECK(r.sum.errors == 6);  // lines 3 to 7, and R5 short of half the chord (5.52) on line 14
  CHECK(r.sum.moves == 4);   // X1 Y2; X5 Z1 and X10 Z2 (diameters 10, 20); the G18 arc
  require_same(text);
}
