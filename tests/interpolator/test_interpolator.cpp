// The sample-data interpolator against hand-worked cases: feed per sample, exact block ends,
// time carried across blocks, arcs in every plane, multi-turn, helix, dwell, exact stop,
// override steps and holds, G93; plus a seeded random property test.
#include "interpolator/interpolator.hpp"

#include "support/canon_list.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

using gm::blu3;
using gm::xyz;

using gm::AxisBlu;
using gm::AxisVec;
using gm::Canon;
using gm::Motion;
using gm::MotionKind;

namespace {

Motion line(AxisVec a, AxisVec b, double f_mm_min, int line_no = 1) {
  Motion m;
  m.kind = MotionKind::Line;
  m.start_mm = a;
  m.end_mm = b;
  m.feed_mm_min = f_mm_min;
  m.line = line_no;
  return m;
}

Motion arc(AxisVec a, AxisVec b, AxisVec c, bool ccw, double f, gm::Plane plane = gm::Plane::XY,
           int turns = 1) {
  Motion m;
  m.kind = MotionKind::Arc;
  m.start_mm = a;
  m.end_mm = b;
  m.center_mm = c;
  m.ccw = ccw;
  m.feed_mm_min = f;
  m.plane = plane;
  m.turns = turns;
  return m;
}

gm::InterpolatorConfig config(double blu = 0.001, int settle = 0) {
  gm::InterpolatorConfig c;
  c.period_s = 0.004;
  c.blu_mm = AxisVec::Constant(blu);
  c.rapid_mm_min = 6000;
  c.settle_samples = settle;
  return c;
}

// All samples of a canon list at a constant override (or a per-sample one).
std::vector<gm::CommandSample> samples(std::vector<Canon> canon,
                                       gm::InterpolatorConfig cfg = config(),
                                       double (*scale)(std::int64_t) = nullptr) {
  gmtest::CanonList src(std::move(canon));
  gm::Interpolator ip(cfg, src);
  std::vector<gm::CommandSample> out;
  gm::CommandSample s;
  for (std::int64_t k = 0;; ++k) {
    gm::OverrideInput o;
    if (scale) o.feed_scale = scale(k);
    if (ip.step(o, s) == gm::InterpStatus::Finished) break;
    out.push_back(s);
    REQUIRE(k < 10'000'000);
  }
  return out;
}

}  // namespace

TEST_CASE("a line at F600 moves 40 BLU per 4 ms sample and ends exactly") {
  // 10 mm at 10 mm/s, T = 4 ms: 0.04 mm = 40 BLU a sample, 250 samples.
  const auto s = samples({line(AxisVec::Zero(), xyz(10, 0, 0), 600)});
  REQUIRE(s.size() == 250);
  for (std::size_t k = 0; k < s.size(); ++k)
    CHECK(s[k].pos_blu == blu3(40 * (static_cast<long>(k) + 1), 0, 0));
  // 10.01 mm: ceil(10.01 / 0.04) = 251 samples, the last one short.
  const auto t = samples({line(AxisVec::Zero(), xyz(10.01, 0, 0), 600)});
  REQUIRE(t.size() == 251);
  CHECK(t.back().pos_blu == blu3(10010, 0, 0));
  CHECK(t[249].pos_blu == blu3(10000, 0, 0));
}

TEST_CASE("time carries across blocks: two collinear blocks sample like one") {
  const auto one = samples({line(AxisVec::Zero(), xyz(7.3, 0, 0), 750)});
  const auto two = samples(
      {line(AxisVec::Zero(), xyz(2.01, 0, 0), 750), line(xyz(2.01, 0, 0), xyz(7.3, 0, 0), 750)});
  REQUIRE(one.size() == two.size());
  for (std::size_t k = 0; k < one.size(); ++k) CHECK(one[k].pos_blu == two[k].pos_blu);
  // The second block started in the sample where the first ended: its block_seq is 2 there.
  const std::size_t k_end =
      static_cast<std::size_t>(std::ceil(2.01 / (12.5 * 0.004))) - 1;  // 12.5 mm/s
  CHECK(two[k_end].block_seq == 2);
  CHECK(two[k_end - 1].block_seq == 1);
}

TEST_CASE("a quarter arc stays on the circle and ends exactly") {
  // R = 10 mm, ccw from (10,0) to (0,10) about the origin at 600 mm/min: length 5π mm.
  const auto s = samples({arc(xyz(10, 0, 0), xyz(0, 10, 0), AxisVec::Zero(), true, 600)});
  CHECK(s.size() == static_cast<std::size_t>(std::ceil(5 * M_PI / 0.04)));
  for (const auto& x : s) {
    const double r =
        std::hypot(static_cast<double>(x.pos_blu[0]), static_cast<double>(x.pos_blu[1]));
    CHECK(std::abs(r - 10000.0) <= 0.5 * std::sqrt(2.0));
    CHECK(x.pos_blu[0] >= 0);
    CHECK(x.pos_blu[1] >= 0);
  }
  CHECK(s.back().pos_blu == blu3(0, 10000, 0));
  // Counter-clockwise: Y grows first.
  CHECK(s[0].pos_blu[1] > 0);
}

TEST_CASE("full circles and multi-turn arcs take the whole circumference per turn") {
  // R = 4 mm at 900 mm/min (15 mm/s): one turn 2π·4/15 s.
  const double turn_s = 2 * M_PI * 4 / 15;
  for (int turns : {1, 3}) {
    INFO("turns " << turns);
    const auto s = samples(
        {arc(xyz(4, 0, 0), xyz(4, 0, 0), AxisVec::Zero(), false, 900, gm::Plane::XY, turns)});
    CHECK(std::abs(static_cast<double>(s.size()) * 0.004 - turns * turn_s) <= 0.004);
    CHECK(s.back().pos_blu == blu3(4000, 0, 0));
    CHECK(s[0].pos_blu[1] < 0);  // G2 (clockwise) from +X goes toward −Y
  }
}

TEST_CASE(
    "a helix moves the normal axis in proportion to the angle, its length is sqrt((Rθ)² + h²)") {
  // Two turns of R = 5 about (0,0) descending 4 mm, cw, 600 mm/min.
  const auto s =
      samples({arc(xyz(5, 0, 0), xyz(5, 0, -4), AxisVec::Zero(), false, 600, gm::Plane::XY, 2)});
  const double length = std::hypot(2 * 2 * M_PI * 5, 4.0);
  CHECK(s.size() == static_cast<std::size_t>(std::ceil(length / 0.04)));
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double u = std::min(1.0, (static_cast<double>(k) + 1) * 0.04 / length);  // fraction done
    CHECK(std::abs(static_cast<double>(s[k].pos_blu[2]) - (-4000.0 * u)) <= 0.5 + 1e-6);
  }
  CHECK(s.back().pos_blu == blu3(5000, 0, -4000));
}

TEST_CASE("arcs in XZ and YZ turn the LinuxCNC way") {
  // G18: in-plane axes (Z, X), ccw seen from +Y goes from +Z toward +X (rs274 ARC_FEED first
  // axis Z, second X; rotation > 0 is G3). From (0,0,5) about the origin, ccw: X grows first.
  auto s = samples({arc(xyz(0, 0, 5), xyz(5, 0, 0), AxisVec::Zero(), true, 600, gm::Plane::XZ)});
  CHECK(s[0].pos_blu[0] > 0);
  CHECK(s.back().pos_blu == blu3(5000, 0, 0));
  CHECK(s.size() == static_cast<std::size_t>(std::ceil(2.5 * M_PI / 0.04)));  // a quarter turn
  // G19: in-plane axes (Y, Z), ccw from +Y toward +Z.
  s = samples({arc(xyz(0, 5, 0), xyz(0, 0, 5), AxisVec::Zero(), true, 600, gm::Plane::YZ)});
  CHECK(s[0].pos_blu[2] > 0);
  CHECK(s.size() == static_cast<std::size_t>(std::ceil(2.5 * M_PI / 0.04)));
  // The same end point clockwise is three quarters of a turn.
  s = samples({arc(xyz(0, 5, 0), xyz(0, 0, 5), AxisVec::Zero(), false, 600, gm::Plane::YZ)});
  CHECK(s[0].pos_blu[2] < 0);
  CHECK(s.size() == static_cast<std::size_t>(std::ceil(7.5 * M_PI / 0.04)));
}

TEST_CASE("a dwell holds for exactly its time, exact stop holds settle_samples") {
  gm::Dwell d;
  d.seconds = 0.1;
  d.line = 2;
  // 1 mm at 600 mm/min = 25 samples, then 0.1 s = 25 samples of dwell, then 25 more.
  auto s = samples(
      {line(AxisVec::Zero(), xyz(1, 0, 0), 600), d, line(xyz(1, 0, 0), xyz(2, 0, 0), 600, 3)});
  REQUIRE(s.size() == 75);
  for (std::size_t k = 25; k < 50; ++k) {
    CHECK(s[k].pos_blu == blu3(1000, 0, 0));
    CHECK((s[k].events & gm::kEventDwell) != 0);
    CHECK(s[k].line == 2);
  }
  // Exact stop: a block of 1.01 mm ends inside sample 26; the rest of that sample is dropped
  // and 7 settle samples follow before the next block starts.
  Motion a = line(AxisVec::Zero(), xyz(1.01, 0, 0), 600);
  a.path_mode = gm::PathMode::ExactStop;
  s = samples({a, line(xyz(1.01, 0, 0), xyz(2.01, 0, 0), 600)}, config(0.001, 7));
  REQUIRE(s.size() == 26 + 7 + 25);
  CHECK(s[25].pos_blu == blu3(1010, 0, 0));
  for (std::size_t k = 26; k < 33; ++k) CHECK((s[k].events & gm::kEventSettle) != 0);
  CHECK(s[33].pos_blu == blu3(1050, 0, 0));  // the next block starts on a fresh sample
}

TEST_CASE("M66: a wait for a rise, fall or high level runs to its timeout, low and L0 pass") {
  // 1 mm at 600 mm/min = 25 samples; the inputs of a simulation stay low, so L3 Q0.1 waits
  // 0.1 s = 25 samples and L4 (low) and L0 none: 75 samples in all.
  auto wait = [](int mode, double q) {
    gm::Event e;
    e.kind = gm::EventKind::WaitInput;
    e.mode = mode;
    e.value = q;
    e.line = 2;
    return Canon(std::in_place_type<gm::Event>, e);
  };
  auto s = samples({line(AxisVec::Zero(), xyz(1, 0, 0), 600), wait(3, 0.1), wait(4, 5.0),
                    wait(0, 0.0), line(xyz(1, 0, 0), xyz(2, 0, 0), 600, 3)});
  REQUIRE(s.size() == 75);
  for (std::size_t k = 25; k < 50; ++k) {
    CHECK(s[k].pos_blu == blu3(1000, 0, 0));
    CHECK((s[k].events & gm::kEventInputWait) != 0);
    CHECK((s[k].events & gm::kEventDwell) == 0);
  }
  CHECK((s[50].events & gm::kEventInputWait) == 0);
}

TEST_CASE("an override step changes V[k] at the next sample, 0 % holds without losing position") {
  auto s = samples({line(AxisVec::Zero(), xyz(20, 0, 0), 600)}, config(), [](std::int64_t k) {
    return k < 10 ? 1.0 : k < 20 ? 2.0 : k < 30 ? 0.0 : 1.0;
  });
  CHECK(s[9].pos_blu[0] - s[8].pos_blu[0] == 40);
  CHECK(s[10].pos_blu[0] - s[9].pos_blu[0] == 80);  // doubled exactly at the next sample
  for (std::size_t k = 20; k < 30; ++k) {
    CHECK(s[k].pos_blu == s[19].pos_blu);
    CHECK((s[k].events & gm::kEventHold) != 0);
  }
  CHECK(s[30].pos_blu[0] - s[29].pos_blu[0] == 40);
  CHECK(s.back().pos_blu == blu3(20000, 0, 0));
  // 20 mm: 10 samples at 40 BLU, 10 at 80 (1.2 mm), 10 held, then 18.8 mm at 40 = 470 samples.
  CHECK(s.size() == 10 + 10 + 10 + 470);
}

TEST_CASE("rapids run at the rapid rate times the rapid override, G93 takes its inverse time") {
  Motion r = line(AxisVec::Zero(), xyz(10, 0, 0), 0);
  r.kind = MotionKind::Rapid;
  // 6000 mm/min = 100 mm/s: 0.4 mm a sample, 25 samples; at 50 % rapid override 50 samples.
  CHECK(samples({r}).size() == 25);
  gmtest::CanonList src({r});
  gm::Interpolator ip(config(), src);
  gm::CommandSample cs;
  gm::OverrideInput o;
  o.rapid_scale = 0.5;
  o.feed_scale = 3.0;  // does not touch rapids
  int n = 0;
  while (ip.step(o, cs) == gm::InterpStatus::Working) ++n;
  CHECK(n == 50);
  // G93: 10 mm in 0.5 s whatever the F word: 125 samples.
  Motion g = line(AxisVec::Zero(), xyz(10, 0, 0), 1200);
  g.inverse_time_s = 0.5;
  CHECK(samples({g}).size() == 125);
}

TEST_CASE(
    "zero-length moves take no time, events pass through, OverrideDisable ignores the override") {
  gm::Event off{1, gm::EventKind::OverrideDisable, {}};
  gm::Event pause{1, gm::EventKind::Pause, {}};
  auto s = samples({line(AxisVec::Zero(), AxisVec::Zero(), 600), off, pause,
                    line(AxisVec::Zero(), xyz(1, 0, 0), 600)},
                   config(), [](std::int64_t) { return 0.5; });
  REQUIRE(s.size() == 25);  // 100 % although 50 % is asked: disabled
  CHECK((s[0].events & gm::kEventPause) != 0);
  CHECK(s[0].feed_scale == 1.0);
  gm::Event end{1, gm::EventKind::End, {}};
  s = samples(
      {line(AxisVec::Zero(), xyz(1, 0, 0), 600), end, line(xyz(1, 0, 0), xyz(2, 0, 0), 600)});
  CHECK(s.size() == 25);  // nothing after M2 runs
}

TEST_CASE("a G33 move ignores the feed override (LinuxCNC's synchronised moves)") {
  gm::Motion g33 = line(AxisVec::Zero(), xyz(1, 0, 0), 600);  // K 1.5 mm x S 400 rpm
  g33.mm_per_rev = 1.5;
  g33.spindle_rpm = 400.0;
  g33.spindle_synced = true;
  auto s = samples({g33, line(xyz(1, 0, 0), xyz(2, 0, 0), 600)}, config(),
                   [](std::int64_t) { return 0.5; });
  // 1 mm at 600 mm/min is 25 samples whatever the override; the next 1 mm at 50 % takes 50
  REQUIRE(s.size() == 75);
  CHECK(s[10].feed_scale == 1.0);
  CHECK(s[40].feed_scale == 0.5);
}

TEST_CASE("G95 under G96: the feed follows the radius, capped at D (closed form)") {
  // Facing from X10 to X0 at 0.1 mm/rev, 100 m/min, D3000: v(r) = 0.1 rpm(r) / 60 mm/s with
  // rpm = min(3000, 100000 / (2 pi r)). The time is the integral of dr / v: r dr / c above the
  // radius where the cap starts, r / v_max below it.
  gm::Motion face = line(xyz(10, 0, 0), xyz(0, 0, 0), 0);
  face.mm_per_rev = 0.1;
  face.css_surface_mm_min = 100000.0;
  face.css_max_rpm = 3000.0;
  face.feed_mm_min = face.mm_per_rev * face.spindle_rpm_at(10.0);
  const double pi = 3.14159265358979323846;
  const double r_cap = 100000.0 / (2 * pi * 3000.0);
  const double c = 0.1 * 100000.0 / (2 * pi * 60.0);  // v(r) = c / r above r_cap, mm/s
  const double t = (100.0 - r_cap * r_cap) / (2 * c) + r_cap / (0.1 * 3000.0 / 60.0);
  const auto s = samples({face});
  CHECK(std::abs(static_cast<double>(s.size()) * 0.004 - t) < 0.008);  // within two samples
  // The speed at the start is the feed at r = 10 and at the end the capped one.
  // (over 10 samples: one sample is ~10 BLU, so its rounding alone is 10 %)
  const double v0 = static_cast<double>(s[1].pos_blu[0] - s[11].pos_blu[0]) * 0.001 / 0.04;
  CHECK(v0 == Approx(c / 10.0).epsilon(0.02));
  const std::size_t e = s.size() - 2;
  const double v1 = static_cast<double>(s[e - 10].pos_blu[0] - s[e].pos_blu[0]) * 0.001 / 0.04;
  CHECK(v1 == Approx(5.0).epsilon(0.01));
}

TEST_CASE("a spindle with a ramp: G95 feeds follow its speed, G33 waits until it is at speed") {
  // M3 S600 with 300 rpm/s: at speed after 2 s. 10 mm at 0.1 mm/rev: during the ramp the feed
  // is 0.1 x 300 t / 60 mm/s, 1 mm in 2 s; the other 9 mm at 1 mm/s take 9 s: 11 s in all.
  gm::InterpolatorConfig cfg = config();
  cfg.spindle_accel_rpm_s = 300.0;
  gm::Motion g95 = line(AxisVec::Zero(), xyz(0, 0, -10), 60.0);
  g95.mm_per_rev = 0.1;
  g95.spindle_rpm = 600.0;
  const gm::Event speed{1, gm::EventKind::SpindleSpeed, {}, 0, 600.0};
  const gm::Event start{1, gm::EventKind::SpindleStart, {}, 1, 600.0};
  auto s = samples({speed, start, g95}, cfg);
  CHECK(std::abs(static_cast<double>(s.size()) * 0.004 - 11.0) < 0.012);
  // G33: no cut until the spindle is at speed (2 s), then 10 mm at 1 mm/s.
  gm::Motion g33 = g95;
  g33.spindle_synced = true;
  s = samples({speed, start, g33}, cfg);
  CHECK(std::abs(static_cast<double>(s.size()) * 0.004 - 12.0) < 0.012);
  CHECK((s[100].events & gm::kEventSpindleWait) != 0);
  CHECK(s[100].pos_blu[2] == 0);
  // Without a ramp (the default) both take 10 s.
  CHECK(samples({speed, start, g95}).size() == 2500);
}

TEST_CASE(
    "a spindle with a ramp under G96: it ramps towards the radius's speed, the feed follows") {
  // Turning along Z at r = 50 mm: G96 100 m/min gives 100000 / (2 pi 50) = 318.31 rpm. With
  // 100 rpm/s the spindle is there after t1 = 3.1831 s, having fed 0.2 x 318.31 x t1 / 120 =
  // 1.6887 mm at 0.2 mm/rev; the other 18.3113 mm at 0.2 x 318.31 / 60 = 1.06103 mm/s take
  // 17.2580 s: 20.4411 s in all (the same steps in the code below).
  gm::InterpolatorConfig cfg = config();
  cfg.start_mm = xyz(50, 0, 0);  // the tool is at r = 50 from the first sample on
  gm::InterpolatorConfig no_ramp = cfg;
  cfg.spindle_accel_rpm_s = 100.0;
  gm::Motion cut = line(xyz(50, 0, 0), xyz(50, 0, -20), 0.0);
  cut.mm_per_rev = 0.2;
  cut.css_surface_mm_min = 100000.0;
  cut.css_max_rpm = 2000.0;
  const double pi = 3.14159265358979323846;
  const double rpm = 100000.0 / (2 * pi * 50.0);
  const double t1 = rpm / 100.0;
  const double ramp_mm = 0.2 * rpm * t1 / 120.0;
  const double t = t1 + (20.0 - ramp_mm) / (0.2 * rpm / 60.0);
  const gm::Event speed{1, gm::EventKind::SpindleSpeed, {}, 0, 100.0};  // S100 (m/min): not rpm
  const gm::Event start{1, gm::EventKind::SpindleStart, {}, 1, 100.0};
  const auto s = samples({speed, start, cut}, cfg);
  CHECK(std::abs(static_cast<double>(s.size()) * 0.004 - t) < 0.012);
  // Without the ramp: 20 mm at 1.06103 mm/s.
  CHECK(std::abs(static_cast<double>(samples({speed, start, cut}, no_ramp).size()) * 0.004 -
                 20.0 / (0.2 * rpm / 60.0)) < 0.008);
}

TEST_CASE("property: random chains end every block exactly and never outrun the feed") {
  const char* env = std::getenv("GMOTION_SEED");
  const std::uint64_t seed0 = env ? std::strtoull(env, nullptr, 10) : 42u;
  for (int trial = 0; trial < (env ? 1 : 300); ++trial) {
    const std::uint64_t seed = seed0 + static_cast<std::uint64_t>(trial);
    INFO("seed " << seed << " (GMOTION_SEED=" << seed << " replays it)");
    std::mt19937_64 rng(seed);
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    const double blu_mm =
        std::array<double, 3>{0.001, 0.0005, 0.01}[static_cast<std::size_t>(u(0, 3))];
    std::vector<Canon> canon;
    std::vector<AxisVec> ends;
    AxisVec p = AxisVec::Zero();
    double max_f = 0;
    for (int b = 0; b < 8; ++b) {
      const double f = u(50, 5000);
      max_f = std::max(max_f, f);
      if (u(0, 1) < 0.5) {
        const AxisVec q = xyz(u(-20, 20), u(-20, 20), u(-5, 5));
        canon.push_back(line(p, q, f));
        p = q;
      } else {
        const auto plane = static_cast<gm::Plane>(static_cast<int>(u(0, 3)));
        const gm::PlaneAxes pa = gm::plane_axes(plane);
        const int a = pa.a, bb = pa.b, n = pa.n;
        AxisVec c = p;
        c[a] += u(-5, 5);
        c[bb] += u(-5, 5);
        const double r = std::hypot(p[a] - c[a], p[bb] - c[bb]), phi = u(-M_PI, M_PI);
        AxisVec q = c;
        q[a] = c[a] + r * std::cos(phi);
        q[bb] = c[bb] + r * std::sin(phi);
        q[n] = p[n] + u(-2, 2);  // helical
        canon.push_back(arc(p, q, c, u(0, 1) < 0.5, f, plane, 1 + static_cast<int>(u(0, 2))));
        p = q;
      }
      ends.push_back(p);
    }
    // Odd trials stop exactly after every block, so each block end is observable: the samples
    // that wait for the filter (kEventSettle) must sit exactly on that block's rounded end.
    const bool exact = trial % 2 == 1;
    if (exact)
      for (auto& c : canon) std::get<Motion>(c).path_mode = gm::PathMode::ExactStop;
    auto rounded = [&](const AxisVec& v) {
      AxisBlu q = AxisBlu::Zero();
      for (int i = 0; i < 3; ++i) q[i] = std::llround(v[i] / blu_mm);
      return q;
    };
    gm::InterpolatorConfig cfg = config(blu_mm, exact ? 2 : 0);
    gmtest::CanonList src(canon);
    gm::Interpolator ip(cfg, src);
    gm::CommandSample s, prev;
    prev.pos_blu = AxisBlu::Zero();
    std::uint64_t seq = 0;
    double scale = 1.0;
    int settles = 0;
    for (std::int64_t k = 0;; ++k) {
      if (k % 37 == 0) scale = u(0.1, 2.0);
      gm::OverrideInput o;
      o.feed_scale = scale;
      if (ip.step(o, s) == gm::InterpStatus::Finished) break;
      const double step_blu = (s.pos_blu - prev.pos_blu).cast<double>().norm();
      CHECK(step_blu <= max_f / 60.0 * 2.0 * 0.004 / blu_mm + std::sqrt(3.0) + 1e-9);
      CHECK(s.pos_blu.cast<double>().allFinite());
      if ((s.events & gm::kEventSettle) != 0) {
        ++settles;
        CHECK(s.pos_blu == rounded(ends[s.block_seq - 1]));
      }
      seq = s.block_seq;
      prev = s;
    }
    // The last sample is the last block's rounded end point, exactly.
    CHECK(prev.pos_blu == rounded(ends.back()));
    CHECK(seq == canon.size());
    CHECK(settles == (exact ? 2 * static_cast<int>(canon.size()) : 0));
  }
}
