// Runs every tests/bad/*.nc: its first line "; expect LINE:COL CODE [fanuc]" names the first
// diagnostic (and the dialect, when not linuxcnc).
#include "gcode_helpers.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

TEST_CASE("bad-input corpus: each file fails with its stated code at its stated line:col") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(GMOTION_TESTS_DIR) / "bad";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".nc") continue;
    ++files;
    std::ifstream f(entry.path(), std::ios::binary);
    std::string first;
    std::getline(f, first);
    std::smatch m;
    const std::regex re(R"(; expect (\d+):(\d+) (\d+)( fanuc)?)");
    INFO(entry.path().filename().string() << ": " << first);
    REQUIRE(std::regex_search(first, m, re));
    f.clear();
    f.seekg(0);
    std::vector<gm::Diagnostic> d;
    gm::Machine machine;
    gm::InterpreterOptions opts{&machine, false};
    if (m[4].matched) opts.dialect = gm::Dialect::Fanuc;
    const auto sum = gm::check_program_diagnostics(f, entry.path().string(), opts, d);
    REQUIRE(sum.errors >= 1);
    REQUIRE(!d.empty());
    CHECK(d[0].loc.line == std::stoi(m[1]));
    CHECK(d[0].loc.column == std::stoi(m[2]));
    CHECK(d[0].code == std::stoi(m[3]));
  }
  CHECK(files >= 20);
}
