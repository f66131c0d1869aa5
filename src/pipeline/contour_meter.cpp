// ContourMeter: per-sample contour error and steady-arc radial deviations from a SampleRecord.
#include "pipeline/contour_meter.hpp"

#include "interpolator/interpolator.hpp"

#include <algorithm>
#include <limits>

namespace gm {

ContourMeter::ContourMeter(const MachineVec& blu_mm, const AxisLayout& axes, double contour_blu_mm,
                           std::int64_t window_samples, std::int64_t steady_after)
    : blu_mm_(blu_mm),
      contour_blu_mm_(contour_blu_mm),
      window_(window_samples),
      steady_after_(steady_after) {
  // The contour is measured in X, Y and Z; an axis the machine lacks reads slot 8, which stays
  // 0 unless the machine has all nine (and then it has X, Y and Z).
  for (int k = 0; k < 3; ++k) xyz_slot_[static_cast<std::size_t>(k)] = kMaxAxes - 1;
  for (int a = 0; a < axes.count; ++a)
    if (axes.program(a) < 3) xyz_slot_[static_cast<std::size_t>(axes.program(a))] = a;
}

Vec3 ContourMeter::xyz_mm(const MachineVec& v_blu) const {
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const int slot = xyz_slot_[static_cast<std::size_t>(k)];
    p[k] = v_blu[slot] * blu_mm_[slot];
  }
  return p;
}

void ContourMeter::measure(SampleRecord& r, std::span<const Motion> started) {
  for (const Motion& m : started) window_.push(m, r.k);
  if (!started.empty()) block_start_k_ = r.k;
  // Contour error of the table (what a ballbar measures: lost motion and friction show here),
  // not of the motor encoder a semi-closed loop reads.
  const Vec3 table_mm = xyz_mm(r.table_blu);
  r.contour_err_blu = window_.contour_error_mm(table_mm, r.k) / contour_blu_mm_;

  r.arc_ref_dev_blu = r.arc_enc_dev_blu = std::numeric_limits<double>::quiet_NaN();
  const MotionGeometry* m = r.settling ? nullptr : window_.newest();
  // Steady: the interpolator has been moving on this arc for longer than the filter and servo
  // delays, and is not waiting at its end (exact stop), in a dwell or in a hold.
  constexpr std::uint32_t kNotMoving =
      kEventSettle | kEventDwell | kEventHold | kEventSpindleWait | kEventInputWait;
  if ((r.events & kNotMoving) != 0) last_pause_k_ = r.k;
  if (m != nullptr && m->kind == MotionKind::Arc &&
      r.k - std::max(block_start_k_, last_pause_k_) >= steady_after_) {
    const Vec3 ref_mm = xyz_mm(r.ref_blu.cast<double>());
    const Vec3 enc_mm = xyz_mm(r.enc_blu.cast<double>());
    r.arc_ref_dev_blu = m->radial_deviation_mm(ref_mm) / contour_blu_mm_;
    r.arc_enc_dev_blu = m->radial_deviation_mm(enc_mm) / contour_blu_mm_;
  }
}

}  // namespace gm
