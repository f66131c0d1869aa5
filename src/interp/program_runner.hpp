// The back half of the program driver (program rules and the interpreter, one parsed line at a
// time) and LineDriver, which feeds it lines from the front half.
#pragma once

#include "common/diagnostic.hpp"
#include "interp/dialect.hpp"
#include "interp/expression.hpp"
#include "interp/fanuc_modal.hpp"
#include "interp/g7x_driver.hpp"
#include "interp/haas_codes.hpp"
#include "interp/interpreter.hpp"
#include "interp/lathe_fanuc.hpp"
#include "interp/line_source.hpp"
#include "interp/macro_modal_call.hpp"
#include "interp/macro_variables.hpp"
#include "interp/oword_flow.hpp"
#include "interp/parameters.hpp"
#include "interp/program.hpp"
#include "interp/subroutine_files.hpp"
#include "interp/system_parameters.hpp"

#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <vector>

namespace gm {

/// The back half: program-level rules (% delimiters, block delete, missing end), the dialect's
/// rules (DialectRules) and the interpreter, one parsed line at a time; shared by check_program
/// and ProgramStream.
class ProgramRunner {
 public:
  ProgramRunner(std::string filename, const InterpreterOptions& opts);
  ProgramRunner(const ProgramRunner&) = delete;
  ProgramRunner& operator=(const ProgramRunner&) = delete;

  /// Processes one parsed line. Appends canon to `out` and diagnostics to `diags`.
  /// Returns false when the program is over (end code or closing %).
  bool process(ParsedLine& p, std::vector<Canon>& out, std::vector<Diagnostic>& diags,
               FlowJump& jump);
  /// The input (file `file`) ended after line `last_line` (0: empty input): reports a missing
  /// program end, or what is still open. True when reading goes on where `jump` says: checking
  /// every error (InterpreterOptions::check_all) after a call whose subroutine was not found.
  bool end_of_input(int last_line, std::vector<Diagnostic>& diags, FlowJump& jump, int file = 0);
  /// A subroutine file found on the path could not be opened when the program jumped to it.
  void cannot_open(int file, int line, int from_file, std::vector<Diagnostic>& diags);
  /// The driver could not seek where the control flow asked (the input is a pipe).
  void cannot_seek(int line, std::vector<Diagnostic>& diags);
  /// Writes the parameters to the parameter file (if one is named and it was read), once.
  void save_parameters(std::vector<Diagnostic>& diags) { system_.save(diags); }
  /// The text of the last line processed is about to change or go (its batch is handed back):
  /// it is copied for the missing-end diagnostic (lines are only pointed to until then).
  void keep_last_line();

  SubroutineFiles& files() { return files_; }
  bool done() const { return done_; }
  const std::string& filename() const { return filename_; }
  const ParameterStore& parameters() const { return params_; }
  const Machine& machine() const { return machine_; }
  std::int64_t blocks() const { return blocks_; }

 private:
  /// One line's in- and outputs, handed from decision to decision.
  struct Line {
    ParsedLine& p;
    std::vector<Canon>& out;
    std::vector<Diagnostic>& diags;
    FlowJump& jump;
  };
  bool process_line(Line& l);
  bool skipped_line(Line& l);
  bool truncated_line(Line& l);
  bool well_formed(Line& l);
  void main_m99_ends(grammar::Block& block) const;
  bool content(Line& l);
  bool local_call(Line& l);
  void add_missing_tools(Line& l);
  bool dialect_rewrite(Line& l);
  bool modal_macro(Line& l, const grammar::Block& call);
  bool evaluate(Line& l, bool& more);
  bool run_block(Line& l);
  bool control(Line& l);
  bool macro_then(Line& l);
  bool sequence_search(Line& l, bool& handled);
  bool fanuc_sub_refused(Line& l) const;
  // Fanuc/Haas lathe (--dialect fanuc on a lathe machine; interp/lathe_fanuc.hpp).
  bool lathe_block(Line& l, bool& handled);
  bool lathe_profile_line(Line& l);
  bool lathe_moves(Line& l);
  bool directive(const grammar::Message& m, Line& l);
  /// The program is over at an error: `err` on the line as a diagnostic; false.
  bool stop(const InterpError& err, Line& l);
  /// check_all: the note after an error that ends checking (the lines after it are not read).
  void stopped_here(SourceLoc loc, std::vector<Diagnostic>& diags, std::string_view why) const;
  bool start_failed(std::vector<Diagnostic>& diags) {
    return !start_error_.empty() && report_start_error(diags);
  }
  bool report_start_error(std::vector<Diagnostic>& diags);
  void remember(const std::string& text) { last_text_ = &text; }

  std::string filename_;
  Machine default_machine_;
  const Machine& machine_;
  bool block_delete_;
  bool check_all_;
  bool fanuc_subs_disabled_;
  int dropped_calls_ = 0;  ///< check_all: calls read on after (kMaxDroppedCalls at most)
  Interpreter interp_;
  ParameterStore params_;
  MacroVariables macro_vars_{params_};  ///< --dialect fanuc: Macro B's variables
  long main_program_ = -1;              ///< the main program's O number (#4115), -1: none
  SystemParameters system_;
  LineEvaluator evaluator_;
  SubroutineFiles files_;
  OwordFlow flow_;
  G7xDriver g7x_;
  DialectRules rules_;
  HaasCodes haas_;             ///< --dialect haas: G154, G187, M97, ...
  ModalMacroCall modal_call_;  ///< --dialect fanuc, haas: G66/G67
  FanucModal fanuc_;           ///< --dialect fanuc, haas: G16, G68, G51, G51.1, G80's group 01
  std::string last_line_;      ///< the last line's text, kept (keep_last_line)
  const std::string* last_text_ = nullptr;  ///< the last line's text, not yet kept
  bool log_warned_ = false;
  bool done_ = false;
  bool opened_percent_ = false;
  bool first_content_seen_ = false;
  std::int64_t blocks_ = 0;
  std::vector<Diagnostic> start_error_;
  // Fanuc/Haas lathe conventions: on when the dialect is fanuc and the machine a lathe.
  bool fanuc_lathe_ = false;
  FanucLathe lathe_;
  enum class LatheRead : std::uint8_t { None, Searching, Collecting };
  LatheRead lathe_read_ = LatheRead::None;  ///< reading a G70-G72 profile Nns..Nnf
  LinePos lathe_cycle_pos_;                 ///< the cycle's line
  std::string lathe_cycle_text_;            ///< ... its text (for its errors)
  bool lathe_return_ = false;  ///< after the profile, back to the line after the cycle's
};

/// Both halves, what ProgramStream pulls a line at a time: on one thread, or with read-ahead
/// (InterpreterOptions::read_ahead) the lines read and parsed on a second thread (ParallelFront)
/// until the program first jumps (a loop or a call re-reads it: the reader stops and the rest is
/// read here, seeking as asked). The same lines reach the interpreter either way.
class LineDriver {
 public:
  /// `tally`: where tally() adds the summary's moves up (null: tally() is not called).
  LineDriver(std::istream& in, std::string filename, const InterpreterOptions& opts,
             MoveTally* tally = nullptr)
      : front_(in, fanuc_family(opts.dialect)),
        back_(std::move(filename), opts),
        source_(front_, back_),
        tally_(tally) {
    if (opts.read_ahead)  // front_ reads nothing yet
      ahead_ = std::make_unique<ParallelFront>(
          in, fanuc_family(opts.dialect),
          opts.dialect == Dialect::LinuxCNC ? &back_.machine().layout : nullptr, tally);
  }
  /// Reads, parses and interprets one line; false when the program is over.
  bool step(std::vector<Canon>& out, std::vector<Diagnostic>& diags);
  /// Adds the commands step() just gave to the tally: on the reader thread while it reads
  /// ahead (ParallelFront::defer), else here. The tally is complete after stop_reading().
  void tally(const std::vector<Canon>& out) {
    if (batch_ != nullptr)
      ahead_->defer(out);
    else
      tally_->add(out);
  }
  /// Stops reading ahead (the program is over): the tally is complete.
  void stop_reading() {
    back_.keep_last_line();
    batch_ = nullptr;
    ahead_.reset();
  }
  const ProgramRunner& back() const { return back_; }
  /// The program is over: writes the parameter file (once).
  void finish(std::vector<Diagnostic>& diags) { back_.save_parameters(diags); }

 private:
  /// step() on the reader thread's lines (file 0, the program).
  bool step_ahead(std::vector<Canon>& out, std::vector<Diagnostic>& diags);

  LineParser front_;
  ProgramRunner back_;
  LineSource source_;
  MoveTally* tally_;
  ParsedLine line_;
  std::unique_ptr<ParallelFront> ahead_;   ///< read-ahead until the first jump, else null
  ParallelFront::Batch* batch_ = nullptr;  ///< the batch being interpreted
  std::size_t next_ = 0;                   ///< its next line
};

}  // namespace gm
