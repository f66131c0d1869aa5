// A CanonSource that hands on a fixed list of canonical commands (interpolator and planner tests).
#pragma once

#include "motion/canon.hpp"

#include <cstddef>
#include <utility>
#include <vector>

namespace gmtest {

class CanonList : public gm::CanonSource {
 public:
  explicit CanonList(std::vector<gm::Canon> v) : v_(std::move(v)) {}
  bool next(gm::Canon& out) override {
    if (i_ >= v_.size()) return false;
    out = v_[i_++];
    return true;
  }

 private:
  std::vector<gm::Canon> v_;
  std::size_t i_ = 0;
};

}  // namespace gmtest
