// Verifies a run against the tolerance in force: worst contour error per line, cuts and rapids
// apart.
#pragma once

#include "common/axis.hpp"
#include "motion/block_sink.hpp"
#include "motion/canon.hpp"
#include "motion/sample_block.hpp"
#include "motion/sample_record.hpp"

#include <cmath>
#include <cstdint>
#include <string>

namespace gm {

/// Fed every record of a run (with the motion that became current in it, as ContourMeter is),
/// compares |contour_err| with the path tolerance of the block the sample is in — cutting
/// moves (G1/G2/G3) and rapids (G0) apart. Blocks with no tolerance (0) are not judged.
class ToleranceCheck : public BlockSink {
 public:
  /// `contour_blu_mm`: the length of one contour_err_blu unit (the smallest axis BLU), mm.
  /// `allowance_mm`: what a sample may exceed the tolerance by without counting as over (one
  /// BLU with tolerance_on = encoder and the servo on: the encoder's quantisation in the loop).
  /// `period_s`: the sample period consume() times the rows with (t = k·T).
  explicit ToleranceCheck(double contour_blu_mm, double allowance_mm = 0.0, double period_s = 0.0)
      : blu_mm_(contour_blu_mm), allowance_mm_(allowance_mm), period_s_(period_s) {}

  /// Judges rows first..count-1 of `b` (contour column filled), each with the last motion
  /// b.motions started in it; `period_s`: the sample period (t = k·T, as SampleBlock::record).
  void add_block(const SampleBlock& b, int first, double period_s);
  void consume(const SampleBlock& b, int first) override { add_block(b, first, period_s_); }

  struct Worst {
    std::int64_t samples = 0;  ///< samples judged (a tolerance was in force)
    std::int64_t over = 0;     ///< samples whose error exceeded it
    double err_mm = 0.0;       ///< largest |contour error| / tolerance: the error…
    double tol_mm = 0.0;       ///< …and the tolerance at that sample
    double ratio = 0.0;
    int line = 0;
    double t_s = 0.0;
  };
  const Worst& cutting() const { return cut_; }
  const Worst& rapids() const { return rapid_; }
  bool judged() const { return cut_.samples + rapid_.samples > 0; }
  bool exceeded() const { return cut_.over + rapid_.over > 0; }
  /// Two lines for the run summary ("" when nothing was judged).
  std::string text() const;
  /// The JSON member `"tolerance":{"cutting":{…},"rapids":{…}}` for --summary-json ("" when
  /// nothing was judged, so summaries of programs without a tolerance are unchanged).
  std::string json_member() const;

 protected:  // for a per-sample reference model (tests/support)
  void start(const Motion& m) {
    tol_mm_ = m.path_tolerance_mm;  // under G64, a G9 block's too; 0 under G61 and G61.1
    rapid_block_ = m.kind == MotionKind::Rapid;
  }
  /// Judges one sample against the tolerance in force (> 0); `t_s()` its time, asked only when
  /// it is the worst so far.
  template <typename Time>
  void judge(double contour_err_blu, int line, Time&& t_s) {
    Worst& w = rapid_block_ ? rapid_ : cut_;
    const double err = std::abs(contour_err_blu) * blu_mm_;
    ++w.samples;
    // A nanometre of slack for the BLU-to-mm products (the bound itself is planned with margin).
    if (err > tol_mm_ + allowance_mm_ + 1e-9) ++w.over;
    const double ratio = err / tol_mm_;
    if (ratio > w.ratio) {
      w.ratio = ratio;
      w.err_mm = err;
      w.tol_mm = tol_mm_;
      w.line = line;
      w.t_s = t_s();
    }
  }

  double blu_mm_;
  double allowance_mm_ = 0.0;
  double period_s_ = 0.0;
  double tol_mm_ = 0.0;
  bool rapid_block_ = false;
  Worst cut_, rapid_;
};

}  // namespace gm
