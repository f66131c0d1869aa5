// Fanuc Macro B under --dialect fanuc through the CLI: each test names the section of the FANUC
// Series 16i/18i-MB operator's manual (B-63534EN, part II chapter 15 "Custom macro") it follows;
// the expected moves are worked by hand.
#include <catch2/catch.hpp>

#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {
using gmtest::sh;
using MacroPoint = std::array<double, 3>;

std::string macro_src(const std::string& rel) {
  return std::string(GMOTION_TESTS_DIR) + "/../" + rel;
}

// Writes `text` to a scratch file (loops and calls re-read the program: a file, not a pipe).
std::string macro_program(const std::string& name, const std::string& text) {
  const auto path = gmtest::scratch_dir("macro-b") / name;
  std::ofstream(path) << text;
  return path.string();
}

struct MacroMoves {
  int code = 0;
  std::string out;
  std::vector<std::string> kinds;
  std::vector<MacroPoint> ends;
};

// `gmotion moves FILE ARGS`: each move's kind and end point.
MacroMoves macro_moves(const std::string& file, const std::string& args = "--dialect fanuc") {
  MacroMoves m;
  const auto r = sh(gmtest::gmotion_bin() + " moves " + file + " " + args + " 2>&1");
  m.code = r.code;
  m.out = r.out;
  for (std::size_t at = r.out.find("\"kind\":\""); at != std::string::npos;
       at = r.out.find("\"kind\":\"", at + 1)) {
    const std::size_t k = at + 8;
    m.kinds.push_back(r.out.substr(k, r.out.find('"', k) - k));
    const std::size_t e = r.out.find("\"end\":[", at);
    MacroPoint p{};
    const char* c = r.out.c_str() + e + 7;
    for (double& v : p) {
      char* next = nullptr;
      v = std::strtod(c, &next);
      c = next + 1;
    }
    m.ends.push_back(p);
  }
  return m;
}

void check_ends(const MacroMoves& m, const std::vector<MacroPoint>& want) {
  INFO(m.out);
  REQUIRE(m.ends.size() == want.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      INFO("move " << i << " axis " << a);
      CHECK(std::abs(m.ends[i][static_cast<std::size_t>(a)] -
                     want[i][static_cast<std::size_t>(a)]) < 1e-9);
    }
}

// `gmotion check FILE --dialect fanuc`: exit code and output.
gmtest::CommandResult macro_check(const std::string& file,
                                  const std::string& args = "--dialect fanuc") {
  return sh(gmtest::gmotion_bin() + " check " + file + " " + args + " 2>&1");
}
}  // namespace

TEST_CASE("macro-b: bolt-hole circle through G65 with arguments (II-15.6.1 simple call)") {
  // G65 P9010 X50 Y40 R20 A30 H4 Z-5 F200: #24 #25 #18 #1 #11 #26 #9 (argument specification
  // I); four holes at 30, 120, 210, 300 degrees on R20 about (50, 40); the caller's #1 = 7 is
  // restored by M99.
  const double s = 20.0 * std::sqrt(3.0) / 2.0;  // 17.3205...
  const MacroMoves m = macro_moves(macro_src("programs/dialects/fanuc_bolt_circle.nc"));
  CHECK(m.code == 0);
  std::vector<MacroPoint> want{{0, 0, 10}};
  double z = 10;  // the first hole is reached at Z10, the others at the Z2 clearance
  for (const MacroPoint& hole : {MacroPoint{50 + s, 50, 0}, MacroPoint{40, 40 + s, 0},
                                 MacroPoint{50 - s, 30, 0}, MacroPoint{60, 40 - s, 0}}) {
    want.push_back({hole[0], hole[1], z});
    z = 2;
    want.push_back({hole[0], hole[1], -5});
    want.push_back({hole[0], hole[1], 2});
  }
  want.push_back({60, 40 - s, 10});
  want.push_back({7, 0, 10});
  check_ends(m, want);
  CHECK(m.kinds[2] == "line");  // G1 Z#26 F#9: a feed move
  // As a LinuxCNC program it is refused (rs274 reads no Macro B).
  CHECK(macro_check(macro_src("programs/dialects/fanuc_bolt_circle.nc"), "").code == 1);
}

TEST_CASE("macro-b: peck loop with WHILE [...] DO1 ... END1 (II-15.5.3 iteration)") {
  // depths 0 -> -2.5 -> -5 -> -7.5 clipped to -7 by IF ... THEN (II-15.5.2), then #100 GT #102
  // is false: the loop ends after its third pass.
  const MacroMoves m = macro_moves(macro_src("programs/dialects/fanuc_peck_loop.nc"));
  CHECK(m.code == 0);
  check_ends(m, {{10, 10, 2},
                 {10, 10, -2.5},
                 {10, 10, 2},
                 {10, 10, -5},
                 {10, 10, 2},
                 {10, 10, -7},
                 {10, 10, 2},
                 {10, 10, 10}});
}

TEST_CASE("macro-b: IF [...] GOTO counter, backward and forward (II-15.5.1, II-15.5.2)") {
  // N10 runs for #1 = 0, 1, 2 (slots at X0, X15, X30), GOTO 99 passes over G0 X500.
  const MacroMoves m = macro_moves(macro_src("programs/dialects/fanuc_goto_counter.nc"));
  CHECK(m.code == 0);
  std::vector<MacroPoint> want;
  for (double x : {0.0, 15.0, 30.0}) {
    want.push_back({x, 0, 1});
    want.push_back({x, 0, -1});
    want.push_back({x, 20, -1});
    want.push_back({x, 20, 1});
  }
  want.push_back({0, 0, 1});
  check_ends(m, want);
}

TEST_CASE("macro-b: vacant variables, the manual's table (II-15.1 undefined variable)") {
  // #1 vacant: #2 = #1 is vacant, #3 = #1 * 5 is 0; EQ/NE tell vacant from 0, GE/GT read it as 0;
  // a vacant variable omits its word (G0 X#2 keeps X5).
  const std::string f = macro_program("vacant.nc",
                                      "G21 G90\n"
                                      "G0 X5 Y1 Z1\n"
                                      "#1 = #0\n"
                                      "#2 = #1\n"
                                      "#3 = #1 * 5\n"
                                      "#4 = #1 + #1\n"
                                      "IF [#1 EQ #0] THEN #10 = 1\n"
                                      "IF [#1 NE 0] THEN #11 = 1\n"
                                      "IF [#3 EQ #0] THEN #12 = 1 (0 IS NOT VACANT)\n"
                                      "IF [#1 GE #0] THEN #13 = 1\n"
                                      "IF [#1 GT 0] THEN #14 = 1\n"
                                      "IF [#12 EQ #0] THEN #15 = 10\n"
                                      "G0 X#2 Y[#3 + #4] Z[#10 + #11 + #13 + #14 + #15]\n"
                                      "G0 X#12 Y#100 Z#500 (ALL VACANT AT THE START: NO MOVE)\n"
                                      "M30\n");
  const MacroMoves m = macro_moves(f);
  CHECK(m.code == 0);
  check_ends(m, {{5, 1, 1}, {5, 0, 13}});
}

TEST_CASE("macro-b: operators, functions and precedence (II-15.3, Table 15.3(a))") {
  // FIX[-1.2] = -1, FUP[-1.2] = -2 (toward and away from zero); ATAN[-1]/[-1] = 225 (0..360);
  // 6 AND 3 = 2, 6 OR 3 = 7, 6 XOR 3 = 5 bit by bit; 1 + 2 AND 3 = 1 + [2 AND 3] = 3 (AND at
  // the level of *); #1 = #2 + #3 without brackets; 7 MOD 4 = 3; SQRT, ABS, ROUND, LN, EXP.
  const std::string f =
      macro_program("ops.nc",
                    "G21 G90\n"
                    "#2 = 10.\n"
                    "#3 = 4.\n"
                    "#1 = #2 + #3 * 2 / 4\n"
                    "#4 = FIX[-1.2] * 10 + FUP[-1.2]\n"
                    "#5 = ATAN[-1]/[-1]\n"
                    "#6 = [6 AND 3] * 100 + [6 OR 3] * 10 + [6 XOR 3]\n"
                    "#7 = 1 + 2 AND 3\n"
                    "#8 = SQRT[16] + ABS[-2] + ROUND[2.5] + 7 MOD 4 + LN[EXP[1]]\n"
                    "#9 = [#1 EQ 12] AND [#2 GT #3]\n"
                    "G1 X#1 Y#4 Z#5 F100\n"
                    "G1 X#6 Y#7 Z#8\n"
                    "G1 X#9 Y[SIN[30] + COS[60]] Z[TAN[45]]\n"
                    "M30\n");
  const MacroMoves m = macro_moves(f);
  CHECK(m.code == 0);
  check_ends(m, {{12, -12, 225}, {275, 3, 4 + 2 + 3 + 3 + 1}, {1, 1, 1}});
}

TEST_CASE("macro-b: system variables posts read (II-15.2)") {
  // #5001-#5003 block end point, #5041-#5043 current position (work coordinates), #4001-#4014
  // modal G codes of the block before, #4109 F, #4114 its N, #3901/#3902 parts counts.
  const std::string f = macro_program("system.nc",
                                      "G21 G90 G17 G94\n"
                                      "N5 G1 X12. Y7. Z3. F250.\n"
                                      "#1 = #5001 + #5042 + #5003\n"
                                      "#2 = #4001 * 1000 + #4003 * 10 + #4002 / 10\n"
                                      "#3 = #4006 + #4014 + #4109 + #4114\n"
                                      "#3901 = #3901 + 1\n"
                                      "G0 X#1 Y#2 Z[#3 + #3901]\n"
                                      "M30\n");
  const MacroMoves m = macro_moves(f);
  CHECK(m.code == 0);
  check_ends(m, {{12, 7, 3}, {22, 1901.7, 21 + 54 + 250 + 5 + 1}});
}

TEST_CASE("macro-b: G65 locals are the call's own, M98 shares them (II-15.6.1, II-15.6)") {
  // The macro's #1-#33 start vacant but for its arguments (#5 vacant: Y omitted) and go at M99;
  // M98 P#10 (a variable as the P word) calls :200, which sees the caller's #10.
  const std::string f = macro_program("locals.nc",
                                      "G21 G90\n"
                                      "#5 = 3.\n"
                                      "#10 = 200\n"
                                      "G65 P100 A1. B2.\n"
                                      "M98 P#10\n"
                                      "G0 X[#5 + 1] Y#1 (#1 IS VACANT HERE: Y OMITTED)\n"
                                      "M30\n"
                                      "O100\n"
                                      "G0 X[#1 + #2] Y#5 Z#10\n"
                                      "#5 = 40.\n"
                                      "M99\n"
                                      ":200\n"
                                      "G0 Z#10\n"
                                      "M99\n");
  const MacroMoves m = macro_moves(f);
  CHECK(m.code == 0);
  check_ends(m, {{3, 0, 0}, {3, 0, 200}, {4, 0, 200}});
}

// FANUC Series 16i/18i-PB operator's manual B-63684EN, p. 278 "Mixture of argument
// specifications I and II": G65 A1.0 B2.0 I-3.0 I4.0 D5.0 P1000 gives #1 1.0, #2 2.0, #3
// vacant, #4 -3.0, #5 and #6 vacant, #7 5.0 (I4.0, the second I, and D both name #7: the later
// D wins). Haas 96-8000 "Local Variables" table: the n-th I, J, K set #(3n+1), #(3n+2), #(3n+3)
// (#7 D or I, #8 E or J, ... #31 I, #32 J, #33 K).
TEST_CASE("macro-b: G65 argument specification II, the manual's example and table") {
  const std::string f = macro_program("spec2.nc",
                                      "G21 G90 G0 X0 Y0 Z0\n"
                                      "G65 P1000 A1.0 B2.0 I-3.0 I4.0 D5.0\n"
                                      "G65 P2000 A1 B2 C3 I4 J5 K6 I7 J8 K9 I10 J11 K12 I13 J14 "
                                      "K15 I16 J17 K18 I19 J20 K21 I22 J23 K24 I25 J26 K27 I28 "
                                      "J29 K30 I31 J32 K33\n"
                                      "M30\n"
                                      "O1000\n"
                                      "G0 X#1 Y#2 Z#4\n"
                                      "G0 X#7\n"
                                      "#10 = 0\n"
                                      "IF [#3 EQ #0] THEN #10 = #10 + 1\n"
                                      "IF [#5 EQ #0] THEN #10 = #10 + 10\n"
                                      "IF [#6 EQ #0] THEN #10 = #10 + 100\n"
                                      "G0 Y#10\n"
                                      "M99\n"
                                      "O2000\n"
                                      "#100 = 0\n"
                                      "#101 = 1\n"
                                      "WHILE [#101 LE 33] DO1\n"
                                      "IF [#[#101] EQ #101] THEN #100 = #100 + 1\n"
                                      "#101 = #101 + 1\n"
                                      "END1\n"
                                      "G0 X#100 Y0 Z0\n"
                                      "M99\n");
  const MacroMoves m = macro_moves(f);
  CHECK(m.code == 0);
  // (G0 X0 Y0 Z0 from there moves nothing.) #1 #2 #4; #7 = 5 (D); #3, #5, #6 vacant (111);
  // then all 33 variables equal their numbers.
  check_ends(m, {{1, 2, -3}, {5, 2, -3}, {5, 111, -3}, {33, 0, 0}});
}

TEST_CASE("macro-b: errors are located and name what is wrong") {
  const auto error = [](const std::string& name, const std::string& text,
                        const std::string& where_what) {
    const std::string f = macro_program(name, text);
    const auto r = macro_check(f);
    INFO(r.out);
    CHECK(r.code == 1);
    CHECK(r.out.find(f + where_what) != std::string::npos);
  };
  // II-15.5.1: GOTO to a sequence number the program does not have
  error("goto.nc", "G0 X1\nGOTO 50\nN40 G0 X2\nM30\n",
        ":2:1: error: GOTO 50: no block N50 in this program");
  // II-15.5.3: DO m and END m in pairs, nested not overlapping, m = 1..3
  error("end.nc", "G0 X1\nEND2\nM30\n", ":2:1: error: END2 without WHILE [...] DO2");
  error("overlap.nc",
        "#1 = 0\nWHILE [#1 LT 2] DO1\nWHILE [#1 LT 2] DO2\n#1 = #1 + 1\nEND1\nEND2\nM30\n",
        ":5:1: error: END1 closes DO1 (line 2) while DO2 (line 3) inside it is open");
  error("nested.nc", "#1 = 0\nWHILE [#1 LT 2] DO1\nWHILE [#1 LT 2] DO1\nEND1\nEND1\nM30\n",
        ":3:1: error: DO1 inside the loop DO1 of line 2");
  error("range.nc", "#1 = 0\nWHILE [#1 LT 2] DO4\nEND4\nM30\n",
        ":2:17: error: DO4: the loop number is 1, 2 or 3");
  error("open.nc", "#1 = 0\nWHILE [#1 LT 2] DO1\n#1 = #1 + 1\n",
        ":2:1: error: the program ends inside the loop DO1");
  // II-15.2: an unknown system variable, #0 set, and the #3000 alarm with its message
  error("sysvar.nc", "#1 = #4999\nM30\n", ":1:6: error: unknown system variable #4999");
  error("null.nc", "#0 = 1\nM30\n", ":1:1: error: #0 is always vacant");
  error("alarm.nc", "G0 X1\n#3000 = 12 (TOOL BROKEN)\nG0 X2\nM30\n",
        ":2:1: error: alarm 3012: TOOL BROKEN");
  // argument specification II: only I, J, K repeat, up to 10 times each
  error("spec2.nc", "G65 P100 A1 I1 J2 I3 A4\nM30\nO100\nM99\n",
        ":1:22: error: argument A given twice");
  error("spec2_11.nc", "G65 P100 I1 I2 I3 I4 I5 I6 I7 I8 I9 I10 I11\nM30\nO100\nM99\n",
        ":1:41: error: I given 11 times");
  // the iteration bound holds for IF/GOTO loops too
  const auto r = macro_check(macro_program("forever.nc", "N1 G0 X1\nGOTO 1\nM30\n"),
                             "--dialect fanuc --max-iterations 1000");
  CHECK(r.code == 1);
  CHECK(r.out.find(":2:1: error: loops and calls ran past --max-iterations (1000)") !=
        std::string::npos);
}

TEST_CASE("macro-b: linuxcnc reads none of it") {
  CHECK(macro_check(macro_program("lc1.nc", "#1 = #2 + #3\nM30\n"), "").code == 1);
  CHECK(macro_check(macro_program("lc2.nc", "#1 = 1\nIF [#1 EQ 1] GOTO 5\nN5 M30\n"), "").code ==
        1);
  CHECK(macro_check(macro_program("lc3.nc", ":100\nM30\n"), "").code == 1);
  // the same program reads as Fanuc Macro B
  CHECK(macro_check(macro_program("lc4.nc", "#1 = 1\nIF [#1 EQ 1] GOTO 5\nG0 X1\nN5 M30\n")).code ==
        0);
}

TEST_CASE("macro-b: #500-#999 are kept in the parameter file, #100-#199 are not (II-15.1)") {
  // First run: #500 vacant -> 5, then 6, saved; second run reads 6 -> 7. #100 set each run
  // starts vacant again (the IF sets it to 1 both times); a vacant #501 is not written.
  const std::string var = (gmtest::scratch_dir("macro-b") / "kept.var").string();
  std::filesystem::remove(var);
  const std::string f = macro_program("kept.nc",
                                      "G21 G90\n"
                                      "IF [#500 EQ #0] THEN #500 = 5\n"
                                      "#500 = #500 + 1\n"
                                      "IF [#100 EQ #0] THEN #100 = 1\n"
                                      "#100 = #100 + 1\n"
                                      "G0 X#500 Y#100 Z#501\n"
                                      "M30\n");
  check_ends(macro_moves(f, "--dialect fanuc --parameter-file " + var), {{6, 2, 0}});
  check_ends(macro_moves(f, "--dialect fanuc --parameter-file " + var), {{7, 2, 0}});
  std::ifstream in(var);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text.find("500\t7.000000\n") != std::string::npos);
  CHECK(text.find("\n100\t") == std::string::npos);
  CHECK(text.find("\n501\t") == std::string::npos);
}
