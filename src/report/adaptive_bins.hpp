// Streaming decimation with flat memory: samples fold into at most `cap` bins of 2^m samples each.
#pragma once

#include <cstdint>
#include <vector>

namespace gm::report {

/// Folds a stream of samples into consecutive bins of equal width (a power of two, in samples)
/// whose count never exceeds `cap`: when a sample would open bin cap+1, neighbouring bins are
/// merged pairwise and the width doubles. A Bin is made from one sample and has
/// `void merge(const Bin& later)` (associative: min/max, first, worst), so the bins equal what
/// binning the whole stream at the final width would give; peaks are never lost.
template <typename Bin>
class AdaptiveBins {
 public:
  /// `cap` is rounded up to an even number >= 2 (so a halving leaves only full bins).
  explicit AdaptiveBins(std::size_t cap) : cap_(cap < 2 ? 2 : cap + cap % 2) {
    bins_.reserve(cap_);
  }

  /// Adds the next sample, already made into a one-sample bin.
  void add(const Bin& one) {
    if (fill_ == 0) {
      if (bins_.size() == cap_) halve();
      bins_.push_back(one);
    } else {
      bins_.back().merge(one);
    }
    ++samples_;
    if (++fill_ == width_) fill_ = 0;
  }

  const std::vector<Bin>& bins() const { return bins_; }
  /// Samples per bin (the last bin may hold fewer).
  std::int64_t width() const { return width_; }
  std::int64_t samples() const { return samples_; }

 private:
  void halve() {
    std::size_t out = 0;
    for (std::size_t i = 0; i < bins_.size(); i += 2, ++out) {
      Bin b = bins_[i];
      if (i + 1 < bins_.size()) b.merge(bins_[i + 1]);
      bins_[out] = b;
    }
    bins_.resize(out);
    width_ *= 2;
  }

  std::size_t cap_;
  std::vector<Bin> bins_;
  std::int64_t width_ = 1;
  std::int64_t fill_ = 0;  ///< samples in the open (last) bin; 0 = the next sample opens a bin
  std::int64_t samples_ = 0;
};

}  // namespace gm::report
