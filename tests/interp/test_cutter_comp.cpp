// Cutter radius compensation: hand-worked tool paths (offset lines meet at concave corners, an arc
// around the programmed point at convex ones), the move after G40, and the errors.
#include "common/error_codes.hpp"
#include "gcode_helpers.hpp"
#include "interp/cutter_comp.hpp"

#include <catch2/catch.hpp>

using namespace gmtest;
using gm::AxisVec;
using gm::ErrorCode;
using gm::MotionKind;
using gm::xyz;

namespace {
bool near(const AxisVec& a, const AxisVec& b) {
  return (a - b).norm() < 1e-9;
}
}  // namespace

TEST_CASE("G41 concave corner: the first line ends where the offset lines meet") {
  // Path (0,0) -> (10,0) -> (10,10), tool of radius 3 on the left: offset lines y = 3, x = 7.
  const auto m = motions(
      "G21 G90 F100\n"
      "G0 X-10 Y0\n"
      "G41.1 D6 G1 X0 Y0\n"  // entry along +X: ends 3 to its left, (0, 3)
      "G1 X10\n"             // straight on: no corner
      "G1 Y10\n"
      "G40 G1 X0 Y20\n"
      "M2\n");
  REQUIRE(m.size() == 5);
  CHECK(near(m[1].end_mm, xyz(0, 3, 0)));  // entry, released by the next block
  CHECK(m[1].line == 3);
  CHECK(near(m[2].start_mm, xyz(0, 3, 0)));
  CHECK(near(m[2].end_mm, xyz(7, 3, 0)));   // backed off by r / tan(45 deg) = 3
  CHECK(near(m[3].end_mm, xyz(7, 10, 0)));  // G40: the last line ends where it was going
  CHECK(m[4].line == 6);  // the exit move starts at the tool, ends at the programmed point
  CHECK(near(m[4].start_mm, xyz(7, 10, 0)));
  CHECK(near(m[4].end_mm, xyz(0, 20, 0)));
}

TEST_CASE("G41 convex corner: an arc of the tool radius around the programmed corner") {
  // Path (0,0) -> (10,0) -> (10,-10), tool of radius 3 on the left (outside of the right turn).
  const auto m = motions(
      "G21 G90 F100\n"
      "G0 X-10 Y0\n"
      "G41.1 D6 G1 X0 Y0\n"  // entry along +X: ends at (0, 3)
      "G1 X10\n"
      "G1 Y-10\n"
      "G40 G1 X20 Y-20\n"
      "M2\n");
  REQUIRE(m.size() == 6);
  CHECK(near(m[2].end_mm, xyz(10, 3, 0)));
  REQUIRE(m[3].kind == MotionKind::Arc);
  CHECK(m[3].line == 5);
  CHECK_FALSE(m[3].ccw);  // clockwise around (10,0) from (10,3) to (13,0)
  CHECK(near(m[3].center_mm, xyz(10, 0, 0)));
  CHECK(near(m[3].end_mm, xyz(13, 0, 0)));
  CHECK(near(m[4].end_mm, xyz(13, -10, 0)));
}

TEST_CASE("G42 inside an arc: the arc keeps its centre, radius minus the tool radius") {
  // A G2 arc of radius 10 about (10,0) with the tool on the right: inside, radius 8.
  const auto m = motions(
      "G21 G90 F100\n"
      "G0 X0 Y-10\n"
      "G42.1 D4 G1 X0 Y0\n"  // entry along +Y, tool right: ends at (2, 0)
      "G2 X20 Y0 I10 J0\n"
      "G40 G1 X20 Y-10\n"
      "M2\n");
  REQUIRE(m.size() == 4);
  CHECK(near(m[1].end_mm, xyz(2, 0, 0)));
  REQUIRE(m[2].kind == MotionKind::Arc);
  CHECK(near(m[2].center_mm, xyz(10, 0, 0)));
  CHECK(near(m[2].end_mm, xyz(18, 0, 0)));
}

TEST_CASE("cutter compensation errors") {
  auto first_error = [](const std::string& p) {
    const auto d = diagnose(p);
    REQUIRE_FALSE(d.empty());
    return std::pair{d.front().code, d.front().loc.line};
  };
  CHECK(first_error("G21 F100\nG41.1 D6 G1 X2\nM2\n") ==
        std::pair{code(ErrorCode::CompToolTooLarge), 2});
  CHECK(first_error("G21 F100\nG41.1 D6 G1 X20\nG3 X20 Y4 J2\nM2\n") ==
        std::pair{code(ErrorCode::CompToolTooLarge), 3});
  CHECK(first_error("G21 F100\nG0 Y-10\nG41.1 D6 G1 Y0\nG1 X20\nG1 Y2\nG1 X0\nM2\n") ==
        std::pair{code(ErrorCode::CompGouge), 6});
  CHECK(first_error("G21 F100\nG41.1 D6 G1 X20\nG92 X0\nM2\n") ==
        std::pair{code(ErrorCode::CutterCompMisused), 3});
  CHECK(first_error("G21 F100\nG41.1 D6 G1 X20\nG40\nG2 X30 R10\nM2\n") ==
        std::pair{code(ErrorCode::CutterCompMisused), 4});
  CHECK(first_error("G21 G19 F100\nG41.1 D6\nM2\n") ==
        std::pair{code(ErrorCode::CutterCompMisused), 2});
}

namespace {
// The lines of the commands a queue holds, oldest first.
std::vector<int> lines_of(const gm::CompQueue& q) {
  std::vector<int> out;
  for (const gm::CompQueued& c : q) out.push_back(c.mo.line);
  return out;
}
void push_line(gm::CompQueue& q, int line) {
  gm::CompQueued c;
  c.mo.line = line;
  q.push_back(c);
}
}  // namespace

TEST_CASE("a copied compensation queue holds what its source holds") {
  gm::CompQueue a, b;
  for (int line : {1, 2, 3}) push_line(a, line);
  b = a;
  CHECK(lines_of(b) == std::vector<int>{1, 2, 3});
  push_line(a, 4);  // b is what a held: only the fourth is added
  b = a;
  CHECK(lines_of(b) == std::vector<int>{1, 2, 3, 4});
  gm::CompQueue c = b;
  push_line(c, 5);  // c and b part after their fourth command
  push_line(b, 6);
  c = b;
  CHECK(lines_of(c) == std::vector<int>{1, 2, 3, 4, 6});
  push_line(c, 7);  // a block that failed: its copy had one command more
  c = b;
  CHECK(lines_of(c) == std::vector<int>{1, 2, 3, 4, 6});
  gm::CompQueue d;
  for (int line : {8, 9, 10, 11, 12, 13}) push_line(d, line);  // longer, nothing shared
  c = d;
  CHECK(lines_of(c) == std::vector<int>{8, 9, 10, 11, 12, 13});
  d.clear();
  c = d;
  CHECK(c.empty());
}

TEST_CASE("moves along the normal axis held back in a loop, and a failed block among them") {
  // Compensation on, then 4,000 passes of two Z moves: all 8,000 are held back (they do not move
  // in the plane) until the line to (20, 5) releases them, as LinuxCNC queues them.
  const auto m = motions(
      "G21 G90 G17 G0 X0 Y0 Z5\n"
      "G41.1 D2 G1 X10 Y0 F500\n"
      "#1 = 0\n"
      "o100 while [#1 LT 4000]\n"
      "G1 Z-1\n"
      "G1 Z1\n"
      "#1 = [#1 + 1]\n"
      "o100 endwhile\n"
      "G1 X20 Y5\n"
      "G40 G0 X30\n"
      "M2\n");
  REQUIRE(m.size() == 8004);  // the rapid to Z5, the entry, 8,000 Z moves, the line, the exit
  CHECK(m[1].line == 2);
  CHECK(m[2].line == 5);
  CHECK(m[8001].line == 6);
  CHECK(m[8002].line == 9);
  CHECK(m[8001].end_mm[2] == 1.0);
  CHECK(m[8001].end_mm[1] == m[8002].start_mm[1]);
  // A block that fails while moves are held back (K in the XY plane) changes nothing: the check
  // counts the same moves as without it.
  const std::string head = "G21 G90 G17 G0 X0 Y0 Z5\nG41.1 D2 G1 X10 Y0 F500\nG1 Z-1\nG1 Z1\n";
  const std::string tail = "G1 Z-2\nG1 X20 Y5\nG40 G0 X30\nM2\n";
  const auto moves_of = [](const std::string& program) {
    std::istringstream in(program);
    std::vector<gm::Diagnostic> d;
    gm::InterpreterOptions opts;
    return gm::check_program_diagnostics(in, "test.ngc", opts, d).moves;
  };
  CHECK(moves_of(head + "G2 X12 K1\n" + tail) == 7);
  CHECK(moves_of(head + tail) == 7);
  CHECK(motions(head + tail).size() == 7);
}
