// Subroutine files: `o<name> call` reads name.ngc from the subroutine path (LinuxCNC's
// SUBROUTINE_PATH), with the untrusted-input rules; values worked by hand and checked with rs274.
#include "common/error_codes.hpp"
#include "gcode_helpers.hpp"
#include "interp/subroutine_path.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace gmtest;
namespace fs = std::filesystem;

namespace {

/// A scratch directory with subroutine files, removed at the end of the test.
struct Library {
  fs::path dir;
  Library() {
    char tmpl[] = "/tmp/gmotion-subs-XXXXXX";
    dir = mkdtemp(tmpl);
  }
  ~Library() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  Library(const Library&) = delete;
  Library& operator=(const Library&) = delete;
  void add(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
  }
  gm::InterpreterOptions options(const gm::Machine& m) const {
    gm::InterpreterOptions o{&m, false};
    o.subroutine_path = {dir.string()};
    return o;
  }
};

std::vector<gm::Motion> streamed(const std::string& program, const gm::InterpreterOptions& o) {
  std::istringstream in(program);
  gm::ProgramStream s(in, "main.ngc", o);
  std::vector<gm::Motion> out;
  gm::Canon c;
  while (s.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) out.push_back(*mo);
  return out;
}

std::vector<gm::Diagnostic> checked(const std::string& program, const gm::InterpreterOptions& o,
                                    gm::CheckThreads threads = gm::CheckThreads::Auto) {
  std::istringstream in(program);
  std::vector<gm::Diagnostic> d;
  gm::check_program_diagnostics(in, "main.ngc", o, d, threads);
  return d;
}

std::vector<double> xs(const std::vector<gm::Motion>& ms) {
  std::vector<double> out;
  for (const auto& m : ms) out.push_back(m.end_mm[0]);
  return out;
}

}  // namespace

TEST_CASE("o<name> call runs name.ngc from the subroutine path, with arguments and a value") {
  Library lib;
  // A loop inside the file (re-read by seeking in the file) and a return value.
  lib.add("steps.ngc",
          "(steps: #1 moves of #2 along X)\no<steps> sub\n#<i>=0\no1 while [#<i> LT #1]\n"
          "G91 G0 X#2\n#<i>=[#<i>+1]\no1 endwhile\nG90\no<steps> endsub [#1*#2]\nM2\n");
  gm::Machine m;
  const auto o = lib.options(m);
  // The label is read in lower case (as LinuxCNC): o<STEPS> finds steps.ngc.
  const std::string program =
      "G21\no<STEPS> call [3] [2]\nG0 Y#<_value>\no<steps> call [1] [10]\nM2\n";
  const auto ms = streamed(program, o);
  CHECK(xs(ms) == std::vector<double>{2, 4, 6, 6, 16});
  REQUIRE(ms.size() == 5);
  CHECK(ms[3].end_mm[1] == 6.0);  // the returned 3*2
  CHECK(ms[0].line == 5);         // a line of steps.ngc
  for (auto threads : {gm::CheckThreads::Auto, gm::CheckThreads::Single})
    CHECK(checked(program, o, threads).empty());
}

TEST_CASE("a sub file calls another, a numbered call finds N.ngc, files beyond the open limit") {
  Library lib;
  lib.add("outer.ngc", "o<outer> sub\nG0 X#1\no<inner> call [#1+1]\nG0 X#1\no<outer> endsub\n");
  lib.add("inner.ngc", "o<inner> sub\nG0 X[#1*10]\no<inner> endsub\n");
  lib.add("200.ngc", "o200 sub\nG0 X200\no200 endsub\n");
  for (int k = 0; k < 6; ++k)
    lib.add("f" + std::to_string(k) + ".ngc", "o<f" + std::to_string(k) + "> sub\nG0 X" +
                                                  std::to_string(k + 1) + "\no<f" +
                                                  std::to_string(k) + "> endsub\n");
  gm::Machine m;
  const auto o = lib.options(m);
  CHECK(xs(streamed("o<outer> call [2]\no200 call\nM2\n", o)) ==
        std::vector<double>{2, 30, 2, 200});
  // Six files called twice over: more than SubroutineFiles keeps open (4), reopened as needed.
  std::string p;
  for (int round = 0; round < 2; ++round)
    for (int k = 0; k < 6; ++k) p += "o<f" + std::to_string(k) + "> call\n";
  p += "M2\n";
  CHECK(xs(streamed(p, o)) == std::vector<double>{1, 2, 3, 4, 5, 6, 1, 2, 3, 4, 5, 6});
  CHECK(checked(p, o).empty());
}

TEST_CASE("a file on the path comes before a definition further down the program (LinuxCNC)") {
  Library lib;
  lib.add("part.ngc", "o<part> sub\nG0 X7\no<part> endsub\n");
  gm::Machine m;
  const auto o = lib.options(m);
  // Defined further down and in a file: the file is read first, then the later `sub` line is
  // a redefinition (rs274: "redefining sub: o|part| already defined in file").
  const std::string p = "o<part> call\no<part> sub\nG0 X1\no<part> endsub\nM2\n";
  const auto d = checked(p, o);
  REQUIRE(d.size() == 2);  // the error, then the note that checking stopped there
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[0].code == code(gm::ErrorCode::SubroutineRedefined));
  CHECK(d[0].loc.line == 2);
  // Without a path the later definition is found and runs (X1); when the call returns, the flow
  // runs into that definition, which rs274 refuses: "sub: o|part| found in illegal location".
  const auto plain = checked(p, gm::InterpreterOptions{});
  REQUIRE_FALSE(plain.empty());
  CHECK(plain[0].loc.line == 2);
  CHECK_THAT(plain[0].message, Catch::Contains("o<part> sub found in illegal location"));
}

TEST_CASE("subroutine files: located errors that name the path and the file") {
  Library lib;
  lib.add("empty.ngc", "(no sub in here)\nG0 X1\n");
  lib.add("bad.ngc", "o<bad> sub\nG0 X1\nG1 X[1/0]\no<bad> endsub\n");
  gm::Machine m;
  const auto o = lib.options(m);

  auto d = checked("G0 X0\no<missing> call\nM2\n", o);
  REQUIRE(d.size() == 1);
  CHECK(d[0].code == code(gm::ErrorCode::UndefinedSubroutine));
  CHECK(d[0].loc.line == 2);
  CHECK(d[0].message.find("no file 'missing.ngc' in " + lib.dir.string()) != std::string::npos);

  d = checked("o<empty> call\nM2\n", o);
  REQUIRE(d.size() == 1);
  CHECK(d[0].message.find("not defined in its file " + (lib.dir / "empty.ngc").string()) !=
        std::string::npos);

  // An error inside the file is located in the file (file:line:col).
  d = checked("G0 X0\no<bad> call\nM2\n", o);
  REQUIRE(d.size() == 1);
  CHECK(d[0].code == code(gm::ErrorCode::DivisionByZero));
  CHECK(d[0].file == (lib.dir / "bad.ngc").string());
  CHECK(d[0].loc.line == 3);
  CHECK(gm::format_diagnostic("main.ngc", d[0]).rfind((lib.dir / "bad.ngc").string() + ":3:", 0) ==
        0);

  // No path: the message says so.
  gm::InterpreterOptions none{&m, false};
  d = checked("o<empty> call\nM2\n", none);
  REQUIRE(d.size() == 1);
  CHECK(d[0].message.find("no subroutine path is set") != std::string::npos);
}

TEST_CASE("a sub defined inside the body of a sub file's sub is an error") {
  // rs274 2.9 runs such a body in line and returns at its endsub; gmotion stops there.
  Library lib;
  lib.add("outer.ngc",
          "o<outer> sub\n  G0 X1\n  o<inner> sub\n    G0 X2\n  o<inner> endsub\n"
          "  G0 X5\no<outer> endsub\nM2\n");
  gm::Machine m;
  const auto d = checked("G0 X0\no<outer> call\nM2\n", lib.options(m));
  REQUIRE(d.size() == 2);  // the error, then the note that checking stopped there
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[0].code == code(gm::ErrorCode::ControlMismatch));
  CHECK(d[0].file == (lib.dir / "outer.ngc").string());
  CHECK(d[0].loc.line == 3);
  CHECK(d[0].loc.column == 3);
  CHECK(d[0].message ==
        "nested subroutine definition: o<inner> sub inside the body of the called subroutine "
        "o<outer>; a sub is defined outside every other sub");
}

TEST_CASE("a program cannot name a file outside the subroutine path") {
  Library lib;
  fs::create_directory(lib.dir / "inner");
  lib.add("escape.ngc", "o<escape> sub\nG0 X1\no<escape> endsub\n");
  gm::Machine m;
  gm::InterpreterOptions o{&m, false};
  o.subroutine_path = {(lib.dir / "inner").string()};
  for (const char* name : {"../escape", "/tmp/escape", ".hidden", "inner/../../escape", "~x"}) {
    CAPTURE(name);
    const auto d = checked(std::string("o<") + name + "> call\nM2\n", o);
    REQUIRE(d.size() == 1);
    CHECK(d[0].code == code(gm::ErrorCode::UndefinedSubroutine));
    CHECK(d[0].message.find("not looked up") != std::string::npos);
  }
  CHECK(gm::SubroutinePath::safe_name("my_sub-2.v1"));
  CHECK_FALSE(gm::SubroutinePath::safe_name("a/b"));
  CHECK(gm::SubroutinePath::split("a::b:") == std::vector<std::string>{"a", "b"});
}

TEST_CASE("return and endsub leave the current call whatever their label (rs274's retval.ngc)") {
  // rs274 2.9 prints 4712, 246, 0 for this (LinuxCNC's sample program retval.ngc, rewritten).
  const auto ms = motions(
      "o1 sub\no2 if [#1 GT 0]\no2 return [123*#1]\no2 endif\no3 if [#1 LT 0]\no3 return\n"
      "o3 endif\no1 endsub [4712]\n"
      "o1 call [0]\nG0 X#<_value>\no1 call [2]\nG0 X#<_value>\no1 call [-1]\nG0 X#<_value>\n"
      "M2\n");
  CHECK(xs(ms) == std::vector<double>{4712, 246, 0});
}

TEST_CASE("polar coordinates: @ radius and ^ angle about the origin (LinuxCNC), and their errors") {
  // G90: @10 ^90 is (0, 10); then ^180 keeps the radius: (-10, 0). G91 @5 adds to the radius.
  const auto ms = motions("G21 G90\nG0 @10 ^90\nG0 ^180\nG91 G0 @5\nM2\n");
  REQUIRE(ms.size() == 3);
  CHECK(ms[0].end_mm[0] == Approx(0.0).margin(1e-12));
  CHECK(ms[0].end_mm[1] == Approx(10.0));
  CHECK(ms[1].end_mm[0] == Approx(-10.0));
  CHECK(ms[2].end_mm[0] == Approx(-15.0));
  auto d = diagnose("G0 X1 @2\nM2\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].code == code(gm::ErrorCode::PolarMisused));
  CHECK(d[0].loc.column == 7);
  d = diagnose("G91 G0 ^30\nM2\n");  // at the origin: no direction (rs274 refuses it too)
  REQUIRE(d.size() == 1);
  CHECK(d[0].code == code(gm::ErrorCode::PolarMisused));
}
