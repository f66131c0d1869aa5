// Syntax tree of one G-code line (block): words and comments, positions into the compacted line.
#pragma once

#include <boost/spirit/home/x3/support/ast/position_tagged.hpp>

#include <cstddef>
#include <vector>

namespace gm::grammar::ast {

namespace x3 = boost::spirit::x3;

/// One word: a letter and the text of its number. Offsets index the compacted line (spaces and
/// tabs removed, letters upper-cased); id_first/id_last span the whole word.
struct Word : x3::position_tagged {
  char letter = 0;
  int num_first = 0;  ///< offset of the number's first character
  int num_last = 0;   ///< one past its last character
};

/// A parenthesised comment; the text (between the parentheses) is [text_first, text_last).
struct Comment : x3::position_tagged {
  int text_first = 0;
  int text_last = 0;
};

/// One line. The vectors are reused from line to line (counts, not sizes, say what is valid),
/// so parsing allocates nothing once they have grown.
struct Block : x3::position_tagged {
  const char* origin = nullptr;  ///< start of the compacted line (offsets are relative to it)
  std::vector<Word> words;
  std::size_t word_count = 0;
  std::vector<Comment> comments;
  std::size_t comment_count = 0;

  void reset(const char* line_start) {
    origin = line_start;
    word_count = 0;
    comment_count = 0;
  }
  Word& next_word() {
    if (word_count == words.size()) words.emplace_back();
    return words[word_count++];
  }
  Comment& next_comment() {
    if (comment_count == comments.size()) comments.emplace_back();
    return comments[comment_count++];
  }
};

}  // namespace gm::grammar::ast
