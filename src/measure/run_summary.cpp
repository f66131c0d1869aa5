// Running statistics of a pipeline run and their text/JSON rendering.
#include "measure/run_summary.hpp"

#include "common/isa.hpp"
#include "interpolator/interpolator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>

namespace gm {

RunSummary::RunSummary(const Machine& machine)
    : machine_(machine),
      axes_(machine.axis_count()),
      blu_mm_(machine.blu_mm()),
      period_s_(machine.period_s) {
  for (int a = 0; a < machine.axis_count(); ++a) {
    const AxisConfig& ac = machine.axes[static_cast<std::size_t>(a)];
    AxisSummary& s = axes[static_cast<std::size_t>(a)];
    s.v_limit.limit = ac.v_max_mm_s;
    s.f_limit.limit = ac.f_max_N;
    s.p_limit.limit = ac.p_max_W;
    mass_kg_[a] = ac.mass_kg;
    damping_kg_s_[a] = ac.damping_kg_s;
    unit_per_si_[a] = units::unit_per_si(axis_is_rotary(machine.layout.program(a)));
  }
}

void RunSummary::measure_vibration(int filter_samples, double window_s) {
  vibration_.emplace(axes_, filter_samples, period_s_, window_s);
}

namespace {

__extension__ typedef double Lanes __attribute__((vector_size(32)));
__extension__ typedef std::int64_t Mask __attribute__((vector_size(32)));
__extension__ typedef std::uint64_t Bits __attribute__((vector_size(32)));

/// One axis's rows of a block as add_block() derives them: column j is row i0 + j. v[0] and a[0]
/// hold the previous sample's velocity and acceleration, so v[j + 1], a[j + 1] are row j's.
struct AxisRows {
  std::int64_t refp[kBlockSamples + 1];  ///< the previous sample's ref, then the rows'
  const std::int64_t* enc;               ///< the rows' encoder counts
  int moved;                             ///< the last row whose ref changed (−1: none)
  double dref[kBlockSamples];            ///< ref − previous ref, as a double
  double ferr[kBlockSamples];            ///< |ref − enc|
  double v[kBlockSamples + 4], a[kBlockSamples + 4];
  double vel[kBlockSamples], accel[kBlockSamples], jerk[kBlockSamples];
  double force[kBlockSamples], power[kBlockSamples];
};

/// The running maxima (peak values at the start) and limit counts of one axis.
struct AxisPeaks {
  double ferr, v, vl, a, j, f, p;
  std::int64_t n_v = 0, n_f = 0, n_p = 0;
};

struct AxisConsts {
  double blu, T, mass, damping, v_lim, f_lim, p_lim;
  double unit_per_si;  ///< mm per metre, or degrees per radian on a rotary axis
};

// Vectors pass by reference: a 32-byte vector by value changes the psABI without AVX.
__attribute__((always_inline)) inline void load(Lanes& x, const double* p) {
  std::memcpy(&x, p, sizeof x);
}
__attribute__((always_inline)) inline void store(double* p, const Lanes& x) {
  std::memcpy(p, &x, sizeof x);
}
__attribute__((always_inline)) inline void vabs(Lanes& x) {
  x = (Lanes)((Mask)x & (Mask{} + INT64_MAX));  // fabs: the sign bit cleared
}
__attribute__((always_inline)) inline void vmax(Lanes& m, const Lanes& x) {
  m = m < x ? x : m;  // std::max(m, x) per lane
}
__attribute__((always_inline)) inline double hmax(const Lanes& m, double s) {
  for (int l = 0; l < 4; ++l) s = std::max(s, m[l]);
  return s;
}

// The summary's per-sample arithmetic, element-wise over the n rows in `r`: four rows a vector, the
// rest one at a time with the same expressions (IEEE operations round the same either way).
__attribute__((always_inline)) inline void axis_rows(AxisRows& r, int n, const AxisConsts& c,
                                                     AxisPeaks& pk) {
  const int n4 = n & ~3;
  // The integers: ref differences and |ref − enc| to doubles, and the last row that moved. An
  // integer x in [−2^51, 2^51) is exactly the double with bits 0x4338000000000000 + x, less
  // 1.5·2^52 (static_cast's value); a block with any other falls back to static_cast.
  const Bits magic = Bits{} + 0x4338000000000000u, half = Bits{} + (std::uint64_t{1} << 51);
  const Lanes magic_value = Lanes{} + 0x1.8p52;
  Bits out_of_range = {};
  Mask last_moved = Mask{} - 1;
  const Mask lane = {0, 1, 2, 3};
  for (int j = 0; j < n4; j += 4) {
    Bits cur, prev, enc;
    std::memcpy(&cur, r.refp + j + 1, sizeof cur);
    std::memcpy(&prev, r.refp + j, sizeof prev);
    std::memcpy(&enc, r.enc + j, sizeof enc);
    const Bits d = cur - prev;  // unsigned: wraps, as the int64 difference's bits
    const Bits e = cur - enc;
    const Bits sign = (Bits)((Mask)e >> 63);
    const Bits e_abs = (e ^ sign) - sign;
    out_of_range |= ((d + half) >> 52) | (e_abs >> 51);
    Lanes x = (Lanes)(d + magic) - magic_value;
    store(r.dref + j, x);
    x = (Lanes)(e_abs + magic) - magic_value;
    store(r.ferr + j, x);
    const Mask moved = (Mask)(d != 0);
    last_moved = (moved & (lane + j)) | (~moved & last_moved);
  }
  bool exact = true;
  for (int l = 0; l < 4; ++l) {
    exact = exact && out_of_range[l] == 0;
    r.moved = std::max(r.moved, static_cast<int>(last_moved[l]));
  }
  for (int j = exact ? n4 : 0; j < n; ++j) {
    const std::int64_t d = r.refp[j + 1] - r.refp[j];
    r.dref[j] = static_cast<double>(d);
    r.ferr[j] = static_cast<double>(std::llabs(r.refp[j + 1] - r.enc[j]));
    if (d != 0) r.moved = std::max(r.moved, j);
  }
  const Lanes zero = {};
  const Lanes blu = zero + c.blu, T = zero + c.T, per_si = zero + c.unit_per_si;
  Lanes x, y;
  for (int j = 0; j < n4; j += 4) {
    load(x, r.dref + j);
    store(r.v + j + 1, x * blu / T);  // mm/s
  }
  for (int j = n4; j < n; ++j) r.v[j + 1] = r.dref[j] * c.blu / c.T;
  for (int j = 0; j < n4; j += 4) {
    load(x, r.v + j + 1);
    load(y, r.v + j);
    store(r.a + j + 1, (x - y) / T);
  }
  for (int j = n4; j < n; ++j) r.a[j + 1] = (r.v[j + 1] - r.v[j]) / c.T;
  Lanes m_ferr = zero + pk.ferr, m_v = zero + pk.v, m_vl = zero + pk.vl, m_a = zero + pk.a,
        m_j = zero + pk.j, m_f = zero + pk.f, m_p = zero + pk.p;
  Mask n_v = {}, n_f = {}, n_p = {};
  const Lanes mass = zero + c.mass, damping = zero + c.damping, v_lim = zero + c.v_lim,
              f_lim = zero + c.f_lim, p_lim = zero + c.p_lim;
  for (int j = 0; j < n4; j += 4) {
    Lanes v, acc, acc_prev, ferr;
    load(v, r.v + j + 1);
    load(acc, r.a + j + 1);
    load(acc_prev, r.a + j);
    load(ferr, r.ferr + j);
    Lanes jerk = (acc - acc_prev) / T;
    Lanes vel = v, accel = acc;
    vabs(vel);
    vabs(accel);
    vabs(jerk);
    const Lanes v_m_s = v / per_si, a_m_s2 = acc / per_si;  // m or rad
    Lanes force = mass * a_m_s2 + damping * v_m_s;
    vabs(force);
    Lanes power = force * v_m_s;
    vabs(power);
    store(r.vel + j, vel);
    store(r.accel + j, accel);
    store(r.jerk + j, jerk);
    store(r.force + j, force);
    store(r.power + j, power);
    vmax(m_ferr, ferr);
    vmax(m_v, vel);
    vmax(m_vl, vel);
    vmax(m_a, accel);
    vmax(m_j, jerk);
    vmax(m_f, force);
    vmax(m_p, power);
    n_v -= vel > v_lim;
    n_f -= force > f_lim;
    n_p -= power > p_lim;
  }
  for (int j = n4; j < n; ++j) {
    const double v = r.v[j + 1], acc = r.a[j + 1];
    const double jerk = (acc - r.a[j]) / c.T;
    r.vel[j] = std::abs(v);
    r.accel[j] = std::abs(acc);
    r.jerk[j] = std::abs(jerk);
    const double v_m_s = v / c.unit_per_si, a_m_s2 = acc / c.unit_per_si;
    r.force[j] = std::abs(c.mass * a_m_s2 + c.damping * v_m_s);
    r.power[j] = std::abs(r.force[j] * v_m_s);
    pk.ferr = std::max(pk.ferr, r.ferr[j]);
    pk.v = std::max(pk.v, r.vel[j]);
    pk.vl = std::max(pk.vl, r.vel[j]);
    pk.a = std::max(pk.a, r.accel[j]);
    pk.j = std::max(pk.j, r.jerk[j]);
    pk.f = std::max(pk.f, r.force[j]);
    pk.p = std::max(pk.p, r.power[j]);
    pk.n_v += r.vel[j] > c.v_lim;
    pk.n_f += r.force[j] > c.f_lim;
    pk.n_p += r.power[j] > c.p_lim;
  }
  // The maxima are of the same values whatever the grouping (a NaN never becomes one).
  pk.ferr = hmax(m_ferr, pk.ferr);
  pk.v = hmax(m_v, pk.v);
  pk.vl = hmax(m_vl, pk.vl);
  pk.a = hmax(m_a, pk.a);
  pk.j = hmax(m_j, pk.j);
  pk.f = hmax(m_f, pk.f);
  pk.p = hmax(m_p, pk.p);
  for (int l = 0; l < 4; ++l) pk.n_v += n_v[l], pk.n_f += n_f[l], pk.n_p += n_p[l];
}

__attribute__((target("avx2"))) void axis_rows_avx2(AxisRows& r, int n, const AxisConsts& c,
                                                    AxisPeaks& pk) {
  axis_rows(r, n, c, pk);
}
void axis_rows_portable(AxisRows& r, int n, const AxisConsts& c, AxisPeaks& pk) {
  axis_rows(r, n, c, pk);
}

}  // namespace

void RunSummary::add_block(const SampleBlock& b, int first) {
  const int i0 = first, i1 = b.count;
  if (i1 <= i0) return;
  const int n = i1 - i0;
  const int* line = b.line + i0;
  std::int64_t last_motion_k = last_motion_k_;
  static const bool avx2 = active_isa() != Isa::Portable;
  // Per axis: the differences and following errors row by row (integers), then add()'s
  // floating-point expressions a column at a time. The peaks keep running maxima and look for
  // the first row reaching a maximum only when it beats the peak, which is where update()
  // row by row would have stopped (it keeps the first occurrence).
  AxisRows r;  // 25 kB of stack, not initialised: each pass writes what the next reads
  for (int a = 0; a < axes_; ++a) {
    AxisSummary& ax = axes[static_cast<std::size_t>(a)];
    const std::int64_t* ref = b.ref_blu.v[a] + i0;
    const std::int64_t* enc = b.enc_blu.v[a] + i0;
    r.refp[0] = prev_ref_[a];
    std::memcpy(r.refp + 1, ref, static_cast<std::size_t>(n) * sizeof *ref);
    r.enc = enc;
    r.moved = -1;
    r.v[0] = prev_v_[a];
    r.a[0] = prev_a_[a];
    const AxisConsts c{blu_mm_[a],
                       period_s_,
                       mass_kg_[a],
                       damping_kg_s_[a],
                       ax.v_limit.limit * (1 + 1e-9),
                       ax.f_limit.limit * (1 + 1e-9),
                       ax.p_limit.limit * (1 + 1e-9),
                       unit_per_si_[a]};
    AxisPeaks pk{ax.following_err_blu.value, ax.velocity_mm_s.value, ax.v_limit.worst.value,
                 ax.accel_mm_s2.value,       ax.jerk_mm_s3.value,    ax.f_limit.worst.value,
                 ax.p_limit.worst.value};
    if (avx2)
      axis_rows_avx2(r, n, c, pk);
    else
      axis_rows_portable(r, n, c, pk);
    ax.following_err_blu.update_block(pk.ferr, r.ferr, line, 0, n);
    ax.velocity_mm_s.update_block(pk.v, r.vel, line, 0, n);
    ax.accel_mm_s2.update_block(pk.a, r.accel, line, 0, n);
    ax.jerk_mm_s3.update_block(pk.j, r.jerk, line, 0, n);
    ax.v_limit.worst.update_block(pk.vl, r.vel, line, 0, n);
    ax.f_limit.worst.update_block(pk.f, r.force, line, 0, n);
    ax.p_limit.worst.update_block(pk.p, r.power, line, 0, n);
    ax.v_limit.violations += pk.n_v;
    ax.f_limit.violations += pk.n_f;
    ax.p_limit.violations += pk.n_p;
    prev_ref_[a] = ref[n - 1];
    prev_v_[a] = r.v[n];
    prev_a_[a] = r.a[n];
    if (r.moved >= 0) last_motion_k = std::max(last_motion_k, b.k0 + i0 + r.moved);
  }
  last_motion_k_ = last_motion_k;
  // The sums run in row order, as add() adds them.
  double m_c = contour_err_blu.value;
  double* cabs = r.vel;  // free again
  double sq = contour_sq_sum_, ref_sum = arc_ref_sum_, enc_sum = arc_enc_sum_;
  std::int64_t arcs = 0, holds = 0;
  for (int i = i0; i < i1; ++i) {
    const double c = b.contour_err_blu[i];
    cabs[i - i0] = std::abs(c);
    m_c = std::max(m_c, cabs[i - i0]);
    sq += c * c;
    if (!std::isnan(b.arc_ref_dev_blu[i])) {
      ref_sum += b.arc_ref_dev_blu[i];
      enc_sum += b.arc_enc_dev_blu[i];
      ++arcs;
    }
    holds += (b.events[i] & kEventHold) != 0;
  }
  contour_err_blu.update_block(m_c, cabs, line, 0, n);
  contour_sq_sum_ = sq;
  arc_ref_sum_ = ref_sum;
  arc_enc_sum_ = enc_sum;
  arc_samples += arcs;
  hold_samples_ += holds;
  samples += n;
  if (vibration_) [[unlikely]]
    vibration_->add_block(b, first);
}

void RunSummary::finish(const SampleRecord& last, const AxisBlu& program_end_blu, bool is_settled) {
  for (int a = 0; a < machine_.axis_count(); ++a) {
    axes[static_cast<std::size_t>(a)].final_ref_err_blu = last.ref_blu[a] - program_end_blu[a];
    axes[static_cast<std::size_t>(a)].final_enc_err_blu = last.enc_blu[a] - program_end_blu[a];
  }
  settled = is_settled;
  cycle_time_s = static_cast<double>(samples) * period_s_;
  program_time_s = static_cast<double>(last_motion_k_ + 1) * period_s_;
  hold_time_s = static_cast<double>(hold_samples_) * period_s_;
  contour_rms_blu = samples > 0 ? std::sqrt(contour_sq_sum_ / static_cast<double>(samples)) : 0.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  arc_ref_radial_dev_blu = arc_samples > 0 ? arc_ref_sum_ / static_cast<double>(arc_samples) : nan;
  arc_enc_radial_dev_blu = arc_samples > 0 ? arc_enc_sum_ / static_cast<double>(arc_samples) : nan;
  if (vibration_) vibration_->finish();
}

std::string RunSummary::text() const {
  std::string t;
  auto out = std::back_inserter(t);
  fmt::format_to(out, "samples {}  cycle time {:.3f} s  (motion ends {:.3f} s){}{}\n", samples,
                 cycle_time_s, program_time_s,
                 hold_time_s > 0 ? fmt::format(", {:.3f} s in feed hold", hold_time_s) : "",
                 settled ? "" : "  NOT SETTLED");
  fmt::format_to(out, "contour error  max {:.2f} BLU (line {})  rms {:.2f} BLU\n",
                 contour_err_blu.value, contour_err_blu.line, contour_rms_blu);
  if (vibration_) {
    const VibrationMeter& v = *vibration_;
    fmt::format_to(out,
                   "tool tip (structural modes): the contour error is measured at the tool tip; "
                   "after each stop, {:.3f} s of residual vibration |tip - motor side| and "
                   "settling |tip - ref|\n",
                   v.window_s());
    t += "axis  stops  residual vib BLU (line, at s)   settling BLU (line)   path deflection "
         "BLU (line)\n";
    for (int a = 0; a < machine_.axis_count(); ++a) {
      const AxisVibration& x = v.axis(a);
      fmt::format_to(out,
                     "{:<4}  {:>5}  {:>10.2f} ({:>5}, {:>7.3f})   {:>10.2f} ({:>5})   {:>10.2f} "
                     "({:>5})\n",
                     machine_.layout.letter(a), x.stops, x.residual_blu, x.residual_line,
                     x.residual_t_s, x.settle_blu, x.settle_line, x.deflection_blu,
                     x.deflection_line);
    }
  }
  if (arc_samples > 0)
    fmt::format_to(
        out, "arcs, steady radial deviation  Acc/Dec output {:+.2f} BLU  encoder {:+.2f} BLU\n",
        arc_ref_radial_dev_blu, arc_enc_radial_dev_blu);
  // Linear axes in mm, then rotary axes in degrees, each under its own header.
  for (const bool rotary : {false, true}) {
    bool header = false;
    for (int a = 0; a < machine_.axis_count(); ++a) {
      if (axis_is_rotary(machine_.layout.program(a)) != rotary) continue;
      if (!header)
        t += rotary ? "rotary  ferr max BLU (line)  v max deg/s (line)  a max deg/s2 (line)  j max "
                      "deg/s3 (line)  final ref/enc err BLU\n"
                    : "axis  ferr max BLU (line)   v max mm/s (line)   a max mm/s2 (line)   j max "
                      "mm/s3 (line)   final ref/enc err BLU\n";
      header = true;
      const AxisSummary& s = axes[static_cast<std::size_t>(a)];
      fmt::format_to(
          out,
          fmt::runtime(rotary ? "{:<6}  {:>8.0f} ({:>5})  {:>10.3f} ({:>5})  {:>11.1f} ({:>5})  "
                                "{:>11.0f} ({:>5})  {:+d} / {:+d}\n"
                              : "{:<4}  {:>8.0f} ({:>5})   {:>9.3f} ({:>5})   {:>10.1f} ({:>5})   "
                                "{:>10.0f} ({:>5})   {:+d} / {:+d}\n"),
          machine_.layout.letter(a), s.following_err_blu.value, s.following_err_blu.line,
          s.velocity_mm_s.value, s.velocity_mm_s.line, s.accel_mm_s2.value, s.accel_mm_s2.line,
          s.jerk_mm_s3.value, s.jerk_mm_s3.line, s.final_ref_err_blu, s.final_enc_err_blu);
    }
  }
  bool any = false;
  for (int a = 0; a < machine_.axis_count(); ++a) {
    const AxisSummary& s = axes[static_cast<std::size_t>(a)];
    const bool rotary = axis_is_rotary(machine_.layout.program(a));
    const std::pair<const char*, const LimitCheck*> checks[] = {
        {rotary ? "velocity deg/s" : "velocity mm/s", &s.v_limit},
        {rotary ? "torque Nm" : "force N", &s.f_limit},
        {"power W", &s.p_limit}};
    for (const auto& [name, c] : checks) {
      if (c->violations == 0) continue;
      any = true;
      fmt::format_to(out, "LIMIT {} {}: {} samples over {:.6g}, worst {:.6g} at line {}\n",
                     machine_.layout.letter(a), name, c->violations, c->limit, c->worst.value,
                     c->worst.line);
    }
  }
  if (!any) t += "limits: velocity, force and power within the machine's limits on every axis\n";
  return t;
}

namespace {
std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  return fmt::format("{:.9g}", v);
}
std::string peak(const Peak& p) {
  return fmt::format("{{\"value\":{},\"line\":{}}}", num(p.value), p.line);
}
std::string limit(const LimitCheck& c) {
  return fmt::format("{{\"limit\":{},\"violations\":{},\"worst\":{}}}", num(c.limit), c.violations,
                     peak(c.worst));
}
}  // namespace

std::string RunSummary::json(const std::string& extra_member) const {
  std::string j;
  auto out = std::back_inserter(j);
  fmt::format_to(out,
                 "{{\"samples\":{},\"cycle_time_s\":{},\"program_time_s\":{},\"hold_time_s\":{},"
                 "\"settled\":{},"
                 "\"contour_err_max_blu\":{},\"contour_err_rms_blu\":{},"
                 "\"arc_ref_radial_dev_blu\":{},\"arc_enc_radial_dev_blu\":{},\"axes\":{{",
                 samples, num(cycle_time_s), num(program_time_s), num(hold_time_s),
                 settled ? "true" : "false", peak(contour_err_blu), num(contour_rms_blu),
                 num(arc_ref_radial_dev_blu), num(arc_enc_radial_dev_blu));
  for (int a = 0; a < machine_.axis_count(); ++a) {
    const AxisSummary& s = axes[static_cast<std::size_t>(a)];
    // A rotary axis's members say degrees and torque.
    const bool rotary = axis_is_rotary(machine_.layout.program(a));
    const char* unit = rotary ? "deg" : "mm";
    fmt::format_to(
        out,
        "{}\"{}\":{{\"following_err_max_blu\":{},\"velocity_max_{}_s\":{},\"accel_max_{}_s2\":{},"
        "\"jerk_max_{}_s3\":{},\"limits\":{{\"velocity\":{},\"{}\":{},\"power\":{}}},"
        "\"final_ref_err_blu\":{},\"final_enc_err_blu\":{}}}",
        a == 0 ? "" : ",", static_cast<char>(machine_.layout.letter(a) - 'A' + 'a'),
        peak(s.following_err_blu), unit, peak(s.velocity_mm_s), unit, peak(s.accel_mm_s2), unit,
        peak(s.jerk_mm_s3), limit(s.v_limit), rotary ? "torque" : "force", limit(s.f_limit),
        limit(s.p_limit), s.final_ref_err_blu, s.final_enc_err_blu);
  }
  j += "}";
  if (vibration_) {
    const VibrationMeter& v = *vibration_;
    fmt::format_to(out,
                   ",\"vibration\":{{\"contour_measured_at\":\"tool tip\",\"window_s\":{},"
                   "\"axes\":{{",
                   num(v.window_s()));
    for (int a = 0; a < machine_.axis_count(); ++a) {
      const AxisVibration& x = v.axis(a);
      fmt::format_to(out,
                     "{}\"{}\":{{\"stops\":{},\"residual_max_blu\":{{\"value\":{},\"line\":{}}},"
                     "\"residual_t_s\":{},\"settle_max_blu\":{{\"value\":{},\"line\":{}}},"
                     "\"deflection_max_blu\":{{\"value\":{},\"line\":{}}}}}",
                     a == 0 ? "" : ",", static_cast<char>(machine_.layout.letter(a) - 'A' + 'a'),
                     x.stops, num(x.residual_blu), x.residual_line, num(x.residual_t_s),
                     num(x.settle_blu), x.settle_line, num(x.deflection_blu), x.deflection_line);
    }
    j += "}}";
  }
  if (!extra_member.empty()) j += "," + extra_member;
  j += "}\n";
  return j;
}

}  // namespace gm
