// The servo's linear step response (ServoAxis without rounding, saturation, friction, lost
// motion) and its convolution with the FIR: the chain the encoder tolerance is planned for.
#include "planner/servo_response.hpp"

#include "common/status.hpp"
#include "planner/loop_shaping.hpp"
#include "servo/discrete_plant.hpp"
#include "servo/flexible_modes.hpp"
#include "servo/servo_axis.hpp"

#include <fmt/format.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {

namespace {

// The linear servo's response to a unit step of the reference at k = 0: the table at each
// period's start, and (when `drive` is given) the drive command of every servo sample.
std::vector<double> step_response(const AxisConfig& axis, double period_s, int substeps,
                                  int samples, std::vector<double>* drive) {
  if (!(period_s > 0.0) || substeps < 1 || samples < 1)
    throw InputError("servo response: period > 0, substeps >= 1, samples >= 1");
  const double h = period_s / substeps;
  DiscretePlant plant(axis.plant_num, axis.plant_den, axis.plant_blu_s_per_unit, h);
  const double kv = axis.kv_period_s;
  // Feedforward gains on the reference's differences, as ServoAxis computes them.
  const double ff1 = axis.ff1 * kv / period_s, ff2 = axis.ff2_s * kv / (period_s * period_s);
  double integ = 0.0, prev_pos = 0.0, prev_ref = 0.0, prev_delta = 0.0;
  FlexibleModes modes(axis.mode_hz, axis.mode_damping, h, 0.0);
  std::vector<double> s;
  s.reserve(static_cast<std::size_t>(samples));
  if (drive != nullptr) drive->assign(static_cast<std::size_t>(samples) * substeps, 0.0);
  for (int k = 0; k < samples; ++k) {
    s.push_back(modes.count() > 0 ? modes.output() : plant.position_blu());  // the table, at the
                                                                             // period's start
    const double ref = 1.0, delta = ref - prev_ref;
    const double ff = ff1 * delta + ff2 * (delta - prev_delta);
    for (int j = 0; j < substeps; ++j) {
      const double r = ref + delta * j / substeps;
      const double pos = plant.position_blu();
      const double y = (pos - prev_pos) * kv / h;
      prev_pos = pos;
      const double e = axis.kp_1_s * (r - pos) * kv + ff - y;
      integ += e * h / kv;
      const double u = axis.kv_form == VelocityLoopForm::Ip ? axis.kvi * integ - axis.kvp * y
                                                            : axis.kvp * e + axis.kvi * integ;
      if (drive != nullptr) (*drive)[static_cast<std::size_t>(k) * substeps + j] = u;
      plant.step(u);
      if (modes.count() > 0) modes.step(plant.position_blu());
    }
    prev_ref = ref;
    prev_delta = delta;
  }
  return s;
}

}  // namespace

std::vector<double> servo_step_response(const AxisConfig& axis, double period_s, int substeps,
                                        int samples) {
  return step_response(axis, period_s, substeps, samples, nullptr);
}

std::vector<double> servo_drive_step_response(const AxisConfig& axis, double period_s, int substeps,
                                              int samples) {
  std::vector<double> u;
  step_response(axis, period_s, substeps, samples, &u);
  return u;
}

namespace {

// A step response through matching taps (none: as it is).
std::vector<double> through_match(std::vector<double> s, const MatchTaps* match) {
  if (match == nullptr) return s;
  const std::vector<double> f = match->weights();
  std::vector<double> out(s.size(), 0.0);
  for (std::size_t k = 0; k < s.size(); ++k)
    for (std::size_t j = 0; j < f.size() && j <= k; ++j) out[k] += f[j] * s[k - j];
  return out;
}

}  // namespace

ChainResponse chain_response(const Taps& taps, const AxisConfig& axis, double period_s,
                             int substeps, double tail_area_s, double clip_area_s,
                             const MatchTaps* shaping) {
  if (taps.integer.empty() || taps.b_s <= 0) throw InputError("chain response: no taps");
  // Long enough for any stable loop we accept: grow until the tail is below the limit.
  for (int len = 256;; len *= 2) {
    const std::vector<double> servo =
        through_match(servo_step_response(axis, period_s, substeps, len), shaping);
    std::vector<double> g(servo.size());
    for (std::size_t k = 0; k < servo.size(); ++k) g[k] = servo[k] - (k ? servo[k - 1] : 0.0);
    const std::size_t n = taps.integer.size();
    std::vector<double> c(servo.size() + n - 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double hi = static_cast<double>(taps.integer[i]) / static_cast<double>(taps.b_s);
      for (std::size_t k = 0; k < g.size(); ++k) c[i + k] += hi * g[k];
    }
    // Step response of the chain over the part fully computed (the servo's own length).
    const std::size_t valid = servo.size();
    std::vector<double> step(valid);
    double acc = 0.0;
    for (std::size_t k = 0; k < valid; ++k) step[k] = acc += c[k];
    // Tail areas from the end: tail[k] = T·Σ_{j≥k} |1 − S_j| (over the computed part).
    std::vector<double> tail(valid + 1, 0.0);
    for (std::size_t k = valid; k-- > 0;)
      tail[k] = tail[k + 1] + period_s * std::abs(1.0 - step[k]);
    if (!std::isfinite(tail[0]) || len > (1 << 20))
      throw InputError("tolerance_on = encoder: the servo loop does not settle");
    // The computed part must already be settled far below the limit, else compute longer.
    if (tail[valid / 2] > 1e-3 * tail_area_s) continue;
    // Keeping c_0..c_{K−2} and 1 − S_{K−2} as the last weight moves the output by
    // Σ_{k≥K} Δx_k (1 − S_{k−1}): at most V·tail[K − 1].
    std::size_t K = 1;
    while (K < valid && tail[K - 1] > tail_area_s) ++K;
    ChainResponse r;
    r.weights.assign(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(K));
    r.weights.back() = 1.0 - (K >= 2 ? step[K - 2] : 0.0);  // Σ = 1
    r.tail_area_s = tail[K - 1];
    for (std::size_t k = 0; k + 1 < K; ++k) {
      r.overshoot_s += period_s * std::max(step[k] - 1.0, 0.0);
      r.undershoot_s += period_s * std::max(-step[k], 0.0);
    }
    if (r.overshoot_s + r.undershoot_s > 0.0 && r.overshoot_s + r.undershoot_s <= clip_area_s) {
      // S_k into [0, 1]: the weights become the clipped step response's differences (Σ = 1
      // still, the last weight 1 − S'_{K−2}); the output moves by at most V·clipped_s.
      r.clipped_s = r.overshoot_s + r.undershoot_s;
      double prev = 0.0;
      for (std::size_t k = 0; k + 1 < K; ++k) {
        const double s = std::clamp(step[k], 0.0, 1.0);
        r.weights[k] = s - prev;
        prev = s;
      }
      r.weights.back() = 1.0 - prev;
    }
    // Weights that are exactly 0 at the end (a clipped step response at 1 from there on) hold
    // nothing: the window ends at the last one that does. Those at the start (the servo's pure
    // delay) only delay the output, whose path stays the same: the window starts at the first.
    while (r.weights.size() > 1 && r.weights.back() == 0.0) r.weights.pop_back();
    const auto first =
        std::find_if(r.weights.begin(), r.weights.end() - 1, [](double w) { return w != 0.0; });
    r.weights.erase(r.weights.begin(), first);
    return r;
  }
}

namespace {

bool same_servo(const AxisConfig& a, const AxisConfig& b) {
  return a.plant_num == b.plant_num && a.plant_den == b.plant_den && a.kvp == b.kvp &&
         a.kvi == b.kvi && a.kp_1_s == b.kp_1_s && a.kv_period_s == b.kv_period_s &&
         a.kv_form == b.kv_form && a.ff1 == b.ff1 && a.ff2_s == b.ff2_s && a.mode_hz == b.mode_hz &&
         a.mode_damping == b.mode_damping &&
         a.plant_blu_s_per_unit * a.blu_mm == b.plant_blu_s_per_unit * b.blu_mm;
}

}  // namespace

namespace {

constexpr int kResponseLen = 1 << 14;  ///< samples of a step response (long enough to settle)

// Axis a's step response as its servo sees it: through its matching taps when it has them.
std::vector<double> matched_step_response(const AxisConfig& a, const MatchTaps* match,
                                          double period_s, int substeps) {
  return through_match(servo_step_response(a, period_s, substeps, kResponseLen), match);
}

// Σ_k |a_k − b_k|: the area between two step responses, in samples.
double area_between(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += std::abs(a[k] - b[k]);
  return sum;
}

bool settled(const std::vector<double>& s) {
  return std::abs(s.back() - 1.0) < 1e-9;
}

const MatchTaps* match_of(const std::vector<MatchTaps>* match, int axis) {
  if (match == nullptr) return nullptr;
  for (const MatchTaps& t : *match)
    if (t.axis == axis) return &t;
  return nullptr;
}

// Each linear servo's step response (matched where `match` says) against ref's,
// |S^a_k − S^ref_k| reduced over k by `reduce` (settled servos only) and times `scale`,
// combined over the axes as a Euclidean norm.
template <class Reduce>
double servo_mismatch(const Machine& m, int ref, const std::vector<MatchTaps>* match, double scale,
                      Reduce reduce) {
  const AxisConfig& rc = m.axes[static_cast<std::size_t>(ref)];
  const std::vector<double> sr =
      matched_step_response(rc, match_of(match, ref), m.period_s, m.servo_substeps);
  double sum2 = 0.0;
  for (int i = 0; i < m.layout.count; ++i) {
    const AxisConfig& a = m.axes[static_cast<std::size_t>(i)];
    if (m.layout.program(i) >= 3 || same_servo(a, rc)) continue;
    const std::vector<double> sa =
        matched_step_response(a, match_of(match, i), m.period_s, m.servo_substeps);
    double r = 0.0;
    for (int k = 0; k < kResponseLen; ++k) r = reduce(r, std::abs(sa[k] - sr[k]));
    // Both must have settled: the part not computed would be missing from the area.
    if (!(settled(sa) && settled(sr)))
      throw InputError("tolerance_on = encoder: a servo loop does not settle");
    sum2 += (scale * r) * (scale * r);
  }
  return std::sqrt(sum2);
}

double sum_of(double sum, double d) {
  return sum + d;
}
double max_of(double peak, double d) {
  return std::max(peak, d);
}

// The linear axes' indices.
std::vector<int> linear_axes(const Machine& m) {
  std::vector<int> linear;
  for (int i = 0; i < m.layout.count; ++i)
    if (m.layout.program(i) < 3) linear.push_back(i);
  return linear;
}

// Weights w (Σ = 1) as MatchTaps of `axis`: w_1.. rounded to 1/kScale, F_0 the rest (Σ exact).
// Empty where a weight is not finite or too large for the filter's integer sums (|w| ≥ 2^10).
MatchTaps to_match_taps(const std::vector<double>& w, int axis) {
  MatchTaps t;
  for (const double x : w)
    if (!(std::abs(x) < 1024.0)) return t;
  t.axis = axis;
  t.integer.assign(w.size(), 0);
  std::int64_t rest = MatchTaps::kScale;
  for (std::size_t j = 1; j < w.size(); ++j) {
    t.integer[j] = std::llround(w[j] * static_cast<double>(MatchTaps::kScale));
    rest -= t.integer[j];
  }
  t.integer[0] = rest;
  return t;
}

// Least-squares matching taps of `a` against `ref` (Σ = 1): minimise Σ_k (S^a ∗ f − S^ref)_k²
// over the first kFitSamples, with f_0 = 1 − Σ_{j≥1} f_j, then rounded to MatchTaps.
MatchTaps fit_match(const std::vector<double>& sa, const std::vector<double>& sr, int axis) {
  constexpr int kTaps = 32, kFitSamples = 1024;
  Eigen::MatrixXd A(kFitSamples, kTaps - 1);
  Eigen::VectorXd b(kFitSamples);
  for (int k = 0; k < kFitSamples; ++k) {
    b[k] = sr[static_cast<std::size_t>(k)] - sa[static_cast<std::size_t>(k)];
    for (int j = 1; j < kTaps; ++j)
      A(k, j - 1) =
          (k >= j ? sa[static_cast<std::size_t>(k - j)] : 0.0) - sa[static_cast<std::size_t>(k)];
  }
  const Eigen::VectorXd f = A.colPivHouseholderQr().solve(b);
  MatchTaps t;
  // A fit that is not finite or not small (a loop far from the reference's): no matching.
  if (!(f.allFinite() && f.cwiseAbs().maxCoeff() < 16.0)) return t;
  std::vector<double> w(kTaps);
  for (int j = 1; j < kTaps; ++j) w[static_cast<std::size_t>(j)] = f[j - 1];
  return to_match_taps(w, axis);
}

// The linear axes' step responses (S[n] for linear[n]), each computed once.
std::vector<std::vector<double>> linear_responses(const Machine& m,
                                                  const std::vector<int>& linear) {
  std::vector<std::vector<double>> S;
  for (const int i : linear)
    S.push_back(servo_step_response(m.axes[static_cast<std::size_t>(i)], m.period_s,
                                    m.servo_substeps, kResponseLen));
  return S;
}

// The linear axis (index into `linear`) whose servo is closest to the others': the least
// Euclidean norm of the areas between its step response and theirs.
std::size_t reference_of(const Machine& m, const std::vector<int>& linear,
                         const std::vector<std::vector<double>>& S) {
  std::size_t ref = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < linear.size(); ++c) {
    const AxisConfig& cand = m.axes[static_cast<std::size_t>(linear[c])];
    double sum2 = 0.0;
    for (std::size_t n = 0; n < linear.size(); ++n)
      if (!same_servo(m.axes[static_cast<std::size_t>(linear[n])], cand))
        sum2 += std::pow(area_between(S[n], S[c]), 2);
    if (sum2 < best) best = sum2, ref = c;
  }
  return ref;
}

}  // namespace

int reference_servo_axis(const Machine& m) {
  const std::vector<int> linear = linear_axes(m);
  if (linear.empty()) return -1;
  const std::vector<std::vector<double>> S = linear_responses(m, linear);
  if (!std::all_of(S.begin(), S.end(), settled))
    throw InputError("tolerance_on = encoder: a servo loop does not settle");
  return linear[reference_of(m, linear, S)];
}

double servo_mismatch_s(const Machine& m, int ref, const std::vector<MatchTaps>* match) {
  return servo_mismatch(m, ref, match, m.period_s, sum_of);
}

double servo_mismatch_peak(const Machine& m, int ref, const std::vector<MatchTaps>* match) {
  return servo_mismatch(m, ref, match, 1.0, max_of);
}

namespace {

// The chain the plan is made for: the Acc/Dec taps and axis ref's servo (through its shaping
// taps where it has them), its tail cut where 0.05 BLU at 2 m/s is left (the truncation
// allowance; it scales with speed, docs/tolerance.md) and a step response outside [0, 1] by at
// most half a BLU at 2 m/s clipped into it.
constexpr double kFastMmS = 2000.0;
ChainResponse reference_chain(const Machine& m, const Taps& taps, int ref,
                              const MatchTaps* shaping) {
  const double blu = m.contour_blu_mm();
  return chain_response(taps, m.axes[static_cast<std::size_t>(ref)], m.period_s, m.servo_substeps,
                        0.05 * blu / kFastMmS, 0.5 * blu / kFastMmS, shaping);
}

bool overshoots(const ChainResponse& r) {
  return r.overshoot_s + r.undershoot_s > r.clipped_s;
}

// Every linear axis's zero-phase-error tracking taps (zpetc_weights of its identified loop);
// empty where one cannot be designed.
std::vector<MatchTaps> shaping_taps(const std::vector<int>& linear,
                                    const std::vector<std::vector<double>>& S) {
  std::vector<MatchTaps> taps;
  for (std::size_t n = 0; n < linear.size(); ++n) {
    const LoopModel loop = identify_loop(S[n]);
    if (loop.a.empty()) return {};
    MatchTaps t = to_match_taps(zpetc_weights(loop), linear[n]);
    if (t.integer.empty()) return {};
    taps.push_back(std::move(t));
  }
  return taps;
}

}  // namespace

ServoMatchDesign design_servo_match(const Machine& m, bool servo) {
  ServoMatchDesign d;
  if (!servo || !m.servo_matching || m.tolerance_on != ToleranceOn::Encoder) return d;
  const std::vector<int> linear = linear_axes(m);
  if (linear.empty()) return d;
  // Loops that do not settle within the responses computed: no matching (a plan for the table
  // refuses them: servo_mismatch).
  const std::vector<std::vector<double>> S = linear_responses(m, linear);
  if (!std::all_of(S.begin(), S.end(), settled)) return d;
  const std::size_t ref = reference_of(m, linear, S);
  const int ref_axis = linear[ref];
  // A reference chain that overshoots (a loop without feedforward): every axis shaped by its
  // zero-phase-error taps, kept where the shaped chain does not overshoot.
  const Taps taps = design_taps(m.profile, m.tau_s, m.period_s);
  if (overshoots(reference_chain(m, taps, ref_axis, nullptr))) {
    std::vector<MatchTaps> shaped = shaping_taps(linear, S);
    if (!shaped.empty() && !overshoots(reference_chain(m, taps, ref_axis, &shaped[ref]))) {
      d.ref_axis = ref_axis;
      d.taps = std::move(shaped);
      d.shaped = true;
      return d;
    }
  }
  const AxisConfig& rc = m.axes[static_cast<std::size_t>(ref_axis)];
  for (std::size_t n = 0; n < linear.size(); ++n) {
    if (same_servo(m.axes[static_cast<std::size_t>(linear[n])], rc)) continue;
    MatchTaps t = fit_match(S[n], S[ref], linear[n]);
    if (t.integer.empty()) continue;
    // Kept only where it lowers the axis's mismatch (area of the step-response difference).
    if (!(area_between(through_match(S[n], &t), S[ref]) < area_between(S[n], S[ref]))) continue;
    d.taps.push_back(std::move(t));
  }
  if (!d.taps.empty()) d.ref_axis = ref_axis;
  return d;
}

double drive_speed_limit_mm_s(const Machine& m, const std::vector<MatchTaps>* match) {
  const Taps taps = design_taps(m.profile, m.tau_s, m.period_s);
  std::vector<double> h;
  for (const auto b : taps.integer)
    h.push_back(static_cast<double>(b) / static_cast<double>(taps.b_s));
  const int sub = m.servo_substeps;
  double limit = std::numeric_limits<double>::infinity();
  for (const int i : linear_axes(m)) {
    const AxisConfig& a = m.axes[static_cast<std::size_t>(i)];
    // The weights from command increments to the axis's reference: h, or h ∗ f when matched.
    std::vector<double> w = h;
    if (const MatchTaps* t = match_of(match, i)) {
      const std::vector<double> f = t->weights();
      w.assign(h.size() + f.size() - 1, 0.0);
      for (std::size_t p = 0; p < h.size(); ++p)
        for (std::size_t q = 0; q < f.size(); ++q) w[p + q] += h[p] * f[q];
    }
    const std::vector<double> U = servo_drive_step_response(a, m.period_s, sub, kResponseLen);
    // u at servo sample j of period n is Σ_k W^(j)_k·Δx_{n−k}, W^(j) = U^(j) ∗ w (U^(j)_k the
    // drive at sample j of period k after a unit step, which settles at 0): |u| is at most
    // Σ_k |W^(j)_k| times the largest |Δx|, V·T in counts. Weights too long to convolve here
    // (long filters): Σ|w|·Σ_k|U^(j)_k|, which bounds it.
    const bool direct = w.size() * static_cast<std::size_t>(sub) <= 4096;
    double w1 = 0.0;
    for (const double wp : w) w1 += std::abs(wp);
    double worst = 0.0;
    for (int j = 0; j < sub; ++j) {
      double sum = 0.0;
      if (!direct) {
        for (int k = 0; k < kResponseLen; ++k)
          sum += std::abs(U[static_cast<std::size_t>(k) * sub + j]);
        worst = std::max(worst, w1 * sum);
        continue;
      }
      for (int k = 0; k < kResponseLen + static_cast<int>(w.size()) - 1; ++k) {
        double wk = 0.0;
        for (std::size_t p = 0; p < w.size(); ++p) {
          const int kk = k - static_cast<int>(p);
          if (kk >= 0 && kk < kResponseLen) wk += w[p] * U[static_cast<std::size_t>(kk) * sub + j];
        }
        sum += std::abs(wk);
      }
      worst = std::max(worst, sum);
    }
    const ServoAxis servo(a, m.period_s, sub, 0);
    const double u_max = servo.drive_limit();
    const double u_friction = a.f_max_N > 0.0 ? a.coulomb_N / a.f_max_N * u_max : 0.0;
    // No bound where nothing saturates, the drive cannot overcome its friction or the loop does
    // not settle (the plan refuses such loops where it needs them: servo_mismatch, chain_response).
    if (!(worst > 0.0) || !std::isfinite(worst) || !(u_max > u_friction)) continue;
    limit = std::min(limit, (u_max - u_friction) / (worst * m.period_s) * a.blu_mm);
  }
  return limit;
}

double fir_variation(const Machine& m) {
  const Taps taps = design_taps(m.profile, m.tau_s, m.period_s);
  double v = 0.0, last = 0.0;
  for (const auto b : taps.integer) {
    const double h = static_cast<double>(b) / static_cast<double>(taps.b_s);
    v += std::abs(h - last);
    last = h;
  }
  return v + last;
}

PlannedChain plan_chain(const Machine& m, bool servo) {
  const Taps taps = design_taps(m.profile, m.tau_s, m.period_s);
  PlannedChain c;
  if (!servo || m.tolerance_on != ToleranceOn::Encoder) {
    for (auto b : taps.integer)
      c.weights.push_back(static_cast<double>(b) / static_cast<double>(taps.b_s));
    return c;
  }
  const std::vector<int> linear = linear_axes(m);
  if (linear.empty()) throw InputError("tolerance_on = encoder: the machine has no X, Y or Z");
  // The reference chain: the linear axis whose servo is closest to the others (smallest
  // mismatch); one servo for all gives 0 and the chain is exact. The others are matched to it
  // (servo_matching) and what is left of their difference is charged.
  const ServoMatchDesign match = design_servo_match(m, servo);
  const int ref = match.ref_axis >= 0 ? match.ref_axis : reference_servo_axis(m);
  c.speed_error_s = servo_mismatch_s(m, ref, &match.taps);
  c.step_error = servo_mismatch_peak(m, ref, &match.taps);
  c.drive_speed_mm_s = drive_speed_limit_mm_s(m, &match.taps);
  const ChainResponse r = reference_chain(m, taps, ref, match_of(&match.taps, ref));
  c.extra_margin_mm = kFastMmS * (r.tail_area_s + r.clipped_s);
  c.weights = r.weights;
  return c;
}

}  // namespace gm
