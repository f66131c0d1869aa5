// Syntax tree of one G-code line (block): words, parameter settings and comments, positions into
// the compacted line; expressions as flat reverse-Polish operation lists.
#pragma once

#include "grammar/expr_ops.hpp"

#include <boost/spirit/home/x3/support/ast/position_tagged.hpp>

#include <cstddef>
#include <vector>

namespace gm::grammar::ast {

namespace x3 = boost::spirit::x3;

/// One operation of an expression. Number: the literal's text is [first, last); Named/Exists:
/// the name (between '<' and '>') is [first, last); others: `first` is where the operator or
/// function is written (for error carets).
struct ExprOp {
  Op op = Op::Number;
  int first = 0;
  int last = 0;
};

/// One word: a letter and the text of its number, or an expression. Offsets index the compacted
/// line (spaces and tabs removed, letters upper-cased); id_first/id_last span the whole word.
struct Word : x3::position_tagged {
  char letter = 0;
  bool decimal_point = false;  ///< the number holds a '.' (set by the number rule's point)
  int num_first = 0;           ///< offset of the number's first character
  int num_last = 0;            ///< one past its last character
  int expr_first = 0;  ///< the value is an expression: ops [expr_first, expr_last) (else empty)
  int expr_last = 0;
};

/// A parameter setting `#n=value` or `#<name>=value`.
struct Assign {
  int pos = 0;                          ///< offset of the '#'
  int index_first = 0, index_last = 0;  ///< ops computing n (empty for a named parameter)
  int name_first = -1, name_last = -1;  ///< the name, for #<name>=
  int value_first = 0, value_last = 0;  ///< ops computing the value
};

/// A parenthesised comment; the text (between the parentheses) is [text_first, text_last).
struct Comment : x3::position_tagged {
  int text_first = 0;
  int text_last = 0;
};

/// What the grammar is in the middle of (so a failed item can be dropped).
enum class Open { None, Word, Assign, Comment };

/// One line. The vectors are reused from line to line (counts, not sizes, say what is valid),
/// so parsing allocates nothing once they have grown.
struct Block : x3::position_tagged {
  const char* origin = nullptr;  ///< start of the compacted line (offsets are relative to it)
  std::vector<Word> words;
  std::size_t word_count = 0;
  std::vector<Comment> comments;
  std::size_t comment_count = 0;
  std::vector<ExprOp> ops;
  std::vector<Assign> assigns;
  std::vector<Op> pending;  ///< operators waiting for their right operand
  struct Arg {
    int first, last;  ///< ops of one bracketed O-word argument
  };
  std::vector<Arg> args;  ///< O-word arguments (`o100 call [1] [2]`, `o1 if [#1 GT 0]`)
  int arg_first = 0;
  Open open = Open::None;
  bool macro_b = false;      ///< Fanuc Macro B: `#1 = #2 + #3`, Fanuc's operator precedence
  std::size_t open_ops = 0;  ///< ops.size() when the open item began

  void reset(const char* line_start) {
    origin = line_start;
    word_count = 0;
    comment_count = 0;
    ops.clear();
    assigns.clear();
    pending.clear();
    args.clear();
    open = Open::None;
  }
  Word& next_word() {
    if (word_count == words.size()) words.emplace_back();
    return words[word_count++];
  }
  Comment& next_comment() {
    if (comment_count == comments.size()) comments.emplace_back();
    return comments[comment_count++];
  }
  int offset(const char* p) const { return static_cast<int>(p - origin); }
};

}  // namespace gm::grammar::ast
