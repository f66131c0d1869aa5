// Finding, taking out and adding words of a parsed block (the dialects' rewrites before the
// interpreter runs a block).
#pragma once

#include "grammar/parse.hpp"

#include <cmath>
#include <cstddef>

namespace gm::block_edit {

inline constexpr std::size_t kNone = static_cast<std::size_t>(-1);

/// Index of the first word `letter` at or after `from`, or kNone.
inline std::size_t find(const grammar::Block& b, char letter, std::size_t from = 0) {
  for (std::size_t i = from; i < b.words.size(); ++i)
    if (b.words[i].letter == letter) return i;
  return kNone;
}
/// Index of code `letter` number x 10 (G51.1 = 511), or kNone.
inline std::size_t find_code(const grammar::Block& b, char letter, int number10) {
  for (std::size_t i = 0; i < b.words.size(); ++i)
    if (b.words[i].letter == letter && std::lround(b.words[i].value * 10.0) == number10 &&
        std::fabs(b.words[i].value * 10.0 - static_cast<double>(number10)) < 1e-6)
      return i;
  return kNone;
}
/// The word `letter`, or null.
inline const grammar::Word* word(const grammar::Block& b, char letter) {
  const std::size_t i = find(b, letter);
  return i == kNone ? nullptr : &b.words[i];
}
/// Takes out word `i` (kNone: nothing).
inline void erase(grammar::Block& b, std::size_t i) {
  if (i != kNone) b.words.erase(b.words.begin() + static_cast<std::ptrdiff_t>(i));
}
/// Takes out the first word `letter`, if any.
inline void erase_letter(grammar::Block& b, char letter) {
  erase(b, find(b, letter));
}
/// Sets word `letter` to `value` (added at `loc` when the block has none).
inline void set(grammar::Block& b, char letter, double value, SourceLoc loc) {
  const std::size_t i = find(b, letter);
  if (i == kNone)
    b.words.push_back(grammar::Word{letter, value, loc});
  else
    b.words[i].value = value;
}

}  // namespace gm::block_edit
