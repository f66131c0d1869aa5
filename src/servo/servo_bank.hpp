// The servo of every axis of a machine over a block of samples, the axes as SIMD lanes.
#pragma once

#include "common/block_columns.hpp"
#include "common/isa.hpp"
#include "machine/machine.hpp"
#include "servo/servo_axis.hpp"

#include <string>
#include <vector>

namespace gm {

/// The machine's axes' servos (ServoAxis each) stepped together over rows of a block: what N
/// ServoAxis objects stepped sample by sample give, bit for bit. When every axis has a plant of
/// the same order (1 or 2) and no Coulomb friction, the axes are the lanes of vectors of the
/// instruction set's width (AVX-512 (VL) and AVX2: pieces of 4; portable SSE2: pieces of 2;
/// nine axes are three pieces of 4) and every lane does
/// ServoAxis's operations in its order (no fused multiply-add: the kernel's file is compiled
/// with -ffp-contract=off); otherwise, and for a sample in which a lane's position or reference
/// leaves the range the lanes are exact in (|x| ≥ 2^51 BLU, a loop that has diverged), the
/// ServoAxis objects themselves run. Allocates only in the constructor.
class ServoBank {
 public:
  /// The servos of the first `axes` axes of `m` at period T = period_s with `substeps`
  /// (Machine::servo_substeps). Throws gm::InputError as ServoAxis does.
  ServoBank(const Machine& m, int axes, double period_s, int substeps);

  /// Rows first .. first+n-1 (first + n ≤ kBlockSamples): for each row and axis, table = the
  /// table position at the start of the period, enc = the count ServoAxis::step(ref) returns
  /// and, when `deflection` is given, the modes' deflection (ServoAxis::deflection_blu()) at the
  /// start of the period (0 on an axis without modes).
  /// Returns n, or the number of rows done before the row in which an axis diverged (see
  /// divergence()); the bank is not to be stepped again after that.
  template <int N>
  int step_block(const BluColumns& ref, BluColumns& enc, RealColumns& table, int first, int n,
                 RealColumns* deflection = nullptr);

  /// Samples in a row, up to the last one stepped, in which every axis read within one count of
  /// its reference (the pipeline's settling rule).
  int quiet_run() const { return quiet_run_; }
  /// After step_block stopped early: the axis and ServoAxis's message.
  int diverged_axis() const { return diverged_axis_; }
  const std::string& divergence() const { return divergence_; }
  /// The axes run as SIMD lanes (else as ServoAxis objects).
  bool lanes() const { return lanes_ > 0; }
  /// Tests only: run the lane kernel compiled for `isa` (at most active_isa()).
  void set_isa_for_testing(Isa isa);
  /// Tests only: the lanes' round_half_away on x[0..w) with the kernel of `isa` (at most
  /// active_isa()); w, the lanes rounded (2 or 4), is returned. bad[l] != 0: lane l is out
  /// of the exact range (|x| ≥ 2^51 or NaN) and out[l] means nothing.
  static int round_for_testing(Isa isa, const double* x, double* out, std::int64_t* bad);

  /// Lanes of the widest shape (nine axes: 3 vectors of 4, or 5 of 2; 16 leaves room for 8).
  static constexpr int kMaxLanes = 16;
  /// The lanes' state; public only for the kernel (servo_bank.cpp). Counts and references are
  /// doubles there (exact integers below 2^51; the axes all start at count 0).
  struct alignas(64) LaneState {
    double z[3][kMaxLanes];
    double integ[kMaxLanes], u[kMaxLanes], table_rel[kMaxLanes];
    double prev_count[kMaxLanes], prev_ref[kMaxLanes], prev_delta[kMaxLanes];
  };
  /// The lanes' parameters (unused lanes copy lane 0's and stay at rest).
  struct alignas(64) LaneParams {
    double a[9][kMaxLanes];   ///< Ad, column-major a[j·M + i]
    double bd[3][kMaxLanes];  ///< Bd
    double kp[kMaxLanes], kvp[kMaxLanes], kvi[kMaxLanes], kv_period[kMaxLanes];
    double kv_over_h[kMaxLanes], h_over_kv[kMaxLanes], u_max[kMaxLanes], hb[kMaxLanes];
    double ff1[kMaxLanes], ff2[kMaxLanes];  ///< ServoAxis::ff1_gain(), ff2_gain()
    std::int64_t ip[kMaxLanes];             ///< -1: Ip form, 0: Pi form
  };

 private:
  template <int N>
  int step_axes(const BluColumns& ref, BluColumns& enc, RealColumns& table, int first, int n,
                RealColumns* deflection);
  void to_axes(const LaneState& s);    ///< lanes -> ServoAxis objects
  void from_axes(LaneState& s) const;  ///< ServoAxis objects -> lanes

  std::vector<ServoAxis> axes_;
  int count_ = 0;
  int lanes_ = 0;  ///< 1 when the lanes run, 0 otherwise
  int order_ = 0;  ///< plant order of every axis (lanes)
  int substeps_ = 1;
  Isa isa_ = Isa::Portable;
  bool have_ref_ = false;
  int quiet_run_ = 0;
  int diverged_axis_ = -1;
  std::string divergence_;
  LaneState state_{};
  LaneParams params_{};
};

}  // namespace gm
