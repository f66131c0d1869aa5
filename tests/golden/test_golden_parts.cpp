// The parts of `gmotion golden`: globs, the trace comparison with pins and tolerances, suite.toml
// errors, set-up differences, JUnit escaping and the PNG writer's bytes.
#include "golden/golden_runner.hpp"
#include "golden/junit.hpp"
#include "golden/png_writer.hpp"
#include "golden/suite.hpp"
#include "golden/trace_compare.hpp"
#include "support/scratch_dir.hpp"
#include "trace/trace_schema.hpp"

#include <fmt/format.h>
#include <zlib.h>
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace gm::golden;

namespace {

fs::path parts_dir() {
  return gmtest::scratch_dir("golden-parts");
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

// A CSV trace of axes XY with `rows` rows; row `bump_row` (1-based) gets `bump` added to the
// column `bump_col`. Values: t = k T, line 3 + k/10, every axis column 10 k + its index.
std::string csv_trace(const std::string& name, int rows, int bump_row = 0,
                      const std::string& bump_col = "", double bump = 0) {
  const std::vector<std::string> cols = gm::trace_column_names("XY");
  std::string s =
      "# gmotion test trace v1\n# period_s: 0.004\n" + fmt::format("{}\n", fmt::join(cols, ","));
  for (int k = 0; k < rows; ++k) {
    std::vector<std::string> v;
    for (std::size_t i = 0; i < cols.size(); ++i) {
      double x = i == 0 ? k * 0.004 : i == 1 ? 3 + k / 10 : 10.0 * k + static_cast<double>(i);
      if (k + 1 == bump_row && cols[i] == bump_col) x += bump;
      v.push_back(i == 0 ? fmt::format("{:.6f}", x) : fmt::format("{}", x));
    }
    s += fmt::format("{}\n", fmt::join(v, ","));
  }
  const fs::path p = parts_dir() / name;
  write_text(p, s);
  return p.string();
}

CompareResult compare(const std::string& a, const std::string& b, const PinSpec& pins = {}) {
  gm::TraceReader g(a), f(b);
  return compare_traces(g, f, pins);
}

}  // namespace

TEST_CASE("globs match column names with * for any text") {
  CHECK(glob_match("*", "x_enc"));
  CHECK(glob_match("*_enc", "x_enc"));
  CHECK(glob_match("*_enc", "w_enc"));
  CHECK_FALSE(glob_match("*_enc", "x_ferr"));
  CHECK(glob_match("x_*", "x_cmd"));
  CHECK_FALSE(glob_match("x_*", "y_cmd"));
  CHECK(glob_match("t_s", "t_s"));
  CHECK_FALSE(glob_match("t_s", "t_sx"));
  CHECK(glob_match("*o*r*", "contour_err"));
  CHECK(glob_match("a**b", "ab"));
}

TEST_CASE("the comparison finds the first divergence, honours pins and tolerances") {
  const std::string g = csv_trace("g.csv", 30);
  SECTION("identical traces pass") {
    const CompareResult r = compare(g, csv_trace("same.csv", 30));
    CHECK(r.pass());
    CHECK(r.rows == 30);
    CHECK(largest_differences(r) == "none");
  }
  SECTION("one count in y_enc at row 12: that row, its time and line, both values") {
    const CompareResult r = compare(g, csv_trace("b.csv", 30, 12, "y_enc", 1));
    REQUIRE(r.first);
    CHECK(r.first->row == 12);
    CHECK(r.first->t_s == Approx(11 * 0.004));
    CHECK(r.first->line == 4);
    CHECK(r.first->column == "y_enc");
    CHECK(r.first->golden ==
          10 * 11 + 8);  // y_enc is column 8 (t_s line x_cmd..x_ferr y_cmd y_ref y_enc)
    CHECK(r.first->fresh == 10 * 11 + 8 + 1);
    CHECK(r.beyond == 1);
    CHECK(largest_differences(r) == "y_enc=1");
    CHECK(describe_first(r) ==
          "t = 0.044000 s, line 4, column y_enc: golden 118, now 119 (row 12)");
  }
  const std::string b = csv_trace("c.csv", 30, 5, "x_ref", 3);
  SECTION("a column left out of the pins is not compared") {
    PinSpec p;
    p.columns = {"*_enc", "*_cmd"};
    CHECK(compare(g, b, p).pass());
  }
  SECTION("a tolerance per column glob, the first match winning") {
    PinSpec p;
    p.tolerances = {{"x_ref", 3}, {"x_*", 0}};
    CHECK(compare(g, b, p).pass());
    p.tolerances = {{"x_*", 2}, {"x_ref", 3}};
    CHECK_FALSE(compare(g, b, p).pass());
    p.tolerances.clear();
    p.tolerance_blu = 3;
    CHECK(compare(g, b, p).pass());
  }
  SECTION("a shorter run is a difference that says how many rows each has") {
    const CompareResult r = compare(g, csv_trace("short.csv", 25));
    CHECK_FALSE(r.pass());
    CHECK_FALSE(r.first);
    CHECK(describe_first(r) == "the run now has 25 rows, the golden 30 (equal for the first 25)");
  }
}

TEST_CASE("suite.toml: cases, defaults and located mistakes") {
  const fs::path s = parts_dir() / "suite";
  fs::create_directories(s);
  write_text(s / "a.nc", "G1 X1 F100\nM2\n");
  write_text(s / "suite.toml",
             "[defaults]\ndecimate = 4\ntolerances = { \"*_enc\" = 1 }\n"
             "[[case]]\nprogram = \"a.nc\"\n"
             "[[case]]\nname = \"a-fast\"\nprogram = \"a.nc\"\nflags = \"--override 150\"\n"
             "tolerances = { \"x_enc\" = 2 }\ncolumns = [\"*_enc\"]\n");
  const Suite suite = load_suite(s);
  REQUIRE(suite.cases.size() == 2);
  CHECK(suite.cases[0].name == "a");
  CHECK(suite.cases[0].decimate == 4);
  CHECK(suite.cases[1].flags == "--override 150");
  CHECK(suite.cases[1].pins.columns == std::vector<std::string>{"*_enc"});
  REQUIRE(suite.cases[1].pins.tolerances.size() == 2);
  CHECK(suite.cases[1].pins.tolerances[0].first == "x_enc");  // the case's own first
  CHECK(suite.store == s / "golden");

  write_text(s / "suite.toml", "[[case]]\nprogram = \"a.nc\"\ntau = 0.1\n");
  CHECK_THROWS_WITH(load_suite(s), Catch::Contains("suite.toml:3: unknown key 'tau' in [[case]]"));
  write_text(s / "suite.toml", "[[case]]\nprogram = \"a.nc\"\n[[case]]\nprogram = \"a.nc\"\n");
  CHECK_THROWS_WITH(load_suite(s), Catch::Contains("two cases are named 'a'"));
  write_text(s / "suite.toml", "[[case]]\nname = \"x\"\n");
  CHECK_THROWS_WITH(load_suite(s), Catch::Contains("needs 'program'"));
  fs::remove(s / "suite.toml");
  const Suite folder = load_suite(s);  // no suite.toml: the folder's programs
  REQUIRE(folder.cases.size() == 1);
  CHECK(folder.cases[0].name == "a");
}

TEST_CASE("set-up changes are named by section and key") {
  const std::string a = "name = \"m\"\n[accdec]\ntau_s = 0.164\n[axes.x]\nkp_1_s = 30\n";
  const std::string b = "name = \"m\"\n[accdec]\ntau_s = 0.1\n[axes.x]\nkp_1_s = 30\nextra = 1\n";
  CHECK(setup_changes(a, b) ==
        std::vector<std::string>{"[accdec] tau_s: 0.164 -> 0.1", "[axes.x] extra: (none) -> 1"});
  CHECK(setup_changes(a, a).empty());
}

TEST_CASE("JUnit text is escaped for XML") {
  CaseResult pass{"ok", Outcome::Pass, "", {}, "", "", 0.5};
  CaseResult fail{"b<", Outcome::Fail, "first divergence x", {"largest"}, "divergence", "", 1.0};
  const std::string x = junit_xml("s", {pass, fail}, 2.0);
  CHECK_THAT(x, Catch::Contains("tests=\"2\" failures=\"1\" errors=\"0\""));
  CHECK_THAT(x, Catch::Contains("name=\"b&lt;\""));
  CHECK_THAT(x, Catch::Contains("<testcase classname=\"golden.s\" name=\"ok\" time=\"0.500\"/>"));
  CHECK_THAT(x, Catch::Contains("name=\"b&lt;\""));
  CHECK_THAT(x, Catch::Contains("<failure message=\"first divergence x\" type=\"divergence\">first "
                                "divergence x\nlargest</failure>"));
}

TEST_CASE("the PNG writer writes valid chunks whose pixels decompress back") {
  Raster r(7, 3);
  r.set(2, 1, {255, 0, 0});
  r.text(0, 0, "?", {0, 0, 0});  // clipped at the edge, no crash
  const std::string png = r.png();
  REQUIRE(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
  auto u32 = [&](std::size_t at) {
    return (static_cast<std::uint32_t>(static_cast<unsigned char>(png[at])) << 24) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 1])) << 16) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 2])) << 8) |
           static_cast<unsigned char>(png[at + 3]);
  };
  // Walk the chunks: every CRC matches, IHDR says 7 x 3, IDAT inflates to 3 rows of 1 + 21 bytes.
  std::size_t at = 8;
  std::string idat, types;
  while (at < png.size()) {
    const std::uint32_t n = u32(at);
    const std::string type = png.substr(at + 4, 4);
    types += type;
    const std::uint32_t crc = static_cast<std::uint32_t>(
        crc32(0, reinterpret_cast<const Bytef*>(png.data() + at + 4), n + 4));
    CHECK(crc == u32(at + 8 + n));
    if (type == "IHDR") CHECK((u32(at + 8) == 7 && u32(at + 12) == 3));
    if (type == "IDAT") idat = png.substr(at + 8, n);
    at += 12 + n;
  }
  CHECK(types == "IHDRIDATIEND");
  std::string raw(3 * 22, '\0');
  uLongf len = raw.size();
  REQUIRE(uncompress(reinterpret_cast<Bytef*>(raw.data()), &len,
                     reinterpret_cast<const Bytef*>(idat.data()), idat.size()) == Z_OK);
  CHECK(len == 66);
  CHECK(static_cast<unsigned char>(raw[22 + 1 + 6]) == 255);  // row 1, pixel 2, red
  CHECK(static_cast<unsigned char>(raw[22 + 1 + 7]) == 0);
}
