// G70-G72 geometry against hand-worked numbers: the layers of a roughed taper, the 45-degree
// retract R (scaled on short cuts), a profile offset by D (inside corner met, outside corner
// rounded), and the cycles run from a program.
#include "gcode_helpers.hpp"
#include "interp/lathe_profile.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using gm::lathe::Pt;
using gm::lathe::Seg;
using namespace gmtest;

namespace {

struct Rec {
  char kind;  // 'F' feed, 'R' rapid, 'A' arc
  Pt end, centre;
  bool ccw;
};
struct Recorder : gm::lathe::PathSink {
  std::vector<Rec> moves;
  void feed(Pt e) override { moves.push_back({'F', e, {}, false}); }
  void rapid(Pt e) override { moves.push_back({'R', e, {}, false}); }
  void arc(bool ccw, Pt c, Pt e) override { moves.push_back({'A', e, c, ccw}); }
};

bool near(Pt a, Pt b, double tol = 1e-9) {
  return std::abs(a - b) < tol;
}

// From the cycle's start (Z2, X10) to the profile's start (Z0, X4), then a 45-degree taper out
// to (Z-6, X10): Z = 4 - X on the taper, Z = 2 - (10 - X) / 3 on the lead-in.
std::vector<Seg> taper() {
  return {Seg::line(Pt(2, 10), Pt(0, 4)), Seg::line(Pt(0, 4), Pt(-6, 10))};
}

}  // namespace

TEST_CASE("G71 roughs a taper in layers I apart, each cut ending on the taper") {
  gm::lathe::RoughParams p;
  p.x = 10;
  p.z = 2;
  p.i = 1;
  p.r = 0.5;
  Recorder out;
  std::string err;
  REQUIRE(gm::lathe::rough(taper(), p, out, err));
  std::vector<Rec> cuts;
  for (const Rec& m : out.moves)
    if (m.kind == 'F') cuts.push_back(m);
  // Layers at X = 10, 9, ..., 5, then the finishing feed up the taper to its end.
  REQUIRE(cuts.size() == 7);
  for (int k = 0; k < 6; ++k) {
    const double x = 10 - k;
    INFO("layer X" << x);
    CHECK(near(cuts[static_cast<std::size_t>(k)].end, Pt(4 - x, x)));
  }
  CHECK(near(cuts.back().end, Pt(-6, 10)));
  // Each layer starts on the lead-in line (rapid), and after its cut the tool leaves at 45
  // degrees by R in Z and X, goes back R above the layer's start, then down to it.
  for (std::size_t i = 0; i + 4 < out.moves.size(); ++i) {
    if (out.moves[i].kind != 'F' || out.moves[i + 1].kind != 'R') continue;
    const Pt cut_end = out.moves[i].end;
    const Pt start = out.moves[i + 3].end;  // back at the layer's start
    CHECK(near(out.moves[i + 1].end, cut_end + Pt(0.5, 0.5)));
    CHECK(near(out.moves[i + 2].end, start + Pt(-0.5, 0.5)));
    const double x = start.imag();
    CHECK(start.real() == Approx(2 - (10 - x) / 3));
  }
}

TEST_CASE("G71's retract is scaled down when the cut is shorter than 2 R") {
  gm::lathe::RoughParams p;
  p.x = 10;
  p.z = 2;
  p.i = 1;
  p.r = 1;  // the X5 cut runs from Z1/3 to Z-1: 4/3 long, so the retract is 2/3, not 1
  Recorder out;
  std::string err;
  REQUIRE(gm::lathe::rough(taper(), p, out, err));
  bool seen = false;
  for (std::size_t i = 0; i + 1 < out.moves.size(); ++i)
    if (out.moves[i].kind == 'F' && near(out.moves[i].end, Pt(-1, 5))) {
      CHECK(near(out.moves[i + 1].end, Pt(-1 + 2.0 / 3, 5 + 2.0 / 3), 1e-12));
      seen = true;
    }
  CHECK(seen);
}

TEST_CASE(
    "A profile offset by D: lines move D away, an inside corner is met, an outside one "
    "rounded about the old corner") {
  std::string err;
  // A cylinder at X4 from Z0 to Z-5, then a face up to X8: offset 0.5 towards the start.
  std::vector<Seg> inside{Seg::line(Pt(2, 10), Pt(0, 4)), Seg::line(Pt(0, 4), Pt(-5, 4)),
                          Seg::line(Pt(-5, 4), Pt(-5, 8))};
  REQUIRE(gm::lathe::offset_profile(inside, 0.5, err));
  REQUIRE(inside.size() == 3);
  CHECK(near(inside[0].b, Pt(0, 4.5)));  // the lead-in now ends on the moved profile
  CHECK(near(inside[1].a, Pt(0, 4.5)));
  CHECK(near(inside[1].b, Pt(-4.5, 4.5)));  // the corner, 0.5 from both
  CHECK(near(inside[2].a, Pt(-4.5, 4.5)));
  CHECK(near(inside[2].b, Pt(-4.5, 8)));
  // The cylinder, then a face down to X2: the two part, an arc of 0.5 about (Z-5, X4) joins.
  std::vector<Seg> outside{Seg::line(Pt(2, 10), Pt(0, 4)), Seg::line(Pt(0, 4), Pt(-5, 4)),
                           Seg::line(Pt(-5, 4), Pt(-5, 2))};
  REQUIRE(gm::lathe::offset_profile(outside, 0.5, err));
  REQUIRE(outside.size() == 4);
  const Seg& arc = outside[2];
  CHECK(arc.kind == Seg::Kind::Arc);
  CHECK(near(arc.c, Pt(-5, 4)));
  CHECK(near(arc.a, Pt(-5, 4.5)));
  CHECK(near(arc.b, Pt(-5.5, 4)));
  CHECK(near(outside[3].b, Pt(-5.5, 2)));
}

TEST_CASE("G70 in passes: each pass (P-1)(D-E)/P + E from the profile, the last on it") {
  gm::lathe::FinishParams p;
  p.x = 10;
  p.z = 2;
  p.d = 1;
  p.p = 2;
  std::vector<Seg> cyl{Seg::line(Pt(2, 10), Pt(0, 4)), Seg::line(Pt(0, 4), Pt(-5, 4))};
  Recorder out;
  std::string err;
  REQUIRE(gm::lathe::finish(cyl, p, out, err));
  // Pass 2 at 0.5 from the cylinder, pass 1 on it: rapid to the start, rapid to the profile,
  // feed along it.
  REQUIRE(out.moves.size() == 6);
  CHECK(near(out.moves[1].end, Pt(0, 4.5)));
  CHECK(near(out.moves[2].end, Pt(-5, 4.5)));
  CHECK(near(out.moves[4].end, Pt(0, 4)));
  CHECK(near(out.moves[5].end, Pt(-5, 4)));
}

TEST_CASE("G7x refuses what cannot be cut, with bounded work") {
  std::string err;
  Recorder out;
  gm::lathe::RoughParams p;
  p.x = 10;
  p.z = 2;
  // Turning back in Z: not monotonic.
  std::vector<Seg> back{Seg::line(Pt(2, 10), Pt(0, 4)), Seg::line(Pt(0, 4), Pt(-5, 4)),
                        Seg::line(Pt(-5, 4), Pt(3, 6))};
  CHECK_FALSE(gm::lathe::rough(back, p, out, err));
  CHECK(err == "Not monotonic");
  // A depth of cut far too small for the profile: stopped by the move limit, not run.
  p.i = 1e-9;
  p.x = 1e6;
  out.moves.clear();
  CHECK_FALSE(gm::lathe::rough({Seg::line(Pt(2, 1e6), Pt(0, 4)), Seg::line(Pt(0, 4), Pt(-6, 1e6))},
                               p, out, err));
  CHECK(!err.empty());
}

TEST_CASE("G71 from a program: the profile subroutine's moves are read, the cycle's are run") {
  const auto moves = motions(
      "G18 G21 G8 F100\n"
      "O100 SUB\n"
      "  G0 X4 Z0\n"
      "  G1 X10 Z-6\n"
      "  M3 S1000 (passed over, as LinuxCNC does)\n"
      "O100 ENDSUB\n"
      "G0 X10 Z2\n"
      "G71 Q100 X10 Z2 I1 R0.5\n"
      "M2\n");
  std::vector<gm::Motion> feeds;
  for (const auto& m : moves)
    if (m.kind == gm::MotionKind::Line) feeds.push_back(m);
  REQUIRE(feeds.size() == 7);
  for (int k = 0; k < 6; ++k) {
    CHECK(feeds[static_cast<std::size_t>(k)].end_mm[0] == Approx(10 - k));
    CHECK(feeds[static_cast<std::size_t>(k)].end_mm[2] == Approx(4 - (10 - k)).margin(1e-9));
    CHECK(feeds[static_cast<std::size_t>(k)].line == 8);
  }
}
