// SampleQueue: every record reaches the consumer once, in order; the consumer's exception
// reaches the producer; destruction mid-run neither hangs nor loses the thread.
#include "pipeline/sample_queue.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

using gm::SampleQueue;
using gm::SampleRecord;

TEST_CASE("sample queue delivers every record once and in order") {
  for (std::int64_t n : {std::int64_t{0}, std::int64_t{1}, std::int64_t{4095}, std::int64_t{4096},
                         std::int64_t{4097}, std::int64_t{3 * 4096}, std::int64_t{100003}}) {
    std::vector<std::int64_t> seen;
    seen.reserve(static_cast<std::size_t>(n));
    SampleQueue q([&](SampleRecord& r, std::span<const gm::Motion>) { seen.push_back(r.k); });
    SampleRecord r;
    for (std::int64_t k = 0; k < n; ++k) {
      r.k = k;
      r.line = static_cast<int>(k % 1000);
      q.push(r);
    }
    q.finish();  // after finish() the consumer has taken everything
    INFO("n " << n);
    REQUIRE(seen.size() == static_cast<std::size_t>(n));
    for (std::int64_t k = 0; k < n; ++k) REQUIRE(seen[static_cast<std::size_t>(k)] == k);
  }
}

TEST_CASE("sample queue hands each motion to the consumer with the record it was pushed with") {
  // Motions on every 7th record and on both sides of each batch boundary; line = k marks them.
  auto has_motion = [](std::int64_t k) {
    const auto in_batch = k % static_cast<std::int64_t>(SampleQueue::kBatchSize);
    return k % 7 == 0 || in_batch == 0 ||
           in_batch == static_cast<std::int64_t>(SampleQueue::kBatchSize) - 1;
  };
  const std::int64_t n = 5 * static_cast<std::int64_t>(SampleQueue::kBatchSize) + 11;
  std::int64_t seen = 0, with_motion = 0, wrong = 0;
  SampleQueue q([&](SampleRecord& r, std::span<const gm::Motion> ms) {
    ++seen;
    const gm::Motion* m = ms.empty() ? nullptr : &ms.back();
    if (!ms.empty()) ++with_motion;
    if (ms.size() > 1 || (m != nullptr) != has_motion(r.k) || (m != nullptr && m->line != r.k))
      ++wrong;
  });
  SampleRecord r;
  gm::Motion motion;
  std::int64_t expected = 0;
  for (std::int64_t k = 0; k < n; ++k) {
    r.k = k;
    motion.line = static_cast<int>(k);
    const bool with = has_motion(k);
    expected += with ? 1 : 0;
    q.push(r, with ? std::span<const gm::Motion>(&motion, 1) : std::span<const gm::Motion>());
  }
  q.finish();
  CHECK(seen == n);
  CHECK(with_motion == expected);
  CHECK(wrong == 0);
}

TEST_CASE("sample queue rethrows the consumer's exception to the producer") {
  SampleQueue q([](SampleRecord& r, std::span<const gm::Motion>) {
    if (r.k == 5000) throw std::runtime_error("disk full at 5000");
  });
  SampleRecord r;
  bool thrown = false;
  try {
    for (std::int64_t k = 0; k < 1000000; ++k) {
      r.k = k;
      q.push(r);
    }
    q.finish();
  } catch (const std::runtime_error& e) {
    thrown = true;
    CHECK(std::string(e.what()) == "disk full at 5000");
    CHECK(r.k <
          5000 + 3 * static_cast<std::int64_t>(SampleQueue::kBatchSize) + 1);  // stopped soon after
  }
  CHECK(thrown);
}

TEST_CASE("sample queue destroyed mid-run joins its thread") {
  std::atomic<std::int64_t> consumed{0};
  {
    SampleQueue q([&](SampleRecord&, std::span<const gm::Motion>) { ++consumed; });
    SampleRecord r;
    for (std::int64_t k = 0; k < 50000; ++k) q.push(r);
    // no finish(): the producer gave up (an error, SIGINT); the destructor must not hang
  }
  CHECK(consumed.load() <= 50000);
  CHECK(consumed.load() >= 50000 - 3 * static_cast<std::int64_t>(SampleQueue::kBatchSize));
}

TEST_CASE("sample queue hands several motions per record in order, beyond a batch's worth") {
  // Record k carries k % 5 motions (lines 1000·k + i): 2 per record on average, so batches are
  // handed over when their 1,024 motions are full, before their 4,096 records are; one record
  // then carries 5,000 motions (a list grows for it).
  const std::int64_t n = 3 * static_cast<std::int64_t>(SampleQueue::kBatchSize) + 7;
  std::int64_t wrong = 0, motions = 0;
  SampleQueue q([&](SampleRecord& r, std::span<const gm::Motion> ms) {
    if (static_cast<std::int64_t>(ms.size()) != (r.k == n / 2 ? 5000 : r.k % 5)) ++wrong;
    for (std::size_t i = 0; i < ms.size(); ++i, ++motions)
      if (ms[i].line != static_cast<int>(1000 * r.k + static_cast<std::int64_t>(i))) ++wrong;
  });
  SampleRecord r;
  std::vector<gm::Motion> batch(5000);
  std::int64_t expected = 0;
  for (std::int64_t k = 0; k < n; ++k) {
    r.k = k;
    const auto count = static_cast<std::size_t>(k == n / 2 ? 5000 : k % 5);
    for (std::size_t i = 0; i < count; ++i)
      batch[i].line = static_cast<int>(1000 * k + static_cast<std::int64_t>(i));
    expected += static_cast<std::int64_t>(count);
    q.push(r, std::span<const gm::Motion>(batch.data(), count));
  }
  q.finish();
  CHECK(wrong == 0);
  CHECK(motions == expected);
}
