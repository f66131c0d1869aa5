// The servo's linear step response (ServoAxis without rounding, saturation, friction, lost
// motion) and its convolution with the FIR: the chain the encoder tolerance is planned for.
#include "planner/servo_response.hpp"

#include "common/status.hpp"
#include "servo/discrete_plant.hpp"
#include "servo/flexible_modes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {

std::vector<double> servo_step_response(const AxisConfig& axis, double period_s, int substeps,
                                        int samples) {
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
      plant.step(u);
      if (modes.count() > 0) modes.step(plant.position_blu());
    }
    prev_ref = ref;
    prev_delta = delta;
  }
  return s;
}

ChainResponse chain_response(const Taps& taps, const AxisConfig& axis, double period_s,
                             int substeps, double tail_area_s, double clip_area_s) {
  if (taps.integer.empty() || taps.b_s <= 0) throw InputError("chain response: no taps");
  // Long enough for any stable loop we accept: grow until the tail is below the limit.
  for (int len = 256;; len *= 2) {
    const std::vector<double> servo = servo_step_response(axis, period_s, substeps, len);
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

// Each servo's step response against ref's, |S^a_k − S^ref_k| reduced over k by `reduce`
// (settled servos only) and times `scale`, combined over the axes as a Euclidean norm.
template <class Reduce>
double servo_mismatch(const std::vector<const AxisConfig*>& axes, const AxisConfig& ref,
                      double period_s, int substeps, double scale, Reduce reduce) {
  constexpr int kLen = 1 << 14;
  const std::vector<double> sr = servo_step_response(ref, period_s, substeps, kLen);
  double sum2 = 0.0;
  for (const AxisConfig* a : axes) {
    if (same_servo(*a, ref)) continue;
    const std::vector<double> sa = servo_step_response(*a, period_s, substeps, kLen);
    double r = 0.0;
    for (int k = 0; k < kLen; ++k) r = reduce(r, std::abs(sa[k] - sr[k]));
    // Both must have settled: the part not computed would be missing from the area.
    if (!(std::abs(sa.back() - 1.0) < 1e-9 && std::abs(sr.back() - 1.0) < 1e-9))
      throw InputError("tolerance_on = encoder: a servo loop does not settle");
    sum2 += (scale * r) * (scale * r);
  }
  return std::sqrt(sum2);
}

}  // namespace

double servo_mismatch_s(const std::vector<const AxisConfig*>& axes, const AxisConfig& ref,
                        double period_s, int substeps) {
  return servo_mismatch(axes, ref, period_s, substeps, period_s,
                        [](double sum, double d) { return sum + d; });
}

double servo_mismatch_peak(const std::vector<const AxisConfig*>& axes, const AxisConfig& ref,
                           double period_s, int substeps) {
  return servo_mismatch(axes, ref, period_s, substeps, 1.0,
                        [](double peak, double d) { return std::max(peak, d); });
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

std::vector<double> planned_chain(const Machine& m, bool servo, double& extra_margin_mm,
                                  double* speed_error_s, double* step_error) {
  const Taps taps = design_taps(m.profile, m.tau_s, m.period_s);
  extra_margin_mm = 0.0;
  if (speed_error_s != nullptr) *speed_error_s = 0.0;
  if (step_error != nullptr) *step_error = 0.0;
  if (!servo || m.tolerance_on != ToleranceOn::Encoder) {
    std::vector<double> h;
    for (auto b : taps.integer) h.push_back(static_cast<double>(b) / static_cast<double>(taps.b_s));
    return h;
  }
  std::vector<const AxisConfig*> linear;
  for (int i = 0; i < m.layout.count; ++i)
    if (m.layout.program(i) < 3) linear.push_back(&m.axes[static_cast<std::size_t>(i)]);
  if (linear.empty()) throw InputError("tolerance_on = encoder: the machine has no X, Y or Z");
  // The reference chain: the linear axis whose servo is closest to the others (smallest
  // mismatch); one servo for all gives 0 and the chain is exact.
  const AxisConfig* ref = linear.front();
  double mismatch = 0.0;
  const bool all_same = std::all_of(linear.begin(), linear.end(),
                                    [&](const AxisConfig* a) { return same_servo(*a, *ref); });
  if (!all_same) {
    if (speed_error_s == nullptr)
      throw InputError(
          "tolerance_on = encoder needs the same servo (plant, gains) on X, Y and Z here");
    mismatch = std::numeric_limits<double>::infinity();
    for (const AxisConfig* cand : linear) {
      const double mm = servo_mismatch_s(linear, *cand, m.period_s, m.servo_substeps);
      if (mm < mismatch) mismatch = mm, ref = cand;
    }
    *speed_error_s = mismatch;
    if (step_error != nullptr)
      *step_error = servo_mismatch_peak(linear, *ref, m.period_s, m.servo_substeps);
  }
  // Truncation allowance: 0.05 BLU at 2 m/s (scales with speed; docs/tolerance.md); a step
  // response outside [0, 1] by at most half a BLU at 2 m/s is clipped into it.
  constexpr double kFastMmS = 2000.0;
  const double blu = m.contour_blu_mm();
  const ChainResponse r = chain_response(taps, *ref, m.period_s, m.servo_substeps,
                                         0.05 * blu / kFastMmS, 0.5 * blu / kFastMmS);
  extra_margin_mm = kFastMmS * (r.tail_area_s + r.clipped_s);
  return r.weights;
}

}  // namespace gm
