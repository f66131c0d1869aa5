// Running statistics of a pipeline run and their text/JSON rendering.
#include "trace/run_summary.hpp"

#include "interpolator/interpolator.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
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
  }
}

void RunSummary::add(const SampleRecord& s) {
  const double T = period_s_;
  // The count and the plant constants are copied into this object: the loop stores into it,
  // so reading them through machine_ would reload them every axis.
  const int n = axes_;
  for (int a = 0; a < n; ++a) {
    AxisSummary& ax = axes[static_cast<std::size_t>(a)];
    const double v = static_cast<double>(s.ref_blu[a] - prev_ref_[a]) * blu_mm_[a] / T;  // mm/s
    const double acc = (v - prev_v_[a]) / T;
    const double jerk = (acc - prev_a_[a]) / T;
    ax.following_err_blu.update(static_cast<double>(std::llabs(s.ferr_blu[a])), s.line);
    ax.velocity_mm_s.update(std::abs(v), s.line);
    ax.accel_mm_s2.update(std::abs(acc), s.line);
    ax.jerk_mm_s3.update(std::abs(jerk), s.line);
    // Eq. 26 with the paper's units: F = m·a + c·V in N (m/s, m/s²), P = F·V in W.
    const double v_m_s = v / 1000.0, a_m_s2 = acc / 1000.0;
    const double force = std::abs(mass_kg_[a] * a_m_s2 + damping_kg_s_[a] * v_m_s);
    const double power = std::abs(force * v_m_s);
    auto check = [&](LimitCheck& c, double value) {
      c.worst.update(value, s.line);
      if (value > c.limit * (1 + 1e-9)) ++c.violations;
    };
    check(ax.v_limit, std::abs(v));
    check(ax.f_limit, force);
    check(ax.p_limit, power);
    prev_v_[a] = v;
    prev_a_[a] = acc;
    if (s.ref_blu[a] != prev_ref_[a]) last_motion_k_ = s.k;
  }
  prev_ref_ = s.ref_blu;
  contour_err_blu.update(std::abs(s.contour_err_blu), s.line);
  contour_sq_sum_ += s.contour_err_blu * s.contour_err_blu;
  if (!std::isnan(s.arc_ref_dev_blu)) {
    arc_ref_sum_ += s.arc_ref_dev_blu;
    arc_enc_sum_ += s.arc_enc_dev_blu;
    ++arc_samples;
  }
  if ((s.events & kEventHold) != 0) ++hold_samples_;
  ++samples;
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
  if (arc_samples > 0)
    fmt::format_to(
        out, "arcs, steady radial deviation  Acc/Dec output {:+.2f} BLU  encoder {:+.2f} BLU\n",
        arc_ref_radial_dev_blu, arc_enc_radial_dev_blu);
  fmt::format_to(out,
                 "axis  ferr max BLU (line)   v max mm/s (line)   a max mm/s2 (line)   j max mm/s3 "
                 "(line)   final ref/enc err BLU\n");
  for (int a = 0; a < machine_.axis_count(); ++a) {
    const AxisSummary& s = axes[static_cast<std::size_t>(a)];
    fmt::format_to(out,
                   "{:<4}  {:>8.0f} ({:>5})   {:>9.3f} ({:>5})   {:>10.1f} ({:>5})   {:>10.0f} "
                   "({:>5})   {:+d} / {:+d}\n",
                   machine_.layout.letter(a), s.following_err_blu.value, s.following_err_blu.line,
                   s.velocity_mm_s.value, s.velocity_mm_s.line, s.accel_mm_s2.value,
                   s.accel_mm_s2.line, s.jerk_mm_s3.value, s.jerk_mm_s3.line, s.final_ref_err_blu,
                   s.final_enc_err_blu);
  }
  bool any = false;
  for (int a = 0; a < machine_.axis_count(); ++a) {
    const AxisSummary& s = axes[static_cast<std::size_t>(a)];
    const std::pair<const char*, const LimitCheck*> checks[] = {
        {"velocity mm/s", &s.v_limit}, {"force N", &s.f_limit}, {"power W", &s.p_limit}};
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
    fmt::format_to(
        out,
        "{}\"{}\":{{\"following_err_max_blu\":{},\"velocity_max_mm_s\":{},\"accel_max_mm_s2\":{},"
        "\"jerk_max_mm_s3\":{},\"limits\":{{\"velocity\":{},\"force\":{},\"power\":{}}},"
        "\"final_ref_err_blu\":{},\"final_enc_err_blu\":{}}}",
        a == 0 ? "" : ",", static_cast<char>(machine_.layout.letter(a) - 'A' + 'a'),
        peak(s.following_err_blu), peak(s.velocity_mm_s), peak(s.accel_mm_s2), peak(s.jerk_mm_s3),
        limit(s.v_limit), limit(s.f_limit), limit(s.p_limit), s.final_ref_err_blu,
        s.final_enc_err_blu);
  }
  j += "}";
  if (!extra_member.empty()) j += "," + extra_member;
  j += "}\n";
  return j;
}

}  // namespace gm
