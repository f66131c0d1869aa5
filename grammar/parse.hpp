// X3-free facade of the G-code grammar: one line in, located words, messages and syntax errors out.
#pragma once

#include "common/diagnostic.hpp"
#include "common/error_codes.hpp"
#include "grammar/ast.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace gm::grammar {

/// One word with its value; `letter` is upper case, `loc` is the letter's line:column.
struct Word {
  char letter = 0;
  double value = 0.0;
  SourceLoc loc;
};

/// A syntax error at `loc`.
struct SyntaxError {
  ErrorCode code = ErrorCode::None;
  SourceLoc loc;
  std::string message;
};

/// A (MSG, text) comment: `text` is what follows the comma, without leading spaces.
struct Message {
  std::string text;
  SourceLoc loc;
};

/// One parsed line. The containers are reused from line to line (counts say what is valid),
/// so a BlockParser that keeps parsing into the same Block allocates nothing in steady state.
struct Block {
  int line = 0;
  bool block_delete = false;  ///< the line starts with '/'
  bool percent = false;       ///< the line is a '%' program delimiter
  std::vector<Word> words;
  std::vector<Message> messages;
  std::size_t message_count = 0;
  std::vector<SyntaxError> errors;

  bool has_errors() const { return !errors.empty(); }
};

/// Lines longer than this are refused with LineTooLong (the reader stops storing them).
inline constexpr std::size_t kMaxLineLength = 1u << 20;
/// At most this many syntax errors are reported per line (garbage lines would flood otherwise).
inline constexpr std::size_t kMaxErrorsPerLine = 16;

/// Parses lines one at a time. Spaces and tabs outside comments are insignificant (LinuxCNC):
/// `G 0 1 X 1 0` is `G01 X10`. Letters may be either case. Never throws on bad input.
class BlockParser {
 public:
  /// Parses `text` (one line without '\n'; a trailing '\r' is ignored), numbered `line`
  /// (1-based), into `out`, replacing its previous content.
  void parse(std::string_view text, int line, Block& out);

 private:
  void add_error(Block& out, ErrorCode code, int offset, std::string message);
  std::string compact_;       ///< the line without spaces/tabs outside comments, letters upper
  std::vector<int> columns_;  ///< 1-based source column of each compact_ character (+1 sentinel)
  ast::Block ast_;
  int line_ = 0;
};

}  // namespace gm::grammar
