// Spindle, coolant, tool and I/O codes as canonical events: the sequence LinuxCNC's
// interpreter gives, hand-worked; M0/M1 pauses; user M codes recorded only when their file exists.
#include "gcode_helpers.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace gmtest;
using gm::EventKind;

namespace {

std::vector<gm::Event> events(const std::string& program, const gm::Machine& m = gm::Machine{}) {
  std::vector<gm::Event> out;
  for (const auto& c : run(program, m))
    if (const auto* e = std::get_if<gm::Event>(&c)) out.push_back(*e);
  return out;
}

}  // namespace

TEST_CASE("S, M3, M8, M6 and M2 give the spindle and coolant events in rs274's order") {
  const auto e = events(
      "G21\n"
      "T2 M6\n"        // SELECT_TOOL(2), STOP_SPINDLE_TURNING, CHANGE_TOOL
      "S1200 M3 M8\n"  // S before M3 before M8 (order of execution)
      "M4 S900\n"      // S first although written last
      "M2\n");         // spindle stop, flood off (only what is on), end
  std::vector<EventKind> kinds;
  for (const auto& x : e) kinds.push_back(x.kind);
  const std::vector<EventKind> want{
      EventKind::ToolSelect,   EventKind::SpindleStop,  EventKind::ToolChange,
      EventKind::SpindleSpeed, EventKind::SpindleStart, EventKind::Flood,
      EventKind::SpindleSpeed, EventKind::SpindleStart, EventKind::SpindleStop,
      EventKind::Flood,        EventKind::End};
  REQUIRE(kinds == want);
  CHECK(e[0].index == 2);
  CHECK(e[2].index == 2);
  CHECK(e[3].value == 1200.0);
  CHECK(e[4].index == 1);  // clockwise
  CHECK(e[5].index == 1);  // flood on
  CHECK(e[6].value == 900.0);
  CHECK(e[7].index == -1);  // counter-clockwise at the new speed
  CHECK(e[7].value == 900.0);
  CHECK(e[9].index == 0);   // flood off at the end
  CHECK(e[10].index == 2);  // M2
}

TEST_CASE("M62..M68 and M19 carry their pins, values and modes") {
  const auto e = events(
      "G21\n"
      "M62 P3\n"
      "M65 P1\n"
      "M67 E2 Q-1.5\n"
      "M66 P4 L3 Q2.5\n"
      "M19 R45 P1 Q3\n"
      "M30\n");
  REQUIRE(e.size() >= 6);
  CHECK((e[0].kind == EventKind::DigitalOut && e[0].index == 3 && e[0].value == 1.0 && e[0].sync));
  CHECK((e[1].kind == EventKind::DigitalOut && e[1].index == 1 && e[1].value == 0.0 && !e[1].sync));
  CHECK((e[2].kind == EventKind::AnalogOut && e[2].index == 2 && e[2].value == -1.5 && e[2].sync));
  CHECK((e[3].kind == EventKind::WaitInput && e[3].index == 4 && e[3].mode == 3 &&
         e[3].value == 2.5 && !e[3].analog));
  CHECK((e[4].kind == EventKind::SpindleOrient && e[4].value == 45.0 && e[4].index == 1));
  CHECK((e[5].kind == EventKind::OrientWait && e[5].value == 3.0));
}

TEST_CASE("E is a word letter: X1E5 is X1 then E5 (no exponents in G-code)") {
  const auto e = events("G21\nM67E5Q2\nM30\n");
  REQUIRE(!e.empty());
  CHECK((e[0].kind == EventKind::AnalogOut && e[0].index == 5 && e[0].value == 2.0));
}

TEST_CASE("M0 and M1 hold the run for the machine's pause time, G4 stays a dwell") {
  gm::Machine m;
  m.pause_s = 2.5;
  const auto canon = run("G21\nG4 P0.5\nM0\nM1\nM30\n", m);
  std::vector<gm::Dwell> d;
  for (const auto& c : canon)
    if (const auto* x = std::get_if<gm::Dwell>(&c)) d.push_back(*x);
  REQUIRE(d.size() == 3);
  CHECK((d[0].seconds == 0.5 && !d[0].pause));
  CHECK((d[1].seconds == 2.5 && d[1].pause && d[1].line == 3));
  CHECK((d[2].seconds == 2.5 && d[2].pause && d[2].line == 4));
  gm::Machine none;  // pause_s = 0: no dwell, the stops are events only
  int dwells = 0;
  for (const auto& c : run("G21\nM0\nM30\n", none)) dwells += std::holds_alternative<gm::Dwell>(c);
  CHECK(dwells == 0);
}

TEST_CASE("M100..M199: recorded when the directory has the file, else rs274's error") {
  const auto dir = std::filesystem::temp_directory_path() / "gmotion-test-user-mcodes";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "M101") << "#!/bin/sh\necho never run\n";
  gm::Machine m;
  m.user_mcode_dir = dir.string();
  const auto e = events("G21\nM101 P2 Q-3\nM30\n", m);
  REQUIRE(!e.empty());
  CHECK((e[0].kind == EventKind::UserMcode && e[0].index == 101 && e[0].value == 2.0 &&
         e[0].value2 == -3.0 && e[0].line == 2));
  const auto d = diagnose("G21\nM101\nM102 P1\nM30\n", m);
  REQUIRE(d.size() == 1);
  CHECK(d[0].loc.line == 3);
  CHECK(d[0].code == code(gm::ErrorCode::UnknownMCode));
  const auto d2 = diagnose("G21\nM101\nM30\n");  // no directory at all
  REQUIRE(d2.size() == 1);
  CHECK(d2[0].loc.line == 2);
  std::filesystem::remove_all(dir);
}

TEST_CASE("M6 stops the spindle: a tapping cycle after a tool change is rs274's error") {
  const auto d = diagnose("G21 G90\nS500 M3\nT1 M6\nG84 X1 Y1 Z-2 R1 F100\nM30\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].loc.line == 4);
}

TEST_CASE("M66: #5399 is -1 after a wait that times out, 0 after L0 and L4 (inputs stay low)") {
  const auto texts = gmtest::messages(
      "G21\nM66 P0 L3 Q2\n(DEBUG,#5399)\nM66 P1 L4 Q1\n(DEBUG,#5399)\n"
      "M66 P0 L1 Q1\nM66 E0 L0\n(DEBUG,#5399)\nM2\n");
  CHECK(texts == std::vector<std::string>{"-1.000000", "0.000000", "0.000000"});
}
