// The check summary's tally: a move's length and time with motion_length_mm's bits, and the
// sums of a check read ahead (added up on the reading thread) equal to the serial ones.
#include "gcode_helpers.hpp"
#include "interp/move_tally.hpp"
#include "motion/geometry.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

gm::CheckSummary checked(const std::string& text, gm::CheckThreads threads) {
  std::istringstream in(text);
  gm::Machine m;
  std::vector<gm::Diagnostic> diags;
  return gm::check_program_diagnostics(in, "p.nc", gm::InterpreterOptions{&m, false}, diags,
                                       threads);
}

}  // namespace

TEST_CASE("tally: hand-worked lengths and times") {
  gm::MoveTally t(6000.0);
  std::vector<gm::Canon> out;
  gm::Motion line;  // 3-4-12: 13 mm at 1300 mm/min, 0.6 s
  line.kind = gm::MotionKind::Line;
  line.end_mm = gm::xyz(3, 4, 12);
  line.feed_mm_min = 1300.0;
  out.emplace_back(line);
  gm::Motion rapid;  // 60 mm at the rapid rate, 0.6 s
  rapid.kind = gm::MotionKind::Rapid;
  rapid.start_mm = gm::xyz(0, 0, 10);
  rapid.end_mm = gm::xyz(0, 0, 70);
  out.emplace_back(rapid);
  gm::Motion arc;  // a half circle of radius 2 ccw in XZ (G18), 2 pi mm, G93 in 3 s
  arc.kind = gm::MotionKind::Arc;
  arc.plane = gm::Plane::XZ;
  arc.start_mm = gm::xyz(2, 5, 0);
  arc.end_mm = gm::xyz(-2, 5, 0);
  arc.center_mm = gm::xyz(0, 5, 0);
  arc.ccw = true;
  arc.inverse_time_s = 3.0;
  out.emplace_back(arc);
  gm::Motion rotary;  // A alone: 90 degrees, 1.5 s at 3600 deg/min
  rotary.end_mm[3] = 90.0;
  rotary.feed_mm_min = 3600.0;
  out.emplace_back(rotary);
  out.emplace_back(gm::Dwell{9, 2.5});
  gm::Event end;
  end.line = 9;
  out.emplace_back(end);
  t.add(out);
  CHECK(t.moves() == 4);
  CHECK(t.path_length_mm() == Approx(13.0 + 60.0 + 2.0 * std::numbers::pi + 90.0));
  CHECK(t.time_at_feed_s() == Approx(0.6 + 0.6 + 3.0 + 1.5 + 2.5));
}

TEST_CASE("tally: a move's length has motion_length_mm's bits (random lines and arcs)") {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> pos(-50.0, 50.0), ang(-4.0, 4.0), r(0.01, 30.0);
  gm::MoveTally t(6000.0);
  double path = 0.0, time = 0.0;
  for (int i = 0; i < 20000; ++i) {
    gm::Motion m;
    const int kind = static_cast<int>(rng() % 4);
    m.start_mm = gm::xyz(pos(rng), pos(rng), pos(rng));
    m.feed_mm_min = 100.0 + static_cast<double>(rng() % 5000);
    if (kind == 0) {  // a line, or a rapid
      m.kind = rng() % 2 ? gm::MotionKind::Line : gm::MotionKind::Rapid;
      m.end_mm = gm::xyz(pos(rng), pos(rng), rng() % 3 ? m.start_mm[2] : pos(rng));
    } else if (kind == 1) {  // U V W or rotary only
      m.kind = gm::MotionKind::Line;
      m.end_mm = m.start_mm;
      m.end_mm[3 + static_cast<int>(rng() % 6)] = pos(rng);
    } else {  // an arc or a helix in any plane, some of several turns
      m.kind = gm::MotionKind::Arc;
      m.plane = static_cast<gm::Plane>(rng() % 3);
      const gm::PlaneAxes ax = gm::plane_axes(m.plane);
      m.center_mm = m.start_mm;
      m.center_mm[ax.a] += pos(rng) / 5.0;
      m.center_mm[ax.b] += pos(rng) / 5.0;
      const double rad = r(rng), a0 = ang(rng), a1 = ang(rng);
      m.start_mm[ax.a] = m.center_mm[ax.a] + rad * std::cos(a0);
      m.start_mm[ax.b] = m.center_mm[ax.b] + rad * std::sin(a0);
      m.end_mm = m.start_mm;
      m.end_mm[ax.a] = m.center_mm[ax.a] + (rad + pos(rng) / 1e4) * std::cos(a1);
      m.end_mm[ax.b] = m.center_mm[ax.b] + rad * std::sin(a1);
      if (rng() % 2) m.end_mm[ax.n] += pos(rng);
      if (rng() % 5 == 0) m.end_mm = m.start_mm;  // a full circle
      m.ccw = rng() % 2 == 0;
      m.turns = 1 + static_cast<int>(rng() % 3);
      if (rng() % 4 == 0) m.inverse_time_s = 0.5;
    }
    const double len = gm::motion_length_mm(m);
    path += len;
    if (m.kind == gm::MotionKind::Rapid)
      time += len / 6000.0 * 60.0;
    else if (m.inverse_time_s > 0)
      time += m.inverse_time_s;
    else
      time += len / m.feed_mm_min * 60.0;
    t.add(std::vector<gm::Canon>{m});
    INFO("move " << i);
    REQUIRE(t.path_length_mm() == path);
    REQUIRE(t.time_at_feed_s() == time);
  }
  CHECK(t.moves() == 20000);
}

TEST_CASE("tally: read ahead, a block of many moves adds up as the serial check does") {
  // G81 with L repeats: a block of 6,000 moves, beyond the entries a batch holds, among batches
  // of ordinary lines; and a program ending at M2 with the reader still ahead.
  std::string p = "G21 G90 G17 F500\nG0 Z5\n";
  for (int i = 0; i < 2500; ++i) {
    p += fmt::format("G1 X{} Y{}\n", (i % 37) * 0.5, (i % 11) * 0.25);
    if (i % 700 == 0) p += "G91 G81 X0.5 Y0 Z-1 R1 L2000\nG80 G90\n";
    if (i % 900 == 0) p += "G91 G2 X1 Y0 R20\nG90 G4 P0.25\n";
  }
  p += "M2\n";
  for (int i = 0; i < 5000; ++i) p += "G1 X1\n";
  const gm::CheckSummary a = checked(p, gm::CheckThreads::Single);
  const gm::CheckSummary b = checked(p, gm::CheckThreads::Auto);
  CHECK(a.errors == 0);
  CHECK(a.moves > 26000);
  CHECK(b.moves == a.moves);
  CHECK(b.path_length_mm == a.path_length_mm);
  CHECK(b.time_at_feed_s == a.time_at_feed_s);
}
