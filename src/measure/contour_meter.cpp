// ContourMeter: per-sample contour error and steady-arc radial deviations from a SampleRecord.
#include "measure/contour_meter.hpp"

#include "interpolator/interpolator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {
namespace {

// MotionGeometry::radial_deviation_mm's expression, inlined into the row loop.
inline double arc_radial_dev_mm(const MotionGeometry& g, const Vec3& p_mm) {
  return std::hypot(p_mm[g.ax.a] - g.center_mm[g.ax.a], p_mm[g.ax.b] - g.center_mm[g.ax.b]) -
         g.r0_mm;
}

}  // namespace

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
    if (axes.program(a) < 3) {
      xyz_slot_[static_cast<std::size_t>(axes.program(a))] = a;
      present_[static_cast<std::size_t>(axes.program(a))] = true;
    }
}

Vec3 ContourMeter::xyz_mm(const MachineVec& v_blu) const {
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const int slot = xyz_slot_[static_cast<std::size_t>(k)];
    p[k] = v_blu[slot] * blu_mm_[slot];
  }
  return p;
}

template <typename RefEnc>
inline void ContourMeter::measure_row(std::int64_t k, const Vec3& table_mm, std::uint32_t events,
                                      bool settling, RefEnc&& ref_enc, double& contour_err,
                                      double& arc_ref_dev, double& arc_enc_dev) {
  // Contour error of the table (what a ballbar measures: lost motion and friction show here),
  // not of the motor encoder a semi-closed loop reads.
  contour_err = window_.contour_error_mm(table_mm, k) / contour_blu_mm_;

  arc_ref_dev = arc_enc_dev = std::numeric_limits<double>::quiet_NaN();
  const MotionGeometry* m = settling ? nullptr : window_.newest();
  // Steady: the interpolator has been moving on this arc for longer than the filter and servo
  // delays, and is not waiting at its end (exact stop), in a dwell or in a hold.
  constexpr std::uint32_t kNotMoving =
      kEventSettle | kEventDwell | kEventHold | kEventSpindleWait | kEventInputWait;
  if ((events & kNotMoving) != 0) last_pause_k_ = k;
  if (m != nullptr && m->kind == MotionKind::Arc &&
      k - std::max(block_start_k_, last_pause_k_) >= steady_after_) {
    Vec3 ref_mm, enc_mm;
    ref_enc(ref_mm, enc_mm);
    arc_ref_dev = arc_radial_dev_mm(*m, ref_mm) / contour_blu_mm_;
    arc_enc_dev = arc_radial_dev_mm(*m, enc_mm) / contour_blu_mm_;
  }
}

void ContourMeter::measure(SampleRecord& r, std::span<const Motion> started) {
  for (const Motion& m : started) window_.push(m, r.k);
  if (!started.empty()) block_start_k_ = r.k;
  measure_row(
      r.k, xyz_mm(r.table_blu), r.events, r.settling,
      [&](Vec3& ref_mm, Vec3& enc_mm) {
        ref_mm = xyz_mm(r.ref_blu.cast<double>());
        enc_mm = xyz_mm(r.enc_blu.cast<double>());
      },
      r.contour_err_blu, r.arc_ref_dev_blu, r.arc_enc_dev_blu);
}

void ContourMeter::measure_block(SampleBlock& b, int first) {
  // An axis the machine lacks reads 0 (the record's entries past its axes are 0), times the
  // BLU of slot kMaxAxes − 1, as xyz_mm() computes it.
  static const double kZeroReal[kBlockSamples] = {};
  static const std::int64_t kZeroBlu[kBlockSamples] = {};
  const double* table[3];
  const std::int64_t* ref[3];
  const std::int64_t* enc[3];
  double blu[3];
  for (int c = 0; c < 3; ++c) {
    const int slot = xyz_slot_[static_cast<std::size_t>(c)];
    const bool present = present_[static_cast<std::size_t>(c)];
    table[c] = present ? b.table_blu.v[slot] : kZeroReal;
    ref[c] = present ? b.ref_blu.v[slot] : kZeroBlu;
    enc[c] = present ? b.enc_blu.v[slot] : kZeroBlu;
    blu[c] = blu_mm_[slot];
  }
  const std::size_t motions = b.motions.size();
  std::size_t m = 0;
  while (m < motions && b.motion_row[m] < first) ++m;
  for (int i = first; i < b.count; ++i) {
    const std::int64_t k = b.k0 + i;
    if (m < motions && b.motion_row[m] == i) {
      do window_.push(b.motions[m++], k);
      while (m < motions && b.motion_row[m] == i);
      block_start_k_ = k;
    }
    const Vec3 table_mm(table[0][i] * blu[0], table[1][i] * blu[1], table[2][i] * blu[2]);
    measure_row(
        k, table_mm, b.events[i], b.settling[i],
        [&](Vec3& ref_mm, Vec3& enc_mm) {
          for (int c = 0; c < 3; ++c) {
            ref_mm[c] = static_cast<double>(ref[c][i]) * blu[c];
            enc_mm[c] = static_cast<double>(enc[c][i]) * blu[c];
          }
        },
        b.contour_err_blu[i], b.arc_ref_dev_blu[i], b.arc_enc_dev_blu[i]);
  }
}

}  // namespace gm
