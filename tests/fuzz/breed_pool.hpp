// Which inputs a mutator should breed from: remembers the inputs the target found not worth it
// (invalid, or too long to run) and keeps a pool of parents that were, to mutate in their place.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace fuzz {

/// libFuzzer (clang 14) cannot be told to leave an input out of its corpus, and mutants of an
/// invalid program mostly stop at the same error. So the target tells the pool which inputs are
/// not worth breeding from (`ran`), the mutator remembers every parent that is (`choose`), and
/// in place of a parent that is not it takes one of those remembered. (Keeping one invalid parent
/// in eight spent a third of the time on the mutants of a few invalid lathe programs, each
/// reaching the cycle's bound of 200,000 moves.) The error paths are still reached by mutants of
/// valid programs. Memory is fixed: a table of 2^20 hashes (8 MiB; a hash overwritten by another
/// only lets an invalid parent be mutated) and at most kParents parents.
class BreedPool {
 public:
  static constexpr std::size_t kParents = 1024;

  /// The target ran `text`: `breed` when its mutants are worth running (a valid program of
  /// bounded length, an accepted table).
  void ran(std::string_view text, bool breed) {
    const std::uint64_t h = hash(text);
    std::uint64_t& slot = barren_[h >> (64 - kBits)];
    if (!breed)
      slot = h;
    else if (slot == h)
      slot = 0;
  }

  /// The parent to mutate: `text` itself when it is worth breeding from (it is remembered), else
  /// a remembered parent of at most `max_size` bytes (`text` when there is none). `seed` chooses.
  std::string_view choose(std::string_view text, std::size_t max_size, std::uint32_t seed) {
    const std::uint64_t h = hash(text);
    if (barren_[h >> (64 - kBits)] != h) {
      remember(text, seed);
      return text;
    }
    if (parents_.empty()) return text;
    const std::string& p = parents_[seed % parents_.size()];
    return p.size() <= max_size ? std::string_view(p) : text;
  }

  std::size_t parents() const { return parents_.size(); }

 private:
  static constexpr int kBits = 20;

  static std::uint64_t hash(std::string_view text) {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a, never 0 for the inputs that matter
    for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
    return h == 0 ? 1 : h;
  }
  void remember(std::string_view text, std::uint32_t seed) {
    if (parents_.size() < kParents)
      parents_.emplace_back(text);
    else
      parents_[std::minstd_rand(seed)() % kParents].assign(text);
  }

  std::vector<std::uint64_t> barren_ = std::vector<std::uint64_t>(std::size_t{1} << kBits);
  std::vector<std::string> parents_;
};

}  // namespace fuzz
