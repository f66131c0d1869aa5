// RingDeque: the same contents as std::deque under a seeded mix of pushes and pops, through growth.
#include "common/ring_deque.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <deque>
#include <random>
#include <string>
#include <vector>

TEST_CASE("RingDeque holds what std::deque holds") {
  gm::RingDeque<std::string> ring;
  std::deque<std::string> ref;
  std::mt19937 rng(7);
  for (int step = 0; step < 5000; ++step) {
    // Pushes outnumber pops for a while (growth while wrapped), then pops catch up.
    const bool push = ref.empty() || rng() % 100 < (step < 3000 ? 65u : 45u);
    if (push) {
      const std::string v = "v" + std::to_string(step);
      ring.push_back(v);
      ref.push_back(v);
    } else {
      REQUIRE(ring.front() == ref.front());
      ring.pop_front();
      ref.pop_front();
    }
    REQUIRE(ring.size() == ref.size());
    REQUIRE(ring.empty() == ref.empty());
    if (!ref.empty()) {
      REQUIRE(ring.back() == ref.back());
      const std::size_t i = rng() % ref.size();
      REQUIRE(ring[i] == ref[i]);
    }
  }
  REQUIRE(ring.size() > 100);  // the sweep ends with a long queue (about 700)
  REQUIRE(std::equal(ring.begin(), ring.end(), ref.begin(), ref.end()));
  REQUIRE(std::equal(ring.rbegin(), ring.rend(), ref.rbegin(), ref.rend()));
}

TEST_CASE("RingDeque iterators are random access in queue order") {
  gm::RingDeque<int> ring;
  for (int i = 0; i < 6; ++i) ring.push_back(100);  // pushed and popped: the ring wraps
  for (int i = 0; i < 6; ++i) ring.pop_front();
  for (int v = 0; v < 20; ++v) ring.push_back(3 * v);  // grows from 8 slots while wrapped
  REQUIRE(ring.size() == 20);
  REQUIRE(ring.front() == 0);
  REQUIRE(ring.back() == 57);
  const auto it = std::lower_bound(ring.begin(), ring.end(), 31);
  REQUIRE(it - ring.begin() == 11);
  REQUIRE(*it == 33);
  const auto up = std::upper_bound(ring.begin(), ring.end(), 33);
  REQUIRE(*up == 36);
  int n = 0;
  for (auto r = ring.rbegin(); r != ring.rend() && *r > 40; ++r) ++n;
  REQUIRE(n == 6);  // 42 45 48 51 54 57
  ring.clear();
  REQUIRE(ring.empty());
  ring.push_back(5);
  REQUIRE(ring.front() == 5);
  REQUIRE(ring.size() == 1);
}
