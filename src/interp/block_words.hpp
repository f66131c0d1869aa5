// A block's words sorted by letter and modal group (grbl's parser_block_t), and the import that
// sorts them; the read-ahead thread imports plain lines ahead of the interpreter.
#pragma once

#include "common/axis.hpp"
#include "grammar/parse.hpp"
#include "interp/codes.hpp"
#include "interp/polar.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace gm {

struct InterpError;  // interp/interpreter.hpp

/// The words of one block, by letter and by modal group (grbl's parser_block_t).
struct BlockWords {
  std::array<const grammar::Word*, 26> value{};             ///< value words by letter
  std::array<const Code*, kGroupCount> code{};              ///< the block's code in each group
  std::array<const grammar::Word*, kGroupCount> code_word;  ///< valid where `code` is set
  std::array<const Code*, kGroupCount> codes;  ///< the block's codes in the order written (the
                                               ///< first code_count; the rest never read)
  std::size_t code_count = 0;
  std::uint32_t letters = 0;  ///< the value words' letters (letter_mask: bit i is 'A' + i)
  unsigned axes = 0;          ///< the program axes with a word (bit i: axis i, X = 0)
  const grammar::Word* first_axis = nullptr;
  PolarWords polar;        ///< `@` and `^` (interp/polar.hpp): axis words in place of X and Y
  grammar::Word x_radius;  ///< G7: the X word halved (value['X'] points here then)

  const grammar::Word* operator[](char c) const { return value[static_cast<std::size_t>(c - 'A')]; }
  bool has(char c) const { return (*this)[c] != nullptr; }
  double get(char c, double fallback = 0.0) const { return has(c) ? (*this)[c]->value : fallback; }
  const Code* in(Group g) const { return code[static_cast<std::size_t>(g)]; }
  const grammar::Word* word_of(Group g) const {
    return in(g) ? code_word[static_cast<std::size_t>(g)] : nullptr;
  }
  /// True if the block has code `letter` number10.
  bool has_code(char letter, int number10) const {
    for (std::size_t i = 0; i < code_count; ++i)
      if (codes[i]->letter == letter && codes[i]->number10 == number10) return true;
    return false;
  }
};

/// STEP 1-2: sorts the block's words into `w` (cleared first) by letter and modal group;
/// false with `err` set for an unknown code or letter, an axis the machine lacks (`axes`), two
/// codes of one group, a repeated word, N not first.
bool import_words(const grammar::Block& block, const AxisLayout& axes, BlockWords& w,
                  InterpError& err);
/// The same with `axes`' program axes as bits (program_axis_bits(axes)), worked out once.
bool import_words(const grammar::Block& block, const AxisLayout& axes, unsigned axis_bits,
                  BlockWords& w, InterpError& err);
/// The program axes the machine `axes` has, as bits (bit i: program axis i, X = 0).
inline unsigned program_axis_bits(const AxisLayout& axes) {
  unsigned bits = 0;
  for (int a = 0; a < axes.count; ++a) bits |= 1u << axes.program(a);
  return bits;
}

/// A block whose words the interpreter may take as imported on the read-ahead thread: no
/// expression, O-word, '%' or syntax error (nothing changes its words before it runs).
inline bool importable_ahead(const grammar::Block& b) {
  return !b.words.empty() && !b.percent && !b.has_errors() &&
         b.oword.kind == grammar::OKind::None && !b.needs_evaluation();
}

}  // namespace gm
