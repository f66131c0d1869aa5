// Work offsets, G92 family, G52, G53, G28/G30 and the tool table: hand-worked machine positions.
#include "common/error_codes.hpp"
#include "gcode_helpers.hpp"
#include "machine/tool_table.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <sstream>

using gm::xyz;

using namespace gmtest;
using gm::AxisVec;
using gm::ErrorCode;

TEST_CASE("G10 L2 / L20 and G54..G59.3: machine = program + work offset") {
  const auto m = motions(
      "G21 G90\n"
      "G10 L2 P8 X100 Y-50 Z5\n"  // G59.2
      "G59.2 G0 X1 Y1 Z1\n"       // 101 -49 6
      "G10 L20 P0 X0 Y0\n"        // here becomes 0,0: offset = (101, -49)
      "G0 X10 Y0\n"               // 111 -49 6
      "G54 G0 X10\n"              // 10 -49 6
      "M2\n");
  REQUIRE(m.size() == 3);
  CHECK(m[0].end_mm == xyz(101, -49, 6));
  CHECK(m[1].end_mm == xyz(111, -49, 6));
  CHECK(m[2].end_mm == xyz(10, -49, 6));
}

TEST_CASE("G92 family and G52 share the axis offsets, G92.2 suspends and G92.3 restores") {
  const auto m = motions(
      "G21 G90 G0 X10\n"
      "G92 X0\n"  // offset -10... no: machine 10 gets program 0 -> g92 = +10
      "G0 X5\n"   // 15
      "G92.2\n"   // suspended
      "G0 X5\n"   // 5
      "G92.3\n"   // restored
      "G0 X5\n"   // 15
      "G52 X2\n"  // local offset 2 (replaces)
      "G0 X5\n"   // 7
      "G92.1\n"   // cleared
      "G0 X5\n"   // 5 (zero-length from 7? no: 7 -> 5)
      "M2\n");
  REQUIRE(m.size() == 6);
  CHECK(m[1].end_mm[0] == Approx(15));
  CHECK(m[2].end_mm[0] == Approx(5));
  CHECK(m[3].end_mm[0] == Approx(15));
  CHECK(m[4].end_mm[0] == Approx(7));
  CHECK(m[5].end_mm[0] == Approx(5));
}

TEST_CASE(
    "G28 goes through the intermediate point to the G28.1 position, G53 moves in machine "
    "coordinates") {
  gm::Machine mach;
  const auto m = motions(
      "G21 G90 G10 L2 P1 X10 Y10 Z10\n"
      "G0 X1 Y2 Z3\n"  // machine 11 12 13
      "G28.1\n"        // home = 11 12 13
      "G0 X0 Y0 Z0\n"  // 10 10 10
      "G28 Z5\n"       // via Z 15, then Z 13
      "G53 G0 X-1\n"   // machine X -1
      "G91 G28 X0\n"   // via here, then X 11
      "M2\n",
      mach);
  REQUIRE(m.size() == 6);
  CHECK(m[0].end_mm == xyz(11, 12, 13));
  CHECK(m[1].end_mm == xyz(10, 10, 10));
  CHECK(m[2].end_mm == xyz(10, 10, 15));
  CHECK(m[3].end_mm == xyz(10, 10, 13));
  CHECK(m[4].end_mm == xyz(-1, 10, 13));
  CHECK(m[5].end_mm == xyz(11, 10, 13));  // the via point (here) is a zero-length move
}

TEST_CASE("tool table: T M6, G43 H, G43.1, G43.2, G49, G10 L1/L10 (default table T1 Z50)") {
  const auto m = motions(
      "G21 G90\n"
      "T1 M6\nG43\nG0 Z0\n"              // 50
      "G43 H2\nG0 Z0\n"                  // 60
      "G43.2 H4\nG0 Z0\n"                // 130
      "G43.1 Z-1\nG0 Z0\n"               // -1
      "G49\nG0 Z1\n"                     // 1
      "G10 L1 P3 Z7.5\nG43 H3\nG0 Z0\n"  // 7.5
      "G10 L10 P4 Z0\nG43 H4\nG0 Z0\n"   // here (7.5) becomes Z0: offset 7.5
      "G53 G0 Z0\n"                      // machine 0 whatever the tool
      "M2\n");
  REQUIRE(m.size() == 7);
  CHECK(m[0].end_mm[2] == Approx(50));
  CHECK(m[1].end_mm[2] == Approx(60));
  CHECK(m[2].end_mm[2] == Approx(130));
  CHECK(m[3].end_mm[2] == Approx(-1));
  CHECK(m[4].end_mm[2] == Approx(1));
  CHECK(m[5].end_mm[2] == Approx(7.5));
  CHECK(m[6].end_mm[2] == Approx(0));
}

TEST_CASE("machine-side errors are located on the word at fault") {
  struct Case {
    const char* program;
    ErrorCode code;
    int line, column;
  };
  const Case cases[] = {
      {"G21\nT9\nM2\n", ErrorCode::ToolNumberOutOfRange, 2, 1},
      {"G21\nG43 H9\nM2\n", ErrorCode::ToolNumberOutOfRange, 2, 5},
      {"G21\nM61\nM2\n", ErrorCode::MissingWord, 2, 1},
      {"G21\nG91 G53 G0 X1\nM2\n", ErrorCode::G53Misused, 2, 5},
      {"G21\nG53 G2 X1 R1 F1\nM2\n", ErrorCode::G53Misused, 2, 1},
      {"G21\nG10 L3 P1\nM2\n", ErrorCode::BadLWord, 2, 5},
      {"G21\nG10 L2 P10 X1\nM2\n", ErrorCode::BadCoordSystem, 2, 8},
      {"G21\nG80 X1\nM2\n", ErrorCode::AxisWordsWithoutMotion, 2, 5},
  };
  for (const auto& c : cases) {
    INFO(c.program);
    const auto d = diagnose(c.program);
    REQUIRE(!d.empty());
    CHECK(d[0].code == static_cast<int>(c.code));
    CHECK(d[0].loc.line == c.line);
    CHECK(d[0].loc.column == c.column);
  }
}

TEST_CASE("tool table file: LinuxCNC format, comments, errors with the line") {
  std::istringstream in(
      "; a comment line\n"
      "T1 P1 Z+12.5 D6.0 ;end mill\n"
      "\n"
      "t2 p5 x1 z-3 d3 i10 j20 q2\n");
  const gm::ToolTable t = gm::read_tool_table(in, "t.tbl");
  REQUIRE(t.tools.size() == 2);
  CHECK(t.find(1)->offset_mm[2] == 12.5);
  CHECK(t.find(1)->diameter_mm == 6.0);
  CHECK(t.find(1)->comment == "end mill");
  CHECK(t.find(2)->pocket == 5);
  CHECK(t.find(2)->offset_mm[0] == 1.0);
  CHECK(t.find(2)->orientation == 2);
  CHECK(t.find(3) == nullptr);
  std::istringstream dup("T1 Z1\nT1 Z2\n");
  CHECK_THROWS_WITH(gm::read_tool_table(dup, "d.tbl"), "d.tbl:2: tool table: tool 1 appears twice");
  std::istringstream bad("T1 K5\n");
  CHECK_THROWS_WITH(gm::read_tool_table(bad, "b.tbl"), "b.tbl:1: tool table: unknown word 'K'");
}

TEST_CASE("G81 and G83 expand as LinuxCNC: across, down to R, pecks, retract") {
  const auto m = motions(
      "G21 G90 G0 X0 Y0 Z10\n"
      "G99 G81 X1 Y2 Z-3 R2 F100\n"  // across at 10, down to R 2, feed to -3, back to R
      "G98 G83 X4 Z-5 R2 Q3\n"       // G98: back to the initial level 10; pecks of 3 from R 2
      "M2\n");
  REQUIRE(m.size() == 15);
  CHECK(m[0].end_mm == xyz(0, 0, 10));
  CHECK(m[1].end_mm == xyz(1, 2, 10));
  CHECK(m[2].end_mm == xyz(1, 2, 2));
  CHECK(m[3].kind == gm::MotionKind::Line);
  CHECK(m[3].end_mm == xyz(1, 2, -3));
  CHECK(m[4].end_mm == xyz(1, 2, 2));
  // G83 at the R plane under G98: across at the initial level 10, down to R, pecks -1, -4
  CHECK(m[5].end_mm == xyz(4, 2, 10));
  CHECK(m[6].end_mm == xyz(4, 2, 2));
  CHECK(m[7].end_mm[2] == Approx(-1));      // feed
  CHECK(m[8].end_mm[2] == Approx(2));       // out to R
  CHECK(m[9].end_mm[2] == Approx(-0.746));  // back down to 0.254 mm above the last depth
  CHECK(m[10].end_mm[2] == Approx(-4));     // feed
  CHECK(m[11].end_mm[2] == Approx(2));
  CHECK(m[12].end_mm[2] == Approx(-3.746));
  CHECK(m[13].end_mm[2] == Approx(-5));  // to the bottom
  CHECK(m[14].end_mm[2] == Approx(10));  // G98: the initial level
}

TEST_CASE("canned cycles and G76 are bounded: moves a block, the R plane, spring passes") {
  // Found by fuzzing: G83 R1e22 (written out) Q3 went up to 1e22 mm, where depth - 3 == depth, and
  // pecked forever, every peck held in the block.
  const auto far =
      diagnose("G21 G90 G0 X0 Y0 Z10\nG83 X1 Z-1 R10000000000000000000000 Q3 F100\nM2\n");
  REQUIRE(!far.empty());
  CHECK(far[0].code == static_cast<int>(ErrorCode::ValueOutOfRange));
  CHECK(far[0].loc.line == 2);
  CHECK(far[0].message == "Z would move to 1e+22 mm, outside -1e+12..1e+12 mm");
  // 10 mm in pecks of 0.0001 mm: three moves a peck, 300,000 moves in one block.
  const auto fine = diagnose("G21 G90 G0 X0 Y0 Z10\nG83 X1 Z-10 R1 Q0.0001 F100\nM2\n");
  REQUIRE(!fine.empty());
  CHECK(fine[0].code == static_cast<int>(ErrorCode::ValueOutOfRange));
  CHECK(fine[0].message == "the block expands to more than 100000 moves (repeats, pecks)");
  // 1,000,000 repeats of a drilling cycle (three moves each): refused the same way.
  const auto many = diagnose("G21 G90 G0 X0 Y0 Z10\nG91 G81 X0.001 Z-1 R-9 L1000000 F100\nM2\n");
  REQUIRE(!many.empty());
  CHECK(many[0].message == "the block expands to more than 100000 moves (repeats, pecks)");
  // G76's spring passes H: a whole number, as rs274 ("Non integer value for integer"), and at
  // most 10,000 (H1e29 was cast to int unchecked).
  const std::string g76 = "G21 G18 G90\nG0 X12 Z2\nM3 S500\nG76 P2 Z-20 I-1 J0.4 K1.2 H";
  for (const char* h : {"1.5", "100000000000000000000000000000"}) {
    const auto d = diagnose(g76 + h + "\nM2\n");
    REQUIRE(!d.empty());
    CHECK(d[0].loc.column == 27);
    CHECK_THAT(d[0].message, Catch::Contains("the spring passes must be a whole number up to"));
  }
  // Two spring passes: four moves each (in, along, out, back), as rs274 -g cuts them.
  CHECK(motions(g76 + "2\nM2\n").size() == motions(g76 + "0\nM2\n").size() + 8);
  // 10 mm in pecks of 0.001 mm (30,000 moves): still runs.
  CHECK(motions("G21 G90 G0 X0 Y0 Z10\nG83 X1 Z-10 R1 Q0.001 F100\nM2\n").size() > 30000);
}

TEST_CASE("system parameters: G28/G30, G92, coordinate systems and tool data in mm") {
  // Hand-worked: G55 = (10, 20, -5); the point G55 (1, 2, 3) is machine (11, 22, -2); G92 X0 Y0
  // there makes the G92 offsets (1, 2); the spindle's tool is T1 (Z50 D6 in the default table).
  const auto texts = messages(
      "G21 G10 L2 P2 X10 Y20 Z-5\n"
      "G55 G0 X1 Y2 Z3\n"
      "G28.1\n"
      "G92 X0 Y0\n"
      "(DEBUG,#5220 #5241 #5242 #5243 #5161 #5162 #5163 #5210 #5211 #5212)\n"
      "G20 G10 L2 P2 X1\n"
      "G92.2\n"
      "(DEBUG,#5241 #5210 #5211)\n"
      "G21 T1 M6\n"
      "(DEBUG,#5400 #5403 #5410)\n"
      "M2\n");
  REQUIRE(texts.size() == 3);
  CHECK(texts[0] ==
        "2.000000 10.000000 20.000000 -5.000000 11.000000 22.000000 -2.000000 1.000000 1.000000 "
        "2.000000");
  CHECK(texts[1] == "25.400000 0.000000 1.000000");  // G92.2 keeps the stored values
  CHECK(texts[2] == "1.000000 50.000000 6.000000");
}

TEST_CASE("G10 L2 R turns the system's XY about its origin: machine = R(p + G92) + G54 + tool") {
  // Hand-worked with R90 (x, y) -> (-y, x) about G54 = (100, 50): the program point (10, 0)
  // is machine (100, 60); G91 X5 steps along program X, i.e. machine +Y; G92 X0 at program
  // (10, 5) (machine (95, 60)) makes G92 X = 10, so program X2 Y0 is R(12, 5) = (-5, 12) ->
  // machine (95, 62); G10 L20 X0 Y0 at machine (95, 62) keeps R90 and moves the origin there.
  const auto canon =
      run("G21 G90 G10 L2 P1 X100 Y50 R90\n"
          "G54 G0 X10 Y0\n"  // (100, 60)
          "G91 G0 X0 Y5\n"   // program (10, 5): machine (95, 60)
          "G90 G92 X0\n"     // G92 X = 10
          "G0 X2 Y0\n"       // program (2, 0) + G92 (10, 0) -> R(12, 0) = (0, 12)
          "(DEBUG,#5420 #5421 #5211 #5230)\n"
          "G92.1\n"
          "G10 L20 P1 X0 Y0\n"  // origin = here
          "(DEBUG,#5221 #5222 #5230 #5420 #5421)\n"
          "G1 X0 Y10 F100\n"  // program +Y is machine -X
          "G2 X10 Y0 R10\n"   // centre program (0, 0)
          "M2\n");
  std::vector<gm::Motion> m;
  std::vector<std::string> texts;
  for (const auto& c : canon) {
    if (const auto* mo = std::get_if<gm::Motion>(&c)) m.push_back(*mo);
    if (const auto* e = std::get_if<gm::Event>(&c); e && e->kind == gm::EventKind::Message)
      texts.push_back(e->text);
  }
  REQUIRE(m.size() == 5);
  CHECK(m[0].end_mm[0] == Approx(100));
  CHECK(m[0].end_mm[1] == Approx(60));
  CHECK(m[1].end_mm[0] == Approx(95));
  CHECK(m[1].end_mm[1] == Approx(60));
  // G92 X0 at program X10: G92 = (10, 0). Program (2, 0) -> R(12, 0) = (0, 12) -> (100, 62).
  CHECK(m[2].end_mm[0] == Approx(100).margin(1e-9));
  CHECK(m[2].end_mm[1] == Approx(62));
  REQUIRE(texts.size() == 2);
  CHECK(texts[0] == "2.000000 0.000000 10.000000 90.000000");
  // L20 at machine (100, 62): the origin moves there, R stays 90; the point reads (0, 0).
  CHECK(texts[1] == "100.000000 62.000000 90.000000 0.000000 0.000000");
  CHECK(m[3].end_mm[0] == Approx(90));  // program (0, 10) -> R = (-10, 0)
  CHECK(m[3].end_mm[1] == Approx(62));
  CHECK(m[4].end_mm[0] == Approx(100).margin(1e-9));  // program (10, 0) -> (0, 10)
  CHECK(m[4].end_mm[1] == Approx(72));
  CHECK(m[4].center_mm[0] == Approx(100).margin(1e-9));
  CHECK(m[4].center_mm[1] == Approx(62));
}

TEST_CASE("G10 L2 R: the errors LinuxCNC gives, and arcs out of the XY plane refused") {
  CHECK(diagnose("G21 G10 L20 P1 X0 R10\nM2\n").at(0).code == code(ErrorCode::UnusedWord));
  CHECK(diagnose("G21 G10 L2 P1 X0 I1\nM2\n").at(0).code == code(ErrorCode::UnusedWord));
  const auto d = diagnose("G21 G10 L2 P1 R30\nG54 G18 F100\nG2 X10 Z0 I5 K0\nM2\n");
  REQUIRE(!d.empty());
  CHECK(d[0].loc.line == 3);
}

TEST_CASE("a program writing #5161-#5390: G28 and G10 read them, the active system waits") {
  // G54 = (10, 0) selected; #5221 = 50 leaves the active offset at 10 until G55 then G54
  // select it again; #5161/#5162 are G28's position at once; G10 L2 P2 X5 takes G55's Y from
  // #5242 = 7.
  const auto n = motions(
      "G21 G90 G10 L2 P1 X10\n"
      "G54 G0 X0 Y0\n"  // (10, 0)
      "#5221 = 50\n"
      "G0 X1\n"           // (11, 0): still 10
      "G54 G0 X2\n"       // the same system again: still 10 -> (12, 0)
      "G55\nG54 G0 X0\n"  // selected again: 50
      "#5161 = 3 #5162 = 4\n"
      "G28\n"  // (3, 4)
      "#5242 = 7\n"
      "G10 L2 P2 X5\nG55 G0 X0 Y0\n"  // (5, 7)
      "M2\n");
  REQUIRE(n.size() == 6);
  CHECK(n[1].end_mm[0] == Approx(11));
  CHECK(n[2].end_mm[0] == Approx(12));
  CHECK(n[3].end_mm[0] == Approx(50));
  CHECK(n[4].end_mm[0] == Approx(3));
  CHECK(n[4].end_mm[1] == Approx(4));
  CHECK(n[5].end_mm[0] == Approx(5));
  CHECK(n[5].end_mm[1] == Approx(7));
}

TEST_CASE("G88: feed in, dwell, spindle off, program stop, the operator's retract, spindle on") {
  const auto canon =
      run("G21 G90 S300 M3 F60\nG0 X0 Y0 Z10\n"
          "G98 G88 X5 Y5 Z-4 R2 P0.5\n"  // initial level 10: the operator retracts to Z10
          "G80 M2\n");
  std::vector<std::string> seq;
  for (const auto& c : canon) {
    if (const auto* m = std::get_if<gm::Motion>(&c))
      seq.push_back(fmt::format("{}{} {:g} {:g} {:g}", m->by_operator ? "hand " : "",
                                m->kind == gm::MotionKind::Rapid ? "rapid" : "feed", m->end_mm[0],
                                m->end_mm[1], m->end_mm[2]));
    else if (const auto* d = std::get_if<gm::Dwell>(&c))
      seq.push_back(fmt::format("dwell {:g}", d->seconds));
    else if (const auto* e = std::get_if<gm::Event>(&c); e && e->kind == gm::EventKind::Pause)
      seq.push_back("stop");
    else if (e && e->kind == gm::EventKind::SpindleStop)
      seq.push_back("spindle off");
    else if (e && e->kind == gm::EventKind::SpindleStart)
      seq.push_back("spindle on");
  }
  const std::vector<std::string> want = {
      "spindle on",  "rapid 0 0 10", "rapid 5 5 10",      "rapid 5 5 2", "feed 5 5 -4", "dwell 0.5",
      "spindle off", "stop",         "hand rapid 5 5 10", "spindle on",  "spindle off"};
  CHECK(seq == want);
}
