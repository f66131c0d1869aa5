// gmotion report end to end: a self-contained page whose path, summary and columns match the run.
#include "support/read_file.hpp"
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::filesystem::path write_program(const std::string& name, const std::string& text) {
  const auto p = gmtest::scratch_dir("report") / name;
  std::ofstream(p) << text;
  return p;
}

/// The numbers of the JSON array after `"key":[` in `page`.
std::vector<double> json_numbers(const std::string& page, const std::string& key) {
  const std::string open = "\"" + key + "\":[";
  const auto at = page.find(open);
  REQUIRE(at != std::string::npos);
  const auto end = page.find(']', at);
  std::stringstream ss(page.substr(at + open.size(), end - at - open.size()));
  std::vector<double> v;
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(std::stod(item));
  return v;
}

/// The text between `<script type="application/json" id="ID">` and `</script>`.
std::string script_text(const std::string& page, const std::string& id) {
  const std::string open = "<script type=\"application/json\" id=\"" + id + "\">";
  const auto at = page.find(open);
  REQUIRE(at != std::string::npos);
  const auto end = page.find("</script>", at);
  return page.substr(at + open.size(), end - at - open.size());
}

}  // namespace

TEST_CASE("report: a 10 mm square, programmed path, summary and source lines", "[report]") {
  const auto dir = gmtest::scratch_dir("report");
  const auto prog = write_program("square10.nc",
                                  "G21 G90 G17 G64\n"
                                  "G1 X10 F600 (first side)\n"
                                  "Y10\n"
                                  "X0\n"
                                  "Y0\n"
                                  "M2\n");
  const auto page_path = dir / "square10.html";
  const auto json_path = dir / "square10.json";
  const auto r = gmtest::run_gmotion("report " + prog.string() + " -o " + page_path.string() +
                                     " --summary-json " + json_path.string());
  INFO(r.out);
  REQUIRE(r.code == 0);
  const std::string page = gmtest::slurp(page_path);
  REQUIRE(page.size() > 10000);

  // Self-contained: no URL, no external reference of any kind.
  CHECK(page.find("http://") == std::string::npos);
  CHECK(page.find("https://") == std::string::npos);
  CHECK(page.find(" src=") == std::string::npos);
  CHECK(page.find(" href=") == std::string::npos);
  CHECK(page.find("url(") == std::string::npos);
  CHECK(page.find("@import") == std::string::npos);

  // The programmed path: the view box is 600 units with a 20-unit margin, so the square's 10 mm
  // span 560 units, 56 a millimetre, y up: (x, y) mm -> (20 + 56 x, 20 + 56 (10 − y)).
  CHECK(page.find(R"~(<polyline class="prog" points="20.00,580.00 580.00,580.00 580.00,20.00 )~"
                  R"~(20.00,20.00 20.00,580.00"/>)~") != std::string::npos);
  CHECK(page.find("class=\"rapid\"") == std::string::npos);  // no rapid in XY

  // The summary embedded is the run's --summary-json, byte for byte.
  std::string json = gmtest::slurp(json_path);
  while (!json.empty() && json.back() == '\n') json.pop_back();
  REQUIRE(!json.empty());
  CHECK(script_text(page, "gm-summary") == json);

  // The columns: not decimated (about 4.5 s at 4 ms is ~1100 samples < 2048 columns), and the
  // largest |contour error| over the columns is the summary's.
  CHECK(page.find("one column each (not decimated)") != std::string::npos);
  const std::string data = script_text(page, "gm-data");
  CHECK(data.find(R"~("width":1,)~") != std::string::npos);
  const auto lo = json_numbers(data, "ce_lo"), hi = json_numbers(data, "ce_hi");
  REQUIRE(lo.size() == hi.size());
  double worst = 0;
  for (std::size_t i = 0; i < lo.size(); ++i)
    worst = std::max({worst, std::abs(lo[i]), std::abs(hi[i])});
  std::smatch m;
  REQUIRE(
      std::regex_search(json, m, std::regex(R"~("contour_err_max_blu":\{"value":([-0-9.e+]+))~")));
  CHECK(worst == Approx(std::stod(m[1].str())).epsilon(1e-5));
  const auto t = json_numbers(data, "t");
  REQUIRE(t.size() == lo.size());
  CHECK(t[1] - t[0] == Approx(0.004));

  // The source lines under the cursor, as written in the program.
  CHECK(data.find(R"~("2":"G1 X10 F600 (first side)")~") != std::string::npos);
  CHECK(data.find(R"~("3":"Y10")~") != std::string::npos);
  CHECK(data.find("\"file\":\"" + prog.string() + "\"") != std::string::npos);

  // The taps: the default profile's taps as bars, and its response.
  CHECK(page.find("<svg id=\"taps\"") != std::string::npos);
  CHECK(page.find("<svg id=\"response\"") != std::string::npos);
}

TEST_CASE("report: a long program is decimated, its peaks kept", "[report]") {
  const auto dir = gmtest::scratch_dir("report");
  // 40 strokes of ~10 mm at 1200 mm/min (20 mm/s): ~20 s, ~5000 samples at 4 ms, so 2048
  // columns of 4 samples (between 4096 and 8192 samples).
  std::string text = "G21 G90 G64\nF1200\n";
  for (int i = 0; i < 20; ++i)
    text += "G1 X10 Y" + std::to_string(i) + ".5\nG1 X0 Y" + std::to_string(i + 1) + "\n";
  text += "M2\n";
  const auto prog = write_program("zigzag20.nc", text);
  const auto page_path = dir / "zigzag20.html";
  const auto json_path = dir / "zigzag20.json";
  const auto r = gmtest::run_gmotion("report " + prog.string() + " -o " + page_path.string() +
                                     " --summary-json " + json_path.string());
  INFO(r.out);
  REQUIRE(r.code == 0);
  const std::string page = gmtest::slurp(page_path);
  const std::string data = script_text(page, "gm-data");
  std::smatch m;
  REQUIRE(std::regex_search(
      page, m, std::regex(R"~(decimated: (\d+) samples in (\d+) columns of (\d+) samples)~")));
  const long samples = std::stol(m[1].str()), columns = std::stol(m[2].str()),
             width = std::stol(m[3].str());
  REQUIRE(samples > 4096);
  REQUIRE(samples <= 8192);
  CHECK(width == 4);
  CHECK(columns == (samples + 3) / 4);
  CHECK(data.find(R"~("width":4,)~") != std::string::npos);
  const std::string json = gmtest::slurp(json_path);
  REQUIRE(std::regex_search(json, m, std::regex(R"~("samples":(\d+))~")));
  CHECK(std::stol(m[1].str()) == samples);
  const auto lo = json_numbers(data, "ce_lo"), hi = json_numbers(data, "ce_hi");
  REQUIRE(static_cast<long>(hi.size()) == columns);
  double worst = 0;
  for (std::size_t i = 0; i < lo.size(); ++i)
    worst = std::max({worst, std::abs(lo[i]), std::abs(hi[i])});
  REQUIRE(
      std::regex_search(json, m, std::regex(R"~("contour_err_max_blu":\{"value":([-0-9.e+]+))~")));
  CHECK(worst == Approx(std::stod(m[1].str())).epsilon(1e-5));
  CHECK(page.size() < 2'000'000);
}

TEST_CASE("report: takes run's flags, refuses a page it cannot write, errors located", "[report]") {
  const auto dir = gmtest::scratch_dir("report");
  const auto prog = write_program("line.nc", "G1 X1 F600\nM2\n");
  // A run flag (--override, --profile, --tau) changes what the page says.
  const auto page_path = dir / "line.html";
  auto r = gmtest::run_gmotion("report " + prog.string() +
                               " --profile linear --tau 0.02 "
                               "--override 50 -o " +
                               page_path.string());
  INFO(r.out);
  REQUIRE(r.code == 0);
  const std::string page = gmtest::slurp(page_path);
  CHECK(page.find("profile <b>linear</b>, τ = 0.02 s, T = 0.004 s, 5 taps") != std::string::npos);
  const std::string data = script_text(page, "gm-data");
  const auto ov = json_numbers(data, "ov_hi");
  REQUIRE(!ov.empty());
  CHECK(ov.front() == 50.0);
  // No -o: a usage error (2); a page that cannot be written: an input error (1).
  CHECK(gmtest::run_gmotion("report " + prog.string()).code == 2);
  r = gmtest::run_gmotion("report " + prog.string() + " -o " +
                          (dir / "no-such-dir" / "p.html").string());
  CHECK(r.code == 1);
  CHECK(r.out.find("cannot write the report") != std::string::npos);
  // A program error is located as `run` locates it, and no page is written.
  const auto bad = write_program("bad.nc", "G1 X1 F600\nG1 X2 Q\nM2\n");
  r = gmtest::run_gmotion("report " + bad.string() + " -o " + (dir / "bad.html").string());
  CHECK(r.code == 1);
  CHECK(r.out.find("bad.nc:2:") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "bad.html"));
}

TEST_CASE("report: the tool tip's ringing on a machine with modes, none without", "[report][tip]") {
  const auto dir = gmtest::scratch_dir("report");
  const std::string repo = std::filesystem::path(GMOTION_TESTS_DIR).parent_path().string();
  const auto page_path = dir / "ringing.html";
  const auto json_path = dir / "ringing.json";
  const auto r = gmtest::run_gmotion("report " + repo + "/programs/ringing.nc --machine " + repo +
                                     "/programs/machines/ringing-40hz.toml -o " +
                                     page_path.string() + " --summary-json " + json_path.string());
  REQUIRE(r.code == 0);
  const std::string page = gmtest::slurp(page_path);
  const auto at = page.find("<svg id=\"ringing\"");
  REQUIRE(at != std::string::npos);
  const std::string svg = page.substr(at, page.find("</svg>", at) - at);
  // X and Y have the mode: a line each; Z (no mode, no deflection) none.
  std::size_t lines = 0;
  for (auto p = svg.find("<polyline"); p != std::string::npos; p = svg.find("<polyline", p + 1))
    ++lines;
  CHECK(lines == 2);
  // The note names each axis's worst stop with the summary's values.
  const std::string json = gmtest::slurp(json_path);
  const std::regex x_residual(
      R"("x":\{"stops":\d+,"residual_max_blu":\{"value":([0-9.]+),"line":(\d+)\})");
  std::smatch m;
  REQUIRE(std::regex_search(json, m, x_residual));
  char expect[96];
  std::snprintf(expect, sizeof expect, "X: residual vibration %.2f BLU after line %s",
                std::stod(m[1].str()), m[2].str().c_str());
  CHECK(page.find(expect) != std::string::npos);
  // A worst stop's record: 50 ms before the rest and up to the 0.2 s window, every T = 1 ms.
  const auto pts = svg.find("points=\"");
  REQUIRE(pts != std::string::npos);
  const std::string first = svg.substr(pts + 8, svg.find('"', pts + 8) - pts - 8);
  const auto n = static_cast<std::size_t>(std::count(first.begin(), first.end(), ' ')) + 1;
  CHECK(n > 50);
  CHECK(n <= 250);

  const auto plain = dir / "plain.html";
  const auto prog = write_program("plain.nc", "G21 G90\nG1 X5 F600\nM2\n");
  REQUIRE(gmtest::run_gmotion("report " + prog.string() + " -o " + plain.string()).code == 0);
  const std::string plain_page = gmtest::slurp(plain);
  CHECK(plain_page.find("id=\"ringing\"") == std::string::npos);
  CHECK(plain_page.find("Tool tip ringing") == std::string::npos);
}
