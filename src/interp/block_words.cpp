// The import of a block's words (grbl's STEP 1-2): by letter and modal group, with the checks
// that need no state.
#include "interp/block_words.hpp"

#include "interp/steps.hpp"

#include <fmt/format.h>

namespace gm {

namespace {

// Value words any block may carry whatever its codes (axis words are checked apart).
bool is_free_letter(char c) {
  return c == 'F' || c == 'N' || c == 'S' || c == 'T';
}

std::string machine_axes_text(const AxisLayout& l) {
  std::string s;
  for (int i = 0; i < l.count; ++i)
    s += fmt::format("{}{}", i == 0 ? "" : i + 1 == l.count ? " and " : ", ", l.letter(i));
  return s;
}

// Program axis of each letter A..Z (axis_index), -1 for the others.
constexpr std::array<signed char, 26> kAxisOfLetter = [] {
  std::array<signed char, 26> t{};
  for (int i = 0; i < 26; ++i)
    t[static_cast<std::size_t>(i)] =
        static_cast<signed char>(program_axis_index(static_cast<char>('A' + i)));
  return t;
}();

int letter_axis(char c) {
  return c >= 'A' && c <= 'Z' ? kAxisOfLetter[static_cast<std::size_t>(c - 'A')] : -1;
}

// What import_words fills (the rest is read only where these say it is set).
void clear(BlockWords& w) {
  w.value = {};
  w.code = {};
  w.code_count = 0;
  w.letters = 0;
  w.axes = 0;
  w.first_axis = nullptr;
  w.polar = PolarWords{};
}

}  // namespace

bool import_words(const grammar::Block& block, const AxisLayout& axes, BlockWords& w,
                  InterpError& err) {
  return import_words(block, axes, program_axis_bits(axes), w, err);
}

bool import_words(const grammar::Block& block, const AxisLayout& axes, unsigned machine_axes,
                  BlockWords& w, InterpError& err) {
  clear(w);
  for (std::size_t i = 0; i < block.words.size(); ++i) {
    const grammar::Word& word = block.words[i];
    const char c = word.letter;
    if (c == 'G' || c == 'M') {
      double r = 0;
      const double scaled = c == 'G' ? word.value * 10.0 : word.value;
      if (word.value < 0 || !near_integer(scaled, r) || r > 1e6)
        return fail(err, ErrorCode::BadCodeNumber, word.loc,
                    fmt::format("{}{:g} names no {} code", c, word.value, c));
      const int number10 = c == 'G' ? static_cast<int>(r) : 10 * static_cast<int>(r);
      const Code* code = find_code(c, number10);
      if (!code)
        return fail(err, c == 'G' ? ErrorCode::UnknownGCode : ErrorCode::UnknownMCode, word.loc,
                    fmt::format("{} is not supported", code_name(c, number10)));
      const auto gi = static_cast<std::size_t>(code->group);
      // rs274 (read_g): G80 yields to another code of its group in the same block, whichever
      // comes first, so `G80 G0 X1` is a rapid (CAM posts write it).
      if (w.code[gi] && c == 'G' && number10 == 800) continue;
      if (w.code[gi] && w.code[gi]->letter == 'G' && w.code[gi]->number10 == 800) {
        for (std::size_t k = 0; k < w.code_count; ++k)
          if (w.codes[k] == w.code[gi]) w.codes[k] = code;
        w.code[gi] = code;
        w.code_word[gi] = &word;
        continue;
      }
      if (w.code[gi])
        return fail(err, ErrorCode::ModalGroupViolation, word.loc,
                    fmt::format("{} and {} are both in modal group {}", code_name(*w.code[gi]),
                                code_name(*code), group_name(code->group)));
      w.code[gi] = code;
      w.code_word[gi] = &word;
      w.codes[w.code_count++] = code;
      continue;
    }
    if (c == '@' || c == '^') {  // polar coordinates: axis words in place of X and Y
      const grammar::Word*& slot = c == '@' ? w.polar.radius : w.polar.angle;
      if (slot)
        return fail(
            err, ErrorCode::DuplicateWord, word.loc,
            fmt::format("{} appears twice in the block (first at column {})", c, slot->loc.column));
      slot = &word;
      if (!w.first_axis) w.first_axis = &word;
      continue;
    }
    const int axis = letter_axis(c);
    if (axis >= 0 && (machine_axes & (1u << axis)) == 0)
      return fail(
          err, ErrorCode::AxisUnavailable, word.loc,
          fmt::format("axis {} is not available: this machine has {}", c, machine_axes_text(axes)));
    if (axis < 0 && !is_free_letter(c) && !code_word(c))
      return fail(err, ErrorCode::UnknownLetter, word.loc,
                  fmt::format("unknown word letter {}", c));
    if (c == 'N' && i != 0)
      return fail(err, ErrorCode::LineNumberNotFirst, word.loc,
                  "line number N must be the first word of the block");
    auto& slot = w.value[static_cast<std::size_t>(c - 'A')];
    if (slot)
      return fail(
          err, ErrorCode::DuplicateWord, word.loc,
          fmt::format("{} appears twice in the block (first at column {})", c, slot->loc.column));
    slot = &word;
    w.letters |= std::uint32_t{1} << (c - 'A');
    if (axis >= 0) {
      w.axes |= 1u << axis;
      if (!w.first_axis) w.first_axis = &word;
    }
  }
  return true;
}

}  // namespace gm
