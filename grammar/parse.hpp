// X3-free facade of the G-code grammar: one line in, located words, messages and syntax errors out.
#pragma once

#include "common/diagnostic.hpp"
#include "common/error_codes.hpp"
#include "grammar/ast.hpp"
#include "grammar/expr_ops.hpp"

#include <cstdint>

#include <string>
#include <string_view>
#include <vector>

namespace gm::grammar {

struct ItemFailure;

/// One word with its value; `letter` is upper case, `loc` is the letter's line:column.
/// `decimal_point`: the number was written with a '.' (`P2.`, `P.5`; not `P2000` nor an
/// expression): Fanuc and Haas read `G04 P2000` in milliseconds, `G04 P2.` in seconds. It sits in
/// the padding after `letter` (the word stays 24 bytes).
struct Word {
  char letter = 0;
  bool decimal_point = false;
  double value = 0.0;
  SourceLoc loc;

  Word() = default;
  Word(char l, double v, SourceLoc at, bool point = false)
      : letter(l), decimal_point(point), value(v), loc(at) {}
};

/// A syntax error at `loc`.
struct SyntaxError {
  ErrorCode code = ErrorCode::None;
  SourceLoc loc;
  std::string message;
};

/// What an active comment asks for. LinuxCNC acts on the last comment of a line only.
enum class CommentKind : std::uint8_t {
  Msg,        ///< (MSG, text): shown as it is
  Debug,      ///< (DEBUG, text): shown with #n and #<name> replaced by their values
  Print,      ///< (PRINT, text): as DEBUG (LinuxCNC prints it on stderr)
  Abort,      ///< (ABORT, text): ends the program with an error (text substituted)
  Log,        ///< (LOG, text): written to the log file if one is open
  LogOpen,    ///< (LOGOPEN, file)
  LogAppend,  ///< (LOGAPPEND, file)
  LogClose,   ///< (LOGCLOSE)
};

/// An active comment: `text` is what follows the comma, without leading spaces.
struct Message {
  std::string text;
  SourceLoc loc;
  CommentKind kind = CommentKind::Msg;
};

/// One step of an expression (reverse Polish): literal value, or a name in Block::names.
struct ExprOp {
  Op op = Op::Number;
  double value = 0.0;           ///< Number
  std::uint32_t name = 0;       ///< Named/Exists: offset of the (lower-case) name in Block::names
  std::uint32_t name_size = 0;  ///< and its length
  SourceLoc loc;                ///< where the operand or operator is written
};

/// A half-open range of Block::ops.
struct OpRange {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
  bool empty() const { return first == last; }
};

/// A word whose value is an expression: Block::words[word].value is filled in by evaluating
/// `ops` (the interpreter only ever sees numbers).
struct WordExpr {
  std::uint32_t word = 0;
  OpRange ops;
};

/// A parameter setting `#n=value` (index computes n) or `#<name>=value`.
struct Assignment {
  SourceLoc loc;  ///< the '#'
  bool named = false;
  std::uint32_t name = 0, name_size = 0;  ///< named: the name in Block::names
  OpRange index;                          ///< numbered: computes n
  OpRange value;
};

/// The O-word keywords (LinuxCNC's "O codes").
enum class OKind : std::uint8_t {
  None,
  Sub,
  EndSub,
  Call,
  Return,
  If,
  ElseIf,
  Else,
  EndIf,
  While,
  EndWhile,
  Do,
  Repeat,
  EndRepeat,
  Break,
  Continue,
  Program,  ///< a bare `O1234`: a Fanuc-style (sub)program start, ended by M99
  M98,      ///< `M98 P... L...` first on the line: call a Fanuc-style subprogram
  M99,      ///< `M99` first on the line: return from it (in the main program: program end)
  // Fanuc Macro B (--dialect fanuc), after an optional N: the condition is args[0]
  IfGoto,   ///< `IF [cond] GOTO n`: args[1] is n
  IfThen,   ///< `IF [cond] THEN #i = expr`: the setting is in Block::assignments
  Goto,     ///< `GOTO n`: args[0] is n
  WhileDo,  ///< `WHILE [cond] DO m`: label "m" (1..3)
  MacroDo,  ///< `DO m` without WHILE: an endless loop (label "m")
  EndDo,    ///< `END m` (label "m")
  G65,      ///< `G65 P... L... <arguments>` first on the line: a macro call (words in Block::words)
};
const char* okind_name(OKind k);

/// An O-word line: `o100 while [#1 LT 10]`, `o<name> call [1] [2]`. An M98/M99 line is one too
/// (kind M98/M99, no label: its words, M98 P L, stay in Block::words to be evaluated).
struct OWord {
  OKind kind = OKind::None;
  bool named = false;  ///< o<name> (else numbered)
  /// O[expression]: args[0] is the number, evaluated when the line is reached (label empty)
  bool label_expr = false;
  std::string label;  ///< "100" (leading zeros dropped) or the name in lower case
  SourceLoc loc;      ///< the 'O'
  std::vector<OpRange> args;
};

/// One parsed line. The containers are reused from line to line (counts say what is valid),
/// so a BlockParser that keeps parsing into the same Block allocates nothing in steady state.
struct Block {
  int line = 0;
  bool block_delete = false;  ///< the line starts with '/'
  bool percent = false;       ///< the line is a '%' program delimiter
  bool percent_text = false;  ///< text follows the '%' (`% vfd enable`): errors holds one error
  std::vector<Word> words;
  /// Comments to show (MSG, DEBUG, PRINT): at most one, LinuxCNC acts on the last comment.
  std::vector<Message> messages;
  std::size_t message_count = 0;
  /// The line's last comment when it is ABORT or a LOG comment (directive_count 0 or 1).
  std::vector<Message> directives;
  std::size_t directive_count = 0;
  std::vector<ExprOp> ops;              ///< every expression of the line
  std::vector<WordExpr> word_exprs;     ///< words whose value is an expression
  std::vector<Assignment> assignments;  ///< parameter settings, in the order written
  std::string names;                    ///< parameter names, lower case, back to back
  OWord oword;                          ///< kind None on ordinary lines
  std::vector<SyntaxError> errors;
  /// Fanuc Macro B only: the line's sequence number (its leading N), -1 without one; the text
  /// of its last comment (`#3000 = 1 (TOOL BROKEN)` shows it).
  long sequence = -1;
  std::string remark;

  bool has_errors() const { return !errors.empty(); }
  /// True when something must be evaluated before the interpreter sees the words.
  bool needs_evaluation() const {
    return !word_exprs.empty() || !assignments.empty() ||
           (message_count > 0 && messages[0].kind != CommentKind::Msg) || directive_count > 0;
  }
  std::string_view name_of(std::uint32_t first, std::uint32_t size) const {
    return std::string_view(names).substr(first, size);
  }
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
  /// Reads Fanuc Macro B (--dialect fanuc): `#1 = #2 + #3`, Fanuc's operator precedence, IF,
  /// GOTO, WHILE/DO/END, G65 and `:1234` at the start of a line.
  void set_macro_b(bool on) {
    macro_b_ = on;
    ast_.macro_b = on;
  }
  bool macro_b() const { return macro_b_; }
  /// Lines of only letters and plain numbers are read by hand-written scanners (read_plain_line
  /// on the line itself, read_plain_words on its compacted form) that give the block rule's
  /// result; off: every line takes the block rule (the tests compare both).
  void set_plain_fast_path(bool on) { plain_fast_path_ = on; }

 private:
  // The phases of parse, in order: clear, compact, line start (O-word; Fanuc Macro B's statements
  // with kMacroB), items, convert, comment.
  void clear_block(Block& out) const;
  std::string_view compact_line(std::string_view text);
  std::string_view padded_copy(std::string_view text);
  template <bool kMacroB>
  void parse_line(std::string_view text, int line, Block& out);
  void parse_macro_b(std::string_view text, int line, Block& out);
  template <bool kMacroB>
  bool read_line_start(Block& out, std::string_view compact, std::size_t& start);
  void read_flow_m_code(Block& out, std::string_view compact, std::size_t k);
  bool read_macro_statement(Block& out, std::string_view compact, std::size_t k,
                            std::size_t& start);
  bool macro_arg(Block& out, std::string_view compact, std::size_t& p, const char* what);
  void check_oword_items(Block& out, std::string_view compact);
  bool parse_oword(Block& out, std::string_view compact, std::size_t k, std::size_t& after);
  void read_items(Block& out, std::string_view compact, std::size_t start);
  void report_stray_character(Block& out, const char* begin, const char* pos);
  const char* drop_failed_item(Block& out, const char* begin, const char* end,
                               const ItemFailure& fail);
  void report_item_failure(Block& out, const char* begin, const char* end, const ItemFailure& fail,
                           char letter, int item_pos);
  void drop_open_comment(Block& out, const char* begin, const ItemFailure& fail);
  void convert(Block& out, const char* begin);
  void convert_expressions(Block& out, const char* begin);
  void convert_words(Block& out, const char* begin);
  void active_comment(Block& out, const char* begin);

  SourceLoc loc_at(int offset) const;  ///< the line and source column of compact_[offset]
  void add_error(Block& out, ErrorCode code, int offset, std::string message);
  std::string compact_;       ///< the line without spaces/tabs outside comments, letters upper
  std::vector<int> columns_;  ///< 1-based source column of each compact_ character (+1 sentinel)
  ast::Block ast_;
  int line_ = 0;
  bool macro_b_ = false;
  bool plain_fast_path_ = true;
};

}  // namespace gm::grammar
