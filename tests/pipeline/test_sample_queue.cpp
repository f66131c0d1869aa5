// SampleQueue: every row reaches the consumer once, in order, with its motions; the consumer's
// exception reaches the producer; destruction mid-run neither hangs nor loses the thread.
#include "pipeline/sample_queue.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

using gm::SampleBlock;
using gm::SampleQueue;

namespace {

constexpr std::int64_t kBatchRows =
    static_cast<std::int64_t>(SampleQueue::kBlocks) * gm::kBlockSamples;

// Writes row k (line = k % 1000, X command = k) with `motions` motions of lines 1000·k + i, as
// the pipeline does, and moves on when the block is full.
void write_row(SampleQueue& q, std::int64_t k, std::size_t motions = 0) {
  SampleBlock& b = q.block();
  const int i = b.count;
  b.line[i] = static_cast<int>(k % 1000);
  b.cmd_blu.v[0][i] = k;
  for (std::size_t j = 0; j < motions; ++j) {
    gm::Motion m;
    m.line = static_cast<int>(1000 * k + static_cast<std::int64_t>(j));
    b.motions.push_back(m);
    b.motion_row.push_back(i);
  }
  ++b.count;
  if (b.full()) q.next_block(k + 1);
}

}  // namespace

TEST_CASE("sample queue delivers every row once and in order") {
  for (std::int64_t n :
       {std::int64_t{0}, std::int64_t{1}, std::int64_t{255}, std::int64_t{256}, std::int64_t{257},
        kBatchRows - 1, kBatchRows, kBatchRows + 1, 3 * kBatchRows, std::int64_t{100003}}) {
    std::vector<std::int64_t> seen;
    seen.reserve(static_cast<std::size_t>(n));
    std::int64_t wrong_k = 0;
    SampleQueue q(
        [&](SampleBlock& b) {
          for (int i = 0; i < b.count; ++i) {
            seen.push_back(b.cmd_blu.v[0][i]);
            if (b.k0 + i != b.cmd_blu.v[0][i]) ++wrong_k;  // the block's k0 numbers its rows
          }
        },
        0);
    for (std::int64_t k = 0; k < n; ++k) write_row(q, k);
    q.finish();  // after finish() the consumer has taken everything
    INFO("n " << n);
    REQUIRE(seen.size() == static_cast<std::size_t>(n));
    for (std::int64_t k = 0; k < n; ++k) REQUIRE(seen[static_cast<std::size_t>(k)] == k);
    CHECK(wrong_k == 0);
  }
}

TEST_CASE("sample queue hands each motion to the consumer with the row it was written with") {
  // Row k carries k % 5 motions (lines 1000·k + i), and one row 5,000 (the list grows for it).
  const std::int64_t n = 3 * kBatchRows + 7;
  std::int64_t wrong = 0, motions = 0, rows = 0;
  SampleQueue q(
      [&](SampleBlock& b) {
        std::size_t m = 0;
        for (int i = 0; i < b.count; ++i, ++rows) {
          const std::int64_t k = b.k0 + i;
          std::size_t here = 0;
          for (; m < b.motions.size() && b.motion_row[m] == i; ++m, ++here, ++motions)
            if (b.motions[m].line != static_cast<int>(1000 * k + static_cast<std::int64_t>(here)))
              ++wrong;
          if (static_cast<std::int64_t>(here) != (k == n / 2 ? 5000 : k % 5)) ++wrong;
        }
        if (m != b.motions.size()) ++wrong;
      },
      0);
  std::int64_t expected = 0;
  for (std::int64_t k = 0; k < n; ++k) {
    const auto count = static_cast<std::size_t>(k == n / 2 ? 5000 : k % 5);
    expected += static_cast<std::int64_t>(count);
    write_row(q, k, count);
  }
  q.finish();
  CHECK(rows == n);
  CHECK(wrong == 0);
  CHECK(motions == expected);
}

TEST_CASE("sample queue rethrows the consumer's exception to the producer") {
  SampleQueue q(
      [](SampleBlock& b) {
        if (b.k0 <= 5000 && 5000 < b.k0 + b.count) throw std::runtime_error("disk full at 5000");
      },
      0);
  bool thrown = false;
  std::int64_t k = 0;
  try {
    for (; k < 1000000; ++k) write_row(q, k);
    q.finish();
  } catch (const std::runtime_error& e) {
    thrown = true;
    CHECK(std::string(e.what()) == "disk full at 5000");
    CHECK(k < 5000 + 3 * kBatchRows + 1);  // stopped soon after
  }
  CHECK(thrown);
}

TEST_CASE("sample queue destroyed mid-run joins its thread") {
  std::atomic<std::int64_t> consumed{0};
  {
    SampleQueue q([&](SampleBlock& b) { consumed += b.count; }, 0);
    for (std::int64_t k = 0; k < 50000; ++k) write_row(q, k);
    // no finish(): the producer gave up (an error, SIGINT); the destructor must not hang
  }
  CHECK(consumed.load() <= 50000);
  CHECK(consumed.load() >= 50000 - 3 * kBatchRows);
}
