// Blocks of consecutive samples, one column per axis: what the block-wise stages pass along.
#pragma once

#include "common/axis.hpp"

#include <cstdint>

namespace gm {

/// Samples a block holds at most. The block-wise stages (interpolator, Acc/Dec, servo, contour,
/// trace) each run over a whole block before the next stage starts; 256 samples of nine axes
/// keep a stage's columns in the first-level cache.
inline constexpr int kBlockSamples = 256;

/// One value per axis and sample, structure of arrays: v[a][i] is machine axis a at sample i of
/// the block (machine order; only axes 0..N-1 and samples 0..count-1 are meaningful). Aligned so
/// that a column is a run of whole 64-byte vectors.
template <typename T>
struct alignas(64) AxisColumns {
  T v[kMaxAxes][kBlockSamples];
};

using BluColumns = AxisColumns<std::int64_t>;  ///< positions in BLU (counts)
using RealColumns = AxisColumns<double>;       ///< continuous values, e.g. table positions in BLU

}  // namespace gm
