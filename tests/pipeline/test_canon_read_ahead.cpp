// CanonReadAhead: the commands of its source, in order, each with its geometry; the source's
// exception after every command before it; destruction while the reader has work does not hang.
#include "pipeline/canon_read_ahead.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <stdexcept>
#include <variant>

namespace {

// Motion k (line k) from (k, 0, 0) to (k + 1, 0, 0), its geometry built for even k only; after
// `count` motions it ends, or throws when `throws` (count < 0: it never ends).
class Counting : public gm::CanonSource {
 public:
  Counting(std::int64_t count, bool throws) : count_(count), throws_(throws) {}
  bool next(gm::Canon& out) override {
    geometry_ = nullptr;
    if (count_ >= 0 && k_ == count_) {
      if (throws_) throw std::runtime_error("line " + std::to_string(k_ + 1));
      return false;
    }
    gm::Motion m;
    m.line = static_cast<int>(k_);
    m.start_mm[0] = static_cast<double>(k_);
    m.end_mm[0] = static_cast<double>(k_ + 1);
    out = m;
    if (k_ % 2 == 0) {
      g_ = gm::MotionGeometry::of(m);
      geometry_ = &g_;
    }
    ++k_;
    return true;
  }
  const gm::MotionGeometry* geometry() const override { return geometry_; }

 private:
  std::int64_t count_, k_ = 0;
  bool throws_;
  gm::MotionGeometry g_;
  const gm::MotionGeometry* geometry_ = nullptr;
};

// Reads `a` to its end, checking motion k is the source's k-th; k counts the commands read.
void read_all(gm::CanonReadAhead& a, std::int64_t& k) {
  k = 0;
  gm::Canon c;
  while (a.next(c)) {
    const auto* m = std::get_if<gm::Motion>(&c);
    REQUIRE(m != nullptr);
    REQUIRE(m->line == k);
    REQUIRE(m->end_mm[0] == static_cast<double>(k + 1));
    if (k % 2 == 0) {
      REQUIRE(a.geometry() != nullptr);
      REQUIRE(a.geometry()->start_mm[0] == static_cast<double>(k));
      REQUIRE(a.geometry()->length_mm == 1.0);
    } else {
      REQUIRE(a.geometry() == nullptr);
    }
    ++k;
  }
}

}  // namespace

TEST_CASE("canon read-ahead: every command in order, with its geometry, then the end") {
  constexpr auto kBatch = static_cast<std::int64_t>(gm::CanonReadAhead::kBatchCanon);
  for (const std::int64_t n :
       {std::int64_t{0}, std::int64_t{1}, kBatch - 1, kBatch, kBatch + 1, 5 * kBatch + 7}) {
    INFO(n);
    Counting src(n, false);
    gm::CanonReadAhead a(src);
    std::int64_t k = -1;
    read_all(a, k);
    CHECK(k == n);
    gm::Canon c;
    CHECK_FALSE(a.next(c));  // and stays ended
  }
}

TEST_CASE("canon read-ahead: the source's exception comes after every command before it") {
  constexpr auto kBatch = static_cast<std::int64_t>(gm::CanonReadAhead::kBatchCanon);
  for (const std::int64_t n : {std::int64_t{0}, std::int64_t{3}, kBatch, 4 * kBatch + 5}) {
    INFO(n);
    Counting src(n, true);
    gm::CanonReadAhead a(src);
    std::int64_t k = -1;
    try {
      read_all(a, k);
      FAIL("no exception");
    } catch (const std::runtime_error& e) {
      CHECK(std::string(e.what()) == "line " + std::to_string(n + 1));
    }
    CHECK(k == n);  // every command before the exception, none lost
  }
}

TEST_CASE("canon read-ahead: destroyed while its source has more, it stops and joins") {
  Counting src(-1, false);  // never ends
  gm::CanonReadAhead a(src);
  gm::Canon c;
  for (int i = 0; i < 1000; ++i) REQUIRE(a.next(c));
  CHECK(std::get<gm::Motion>(c).line == 999);
}  // the destructor must return
