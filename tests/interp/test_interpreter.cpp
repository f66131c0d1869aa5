// Interpreter rules: units, distance modes, offsets, feed modes, events, and one test per error.
#include "common/error_codes.hpp"
#include "gcode_helpers.hpp"

#include <catch2/catch.hpp>

using namespace gmtest;
using gm::ErrorCode;
using gm::MotionKind;

TEST_CASE("G0 and G1 end points and feed in mm, mm/min") {
  const auto m = motions("G21 G90\nG0 X1 Y2 Z3\nG1 X4 F600\nM2\n");
  REQUIRE(m.size() == 2);
  CHECK(m[0].kind == MotionKind::Rapid);
  CHECK(m[0].end_mm == gm::xyz(1, 2, 3));
  CHECK(m[0].line == 2);
  CHECK(m[1].kind == MotionKind::Line);
  CHECK(m[1].start_mm == gm::xyz(1, 2, 3));
  CHECK(m[1].end_mm == gm::xyz(4, 2, 3));
  CHECK(m[1].feed_mm_min == 600.0);
}

TEST_CASE("G20 converts lengths and feed to mm once, G21 back") {
  const auto m = motions("G20 G1 X1 Y-0.5 F10\nG21 G1 X1\nM2\n");
  REQUIRE(m.size() == 2);
  CHECK(m[0].end_mm[0] == Approx(25.4));
  CHECK(m[0].end_mm[1] == Approx(-12.7));
  // F10 is read before this block's G20 (LinuxCNC order): 10 mm/min, kept in physical units.
  CHECK(m[0].feed_mm_min == Approx(10.0));
  CHECK(m[1].end_mm[0] == Approx(1.0));
  const auto n = motions("G20\nG1 X1 F10\nM2\n");
  CHECK(n[0].feed_mm_min == Approx(254.0));
}

TEST_CASE("G7 reads X words as diameters (incremental too, G92 X alike), G8 as radii") {
  // Worked by hand; tests/diff/machine/lathe-diameter.ngc checks the same against rs274.
  const auto m =
      motions("G18 G7\nG0 X30 Z2\nG91 G1 X-4 F100\nG90 G8 G0 X20\nG7 X50\nG92 X0\nG0 X10\nM2\n");
  REQUIRE(m.size() == 5);
  CHECK(m[0].end_mm[0] == 15.0);  // diameter 30
  CHECK(m[1].end_mm[0] == 13.0);  // 4 off the diameter is 2 off the radius
  CHECK(m[2].end_mm[0] == 20.0);  // G8 on the line: X20 is a radius
  CHECK(m[3].end_mm[0] == 25.0);
  CHECK(m[4].end_mm[0] == 30.0);  // G92 X0 at radius 25, then diameter 10 = 5 more
  // An arc: the end X in diameter, I K (the centre offset) in radius, as LinuxCNC.
  const auto a = motions("G18 G7 G0 X26 Z-21\nG3 X30 Z-23 I0 K-2 F100\nM2\n");
  REQUIRE(a.size() == 2);
  CHECK(a[1].end_mm[0] == 15.0);
  CHECK(a[1].center_mm[0] == 13.0);
  CHECK(a[1].center_mm[2] == -23.0);
}

TEST_CASE("G91 incremental and G90 absolute") {
  const auto m = motions("G91 G1 X1 Y1 F100\nX1\nG90 X0\nM2\n");
  REQUIRE(m.size() == 3);
  CHECK(m[0].end_mm == gm::xyz(1, 1, 0));
  CHECK(m[1].end_mm == gm::xyz(2, 1, 0));
  CHECK(m[2].end_mm == gm::xyz(0, 1, 0));
}

TEST_CASE("work offsets G54-G59, G92, G92.1 and tool length G43/G49") {
  gm::Machine mach;
  mach.work_offsets_mm[1] = gm::xyz(100, 200, 300);  // G55
  mach.tool_lengths_mm = {0.0, 12.5};
  const auto m = motions(
      "G55 G0 X1 Y2 Z3\n"  // 101 202 303
      "G54 X1\n"           // 1 202 303 (only X programmed)
      "G92 X10\n"          // current X (1) becomes 10: g92 = -9
      "G0 X20\n"           // machine 11
      "G92.1\nG0 X0\n"     // machine 0
      "G43 H1 G0 Z0\n"     // machine Z 12.5
      "G49 G0 Z0\nM2\n",
      mach);
  REQUIRE(m.size() == 6);
  CHECK(m[0].end_mm == gm::xyz(101, 202, 303));
  CHECK(m[1].end_mm == gm::xyz(1, 202, 303));
  CHECK(m[2].end_mm[0] == Approx(11));
  CHECK(m[3].end_mm[0] == Approx(0));
  CHECK(m[4].end_mm[2] == Approx(12.5));
  CHECK(m[5].end_mm[2] == Approx(0));
}

TEST_CASE("G93 rate has LinuxCNC's floor of 0.1 program units/min (interp_inverse.cc)") {
  // 0.05 mm at F1 (1/min) would be 0.05 mm/min; LinuxCNC raises it to 0.1 mm/min: 30 s.
  auto m = motions("G21 G93 G1 X0.05 F1\nM2\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0].feed_mm_min == Approx(0.1));
  CHECK(m[0].inverse_time_s == Approx(30.0));
  // In inches the floor is 0.1 in/min = 2.54 mm/min (rs274 prints 0.1000 in G20).
  m = motions("G20 G93 G1 X0.01 F1\nM2\n");
  CHECK(m[0].feed_mm_min == Approx(2.54));
}

TEST_CASE("G93 inverse time: the move takes 60/F s and F is required on every block") {
  const auto m = motions("G93 G1 X10 F2\nG1 X20 F4\nM2\n");
  REQUIRE(m.size() == 2);
  CHECK(m[0].inverse_time_s == Approx(30.0));
  CHECK(m[0].feed_mm_min == Approx(20.0));  // 10 mm in 0.5 min
  CHECK(m[1].inverse_time_s == Approx(15.0));
  const auto d = diagnose("G93 G1 X10 F2\nG1 X20\nM2\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].code == code(ErrorCode::InverseTimeFeedMissing));
  CHECK(d[0].loc.line == 2);
  CHECK(d[0].loc.column == 1);
  // Back to G94: the old F is gone (LinuxCNC sets feed 0).
  const auto e = diagnose("G1 F100 X1\nG93 G1 X2 F1\nG94 G1 X3\nM2\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].code == code(ErrorCode::ZeroFeed));
}

TEST_CASE("dwell, path modes, events") {
  const auto c =
      run("(MSG, start)\nG4 P1.5\nG61 G1 X1 F100\nG61.1 X2\nG64 P0.1 Q0.1 X3\nG9 "
          "X4\nM0\nM1\nM48\nM49\nM50 P0\nM50\nM3 S1000 T1 M6 M8\nM30\n");
  using gm::EventKind;
  auto ev = [&](std::size_t i) { return std::get<gm::Event>(c.at(i)); };
  CHECK(ev(0).kind == EventKind::Message);
  CHECK(ev(0).text == "start");
  CHECK(std::get<gm::Dwell>(c.at(1)).seconds == 1.5);
  // LinuxCNC: G61 = exact path, G61.1 = exact stop, G64 continuous; G9 = exact stop one block.
  CHECK(std::get<gm::Motion>(c.at(2)).path_mode == gm::PathMode::ExactPath);
  CHECK(std::get<gm::Motion>(c.at(3)).path_mode == gm::PathMode::ExactStop);
  CHECK(std::get<gm::Motion>(c.at(4)).path_mode == gm::PathMode::Continuous);
  CHECK(std::get<gm::Motion>(c.at(5)).path_mode == gm::PathMode::ExactStop);
  // The contour tolerance: G64's P in force, kept by a G9 block along its path; none in G61.x.
  CHECK(std::get<gm::Motion>(c.at(2)).path_tolerance_mm == 0.0);
  CHECK(std::get<gm::Motion>(c.at(3)).path_tolerance_mm == 0.0);
  CHECK(std::get<gm::Motion>(c.at(4)).path_tolerance_mm == Approx(0.1));
  CHECK(std::get<gm::Motion>(c.at(5)).path_tolerance_mm == Approx(0.1));
  CHECK(ev(6).kind == EventKind::Pause);
  CHECK(ev(7).kind == EventKind::OptionalPause);
  CHECK(ev(8).kind == EventKind::OverrideEnable);
  CHECK(ev(9).kind == EventKind::OverrideDisable);
  CHECK(ev(10).kind == EventKind::OverrideDisable);
  CHECK(ev(11).kind == EventKind::OverrideEnable);
  // M3 S1000 T1 M6 M8 in the order of execution: S, T, M6 (stops the spindle), M3, M8.
  const std::vector<EventKind> line13{EventKind::SpindleSpeed, EventKind::ToolSelect,
                                      EventKind::SpindleStop,  EventKind::ToolChange,
                                      EventKind::SpindleStart, EventKind::Flood};
  for (std::size_t i = 0; i < line13.size(); ++i) {
    CHECK(ev(12 + i).kind == line13[i]);
    CHECK(ev(12 + i).line == 13);
  }
  // M30: spindle stop, flood off, end.
  CHECK(ev(18).kind == EventKind::SpindleStop);
  CHECK((ev(19).kind == EventKind::Flood && ev(19).index == 0));
  CHECK(ev(20).kind == EventKind::End);
  CHECK(ev(20).line == 14);
  CHECK(c.size() == 21);
}

TEST_CASE("a bad block changes no state (validated whole before commit)") {
  // The G20 of the failing block must not stick: the next X1 is 1 mm.
  std::vector<gm::Diagnostic> d = diagnose("G20 G1 X1 F-1\nM2\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].code == code(ErrorCode::NegativeFeed));
  CHECK(d[0].loc.column == 11);
}

TEST_CASE("block delete is honoured only when enabled") {
  const std::string p = "G1 F100 X1\n/G1 X5\nM2\n";
  gm::Machine mach;
  std::istringstream in(p);
  gm::ProgramStream s(in, "t", gm::InterpreterOptions{&mach, true});
  gm::Canon c;
  int n = 0;
  while (s.next(c)) n += std::holds_alternative<gm::Motion>(c);
  CHECK(n == 1);
  CHECK(motions(p).size() == 2);
}

TEST_CASE("% delimited program ends at the second %") {
  const auto c = run("%\nG1 X1 F100\n%\nthis is ignored\n");
  REQUIRE(c.size() == 2);
  CHECK(std::get<gm::Event>(c[1]).kind == gm::EventKind::End);
  CHECK(diagnose("%\nG1 X1 F100\n%\n").empty());
}

TEST_CASE("text after a % is one error under linuxcnc, a passed-over tape marker under fanuc") {
  // rs274 2.9: "Bad character '%' used" (a comment after it too); before, one error per letter.
  for (const char* p : {"% vfd enable\nG0 X1\nM2\n", "G0 X1\nM2\n% (end)\n"}) {
    INFO(p);
    const bool first = p[0] == '%';
    const auto d = diagnose(p);
    REQUIRE(d.size() == (first ? 1u : 0u));
    if (!first) continue;
    CHECK(d[0].code == code(gm::ErrorCode::UnexpectedCharacter));
    CHECK(d[0].loc.line == 1);
    CHECK(d[0].loc.column == 1);
    CHECK(d[0].message ==
          "bad character '%' used: a '%' line holds nothing else (--dialect fanuc passes the "
          "text after it over)");
  }
  gm::Machine m;
  gm::InterpreterOptions o{&m, false};
  o.dialect = gm::Dialect::Fanuc;
  std::istringstream in("% vfd enable\nG0 X1\n%  rewind\nG0 X9\n");
  std::vector<gm::Diagnostic> d;
  gm::check_program_diagnostics(in, "t.nc", o, d);
  REQUIRE(d.size() == 2);  // one warning per marker line; the second '%' ends the program
  CHECK(d[0].severity == gm::Severity::Warning);
  CHECK(d[0].loc.line == 1);
  CHECK(d[0].loc.column == 1);
  CHECK(d[0].message == "text after a '%' tape marker is passed over (--dialect fanuc)");
  CHECK(d[1].loc.line == 3);
}

TEST_CASE("a UTF-8 byte-order mark opening the file is skipped in every dialect") {
  for (const gm::Dialect dialect : {gm::Dialect::LinuxCNC, gm::Dialect::Fanuc, gm::Dialect::Grbl}) {
    gm::Machine m;
    gm::InterpreterOptions o{&m, false};
    o.dialect = dialect;
    std::istringstream in("\xEF\xBB\xBFG0 X1\nG1 X2 Y& F100\nM2\n");
    std::vector<gm::Diagnostic> d;
    gm::check_program_diagnostics(in, "t.nc", o, d);
    REQUIRE(d.size() == 1);  // only the error on line 2; columns of line 1 count after the mark
    CHECK(d[0].loc.line == 2);
  }
  const auto d = diagnose("\xEF\xBB\xBFG0 X1 &\nM2\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].loc.column == 7);
  CHECK(d[0].message == "unexpected character '&'");
  // Only at the start of the input: elsewhere it is still a stray character.
  CHECK(diagnose("G0 X1\n\xEF\xBB\xBFG0 X2\nM2\n").at(0).message == "unexpected character 0xEF");
}

TEST_CASE("one test per block error: code and line:col") {
  struct Case {
    const char* program;
    ErrorCode code;
    int line, column;
  };
  const Case cases[] = {
      {"G0 G1 X1\nM2\n", ErrorCode::ModalGroupViolation, 1, 4},
      {"G17 G18\nM2\n", ErrorCode::ModalGroupViolation, 1, 5},
      {"M3 M5\nM2\n", ErrorCode::ModalGroupViolation, 1, 4},
      {"G0 X1 X2\nM2\n", ErrorCode::DuplicateWord, 1, 7},
      {"E2 G0 X1\nM2\n", ErrorCode::UnusedWord, 1, 1},  // E: M66..M68's word
      {"G0 X1 A2\nM2\n", ErrorCode::AxisUnavailable, 1, 7},
      {"G12 X1\nM2\n", ErrorCode::UnknownGCode, 1, 1},
      {"M97\nM2\n", ErrorCode::UnknownMCode, 1, 1},
      {"G1.5 X1\nM2\n", ErrorCode::UnknownGCode, 1, 1},
      {"G1.25 X1\nM2\n", ErrorCode::BadCodeNumber, 1, 1},
      {"X1\nM2\n", ErrorCode::AxisWordsWithoutMotion, 1, 1},
      {"G1 X1\nM2\n", ErrorCode::ZeroFeed, 1, 1},
      {"G1 X1 F0\nM2\n", ErrorCode::ZeroFeed, 1, 1},
      {"G1 X1 F-5\nM2\n", ErrorCode::NegativeFeed, 1, 7},
      {"G4\nM2\n", ErrorCode::DwellWithoutP, 1, 1},
      {"G4 P-1\nM2\n", ErrorCode::NegativeDwell, 1, 4},
      {"G92\nM2\n", ErrorCode::G92WithoutAxes, 1, 1},
      {"G0 X1 I3\nM2\n", ErrorCode::UnusedWord, 1, 7},
      {"G0 X1 R3\nM2\n", ErrorCode::UnusedWord, 1, 7},
      {"G43 H7\nM2\n", ErrorCode::ToolNumberOutOfRange, 1, 5},
      // Values past an int, a double or +-1e12 mm once converted (tests/fuzz/regressions/program).
      {"G43 H99999999999\nM2\n", ErrorCode::ToolNumberOutOfRange, 1, 5},
      {"T99999999999\nM2\n", ErrorCode::ValueOutOfRange, 1, 1},
      {"G0 X1000000000001\nM2\n", ErrorCode::ValueOutOfRange, 1, 4},
      {"G91 G0 X600000000000\nX600000000000\nM2\n", ErrorCode::ValueOutOfRange, 2, 1},
      {"G1 F10000000000000\nM2\n", ErrorCode::ValueOutOfRange, 1, 4},
      {"G93 G1 X10 F1000000000000\nM2\n", ErrorCode::ValueOutOfRange, 1, 12},
      // Under cutter compensation too (the rate of the programmed path; fuzz_program found inf).
      {"T1 M6\nG0 X-8 Y0\nG42 G1 X0 Y0 F400\nG93 G1 X10 F1000000000000\nM2\n",
       ErrorCode::ValueOutOfRange, 4, 12},
      {"T1 M6\nG0 X-8 Y0\nG42 G1 X0 Y0 F400\nG1 X5\nG93 G2 X15 Y0 I5 J0 F1000000000000\nM2\n",
       ErrorCode::ValueOutOfRange, 5, 21},
      {"T1 M6\nG0 X-8 Y0\nG93 G42 G1 X0 Y0 F1000000000000\nM2\n", ErrorCode::ValueOutOfRange, 3,
       18},
      {"G1 F100\nG2 X1 R1000000000001\nM2\n", ErrorCode::ValueOutOfRange, 2, 7},
      {"G1 X1 N5 F1\nM2\n", ErrorCode::LineNumberNotFirst, 1, 7},
      {"M50 P2\nM2\n", ErrorCode::BadPWord, 1, 5},
      {"G1 F100\nG2 X1 Y1 I1 P0\nM2\n", ErrorCode::BadPWord, 2, 13},
      {"G1 F100\nG2 X1 K1\nM2\n", ErrorCode::ArcOffsetWrongPlane, 2, 7},
      {"G1 F100\nG18 G2 X1 J1\nM2\n", ErrorCode::ArcOffsetWrongPlane, 2, 11},
      {"G1 F100\nG2 X2 R1 I1\nM2\n", ErrorCode::ArcRWithIjk, 2, 7},
      {"G1 F100\nG2 X1\nM2\n", ErrorCode::ArcMissingCenter, 2, 1},
      {"G1 F100\nG2 X0 Y0 R5\nM2\n", ErrorCode::ArcRSameEndPoint, 2, 10},
      {"G1 F100\nG2 X10 Y0 I0.001\nM2\n", ErrorCode::ArcZeroRadius, 2, 11},
      {"G1 F100\nG2 X10 Y0 R4.9987\nM2\n", ErrorCode::ArcRadiusTooSmall, 2, 11},
      {"G1 F100\nG2 X10 Y0 I5.02\nM2\n", ErrorCode::ArcRadiusMismatch, 2, 11},
      {"G1 F100 X1\n\nG1 X2\n", ErrorCode::MissingProgramEnd, 3, 1},
  };
  for (const auto& c : cases) {
    INFO(c.program);
    const auto d = diagnose(c.program);
    REQUIRE(d.size() == 1);
    CHECK(d[0].code == code(c.code));
    CHECK(d[0].loc.line == c.line);
    CHECK(d[0].loc.column == c.column);
    CHECK_FALSE(d[0].message.empty());
  }
}

TEST_CASE("every bad line of a program is reported and nothing runs") {
  const std::string p = "G1 X1\nG1 F100 X1 X2\nG0 Y#<_undefined>\nG0 X3\n";
  const auto d = diagnose(p);
  REQUIRE(d.size() == 4);
  CHECK(d[0].loc.line == 1);
  CHECK(d[1].loc.line == 2);
  CHECK(d[2].loc.line == 3);
  CHECK(d[3].code == code(ErrorCode::MissingProgramEnd));
  CHECK(d[3].loc.line == 4);
  CHECK_THROWS_AS(run(p), gm::InputError);
}
