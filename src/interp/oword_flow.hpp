// O-word control flow (LinuxCNC's O codes): subroutines, if/elseif/else, while, do/while, repeat,
// break/continue. The program is re-read, never held: the driver seeks when asked.
#pragma once

#include "grammar/parse.hpp"
#include "interp/expression.hpp"
#include "interp/interpreter.hpp"
#include "interp/parameters.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace gm {

class MacroVariables;

/// Where a line is in the program text.
struct LinePos {
  std::uint64_t offset = 0;  ///< first byte of the line
  std::uint64_t next = 0;    ///< first byte of the line after it
  int line = 0;              ///< 1-based line number
  int file = 0;              ///< 0: the program; > 0: a subroutine file (SubroutineFinder)
};

/// What the driver must do after an O-word line.
struct FlowJump {
  bool seek = false;
  std::uint64_t offset = 0;  ///< continue reading here ...
  int line = 0;              ///< ... with this line number
  int file = 0;              ///< ... of this file (0: the program)
};

/// Finds the file of a subroutine the program has not defined (LinuxCNC: `o<name> call` reads
/// `name.ngc` from the subroutine path). The driver implements it: it owns the files.
class SubroutineFinder {
 public:
  virtual ~SubroutineFinder() = default;
  /// The id (> 0) of the file for `label`, or 0 when there is none.
  virtual int find(const std::string& label) = 0;
  /// Why there is none, for the error ("no file 'x.ngc' in DIR").
  virtual std::string miss(const std::string& label) const = 0;
  /// The name of file `id` (for messages).
  virtual std::string file_name(int id) const = 0;
};

/// LinuxCNC allows this many nested subroutine calls (rs274 2.9: the tenth fails).
inline constexpr int kMaxCallDepth = 9;
/// Default bound on loop iterations and calls, so that no program runs forever.
inline constexpr std::int64_t kDefaultMaxIterations = 10'000'000;

class OwordFlow {
 public:
  OwordFlow(ParameterStore& params, std::int64_t max_iterations, SubroutineFinder* finder = nullptr)
      : params_(params), finder_(finder), max_iterations_(max_iterations) {}

  /// True while lines are passed over (a false condition, a sub definition, a forward search):
  /// then only O-word lines matter.
  bool skipping() const { return skip_.mode != Skip::None; }

  /// Handles an O-word line at `pos`. False with `err` set on an error; `jump` says where to
  /// continue when the program must be re-read from elsewhere.
  bool handle(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);

  /// The input ended: false with `err` set if a sub, if or loop is still open (or a called
  /// subroutine was never found); `err_file` is then the file the error is in.
  bool at_end(int last_line, InterpError& err, int& err_file) const;

  /// The program's closing '%' at `at` was reached: false with `err` set if a forward search
  /// for a sub is under way (rs274 2.9 reads nothing after it: "Failed to find sub ... before
  /// EOF").
  bool closing_percent(SourceLoc at, InterpError& err) const;

  int call_depth() const { return calls_; }

  // Fanuc Macro B (--dialect fanuc; interp/macro_flow.cpp) -------------------------------------
  /// Reads Fanuc Macro B from now on: variables through `m`, G65 calls with #1-#33 locals.
  void set_macro(MacroVariables* m);
  /// `IF [cond] THEN ...`: the condition's value (vacant is false).
  bool condition(const grammar::Block& b, bool& holds, InterpError& err);
  /// True while a GOTO searches for its sequence number: every line's N matters.
  bool finding_sequence() const { return skip_.mode == Skip::FindSequence; }
  /// ... and has come round to the program's start.
  bool sequence_wrapped() const { return skip_.wrapped; }
  /// During that search, the line at `pos` with sequence number `n` (-1: none): 1 when it is
  /// the target (the search ends and the line runs), 0 to pass it over, -1 on an error (the
  /// search came round to the GOTO line without finding it).
  int sequence_line(long n, const LinePos& pos, InterpError& err);
  /// The search met the program's end (the input's end or its closing '%'): it continues from
  /// the program's start (true, `jump` set), or, having done so already, fails.
  bool sequence_end(FlowJump& jump, InterpError& err);
  /// The program number of the program being run (#4115): the innermost M98/G65 call's, else
  /// the main program's `O` line (`main_program`, -1 when it has none).
  double program_number(long main_program) const;

  /// Haas's `M97 P n [L k]` at `pos` (interp/haas_flow.cpp): calls the blocks from N n of the
  /// same program to M99 (L: k times). False with `err` on an error.
  bool m97(const grammar::Block& b, const LinePos& pos, InterpError& err);

  /// After at_end's UndefinedSubroutine: drops the search for the called subroutine and goes on
  /// after the call line, as if the call had returned at once (`check` reads on). False when no
  /// search was open.
  bool drop_missing_call(FlowJump& jump);

 private:
  enum class Frame : std::uint8_t { Call, If, While, Do, Repeat, MacroLoop };
  struct Open {
    Frame kind;
    std::string label;
    LinePos pos;           ///< the opening line (call: the call line)
    double remaining = 0;  ///< repeat: iterations left
    bool branch_taken = false;
    bool fanuc = false;     ///< call: an M98 subprogram (ends with M99)
    bool again = false;     ///< call: M98 L with repeats left returns to the call line itself
    bool macro = false;     ///< call: a G65 macro call (locals #1-#33 of its own)
    std::uint64_t end = 0;  ///< MacroLoop: the offset of its END line once seen (0: not yet)
  };
  /// A subroutine seen: its `sub` line, or its bare `O1234` line (Fanuc-style, for M98).
  struct SubDef {
    LinePos pos;
    bool fanuc = false;
  };
  enum class Skip : std::uint8_t {
    None,
    SubBody,       ///< passing over a definition: to its endsub
    FindSub,       ///< searching forward for a called sub
    IfBranch,      ///< condition false: to the next elseif/else/endif
    IfDone,        ///< a branch ran: to endif
    LoopEnd,       ///< break/false: past the loop's end line
    ToLoopEnd,     ///< continue in do/repeat: to the loop's end line, then run it
    MacroLoopEnd,  ///< a false WHILE [..] DO m: past its END m
    FindSequence,  ///< GOTO n: to the line numbered N n in the same program
  };
  struct SkipState {
    Skip mode = Skip::None;
    std::string label;
    std::string shown;  ///< the label as written in messages: o<name> or o100
    SourceLoc started;  ///< the line that began the skip (for errors at the end)
    grammar::OKind started_kind = grammar::OKind::None;
    int started_file = 0;  ///< the file of the line that began the skip
    int file = 0;          ///< FindSub: the file searched
    bool fanuc = false;    ///< FindSub: an M98 call (looks for a bare `O1234`)
    long sequence = -1;    ///< FindSequence: the N searched for
    bool wrapped = false;  ///< FindSequence: searching from the program's start again
    LinePos from;          ///< FindSequence: the GOTO line
  };

  bool evaluate_arg(const grammar::Block& b, std::size_t i, double& v, InterpError& err);
  bool normal(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  // normal's constructs: sub, call, if/elseif/else/endif, while/endwhile, repeat/endrepeat,
  // break/continue.
  bool define_sub(const grammar::Block& b, const LinePos& pos, InterpError& err);
  bool call_sub(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool if_line(const grammar::Block& b, const LinePos& pos, InterpError& err);
  bool while_line(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool repeat_line(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool leave_loop(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  /// True when the innermost open construct is a `k` labelled as `o`.
  bool top_is(const grammar::OWord& o, Frame k) const;
  /// The error for an end line (`o`) without its opening line (`opens`).
  bool mismatch(const grammar::OWord& o, const char* opens, InterpError& err) const;
  bool skipped(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool enter_sub(const std::string& label, const LinePos& body, SourceLoc loc, FlowJump& jump,
                 bool seek, InterpError& err);
  bool m98(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  /// M98 and G65 after their words: L repeats, then enter or search for O`label`.
  bool count_repeat(const grammar::Word* l);
  bool fanuc_call(const grammar::OWord& o, const std::string& label, const grammar::Word* l,
                  const LinePos& pos, FlowJump& jump, InterpError& err);
  // Fanuc Macro B's statements (interp/macro_flow.cpp).
  bool macro_statement(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                       InterpError& err);
  bool macro_goto(const grammar::Block& b, std::size_t arg, const LinePos& pos, FlowJump& jump,
                  InterpError& err);
  bool macro_loop(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool macro_end(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool g65(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool macro_skipped(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err);
  /// The line after the current program's `O` line (the file's start for the main program).
  LinePos program_start() const;
  bool found_sub(const grammar::OWord& o, const LinePos& pos, FlowJump& jump, InterpError& err);
  bool leave_sub(const grammar::Block& b, FlowJump& jump, InterpError& err);
  bool count_iteration(SourceLoc loc, InterpError& err);
  void skip(Skip mode, const std::string& label, const grammar::Block& b, int file);
  /// Index of the innermost open loop labelled `label`, or -1.
  int find_loop(const std::string& label) const;
  /// rs274's one label per construct: records where an if/while/do/repeat label is first run
  /// (per subroutine being run, as LinuxCNC's offset_map keys "sub#label"); false with `err`
  /// when the label was run before at another line (LinuxCNC: "duplicate O-word label").
  bool note_label(const grammar::OWord& o, Frame kind, const LinePos& pos, InterpError& err);

  ParameterStore& params_;
  SubroutineFinder* finder_;
  Evaluator eval_;
  std::int64_t max_iterations_;
  std::int64_t iterations_ = 0;
  std::vector<Open> stack_;
  std::unordered_map<std::string, SubDef> subs_;  ///< label -> the `sub` (or `O1234`) line
  struct LabelUse {
    Frame kind;
    int line;
  };
  /// "sub#label" -> the first if/while/do/repeat run with it (note_label). At most
  /// kMaxLabels are kept, so that a program of endless distinct labels keeps memory flat.
  std::unordered_map<std::string, LabelUse> labels_;
  static constexpr std::size_t kMaxLabels = std::size_t{1} << 20;
  std::string label_key_;  ///< note_label's scratch key
  /// rs274 2.9's doing_break: set by any `break`, cleared by the `while` line ending a do loop,
  /// which then does not loop back. So after a break out of a while loop, the next do ... while
  /// loop runs once (LinuxCNC's behaviour, reproduced).
  bool break_pending_ = false;
  SkipState skip_;
  std::vector<double> pending_args_;  ///< FindSub: the arguments of the call
  LinePos pending_return_;            ///< FindSub: the call line
  bool pending_fanuc_ = false;        ///< the pending call is an M98
  bool pending_again_ = false;        ///< ... whose return re-reads the call line (L repeats)
  bool pending_macro_ = false;        ///< the pending call is a G65 (locals #1-#33 its own)
  /// G65: #1-#33 on entry (vacant but for the arguments).
  std::array<double, ParameterStore::kMacroLocals> pending_locals_{};
  MacroVariables* macro_ = nullptr;
  /// M98 L repeats left, by the caller's call depth (LinuxCNC m98_loop_counter); -1: none.
  std::array<int, kMaxCallDepth + 1> m98_loops_ = make_loops();
  static std::array<int, kMaxCallDepth + 1> make_loops() {
    std::array<int, kMaxCallDepth + 1> a{};
    a.fill(-1);
    return a;
  }
  int calls_ = 0;
};

}  // namespace gm
