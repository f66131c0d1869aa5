// Servo matching: an axis's reference shaped so that its servo responds as the reference axis's.
#pragma once

#include "accdec/taps.hpp"
#include "common/block_columns.hpp"

#include <cstdint>
#include <vector>

namespace gm {

/// The matching taps of one axis, F_0..F_{n−1} with Σ F_j = kScale: the axis's servo follows
/// (1/kScale)·Σ_j F_j·y[k−j] instead of the Acc/Dec output y (ServoMatch; designed by
/// planner/servo_response's design_servo_match, so that this axis's servo step response
/// convolved with F/kScale is, in least squares, the reference axis's).
struct MatchTaps {
  static constexpr std::int64_t kScale = std::int64_t{1} << 24;
  int axis = -1;                      ///< machine axis index
  std::vector<std::int64_t> integer;  ///< F_j, Σ = kScale
  /// F_j / kScale: the weights the planner's mismatch is computed with, exactly.
  std::vector<double> weights() const;
};

/// A matched axis's Acc/Dec: its reference is the command filtered by the Acc/Dec taps b and its
/// MatchTaps F together, rounded once,
///   out[k] = round_half_away( Σ_i c_i·x[k−i] / (b_s·kScale) ),  c = b ∗ F,
/// exactly (a double sum where its error bound decides the rounding, else 128-bit integers), so,
/// with Σ c_i = b_s·kScale, once the last len inputs are equal the output is the input exactly. It
/// replaces the shared FirAccDec's output on that axis: one rounding, as the filter's, so the
/// planner's rounding margin is unchanged. The history before the first sample is the start
/// position 0 (the Acc/Dec filter's). Allocates only in the constructor.
class ServoMatch {
 public:
  ServoMatch() = default;
  /// `fir`: the machine's Acc/Dec taps (integer, b_s); `axes`: the matched axes' taps.
  ServoMatch(const Taps& fir, std::vector<MatchTaps> axes);

  /// Rows first .. first+n-1: the matched axes' `ref` computed from their command `cmd`.
  void apply(const BluColumns& cmd, BluColumns& ref, int first, int n);
  bool empty() const { return axes_.empty(); }
  /// The longest filter's length (b and F together), samples.
  int length() const;
  /// Every matched axis's last `length` inputs are equal (its output is then its input).
  bool settled() const;

 private:
  struct Axis {
    int axis = -1;
    std::vector<std::int64_t> c;  ///< b ∗ F, newest weight first
    std::vector<double> cd;       ///< c as doubles
    bool fast = false;            ///< every |c_i| < 2^52: the double sum may be used
    /// The last len inputs, newest at `head`, each stored at slot s and s + len so that the
    /// window lies in a row: hist[head + j] = x[k − j]. histd: the same as doubles.
    std::vector<std::int64_t> hist;
    std::vector<double> histd;
    int head = 0;
    int equal_run = 0;  ///< how many of the last inputs equal the newest
  };
  std::vector<Axis> axes_;
  std::int64_t scale_ = 1;  ///< b_s·kScale = Σ c_i
};

}  // namespace gm
