// The machine's parameter file (LinuxCNC .var) through the CLI: read at start, written at the end.
#include <catch2/catch.hpp>

#include "support/run_command.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {
using gmtest::sh;
namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A scratch directory holding a machine file that names `params.var` beside it.
struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() / ("gm_varfile_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "machines");
    std::string base =
        slurp(fs::path(GMOTION_TESTS_DIR) / ".." / "programs" / "machines" / "default.toml");
    base.replace(base.find("\n["), 1, "\nparameter_file = \"../params.var\"\n");
    std::ofstream(dir / "machines" / "m.toml") << base;
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string machine() const { return (dir / "machines" / "m.toml").string(); }
  fs::path var() const { return dir / "params.var"; }
  std::string program(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

}  // namespace

TEST_CASE("parameter file: offsets set by one run move the next, as LinuxCNC keeps them") {
  Scratch s;
  const std::string setup = s.program("setup.ngc",
                                      "G10 L2 P1 X100 Y-20 Z5\n"
                                      "G10 L2 P2 X7\n"
                                      "G55\n"
                                      "G0 X1 Y2\n"
                                      "M2\n");
  // check reads the file (none yet) and writes nothing
  CHECK(
      sh(gmtest::gmotion_bin() + " check " + setup + " --machine " + s.machine() + " 2>&1").code ==
      0);
  CHECK_FALSE(fs::exists(s.var()));
  // moves runs it and writes the file: G54 X is #5221, G55's #5241; M2 selected G54 again
  auto r = sh(gmtest::gmotion_bin() + " moves " + setup + " --machine " + s.machine());
  REQUIRE(r.code == 0);
  CHECK(r.out == "{\"line\":4,\"kind\":\"rapid\",\"end\":[8,2,0],\"feed\":0}\n");
  const std::string text = slurp(s.var());
  CHECK(text.find("5220\t1.000000\n5221\t100.000000\n5222\t-20.000000\n5223\t5.000000\n") !=
        std::string::npos);
  CHECK(text.find("5241\t7.000000\n") != std::string::npos);
  // the next program starts with those offsets: G54 X0 Y0 is machine (100, -20, 5)
  const std::string part = s.program("part.ngc", "G0 X0 Y0 Z0\nG55 G0 X0\nM30\n");
  r = sh(gmtest::gmotion_bin() + " moves " + part + " --machine " + s.machine());
  REQUIRE(r.code == 0);
  CHECK(r.out ==
        "{\"line\":1,\"kind\":\"rapid\",\"end\":[100,-20,5],\"feed\":0}\n"
        "{\"line\":2,\"kind\":\"rapid\",\"end\":[7,-20,5],\"feed\":0}\n");
}

TEST_CASE("parameter file: #5220 selects the coordinate system, #5210 re-applies G92") {
  Scratch s;
  std::ofstream(s.var()) << "5210\t1\n5211\t-3\n5220\t3\n5261\t50\n";
  const std::string prog = s.program("p.ngc", "G0 X0 Y0\nG92.2\nG0 X0\nM2\n");
  const auto r = sh(gmtest::gmotion_bin() + " moves " + prog + " --machine " + s.machine());
  REQUIRE(r.code == 0);
  // G56 (X 50) with the G92 shift of -3: machine X 47; after G92.2, X 50 (checked with rs274)
  CHECK(r.out ==
        "{\"line\":1,\"kind\":\"rapid\",\"end\":[47,0,0],\"feed\":0}\n"
        "{\"line\":3,\"kind\":\"rapid\",\"end\":[50,0,0],\"feed\":0}\n");
  const std::string text = slurp(s.var());
  CHECK(text.find("5210\t0.000000\n5211\t-3.000000\n") != std::string::npos);  // G92.2: off, kept
  CHECK(text.find("5220\t1.000000\n") != std::string::npos);                   // M2: G54
}

TEST_CASE("parameter file: #5210 keeps the value read until G92.. sets 1 or 0 (rs274)") {
  Scratch s;
  std::ofstream(s.var()) << "5210\t2\n5211\t-3\n";
  const std::string prog =
      s.program("p.ngc", "(DEBUG,#5210)\nG0 X0\nG92.3\n(DEBUG,#5210)\nG92.2\n(DEBUG,#5210)\nM2\n");
  const auto r = sh(gmtest::gmotion_bin() + " moves --messages " + prog + " --machine " +
                    s.machine() + " | grep -v rapid");
  REQUIRE(r.code == 0);
  CHECK(r.out ==
        "{\"line\":1,\"kind\":\"message\",\"text\":\"2.000000\"}\n"
        "{\"line\":4,\"kind\":\"message\",\"text\":\"1.000000\"}\n"
        "{\"line\":6,\"kind\":\"message\",\"text\":\"0.000000\"}\n");
  std::ofstream(s.var()) << "5210\t2\n5211\t-3\n";
  const std::string keep = s.program("k.ngc", "G0 X0\nM2\n");
  REQUIRE(sh(gmtest::gmotion_bin() + " moves " + keep + " --machine " + s.machine()).code == 0);
  CHECK(slurp(s.var()).find("5210\t2.000000\n") != std::string::npos);  // written back as read
}

TEST_CASE("parameter file: a corrupt file is a located error and is not overwritten") {
  Scratch s;
  const std::string corrupt = "5221\t1.0\n5161\t2.0\n";
  std::ofstream(s.var()) << corrupt;
  const std::string prog = s.program("p.ngc", "G0 X1\nM2\n");
  const auto r =
      sh(gmtest::gmotion_bin() + " moves " + prog + " --machine " + s.machine() + " 2>&1");
  CHECK(r.code == 1);
  CHECK(r.out.find("params.var:2:1: error: parameter #5161 out of order") != std::string::npos);
  CHECK(r.out.find("\n  5161\t2.0\n  ^\n") != std::string::npos);
  CHECK(slurp(s.var()) == corrupt);
}

TEST_CASE("parameter file: --parameter-file replaces the machine's, --no-parameter-file opts out") {
  Scratch s;
  std::ofstream(s.var()) << "5221\t10\n";  // the machine's file: G54 X = 10
  const std::string prog = s.program("p.ngc", "G0 X1\nG10 L2 P1 X3\nM2\n");
  const std::string base = gmtest::gmotion_bin() + " moves " + prog + " --machine " + s.machine();
  // --no-parameter-file: G54 starts at 0 and nothing is written, the machine's file untouched
  auto r = sh(base + " --no-parameter-file");
  REQUIRE(r.code == 0);
  CHECK(r.out == "{\"line\":1,\"kind\":\"rapid\",\"end\":[1,0,0],\"feed\":0}\n");
  CHECK(slurp(s.var()) == "5221\t10\n");
  // --parameter-file FILE: that file is read (a missing one is not an error) and written instead
  const fs::path other = s.dir / "other.var";
  r = sh(base + " --parameter-file " + other.string());
  REQUIRE(r.code == 0);
  CHECK(r.out == "{\"line\":1,\"kind\":\"rapid\",\"end\":[1,0,0],\"feed\":0}\n");
  CHECK(slurp(other).find("5221\t3.000000\n") != std::string::npos);
  CHECK(slurp(s.var()) == "5221\t10\n");
  r = sh(base + " --parameter-file " + other.string());
  CHECK(r.out == "{\"line\":1,\"kind\":\"rapid\",\"end\":[4,0,0],\"feed\":0}\n");
  // the machine's file still applies without a flag
  r = sh(base);
  CHECK(r.out == "{\"line\":1,\"kind\":\"rapid\",\"end\":[11,0,0],\"feed\":0}\n");
  // the two flags exclude each other (a usage error)
  CHECK(sh(base + " --no-parameter-file --parameter-file " + other.string() + " 2>&1").code == 2);
}
