// Expressions, parameters and active comments: values checked against LinuxCNC 2.9's rs274 by hand.
#include "common/error_codes.hpp"
#include "gcode_helpers.hpp"
#include "interp/parameters.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace gmtest;

namespace {

// (DEBUG, #1) after `#1=expr`: the value rs274 prints (%f).
std::string debug_value(const std::string& expr) {
  const auto m = messages("#1=" + expr + "\n(DEBUG,#1)\nM2\n");
  return m.empty() ? "<none>" : m.back();
}

}  // namespace

TEST_CASE("operators follow LinuxCNC's precedence, each level left to right (rs274 values)") {
  CHECK(debug_value("[2**3**2]") == "64.000000");  // (2**3)**2
  CHECK(debug_value("[-2**2]") == "4.000000");     // unary minus binds tightest
  CHECK(debug_value("[2*3**2]") == "18.000000");
  CHECK(debug_value("[1+2*3 EQ 7]") == "1.000000");
  CHECK(debug_value("[2 GT 1 + 1]") == "0.000000");    // + before GT
  CHECK(debug_value("[1 OR 1 AND 0]") == "0.000000");  // AND OR XOR share one level
  CHECK(debug_value("[0 AND 1 OR 1]") == "1.000000");
  CHECK(debug_value("[7 MOD -3]") == "1.000000");
  CHECK(debug_value("[-7 MOD 3]") == "2.000000");
  CHECK(debug_value("[1 EQ 1.00001]") == "1.000000");  // EQ within 1e-4
  CHECK(debug_value("[1 EQ 1.001]") == "0.000000");
  CHECK(debug_value("[1 GE 1.00001]") == "0.000000");
  CHECK(debug_value("[0.5 AND 2]") == "1.000000");
  CHECK(debug_value("[1 +-2]") == "-1.000000");
  CHECK(debug_value("[2*-3]") == "-6.000000");
}

TEST_CASE("functions work in degrees and round like LinuxCNC (rs274 values)") {
  CHECK(debug_value("[ATAN[1]/[-1]]") == "135.000000");
  CHECK(debug_value("SIN[30]") == "0.500000");
  CHECK(debug_value("[ACOS[0.5]]") == "60.000000");
  CHECK(debug_value("[ROUND[2.5]]") == "3.000000");
  CHECK(debug_value("[ROUND[-2.5]]") == "-3.000000");
  CHECK(debug_value("[FIX[-2.5]]") == "-3.000000");
  CHECK(debug_value("[FUP[-2.5]]") == "-2.000000");
  CHECK(debug_value("[EXP[1]]") == "2.718282");
  CHECK(debug_value("[SQRT[2]]") == "1.414214");
  CHECK(debug_value("[ABS[-3]+LN[1]]") == "3.000000");
}

TEST_CASE("settings on a line take effect after the whole line is read (rs274)") {
  // #2 reads the old #1; the motion reads the old #3; the last of two settings wins.
  auto m = messages("#1=5 #2=[#1+1]\n(DEBUG,#1 #2)\nM2\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0] == "5.000000 1.000000");
  auto mv = motions("#3=7\n#3=1 #3=2 G1 X#3 F100\nG1 X#3\nM2\n");
  REQUIRE(mv.size() == 2);
  CHECK(mv[0].end_mm[0] == 7.0);
  CHECK(mv[1].end_mm[0] == 2.0);
  // The comment of the line sees the new values.
  m = messages("#1=5 (DEBUG,#1)\nM2\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0] == "5.000000");
}

TEST_CASE("a named parameter exists from its setting on: later reads on the line see 0 (rs274)") {
  auto m = messages("#<x>=1 #<y>=[#<x>+1]\n(DEBUG,#<x> #<y>)\nM2\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0] == "1.000000 1.000000");
  m = messages("#<x>=[#<x>+1]\n(DEBUG,#<x>)\nM2\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0] == "1.000000");
  // A read before the setting is an error, as in rs274.
  const auto d = diagnose("G0 X#<w> #<w>=1\nM2\n");
  REQUIRE(!d.empty());
  CHECK(d[0].code == code(gm::ErrorCode::UndefinedParameter));
}

TEST_CASE("named parameters, EXISTS and predefined ones (rs274)") {
  auto mv = motions("#<width>=20 #<_depth>=-1.5\nG1 X[#<width>/2] Z#<_DEPTH> F100\nM2\n");
  REQUIRE(mv.size() == 1);
  CHECK(mv[0].end_mm[0] == 10.0);
  CHECK(mv[0].end_mm[2] == -1.5);
  auto m =
      messages("#<a>=1\n(DEBUG,[#<a>] #<b>)\n#2=EXISTS[#<a>] #3=EXISTS[#<b>]\n(DEBUG,#2 #3)\nM2\n");
  REQUIRE(m.size() == 2);
  CHECK(m[0] == "[1.000000] ######");
  CHECK(m[1] == "1.000000 0.000000");
  m = messages(
      "G20\nG1 X1 Y2 F10 G91\n(DEBUG,#<_motion_mode> #<_plane> #<_coord_system> #<_metric> "
      "#<_imperial> #<_incremental> #<_feed> #<_x> #<_y> #5420 #<_line>)\nM2\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0] ==
        "10.000000 170.000000 540.000000 0.000000 1.000000 1.000000 10.000000 1.000000 "
        "2.000000 1.000000 3.000000");
}

TEST_CASE("%d, %f and %.Nf in DEBUG/PRINT comments format the values after them (rs274 2.9)") {
  // A format holds for the rest of the comment; a '%' that starts none is text ('%.' loses it);
  // a value within 1e-4 of 0 prints as 0; MSG is never formatted.
  const auto m = messages(
      "#<v>=2.71828 #2=2.5 #3=-0.00005\n"
      "(DEBUG, i %d#<v> f %f#<v> n %.2f#<v> k %.8f#3 #2)\n"
      "(DEBUG, h %d#2 100% %.q #2 %%)\n"
      "(PRINT, p %.1f#<v>)\n(MSG, m %d#<v>)\nM2\n");
  REQUIRE(m.size() == 4);
  CHECK(m[0] == "i 3 f 2.7183 n 2.72 k 0.00000000 2.50000000");
  CHECK(m[1] == "h 2 100% .q 2 %%");
  CHECK(m[2] == "p 2.7");
  CHECK(m[3] == "m %d#<v>");
}

TEST_CASE("EXISTS of a numbered parameter: 1 for every parameter number (rs274 2.9)") {
  // #1 set, #123 never set, #[1+1] computed: numbers 1..5601 exist; #0 and #99999 do not; an
  // unknown global name does not, the predefined #<_x> does.
  const auto m = messages(
      "#1=5\n#10=EXISTS[#1] #11=EXISTS[#<_unknown>] #12=EXISTS[#123] #13=EXISTS[#[1+1]]\n"
      "#14=EXISTS[#0] #15=EXISTS[#99999] #16=EXISTS[#<_x>]\n(DEBUG,#10 #11 #12 #13 #14 #15 #16)\n"
      "M2\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0] == "1.000000 0.000000 1.000000 1.000000 0.000000 0.000000 1.000000");
  // rs274: "Non integer value for integer".
  const auto d = diagnose("#10=EXISTS[#1.5]\nM2\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].code == code(gm::ErrorCode::ParameterOutOfRange));
  CHECK(d[0].loc.line == 1);
  CHECK(d[0].loc.column == 5);
  CHECK(d[0].message == "EXISTS[#1.5]: a parameter number is an integer");
}

TEST_CASE("only the last comment of a line acts, MSG is shown as written (rs274)") {
  CHECK(messages("(MSG,a)(MSG,b)\nM2\n") == std::vector<std::string>{"b"});
  CHECK(messages("(MSG,c)(plain)\nM2\n").empty());
  CHECK(messages("#1=3\n(MSG,#1)\nM2\n") == std::vector<std::string>{"#1"});
  CHECK(messages("#1=5\n(DEBUG,#1.5 ##1 #1x #6000)\nM2\n") ==
        std::vector<std::string>{"5.000000.5 #5.000000 5.000000x ######"});
}

TEST_CASE("expression and parameter errors are located and name what is at fault") {
  struct Case {
    const char* program;
    gm::ErrorCode code;
    int line, column;
    const char* says;
  };
  const Case cases[] = {
      {"G0 X[1/0]\n", gm::ErrorCode::DivisionByZero, 1, 7, "1 / 0"},
      {"G0 X[SQRT[-1]]\n", gm::ErrorCode::DomainError, 1, 6, "SQRT[-1]"},
      {"G0 X[ACOS[2]]\n", gm::ErrorCode::DomainError, 1, 6, "ACOS"},
      {"G0 X[-8**[1/3]]\n", gm::ErrorCode::DomainError, 1, 8, "non-integer power"},
      {"G0 X[0**-1]\n", gm::ErrorCode::NotANumber, 1, 7, "infinity"},
      {"G0 X[10 MOD 0]\n", gm::ErrorCode::NotANumber, 1, 9, "not a number"},
      {"G0 X#6000\n", gm::ErrorCode::ParameterOutOfRange, 1, 5, "#6000"},
      {"G0 X#0\n", gm::ErrorCode::ParameterOutOfRange, 1, 5, "#0"},
      {"G0 X#1.5\n", gm::ErrorCode::ParameterOutOfRange, 1, 5, "not an integer"},
      {"#5400=1\n", gm::ErrorCode::ParameterReadOnly, 1, 1, "#5400"},
      {"#<_x>=1\n", gm::ErrorCode::ParameterReadOnly, 1, 1, "_x"},
      {"G0 X#<depth>\n", gm::ErrorCode::UndefinedParameter, 1, 5, "#<depth>"},
      {"(ABORT,stop #<_x>)\n", gm::ErrorCode::CommentAbort, 1, 1, "stop 0.000000"},
  };
  for (const auto& c : cases) {
    INFO(c.program);
    const auto d = diagnose(std::string(c.program) + "M2\n");
    REQUIRE(!d.empty());
    CHECK(d[0].code == code(c.code));
    CHECK(d[0].loc.line == c.line);
    CHECK(d[0].loc.column == c.column);
    CHECK_THAT(d[0].message, Catch::Contains(c.says));
  }
}

TEST_CASE("the parameter store: LinuxCNC's table and the .var file") {
  using gm::ParameterStore;
  CHECK(ParameterStore::valid(1));
  CHECK(ParameterStore::valid(5601));
  CHECK_FALSE(ParameterStore::valid(0));
  CHECK_FALSE(ParameterStore::valid(5602));
  CHECK(ParameterStore::read_only(5400));
  CHECK(ParameterStore::read_only(5413));
  CHECK_FALSE(ParameterStore::read_only(5414));
  CHECK(ParameterStore::read_only(5420));
  CHECK(ParameterStore::read_only(5428));
  CHECK_FALSE(ParameterStore::read_only(5399));
  CHECK(ParameterStore::persistent(5161));
  CHECK(ParameterStore::persistent(5221));
  CHECK_FALSE(ParameterStore::persistent(100));

  ParameterStore s;
  CHECK(s.get(5220) == 1.0);  // G54
  s.set(5221, 12.5);
  s.set(100, 3.0);  // not persistent, not in a file: not saved
  s.set_named("_g", 2.0);
  s.set_named("l", 1.0);
  s.push_frame();
  double v = 0;
  CHECK(s.get_named("_g", v));
  CHECK_FALSE(s.get_named("l", v));  // locals belong to their frame
  s.set(1, 9.0);
  s.pop_frame();
  CHECK(s.get(1) == 0.0);  // #1-#30 restored
  CHECK(s.get_named("l", v));

  const auto dir = std::filesystem::temp_directory_path();
  const std::string path = (dir / ("gm_params_" + std::to_string(::getpid()) + ".var")).string();
  std::string err;
  REQUIRE(s.save_var_file(path, err));
  {  // LinuxCNC's required set: 9 + 9 + 11 + 9 x 10 = 119 lines, #5221 first of G54's ten
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(std::count(text.begin(), text.end(), '\n') == 119);
    CHECK_THAT(text, Catch::StartsWith("5161\t0.000000\n"));
    CHECK_THAT(text, Catch::Contains("5220\t1.000000\n5221\t12.500000\n"));
    CHECK_THAT(text, Catch::Contains("5230\t0.000000\n5241\t"));  // #5231-#5240 not saved
    CHECK_THAT(text, Catch::EndsWith("5390\t0.000000\n"));
  }
  {  // a hand-written file: a comment line, a user parameter, G55's X, no #5220
    std::ofstream f(path);
    f << "# saved by hand\n31\t4.25\n  5241 -7.5 trailing words\n";
  }
  ParameterStore t;
  t.set(100, 3.0);
  gm::Diagnostic d;
  REQUIRE(t.load_var_file(path, d));
  CHECK(t.get(31) == 4.25);
  CHECK(t.get(5241) == -7.5);
  CHECK(t.get(100) == 0.0);   // not in the file: 0, as Interp::restore_parameters
  CHECK(t.get(5220) == 0.0);  // (the interpreter then starts in G54)
  REQUIRE(t.save_var_file(path, err));
  {
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK_THAT(text, Catch::StartsWith("31\t4.250000\n5161\t0.000000\n"));
    CHECK_THAT(text, Catch::Contains("5241\t-7.500000\n"));
    CHECK(std::count(text.begin(), text.end(), '\n') == 120);
  }
  const auto corrupt = [&](const char* text, int line, int column, const char* what) {
    {
      std::ofstream bad(path);
      bad << text;
    }
    ParameterStore u;
    gm::Diagnostic e;
    CHECK_FALSE(u.load_var_file(path, e));
    CHECK(e.file == path);
    CHECK(e.loc.line == line);
    CHECK(e.loc.column == column);
    CHECK_THAT(e.message, Catch::Contains(what));
    CHECK(e.code == static_cast<int>(gm::ErrorCode::ParameterFile));
  };
  corrupt("5221 1\n5221 2\n", 2, 1, "out of order");
  corrupt("5221 1\n 5161 2\n", 2, 2, "out of order");
  corrupt("5161 0\n5602 1\n", 2, 1, "out of range");
  corrupt("0 1\n", 1, 1, "out of range");
  corrupt("5161\t\n", 1, 6, "expected a number");
  corrupt("5161 nan\n", 1, 6, "expected a number");
  std::remove(path.c_str());
  ParameterStore missing;  // no file yet: nothing changes (written at the first save)
  missing.set(5221, 2.0);
  REQUIRE(missing.load_var_file(path, d));
  CHECK(missing.get(5221) == 2.0);
}
