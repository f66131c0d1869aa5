// The servo's linear step response against the real ServoAxis, and the FIR + servo chain's
// corner moment against a simulated corner with the servo on (tolerance_on = encoder).
#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "interpolator/arc_compensation.hpp"
#include "machine/machine.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/pipeline.hpp"
#include "planner/filter_moments.hpp"
#include "planner/servo_response.hpp"
#include "servo/servo_axis.hpp"
#include "servo/servo_match.hpp"
#include "support/repo_root.hpp"
#include "support/sample_stepper.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <sstream>
#include <tuple>
#include <vector>

TEST_CASE("linear servo response: the real ServoAxis follows it within the encoder's rounding") {
  const gm::Machine m;
  const gm::AxisConfig& ax = m.axes[0];
  const int n = 400;
  const std::vector<double> S = gm::servo_step_response(ax, m.period_s, m.servo_substeps, n);
  // Settles to 1 from 0. The position step overshoots a little (the P loop around the IP
  // velocity loop): the planner must use the absolute-moment bound (docs/tolerance.md).
  CHECK(S[0] == 0.0);
  CHECK(S[n - 1] == Approx(1.0).margin(1e-9));
  const double peak = *std::max_element(S.begin(), S.end());
  CHECK(peak > 1.01);
  CHECK(peak < 1.2);
  // A smooth 3000 BLU move (cosine ramp over 0.4 s, well inside the drive's limit): the real
  // loop, with its rounded feedback, against Σ g_j r_{k−j}, g the step response's differences.
  std::vector<std::int64_t> ref(n);
  for (int k = 0; k < n; ++k) {
    const double x = std::min(1.0, k / 100.0);
    ref[static_cast<std::size_t>(k)] =
        std::llround(1500.0 * (1.0 - std::cos(3.14159265358979 * x)));
  }
  gm::ServoAxis servo(ax, m.period_s, m.servo_substeps, 0);
  double worst = 0.0;
  for (int k = 0; k < n; ++k) {
    const double table = servo.table_blu();
    servo.step(ref[static_cast<std::size_t>(k)]);
    double lin = 0.0;
    for (int j = 0; j <= k; ++j)
      lin += (S[static_cast<std::size_t>(j)] - (j ? S[static_cast<std::size_t>(j - 1)] : 0.0)) *
             static_cast<double>(ref[static_cast<std::size_t>(k - j)]);
    worst = std::max(worst, std::abs(table - lin));
  }
  CHECK(worst < 1.0);  // the quantised feedback moves the table by less than one count
}

TEST_CASE("FIR + servo chain: monotone step, unit sum, corner moment matches a servo-on run") {
  gm::Machine m;
  m.tolerance_on = gm::ToleranceOn::Encoder;
  m.servo_matching =
      false;  // the loop as it is, not shaped (see "shaped by zero-phase-error taps")
  const gm::PlannedChain pc = gm::plan_chain(m, true);
  const std::vector<double>& c = pc.weights;
  const double margin_mm = pc.extra_margin_mm;
  const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
  CHECK(c.size() > taps.integer.size());
  CHECK(margin_mm >= 0.0);
  CHECK(margin_mm <= 0.05 * m.contour_blu_mm() + 1e-15);
  double s = 0.0;
  for (double w : c) s += w;
  CHECK(s == Approx(1.0).margin(1e-12));
  const gm::FilterMoments chain(c, m.period_s), fir(taps, m.period_s);
  // It overshoots: D(P) never falls below the overshoot area, and zones are the whole window.
  CHECK(chain.overshoot_s() > 0.0);
  CHECK(chain.zone_floor_s() == chain.tau_s());
  CHECK(fir.overshoot_s() == 0.0);
  CHECK(fir.zone_floor_s() == 0.0);
  // The servo adds lag: the chain cuts the corner more than the FIR alone (and the FIR is
  // unchanged when the servo is off or tolerance_on = acc_dec).
  CHECK(chain.corner_moment_s(0) > 1.2 * fir.corner_moment_s(0));
  CHECK(gm::plan_chain(m, false).weights.size() == taps.integer.size());
  // Moments fall with the pause and vanish past the chain's length.
  CHECK(chain.corner_moment_s(0.05) < chain.corner_moment_s(0.0));
  CHECK(chain.corner_moment_s(chain.tau_s()) == Approx(chain.overshoot_s()).epsilon(1e-9));
  CHECK(chain.corner_moment_s(chain.tau_s()) < 0.2 * chain.corner_moment_s(0.0));

  // A 90° corner at F3000 (50 mm/s) with the servo on and no tolerance: the table's worst
  // contour error is at most V·D_chain(0) plus the encoder's rounding in the loop, and close
  // to it (the signed moments are a little below the positive parts the bound takes).
  std::istringstream in("G21 G90 G17 G64\nG1 X30 Y0 F3000\nY30\nM2\n");
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, "corner.nc", opts);
  gm::RunConfig cfg;
  cfg.machine = m;
  cfg.servo = true;
  gmtest::SampleStepper p(cfg, stream);
  gm::SampleRecord rec;
  double worst_mm = 0.0;
  while (p.step({}, rec) == gm::PipelineStatus::Working)
    worst_mm = std::max(worst_mm, std::abs(rec.contour_err_blu) * m.contour_blu_mm());
  const double form_mm = 50.0 * chain.corner_moment_s(0.0);
  const double fir_mm = 50.0 * fir.corner_moment_s(0.0);
  CAPTURE(form_mm, fir_mm, worst_mm);
  CHECK(worst_mm <= form_mm + 1.0 * m.contour_blu_mm());
  CHECK(worst_mm >= 0.85 * form_mm);
  CHECK(worst_mm > fir_mm * 1.05);
}

TEST_CASE("different X, Y, Z servos: planned on the closest one plus a speed-proportional error") {
  const gm::Machine m = [] {
    gm::Machine d = gm::default_machine();
    d.tolerance_on = gm::ToleranceOn::Encoder;
    return d;
  }();
  const gm::AxisConfig& x = m.axes[0];
  // Same servo: no mismatch. The built-in Y (the paper's second axis) against X: the area
  // between their step responses, T·Σ|S_y − S_x| = 2.98·10⁻⁵ s (docs/tolerance.md); against Y
  // both X and Z differ by that.
  gm::Machine one = m;
  one.axes[1] = x;
  CHECK(gm::servo_mismatch_s(one, 0) == 0.0);
  const double xy = gm::servo_mismatch_s(m, 0);
  CHECK(xy == Approx(2.98e-5).epsilon(0.01));
  CHECK(gm::servo_mismatch_s(m, 1) == Approx(std::sqrt(2.0) * xy));
  CHECK(gm::reference_servo_axis(m) == 0);
  // The planner plans on X (closest to the others: X and Z agree) and reports the mismatch,
  // unmatched with servo_matching off.
  gm::Machine unmatched = m;
  unmatched.servo_matching = false;
  const gm::PlannedChain c = gm::plan_chain(unmatched, true);
  CHECK(c.speed_error_s == Approx(xy));
  gm::Machine mx = unmatched;
  for (auto& a : mx.axes) a = x;
  CHECK(gm::plan_chain(mx, true).weights == c.weights);
  CHECK(gm::plan_chain(mx, true).speed_error_s == 0.0);
}

TEST_CASE("with feedforward the real ServoAxis follows the linear response within 1 BLU") {
  // The shipped feedforward machine's X (programs/machines/default-ff.toml) and velocity
  // feedforward alone, at 1 and 4 servo substeps: the reference's differences enter both.
  for (const auto& [ff1, ff2, substeps] :
       {std::tuple{0.857, 0.01431, 1}, std::tuple{0.857, 0.01431, 4}, std::tuple{1.0, 0.0, 1}}) {
    gm::Machine m;
    gm::AxisConfig ax = m.axes[0];
    ax.ff1 = ff1;
    ax.ff2_s = ff2;
    const int n = 400;
    const std::vector<double> S = gm::servo_step_response(ax, m.period_s, substeps, n);
    CHECK(S[n - 1] == Approx(1.0).margin(1e-9));
    std::vector<std::int64_t> ref(n);
    for (int k = 0; k < n; ++k) {
      const double x = std::min(1.0, k / 100.0);
      ref[static_cast<std::size_t>(k)] =
          std::llround(1500.0 * (1.0 - std::cos(3.14159265358979 * x)));
    }
    gm::ServoAxis servo(ax, m.period_s, substeps, 0);
    double worst = 0.0, worst_nofb = 0.0;
    for (int k = 0; k < n; ++k) {
      const double table = servo.table_blu();
      servo.step(ref[static_cast<std::size_t>(k)]);
      double lin = 0.0;
      for (int j = 0; j <= k; ++j)
        lin += (S[static_cast<std::size_t>(j)] - (j ? S[static_cast<std::size_t>(j - 1)] : 0.0)) *
               static_cast<double>(ref[static_cast<std::size_t>(k - j)]);
      worst = std::max(worst, std::abs(table - lin));
      worst_nofb = std::max(worst_nofb, std::abs(table - ref[static_cast<std::size_t>(k)]));
    }
    CAPTURE(ff1, ff2, substeps, worst, worst_nofb);
    CHECK(worst < 1.0);
    CHECK(worst_nofb > 5.0);  // the loop still lags or leads the reference: the model is needed
  }
}

TEST_CASE("feedforward chain: the ringing left is clipped, the planner sees no overshoot") {
  gm::Machine m;
  m.tolerance_on = gm::ToleranceOn::Encoder;
  for (auto& a : m.axes) a.ff1 = 0.857, a.ff2_s = 0.01431;
  const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
  // The chain's step response leaves [0, 1] by a sliver (numbers of 2026-11-28; 1.59 ms above 1
  // without feedforward): under half a BLU at 2 m/s, so it is clipped and charged to the margin.
  const double blu = m.contour_blu_mm();
  const gm::ChainResponse r =
      gm::chain_response(taps, m.axes[0], m.period_s, 1, 0.05 * blu / 2000.0, 0.5 * blu / 2000.0);
  CHECK(r.overshoot_s > 0.0);
  CHECK(r.overshoot_s < 2e-7);
  CHECK(r.clipped_s == r.overshoot_s + r.undershoot_s);
  const gm::PlannedChain pc = gm::plan_chain(m, true);
  const std::vector<double>& c = pc.weights;
  const double margin_mm = pc.extra_margin_mm;
  CHECK(c == r.weights);
  CHECK(margin_mm == Approx(2000.0 * (r.tail_area_s + r.clipped_s)));
  CHECK(margin_mm <= 0.55 * blu);
  const gm::FilterMoments chain(c, m.period_s), fir(taps, m.period_s);
  CHECK(chain.overshoot_s() == 0.0);
  CHECK(chain.undershoot_s() == 0.0);
  CHECK(chain.zone_floor_s() == 0.0);
  // The corner moment is the FIR's within 2 % (8.80 ms against 8.94 ms): the table rounds a
  // corner as the Acc/Dec output does. Without feedforward: 11.0 ms and the 1.59 ms floor.
  CHECK(chain.corner_moment_s(0) == Approx(fir.corner_moment_s(0)).epsilon(0.02));
  // Not clipped: the chain without feedforward, or with a limit below its overshoot.
  const gm::ChainResponse none =
      gm::chain_response(taps, m.axes[0], m.period_s, 1, 0.05 * blu / 2000.0, 1e-9);
  CHECK(none.clipped_s == 0.0);
  // Clipped, the step response stays at 1 from some weight on and the zero weights after it
  // are dropped, as are the servo's delay's before the first (74 -> 58 weights, 2026-12-02):
  // the chain's output is the same path, two samples earlier, its window shorter. Unclipped,
  // the ringing's tail holds to the truncation limit.
  CHECK(r.weights.size() < none.weights.size());
  CHECK(r.weights.front() != 0.0);
  CHECK(r.weights.back() != 0.0);
  CHECK(none.weights.size() == 72);
  CHECK(r.weights.size() == 58);
  gm::AxisConfig plain = m.axes[0];
  plain.ff1 = plain.ff2_s = 0.0;
  const gm::ChainResponse p =
      gm::chain_response(taps, plain, m.period_s, 1, 0.05 * blu / 2000.0, 0.5 * blu / 2000.0);
  CHECK(p.clipped_s == 0.0);
  CHECK(p.overshoot_s == Approx(1.593e-3).epsilon(0.01));
}

TEST_CASE("a circle commanded on R/|C| leaves the FIR and the feedforward servo on R") {
  // Pre-compensated arcs with tolerance_on = encoder (docs/tolerance.md, "Planning for the
  // table"): the chain c (FIR and X's feedforward servo, X's on both axes: a mismatch is the
  // reserve's) is not symmetric, so a circle at rate ω leaves it on r·|C(e^{jωT})|, C = Σ c_k
  // e^{−jkωT}, turned by arg C. The rule's gain against that sum, then the real FirAccDec and
  // ServoAxis (1 µm BLU) driven on R/|C| and on R: the table's radius, once settled, is R within
  // the rounding, against R·|C| without the correction.
  gm::Machine m;
  m.tolerance_on = gm::ToleranceOn::Encoder;
  for (auto& a : m.axes) a = m.axes[0], a.ff1 = 0.857, a.ff2_s = 0.01431;
  const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
  const std::vector<double> c = gm::plan_chain(m, true).weights;
  const double T = m.period_s;
  const gm::ArcCompensation rule(c, T);
  REQUIRE(rule.enabled());
  const double R_blu = 2000.0;  // 2 mm: well inside the drive's force at these rates
  for (double frac : {0.2, 0.5, 0.9}) {
    const double x = frac * rule.limit_omega_t();
    std::complex<double> C = 0.0;
    for (std::size_t k = 0; k < c.size(); ++k)
      C += c[k] * std::polar(1.0, -static_cast<double>(k) * x);
    CHECK(rule.gain_exact(x) == Approx(std::abs(C)).epsilon(1e-12));
    CHECK(rule.gain(x) == Approx(std::abs(C)).epsilon(1e-6));
    for (const bool compensated : {true, false}) {
      const double rc = compensated ? R_blu / std::abs(C) : R_blu;
      gm::FirAccDec fir(taps, gm::AxisBlu::Zero());
      gm::AxisBlu in = gm::AxisBlu::Zero(), out;
      std::vector<gm::ServoAxis> servo;
      for (int a = 0; a < 2; ++a) servo.emplace_back(m.axes[a], T, m.servo_substeps, 0);
      const auto start = std::llround(rc);
      double lo = 1e300, hi = 0.0;
      const int settle = 4 * static_cast<int>(c.size()), turn = static_cast<int>(6.3 / x);
      for (int k = 0; k < settle + turn; ++k) {
        in[0] = std::llround(rc * std::cos(x * k)) - start;  // relative to the start (rc, 0)
        in[1] = std::llround(rc * std::sin(x * k));
        fir.step(in, out);
        servo[0].step(out[0]);
        servo[1].step(out[1]);
        if (k < settle) continue;
        const double r =
            std::hypot(servo[0].table_blu() + static_cast<double>(start), servo[1].table_blu());
        lo = std::min(lo, r), hi = std::max(hi, r);
      }
      const double want = compensated ? R_blu : R_blu * std::abs(C);
      CAPTURE(frac, x, compensated, std::abs(C), lo, hi, want);
      CHECK(lo > want - 2.0);
      CHECK(hi < want + 2.0);
    }
    CHECK(R_blu * (1.0 - std::abs(C)) > 20.0);  // the correction is far above the rounding
  }
}

TEST_CASE("fir_variation: a window that rises and falls once varies by twice its peak") {
  // Σ|h_k − h_{k−1}| with zeros beyond the weights: up to the peak and down again, 2·max h for
  // the default machine's Blackman window (41 taps: 0.139).
  const gm::Machine m;
  const gm::Taps t = gm::design_taps(m.profile, m.tau_s, m.period_s);
  double peak = 0.0;
  for (const auto b : t.integer)
    peak = std::max(peak, static_cast<double>(b) / static_cast<double>(t.b_s));
  CHECK(gm::fir_variation(m) == Approx(2.0 * peak).epsilon(1e-12));
  CHECK(gm::fir_variation(m) == Approx(0.1386).epsilon(1e-3));
}

namespace {

// The feedforward machine (X and Z one servo, Y another) planned for the table.
gm::Machine ff_encoder_machine() {
  gm::Machine m = gm::load_machine_file(gm::test::kRepoRoot / "programs/machines/default-ff.toml");
  m.tolerance_on = gm::ToleranceOn::Encoder;
  return m;
}

// A command along one axis: at `v_mm_s` from rest for `run` samples, then at −v_mm_s for as
// long (a reversal in one sample: the largest drive its speed can ask for), then rest.
std::vector<std::int64_t> there_and_back(const gm::Machine& m, double v_mm_s, int run, int n) {
  const double step_blu = v_mm_s * m.period_s / m.axes[0].blu_mm;
  std::vector<std::int64_t> x(static_cast<std::size_t>(n));
  double pos = 0.0;
  for (int k = 0; k < n; ++k) {
    pos += k < run ? step_blu : k < 2 * run ? -step_blu : 0.0;
    x[static_cast<std::size_t>(k)] = std::llround(pos);
  }
  return x;
}

// X's and Y's real ServoAxis, there and back at 150 mm/s, against what the FIR's output y does
// through each shaped loop (y convolved with the differences of its servo_step_response through
// its taps): the worst difference in counts, shaped (fed by ServoMatch) and not (fed by y).
std::pair<double, double> tables_against_fir(const gm::Machine& m, const gm::ServoMatchDesign& d) {
  const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
  const int n = 700;
  const std::vector<std::int64_t> x = there_and_back(m, 150.0, 250, n);
  gm::FirAccDec fir(taps, gm::AxisBlu::Zero(), gm::FirStructure::Auto, 1);
  gm::ServoMatch shaping(taps, d.taps);
  std::vector<gm::ServoAxis> shaped, plain;
  std::vector<std::vector<double>> g;  // the shaped loops' impulse responses
  for (int a = 0; a < 2; ++a) {
    const gm::AxisConfig& ax = m.axes[static_cast<std::size_t>(a)];
    shaped.emplace_back(ax, m.period_s, m.servo_substeps, 0);
    plain.emplace_back(ax, m.period_s, m.servo_substeps, 0);
    const std::vector<double> S = gm::servo_step_response(ax, m.period_s, m.servo_substeps, n);
    const std::vector<double> f = d.taps[static_cast<std::size_t>(a)].weights();
    std::vector<double> gi(S.size(), 0.0);
    double prev = 0.0;
    for (std::size_t k = 0; k < S.size(); ++k) {
      double sk = 0.0;
      for (std::size_t j = 0; j < f.size() && j <= k; ++j) sk += f[j] * S[k - j];
      gi[k] = sk - prev;
      prev = sk;
    }
    g.push_back(gi);
  }
  auto cmd = std::make_unique<gm::BluColumns>();
  auto ref = std::make_unique<gm::BluColumns>();
  std::vector<double> y;  // the FIR's output
  double worst_shaped = 0.0, worst_plain = 0.0;
  gm::AxisBlu in = gm::AxisBlu::Zero(), out = gm::AxisBlu::Zero();
  for (int k = 0; k < n; ++k) {
    in[0] = x[static_cast<std::size_t>(k)];
    fir.step(in, out);
    y.push_back(static_cast<double>(out[0]));
    cmd->v[0][0] = cmd->v[1][0] = in[0];
    shaping.apply(*cmd, *ref, 0, 1);
    for (int a = 0; a < 2; ++a) {
      double want = 0.0;  // the table before this sample's step: y up to k − 1
      for (int j = 1; j <= k; ++j)
        want += g[static_cast<std::size_t>(a)][static_cast<std::size_t>(j)] *
                y[static_cast<std::size_t>(k - j)];
      worst_shaped = std::max(worst_shaped, std::abs(shaped[a].table_blu() - want));
      worst_plain = std::max(worst_plain, std::abs(plain[a].table_blu() - want));
      shaped[a].step(ref->v[a][0]);
      plain[a].step(out[0]);
    }
  }
  return {worst_shaped, worst_plain};
}

}  // namespace

TEST_CASE("servo matching: the feedforward machine's Y follows as X does through the real servos") {
  const gm::Machine m = ff_encoder_machine();
  const gm::ServoMatchDesign d = gm::design_servo_match(m, true);
  REQUIRE(d.ref_axis == 0);  // X (Z is the same servo)
  REQUIRE(d.taps.size() == 1);
  CHECK(d.taps[0].axis == 1);
  CHECK(d.taps[0].integer.size() == 32);
  // Off unless planned for the table with the servo on, or with servo_matching off.
  gm::Machine acc = m;
  acc.tolerance_on = gm::ToleranceOn::AccDec;
  CHECK(gm::design_servo_match(acc, true).taps.empty());
  CHECK(gm::design_servo_match(m, false).taps.empty());
  gm::Machine off = m;
  off.servo_matching = false;
  CHECK(gm::design_servo_match(off, true).taps.empty());
  // The mismatch the planner charges, unmatched and matched.
  const double M0 = gm::servo_mismatch_s(m, 0), M1 = gm::servo_mismatch_s(m, 0, &d.taps);
  const double E0 = gm::servo_mismatch_peak(m, 0), E1 = gm::servo_mismatch_peak(m, 0, &d.taps);
  CAPTURE(M0, M1, E0, E1);
  CHECK(M0 == Approx(2.64e-5).epsilon(0.01));
  CHECK(M1 < M0 / 20.0);
  CHECK(E1 < E0 / 50.0);
  CHECK(gm::plan_chain(m, true).speed_error_s == Approx(M1));
  CHECK(gm::plan_chain(off, true).speed_error_s == Approx(M0));

  // The real servos (encoder rounding and all): X's ServoAxis after the FIR, Y's after the FIR
  // (unmatched) and after ServoMatch, on the same command, there and back at 150 mm/s. The
  // tables' difference is the mismatch, at most M·V, and what the encoders' rounding makes the
  // loops do (1 to 2 counts): so the servos count in 0.1 µm here, the same loops in that unit
  // (plant output and velocity gains scaled). Measured 2026-11-30: 11.6 counts unmatched (its
  // bound M·V is 39.6), 1.65 matched (bound 0.93, + the rounding).
  gm::Machine fine = m;
  for (gm::AxisConfig& a : fine.axes)
    a.blu_mm /= 10.0, a.plant_blu_s_per_unit *= 10.0, a.kvp /= 10.0, a.kvi /= 10.0;
  CHECK(gm::design_servo_match(fine, true).taps[0].integer == d.taps[0].integer);
  const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
  const int n = 800;
  const double v = 150.0;
  const std::vector<std::int64_t> x = there_and_back(fine, v, 300, n);
  gm::FirAccDec fir(taps, gm::AxisBlu::Zero(), gm::FirStructure::Auto, 1);
  gm::ServoMatch match(taps, d.taps);
  gm::ServoAxis sx(fine.axes[0], m.period_s, m.servo_substeps, 0);
  gm::ServoAxis sy(fine.axes[1], m.period_s, m.servo_substeps, 0);
  gm::ServoAxis sy_matched(fine.axes[1], m.period_s, m.servo_substeps, 0);
  auto cmd = std::make_unique<gm::BluColumns>();
  auto ref = std::make_unique<gm::BluColumns>();
  double unmatched = 0.0, matched = 0.0;
  gm::AxisBlu in = gm::AxisBlu::Zero(), out = gm::AxisBlu::Zero();
  for (int k = 0; k < n; ++k) {
    in[0] = x[static_cast<std::size_t>(k)];
    fir.step(in, out);
    cmd->v[1][0] = in[0];
    match.apply(*cmd, *ref, 0, 1);
    unmatched = std::max(unmatched, std::abs(sy.table_blu() - sx.table_blu()));
    matched = std::max(matched, std::abs(sy_matched.table_blu() - sx.table_blu()));
    sx.step(out[0]);
    sy.step(out[0]);
    sy_matched.step(ref->v[1][0]);
  }
  const double bound0 = M0 * v / fine.axes[0].blu_mm, bound1 = M1 * v / fine.axes[0].blu_mm;
  CAPTURE(unmatched, matched, bound0, bound1);
  CHECK(unmatched > 0.2 * bound0);
  CHECK(unmatched <= bound0 + 2.0);
  CHECK(matched <= bound1 + 2.0);
  CHECK(matched < unmatched / 3.0);
}

TEST_CASE("drive speed limit: below it the real servo never saturates, at twice it it does") {
  // The feedforward machine with a short Hann filter (τ 0.08 s): the rapid at 200 % from rest
  // that saturated Y's drive in the encoder sweep (docs/tolerance.md). Below the limit even a
  // reversal within one sample leaves every drive command within its limit (measured: at 0.98 of
  // the limit the drive peaks at 0.947 of its own, on X and Y); there and back at twice the
  // limit it saturates (13 samples).
  gm::Machine m = ff_encoder_machine();
  m.profile = "hann";
  m.tau_s = 0.08;
  const double limit = gm::drive_speed_limit_mm_s(m);
  CHECK(limit > 50.0);
  CHECK(limit < 200.0);
  CHECK(gm::plan_chain(m, true).drive_speed_mm_s == Approx(limit));
  const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
  for (int axis : {0, 1}) {
    for (const double v : {0.98 * limit, 2.0 * limit}) {
      const std::vector<std::int64_t> x = there_and_back(m, v, 200, 600);
      gm::FirAccDec fir(taps, gm::AxisBlu::Zero(), gm::FirStructure::Auto, 1);
      gm::ServoAxis servo(m.axes[static_cast<std::size_t>(axis)], m.period_s, m.servo_substeps, 0);
      gm::AxisBlu in = gm::AxisBlu::Zero(), out = gm::AxisBlu::Zero();
      int saturated = 0;
      double peak = 0.0;
      for (const std::int64_t xk : x) {
        in[0] = xk;
        fir.step(in, out);
        servo.step(out[0]);
        saturated += servo.saturated() ? 1 : 0;
        peak = std::max(peak, std::abs(servo.drive_command()) / servo.drive_limit());
      }
      CAPTURE(axis, v, limit, saturated, peak);
      if (v < limit)
        CHECK(saturated == 0);
      else
        CHECK(saturated > 0);
    }
  }
  // The Acc/Dec plan has no such limit.
  gm::Machine acc = m;
  acc.tolerance_on = gm::ToleranceOn::AccDec;
  CHECK(gm::plan_chain(acc, true).drive_speed_mm_s == std::numeric_limits<double>::infinity());
}

TEST_CASE("the default machine's loops shaped: each table settles three samples after the FIR") {
  // The built-in (the paper's) loops have no feedforward: their step responses overshoot by 3 %
  // and creep to 1 (the velocity loop's integral), so the chain planned for the table overshoots.
  // Each axis's loop is identified (order 4, B = z⁻¹·(b_1 + b_2·z⁻¹)) and shaped by its
  // zero-phase-error taps: the loop then follows z⁻¹·B′(z)·B̃(z)/B(1)², steps of κ, 1 − 2κ, κ
  // with κ = b_1·b_2/(b_1 + b_2)² ≤ 1/4 (steps at lags 1, 2, 3), at rest three samples after its
  // command.
  gm::Machine m = gm::default_machine();
  m.tolerance_on = gm::ToleranceOn::Encoder;
  const gm::ServoMatchDesign d = gm::design_servo_match(m, true);
  REQUIRE(d.shaped);
  REQUIRE(d.taps.size() == 3);
  const std::vector<double> Sx = gm::servo_step_response(m.axes[0], m.period_s, 1, 512);
  CHECK(*std::max_element(Sx.begin(), Sx.end()) > 1.04);
  CHECK(std::abs(Sx[50] - 1.0) > 1e-3);
  for (const gm::MatchTaps& t : d.taps) {
    CAPTURE(t.axis);
    CHECK(t.integer.size() == 6);  // deg A + deg B′ + 1
    const std::vector<double> S =
        gm::servo_step_response(m.axes[static_cast<std::size_t>(t.axis)], m.period_s, 1, 512);
    const std::vector<double> f = t.weights();
    std::vector<double> s(S.size(), 0.0);
    for (std::size_t k = 0; k < S.size(); ++k)
      for (std::size_t j = 0; j < f.size() && j <= k; ++j) s[k] += f[j] * S[k - j];
    // The taps are rounded to 2⁻²⁴ (|f| up to about 40): 10⁻⁵.
    CHECK(s[0] == Approx(0.0).margin(1e-5));
    CHECK(s[1] > 0.2);
    CHECK(s[1] <= 0.25 + 1e-5);
    CHECK(s[1] + s[2] == Approx(1.0).margin(1e-5));  // symmetric
    for (std::size_t k = 3; k < s.size(); ++k) CHECK(s[k] == Approx(1.0).margin(1e-5));
  }
  // The chain planned: no negative weight, the FIR's length and three, the servos' difference
  // (X, Z against Y) charged at 1.6·10⁻⁸ s (9.3·10⁻⁷ matched to X unshaped, 2.98·10⁻⁵ unmatched).
  const gm::PlannedChain c = gm::plan_chain(m, true);
  const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
  CHECK(std::all_of(c.weights.begin(), c.weights.end(), [](double w) { return w >= 0.0; }));
  CHECK(c.weights.size() <= taps.integer.size() + 3);
  CHECK(c.speed_error_s < 5e-8);
  CHECK(gm::FilterMoments(c.weights, m.period_s).overshoot_s() == 0.0);

  // The real servos (encoder rounding and all), there and back at 150 mm/s: the shaped table is
  // the FIR's output through the three steps, within the rounding (measured: 0.91 counts);
  // unshaped it lags by up to V/Kp (5 mm) and overshoots (4,259 counts from it).
  const auto [worst_shaped, worst_plain] = tables_against_fir(m, d);
  CAPTURE(worst_shaped, worst_plain);
  CHECK(worst_shaped <= 2.0);
  CHECK(worst_plain > 1000.0);

  // The drives through the taps: the plan's cap V_d (219 mm/s; 259.5 unshaped) keeps them below
  // saturation on a reversal within one sample; at twice it they saturate.
  const double limit = c.drive_speed_mm_s;
  CHECK(limit == Approx(gm::drive_speed_limit_mm_s(m, &d.taps)));
  CHECK(limit < gm::drive_speed_limit_mm_s(m));
  for (const double v : {0.98 * limit, 2.0 * limit}) {
    const std::vector<std::int64_t> x = there_and_back(m, v, 200, 600);
    gm::ServoMatch shaping(taps, d.taps);
    gm::ServoAxis servo(m.axes[0], m.period_s, 1, 0);
    auto cmd = std::make_unique<gm::BluColumns>();
    auto ref = std::make_unique<gm::BluColumns>();
    int saturated = 0;
    for (const std::int64_t xk : x) {
      cmd->v[0][0] = xk;
      shaping.apply(*cmd, *ref, 0, 1);
      servo.step(ref->v[0][0]);
      saturated += servo.saturated() ? 1 : 0;
    }
    CAPTURE(v, limit, saturated);
    if (v < limit)
      CHECK(saturated == 0);
    else
      CHECK(saturated > 0);
  }
}

TEST_CASE("a 20 Hz mode at damping 0.05 on every axis: the shaping cancels its ringing") {
  // The zero-phase-error taps take the mode's poles out with the loop's (an input shaper from
  // the loop's own model): the chain planned for the table is then the FIR and three steps,
  // where unshaped it rings for hundreds of samples with negative weights.
  gm::Machine m = gm::default_machine();
  m.tolerance_on = gm::ToleranceOn::Encoder;
  for (gm::AxisConfig& a : m.axes) a.mode_hz = {20.0}, a.mode_damping = {0.05};
  const gm::ServoMatchDesign d = gm::design_servo_match(m, true);
  REQUIRE(d.shaped);
  const gm::PlannedChain c = gm::plan_chain(m, true);
  gm::Machine off = m;
  off.servo_matching = false;
  const gm::PlannedChain c0 = gm::plan_chain(off, true);
  const auto negative = [](const std::vector<double>& w) {
    double s = 0.0;
    for (const double x : w) s += std::min(x, 0.0);
    return s;
  };
  CAPTURE(c.weights.size(), c0.weights.size(), negative(c0.weights));
  CHECK(negative(c.weights) == 0.0);
  CHECK(c.weights.size() <= gm::design_taps(m.profile, m.tau_s, m.period_s).integer.size() + 6);
  CHECK(c0.weights.size() > 100);
  CHECK(negative(c0.weights) < -0.01);
  // Through the real servos with the mode (the table is the mode's output), measured: 1.68
  // counts shaped, 3,112 unshaped.
  const auto [worst_shaped, worst_plain] = tables_against_fir(m, d);
  CAPTURE(worst_shaped, worst_plain);
  CHECK(worst_shaped <= 2.0);
  CHECK(worst_plain > 1000.0);
}
