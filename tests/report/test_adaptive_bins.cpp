// AdaptiveBins: the width doubles to keep at most `cap` bins, and min/max survive the merges.
#include "report/adaptive_bins.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

namespace {

struct MinMax {
  double lo = 0, hi = 0;
  void merge(const MinMax& later) {
    lo = std::min(lo, later.lo);
    hi = std::max(hi, later.hi);
  }
};

}  // namespace

TEST_CASE("adaptive bins: 100 samples under a cap of 8 give 7 columns of 16", "[report]") {
  gm::report::AdaptiveBins<MinMax> bins(8);
  for (int k = 0; k < 100; ++k) {
    const double v = k == 37 ? 1e6 : k;  // one spike
    bins.add({v, v});
  }
  // 100 samples: width 8 would need 13 bins (> 8), width 16 needs ceil(100/16) = 7.
  REQUIRE(bins.width() == 16);
  REQUIRE(bins.samples() == 100);
  REQUIRE(bins.bins().size() == 7);
  for (std::size_t i = 0; i < 7; ++i) {
    const double first = 16.0 * static_cast<double>(i);
    CHECK(bins.bins()[i].lo == first);
    CHECK(bins.bins()[i].hi == (i == 2 ? 1e6 : std::min(first + 15.0, 99.0)));
  }
}

TEST_CASE("adaptive bins: fewer samples than the cap are kept one per bin", "[report]") {
  gm::report::AdaptiveBins<MinMax> bins(2048);
  for (int k = 0; k < 2048; ++k) bins.add({-k * 1.0, k * 1.0});
  CHECK(bins.width() == 1);
  REQUIRE(bins.bins().size() == 2048);
  CHECK(bins.bins()[1234].lo == -1234.0);
  bins.add({-5000.0, 5000.0});  // the 2049th sample halves them
  CHECK(bins.width() == 2);
  REQUIRE(bins.bins().size() == 1025);
  CHECK(bins.bins()[617].lo == -1235.0);
  CHECK(bins.bins()[617].hi == 1235.0);
  CHECK(bins.bins().back().hi == 5000.0);
}

TEST_CASE("adaptive bins: an odd cap is rounded up to even", "[report]") {
  gm::report::AdaptiveBins<MinMax> bins(3);
  for (int k = 0; k < 5; ++k) bins.add({k * 1.0, k * 1.0});
  // cap 4: samples 0..3 in 4 bins, the 5th halves to 2 bins of 2, then opens a third.
  REQUIRE(bins.width() == 2);
  REQUIRE(bins.bins().size() == 3);
  CHECK(bins.bins()[1].lo == 2.0);
  CHECK(bins.bins()[1].hi == 3.0);
  CHECK(bins.bins()[2].lo == 4.0);
}
