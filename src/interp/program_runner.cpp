// The program driver's back half, a short ordered classifier of each line (program rules,
// dialect rules, control flow, expressions, the interpreter), and the line driver.
#include "interp/program_runner.hpp"

#include "common/error_codes.hpp"

#include <fmt/format.h>

#include <cstdlib>

namespace gm {

namespace {

// An interpreter error on the line whose text is `text`, as a diagnostic.
Diagnostic error_diagnostic(const InterpError& err, const std::string& text) {
  return Diagnostic{Severity::Error, static_cast<int>(err.code), err.loc, err.message,
                    echoed_line(text)};
}

LinePos position_of(const ParsedLine& p) {
  return LinePos{p.offset, p.next_offset, p.number, p.file};
}

// check_all reads on after at most this many calls to subroutines found nowhere (each re-reads
// the rest of the program), then stops checking.
constexpr int kMaxDroppedCalls = 100;

}  // namespace

ProgramRunner::ProgramRunner(std::string filename, const InterpreterOptions& opts)
    : filename_(std::move(filename)),
      machine_(opts.machine ? *opts.machine : default_machine_),
      block_delete_(opts.block_delete),
      check_all_(opts.check_all),
      fanuc_subs_disabled_(opts.fanuc_subs_disabled),
      interp_(machine_),
      system_(interp_, params_, opts.parameter_file),
      files_(opts.subroutine_path),
      flow_(params_, opts.max_iterations, &files_),
      g7x_(interp_, flow_),
      rules_(opts.dialect) {
  interp_.set_result_parameters(&params_);
  // The parameter file: read before the first line (its offsets apply, LinuxCNC Interp::init);
  // an error there is reported with the first line processed and stops the program.
  Diagnostic error;
  if (!system_.load(error)) start_error_.push_back(std::move(error));
  if (fanuc_family(opts.dialect)) {  // Fanuc Macro B: vacant variables, IF/GOTO/WHILE, G65
    macro_vars_.start();
    macro_vars_.set_haas(opts.dialect == Dialect::Haas);
    evaluator_.set_macro(&macro_vars_);
    flow_.set_macro(&macro_vars_);
    files_.set_macro_b(true);
    interp_.allow_comp_reissue();
  }
  fanuc_lathe_ = fanuc_family(opts.dialect) && machine_.lathe;
  fanuc_.set_lathe(fanuc_lathe_);
  if (fanuc_lathe_) {  // X words are diameters and the plane is ZX from the start
    grammar::Block lathe;
    FanucLathe::start_block(lathe);
    std::vector<Canon> none;
    InterpError err;
    interp_.execute(lathe, none, err);
  }
  grammar::Block start;
  if (rules_.start_block(start)) {
    std::vector<Canon> none;
    InterpError err;
    interp_.execute(start, none, err);
  }
}

bool ProgramRunner::process(ParsedLine& p, std::vector<Canon>& out, std::vector<Diagnostic>& diags,
                            FlowJump& jump) {
  if (start_failed(diags)) return false;
  const std::size_t first = diags.size();
  Line l{p, out, diags, jump};
  const bool more = process_line(l);
  if (p.file > 0)
    for (std::size_t i = first; i < diags.size(); ++i) diags[i].file = files_.file_name(p.file);
  return more;
}

// The decisions on a line, in order; each returns whether the program goes on.
bool ProgramRunner::process_line(Line& l) {
  ParsedLine& p = l.p;
  grammar::Block& block = p.block;
  l.jump.seek = false;
  if (done_) return false;
  remember(p.text);
  if (!rules_.line_fits(p.next_offset - p.offset, p.truncated, p.number, p.text, l.diags))
    return true;
  if (fanuc_lathe_) {
    if (p.file == 0 && !p.truncated && p.block.sequence >= 0)
      lathe_.note_sequence(p.block.sequence, FanucLathe::Seen{p.offset, p.next_offset, p.number});
    if (lathe_read_ != LatheRead::None) return lathe_profile_line(l);
  }
  if (flow_.finding_sequence()) {
    bool handled = false;
    const bool more = sequence_search(l, handled);
    if (handled) return more;
  }
  if (flow_.skipping()) return skipped_line(l);
  if (rules_.passed_over(p.text, p.truncated, p.number, l.diags)) return true;
  if (p.truncated) return truncated_line(l);
  if (block.block_delete && block_delete_ && rules_.honours_block_delete()) return true;
  if (!well_formed(l)) return true;
  if (block.percent && first_content_seen_) {  // the closing '%' ends the program
    l.out.emplace_back(Event{p.number, EventKind::End, {}});
    done_ = true;
    return false;
  }
  if (block.percent) opened_percent_ = first_content_seen_ = true;
  main_m99_ends(block);
  if (block.oword.kind != grammar::OKind::None) {
    first_content_seen_ = true;
    return control(l);
  }
  if (block.words.empty() && block.message_count == 0 && !block.needs_evaluation()) return true;
  first_content_seen_ = true;
  if (!block.words.empty()) ++blocks_;
  return content(l);
}

// Passing over lines (a false condition, a sub's body): only O-words matter, nothing else is
// checked.
bool ProgramRunner::skipped_line(Line& l) {
  const ParsedLine& p = l.p;
  InterpError err;  // a sub searched for past the closing '%' (rs274: not found)
  if (p.block.percent && opened_percent_ && p.file == 0 && !p.truncated &&
      !flow_.closing_percent(SourceLoc{p.number, static_cast<int>(p.text.find('%')) + 1}, err))
    return stop(err, l);
  if (p.truncated || p.block.oword.kind == grammar::OKind::None) return true;
  return control(l);
}

// A GOTO's search for its sequence number (Fanuc Macro B): the line numbered N n runs (not
// `handled`); others are passed over; the program's closing '%' sends the search to its start.
bool ProgramRunner::sequence_search(Line& l, bool& handled) {
  const ParsedLine& p = l.p;
  InterpError err;
  handled = true;
  const int found = p.truncated ? 0 : flow_.sequence_line(p.block.sequence, position_of(p), err);
  if (found < 0) return stop(err, l);
  if (found > 0) {
    handled = false;
    return true;
  }
  if (p.block.percent && p.file == 0 && opened_percent_ && !flow_.sequence_wrapped())
    return flow_.sequence_end(l.jump, err) || stop(err, l);
  return skipped_line(l);
}

bool ProgramRunner::truncated_line(Line& l) {
  l.diags.push_back(Diagnostic{Severity::Error,
                               static_cast<int>(ErrorCode::LineTooLong),
                               SourceLoc{l.p.number, 1},
                               fmt::format("line longer than {} bytes", grammar::kMaxLineLength),
                               {}});
  return true;
}

// The grammar's errors, then what the dialect refuses: reported, and the line is not run.
bool ProgramRunner::well_formed(Line& l) {
  grammar::Block& block = l.p.block;
  if (block.percent_text && fanuc_family(rules_.dialect())) {  // `% vfd enable`: a tape marker
    l.diags.push_back(Diagnostic{Severity::Warning, 0, block.errors[0].loc,
                                 "text after a '%' tape marker is passed over (--dialect fanuc)",
                                 echoed_line(l.p.text)});
    block.errors.clear();
  }
  if (block.has_errors()) {
    for (const auto& e : block.errors)
      l.diags.push_back(Diagnostic{Severity::Error, static_cast<int>(e.code), e.loc, e.message,
                                   echoed_line(l.p.text)});
    first_content_seen_ = true;
    return false;
  }
  if (rules_.accepts(block, l.p.text, l.diags)) return true;
  first_content_seen_ = true;
  return false;
}

// M99 in the main program ends it as M2 does (rs274; LinuxCNC's task would loop).
void ProgramRunner::main_m99_ends(grammar::Block& block) const {
  if (block.oword.kind != grammar::OKind::M99 || flow_.call_depth() != 0) return;
  block.oword.kind = grammar::OKind::None;
  for (grammar::Word& w : block.words)
    if (w.letter == 'M' && w.value == 99.0) w.value = 2.0;
}

// A line with words, messages or expressions: evaluated, then collected for a G7x profile or
// run by the interpreter.
bool ProgramRunner::content(Line& l) {
  grammar::Block& block = l.p.block;
  if (block.needs_evaluation()) {
    bool more = true;
    if (!evaluate(l, more)) return more;
  }
  if (rules_.dialect() != Dialect::LinuxCNC) {  // (LinuxCNC: none of these, nothing looked at)
    if (rules_.dialect() == Dialect::Haas && HaasCodes::local_call(block)) return local_call(l);
    if (!dialect_rewrite(l)) return true;
    if (!rules_.machine_codes(block, l.p.text, l.diags)) return true;
    if (!rules_.fanuc_dwell(block, fanuc_lathe_, interp_.state().motion, l.p.text, l.diags))
      return true;
  }
  InterpError err;
  if (g7x_.collecting()) {  // a G7x profile: read, not run
    if (!g7x_.collect(block, err)) l.diags.push_back(error_diagnostic(err, l.p.text));
    return true;
  }
  const grammar::Block* macro =
      fanuc_family(rules_.dialect()) ? modal_call_.after(block, flow_.call_depth()) : nullptr;
  if (macro == nullptr) return run_block(l);
  const std::size_t reported = l.diags.size();
  if (!run_block(l)) return false;
  for (std::size_t i = reported; i < l.diags.size(); ++i)
    if (l.diags[i].severity == Severity::Error) return true;  // the move failed: no call
  return modal_macro(l, *macro);
}

// G66's call after a block that moved: as a G65 line (II-15.6.1) after it.
bool ProgramRunner::modal_macro(Line& l, const grammar::Block& call) {
  InterpError err;
  const int depth = flow_.call_depth();
  if (!flow_.handle(call, position_of(l.p), l.jump, err)) return stop(err, l);
  if (flow_.call_depth() != depth) macro_vars_.set_program(flow_.program_number(main_program_));
  if (flow_.call_depth() > depth) interp_.enter_call(flow_.call_depth());
  return true;
}

// Haas's M97 P n L k: a call of the blocks from N n of this program to M99.
bool ProgramRunner::local_call(Line& l) {
  InterpError err;
  const int depth = flow_.call_depth();
  system_.set_line(l.p.number);
  if (!flow_.m97(l.p.block, position_of(l.p), err)) return stop(err, l);
  if (flow_.call_depth() > depth) interp_.enter_call(flow_.call_depth());
  return true;
}

// What the dialect reads apart from LinuxCNC (Haas's codes, Mach3's, Fanuc's modal rules, tools
// missing from the table), rewritten into the block the interpreter runs. False when the line
// is done: an error reported, or nothing left to run.
bool ProgramRunner::dialect_rewrite(Line& l) {
  grammar::Block& block = l.p.block;
  const Dialect d = rules_.dialect();
  InterpError err;
  bool ok = true;
  if (d == Dialect::Haas) ok = haas_.apply(block, interp_, l.p.text, l.out, l.diags, err);
  if (d == Dialect::Mach3) rules_.mach3_codes(block, l.p.text, l.diags);
  if (ok && fanuc_family(d)) ok = modal_call_.take(block, flow_.call_depth(), err);
  if (ok && fanuc_family(d) && !g7x_.collecting()) {
    ok = fanuc_.apply(block, interp_.state(), err);
    macro_vars_.set_transforms(fanuc_.scaling(), fanuc_.rotating(), fanuc_.polar());
  }
  if (!ok) {
    l.diags.push_back(error_diagnostic(err, l.p.text));
    return false;
  }
  if (!fanuc_lathe_) add_missing_tools(l);  // (a lathe's T0101: once it is read as tool 1)
  return !(block.words.empty() && block.message_count == 0);
}

// Tools the block names and the table lacks, added as zero-length tools (all dialects but
// LinuxCNC's, whose error stays).
void ProgramRunner::add_missing_tools(Line& l) {
  std::vector<ToolEntry> add;
  rules_.missing_tools(l.p.block, interp_.tables().tools, l.p.text, l.diags, add);
  for (const ToolEntry& e : add) interp_.add_tool(e);
}

// Expressions, parameter settings and the directive comments; false when nothing is left to
// run, `more` then saying whether the program goes on.
bool ProgramRunner::evaluate(Line& l, bool& more) {
  grammar::Block& block = l.p.block;
  InterpError err;
  system_.set_line(l.p.number);
  if (!evaluator_.run(block, params_, err)) {
    l.diags.push_back(error_diagnostic(err, l.p.text));
    if (err.code == ErrorCode::CommentAbort) {  // Fanuc's #3000 alarm stops the program
      stopped_here(err.loc, l.diags, "an alarm stops the program");
      done_ = true;
      more = false;
    }
    return false;
  }
  system_.apply_program_writes();
  for (std::size_t i = 0; i < block.directive_count; ++i)
    if (!directive(block.directives[i], l)) return more = false;
  return !(block.words.empty() && block.message_count == 0);
}

bool ProgramRunner::run_block(Line& l) {
  InterpError err;
  if (fanuc_lathe_) {
    bool handled = false;
    const bool more = lathe_block(l, handled);
    if (handled) return more;
    add_missing_tools(l);
  }
  if (!interp_.execute(l.p.block, l.p.imported ? &l.p.words : nullptr, l.out, err)) {
    l.diags.push_back(error_diagnostic(err, l.p.text));
    return true;
  }
  if (l.p.block.sequence >= 0) macro_vars_.set_sequence(l.p.block.sequence);  // #4114
  system_.export_state();
  if (g7x_.pending() && !g7x_.start(position_of(l.p), l.jump, err)) return stop(err, l);
  if (!interp_.state().ended) return true;
  done_ = true;
  return false;
}

// A block under Fanuc/Haas lathe conventions: rewritten (U/W, T0101, G50, ...) and run by the
// caller (not `handled`), or a cycle's first block (recorded), G76 (run here) or G70-G72 with P Q
// (its profile Nns..Nnf is read next: forward, or from where N ns was seen above).
bool ProgramRunner::lathe_block(Line& l, bool& handled) {
  InterpError err;
  FanucLathe::Outcome o = FanucLathe::Outcome::Run;
  handled = true;
  if (!lathe_.rewrite(l.p.block, interp_.state(), o, err)) {
    l.diags.push_back(error_diagnostic(err, l.p.text));
    return true;
  }
  switch (o) {
    case FanucLathe::Outcome::Run:
      handled = false;
      return true;
    case FanucLathe::Outcome::Recorded:
      return true;
    case FanucLathe::Outcome::Moves:
      lathe_cycle_text_ = l.p.text;
      lathe_moves(l);
      return true;
    case FanucLathe::Outcome::Profile:
      break;
  }
  lathe_cycle_pos_ = position_of(l.p);
  lathe_cycle_text_ = l.p.text;
  lathe_read_ = LatheRead::Searching;
  const FanucLathe::Seen* above = l.p.file == 0 ? lathe_.seen(lathe_.profile_first()) : nullptr;
  if (above != nullptr && above->offset >= l.p.offset) above = nullptr;
  lathe_return_ = above != nullptr || lathe_.cycle_code() == 70;
  if (above != nullptr) {
    l.jump.seek = true;
    l.jump.offset = above->offset;
    l.jump.line = above->line;
    l.jump.file = 0;
  }
  return true;
}

// A line while a G70-G72 profile is read: passed over until N ns, then collected up to N nf,
// when the cycle's moves run (and reading goes back after the cycle's line if it must).
bool ProgramRunner::lathe_profile_line(Line& l) {
  ParsedLine& p = l.p;
  if (lathe_read_ == LatheRead::Searching) {
    if (p.truncated || p.file != lathe_cycle_pos_.file ||
        p.block.sequence != lathe_.profile_first())
      return true;
    lathe_read_ = LatheRead::Collecting;
  }
  if (p.truncated) return truncated_line(l);
  if (!well_formed(l)) {
    lathe_read_ = LatheRead::None;
    stopped_here(SourceLoc{p.number, 1}, l.diags, "a profile block is wrong");
    done_ = true;
    return false;
  }
  if (p.block.needs_evaluation()) {
    bool more = true;
    if (!evaluate(l, more) && !more) return false;
  }
  InterpError err;
  if (!lathe_.collect(p.block, err)) {
    lathe_read_ = LatheRead::None;
    return stop(err, l);
  }
  if (p.block.sequence != lathe_.profile_last()) return true;
  lathe_read_ = LatheRead::None;
  if (!lathe_.finish_profile(err)) {
    l.diags.push_back(
        error_diagnostic(err, err.loc.line == lathe_cycle_pos_.line ? lathe_cycle_text_ : p.text));
  } else {
    lathe_moves(l);
  }
  if (lathe_return_) {
    l.jump.seek = true;
    l.jump.offset = lathe_cycle_pos_.next;
    l.jump.line = lathe_cycle_pos_.line + 1;
    l.jump.file = lathe_cycle_pos_.file;
  }
  return true;
}

// The moves of the cycle just read, run as G0-G3/G33 blocks of the cycle's line.
bool ProgramRunner::lathe_moves(Line& l) {
  std::vector<grammar::Block> blocks;
  lathe_.move_blocks(interp_.state(), blocks);
  for (const grammar::Block& b : blocks) {
    InterpError err;
    if (!interp_.execute(b, l.out, err)) {
      l.diags.push_back(error_diagnostic(err, lathe_cycle_text_));
      return false;
    }
  }
  system_.export_state();
  return true;
}

// An O-word line: control flow. An error there ends the program (the flow state is lost).
bool ProgramRunner::control(Line& l) {
  ParsedLine& p = l.p;
  system_.set_line(p.number);
  InterpError err;
  const int depth = flow_.call_depth();
  const grammar::OKind kind = p.block.oword.kind;
  if (fanuc_sub_refused(l)) return true;
  if (kind == grammar::OKind::IfThen && !flow_.skipping()) return macro_then(l);
  if ((kind == grammar::OKind::M98 || kind == grammar::OKind::M99 || kind == grammar::OKind::G65) &&
      !flow_.skipping() && p.block.needs_evaluation() && !evaluator_.run(p.block, params_, err))
    return stop(err, l);
  if (kind == grammar::OKind::Program && depth == 0 && main_program_ < 0 && !flow_.skipping())
    main_program_ = std::atol(p.block.oword.label.c_str());
  bool ok = flow_.handle(p.block, position_of(p), l.jump, err);
  if (ok && flow_.call_depth() != depth)
    macro_vars_.set_program(flow_.program_number(main_program_));  // #4115
  // The interpreter keeps M70/M73 modes per call level (machine's, interp/saved_modes.cpp).
  if (ok && flow_.call_depth() > depth) interp_.enter_call(flow_.call_depth());
  if (ok && flow_.call_depth() < depth) ok = interp_.leave_call(depth, p.number, l.out, err);
  if (ok && !g7x_.after_return(depth, p.number, l.out, err)) {
    l.diags.push_back(error_diagnostic(err, p.text));
    return true;
  }
  return ok || stop(err, l);
}

// `IF [condition] THEN #i = expression` (Fanuc Macro B, B-63534EN II-15.5.2): the setting is
// made when the condition holds.
bool ProgramRunner::macro_then(Line& l) {
  InterpError err;
  bool holds = false;
  if (!flow_.condition(l.p.block, holds, err)) return stop(err, l);
  if (!holds) return true;
  l.p.block.oword.kind = grammar::OKind::None;
  return content(l);
}

// [RS274NGC]DISABLE_FANUC_STYLE_SUB: M98, M99 in a subprogram and a bare O-word line are
// errors, also on lines passed over (rs274 refuses them as it reads the line). The line is
// not run; the program reads on.
bool ProgramRunner::fanuc_sub_refused(Line& l) const {
  const grammar::OWord& o = l.p.block.oword;
  if (!fanuc_subs_disabled_) return false;
  const char* what = o.kind == grammar::OKind::M98                             ? "M98"
                     : o.kind == grammar::OKind::M99 && flow_.call_depth() > 0 ? "M99"
                     : o.kind == grammar::OKind::Program ? "a bare O-word (a subprogram)"
                                                         : nullptr;
  if (what == nullptr) return false;
  l.diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::SubprogramMisused),
                               o.loc,
                               fmt::format("{}: Fanuc-style subprograms are disabled "
                                           "([RS274NGC]DISABLE_FANUC_STYLE_SUB)",
                                           what),
                               echoed_line(l.p.text)});
  return true;
}

// ABORT ends the program with a located error; LOG comments write nothing (no log directory
// is configured), LOGOPEN/LOGAPPEND say so once. False when the program is over.
bool ProgramRunner::directive(const grammar::Message& m, Line& l) {
  using grammar::CommentKind;
  if (m.kind == CommentKind::Abort) {
    l.diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::CommentAbort), m.loc,
                                 fmt::format("program aborted: {}", m.text),
                                 echoed_line(l.p.text)});
    done_ = true;
    return false;
  }
  if ((m.kind == CommentKind::LogOpen || m.kind == CommentKind::LogAppend) && !log_warned_) {
    log_warned_ = true;
    l.diags.push_back(Diagnostic{Severity::Warning, 0, m.loc,
                                 fmt::format("log file '{}' not written: no log directory is "
                                             "allowed (LOG comments are ignored)",
                                             m.text),
                                 echoed_line(l.p.text)});
  }
  return true;
}

bool ProgramRunner::stop(const InterpError& err, Line& l) {
  l.diags.push_back(error_diagnostic(err, l.p.text));
  stopped_here(err.loc, l.diags, "the control flow after this line is unknown");
  done_ = true;
  l.jump.seek = false;
  return false;
}

void ProgramRunner::stopped_here(SourceLoc loc, std::vector<Diagnostic>& diags,
                                 std::string_view why) const {
  if (!check_all_) return;
  diags.push_back(Diagnostic{Severity::Note,
                             0,
                             loc,
                             fmt::format("checking stopped here: {}", why),
                             {},
                             diags.empty() ? std::string() : diags.back().file});
}

bool ProgramRunner::end_of_input(int last_line, std::vector<Diagnostic>& diags, FlowJump& jump,
                                 int file) {
  jump.seek = false;
  if (start_failed(diags) || done_) return false;
  if (flow_.finding_sequence()) {  // a GOTO's search met the end: from the program's start
    InterpError err;
    if (flow_.sequence_end(jump, err)) return true;
    diags.push_back(Diagnostic{Severity::Error,
                               static_cast<int>(err.code),
                               err.loc,
                               err.message,
                               {},
                               files_.file_name(file)});
    done_ = true;
    return false;
  }
  done_ = true;
  if (lathe_read_ != LatheRead::None) {  // the input ended inside a lathe cycle's profile
    diags.push_back(Diagnostic{
        Severity::Error, static_cast<int>(ErrorCode::CycleMisused), lathe_.cycle_loc(),
        lathe_read_ == LatheRead::Searching
            ? fmt::format("{}: no block N{} {}", lathe_.cycle_name(), lathe_.profile_first(),
                          lathe_return_ ? "in the program" : "after the cycle's line")
            : fmt::format("{}: the profile from N{} has no last block N{}", lathe_.cycle_name(),
                          lathe_.profile_first(), lathe_.profile_last()),
        echoed_line(lathe_cycle_text_), files_.file_name(lathe_cycle_pos_.file)});
    return false;
  }
  InterpError err;
  int err_file = 0;
  if (!flow_.at_end(last_line, err, err_file)) {
    diags.push_back(Diagnostic{Severity::Error,
                               static_cast<int>(err.code),
                               err.loc,
                               err.message,
                               {},
                               files_.file_name(err_file)});
    // The subroutine is nowhere: the rest of the program is read as if the call had returned.
    if (!check_all_ || err.code != ErrorCode::UndefinedSubroutine) return false;
    if (++dropped_calls_ > kMaxDroppedCalls) {
      stopped_here(err.loc, diags,
                   fmt::format("more than {} calls to missing subroutines", kMaxDroppedCalls));
      return false;
    }
    done_ = !flow_.drop_missing_call(jump);
    return !done_;
  }
  keep_last_line();
  if (!interp_.state().ended)
    rules_.missing_end(last_line, opened_percent_, last_line_, files_.file_name(file), diags);
  return false;
}

void ProgramRunner::cannot_open(int file, int line, int from_file, std::vector<Diagnostic>& diags) {
  diags.push_back(Diagnostic{Severity::Error,
                             static_cast<int>(ErrorCode::SubroutineFile),
                             SourceLoc{line, 1},
                             fmt::format("cannot read subroutine file {}", files_.file_name(file)),
                             {},
                             files_.file_name(from_file)});
  done_ = true;
}

void ProgramRunner::cannot_seek(int line, std::vector<Diagnostic>& diags) {
  diags.push_back(Diagnostic{
      Severity::Error,
      static_cast<int>(ErrorCode::NotSeekable),
      SourceLoc{line, 1},
      "loops and subroutine calls re-read the program, which cannot seek here (a pipe?): "
      "give it as a file",
      {}});
  done_ = true;
}

bool ProgramRunner::report_start_error(std::vector<Diagnostic>& diags) {
  for (Diagnostic& d : start_error_) diags.push_back(std::move(d));
  start_error_.clear();
  done_ = true;
  return true;
}

void ProgramRunner::keep_last_line() {
  if (last_text_ == nullptr) return;
  if (last_text_->size() <= 512)
    last_line_ = *last_text_;
  else
    last_line_.clear();
  last_text_ = nullptr;
}

bool LineDriver::step(std::vector<Canon>& out, std::vector<Diagnostic>& diags) {
  if (back_.done()) return false;
  if (ahead_) return step_ahead(out, diags);
  FlowJump jump;
  if (!source_.next(line_)) {
    const int last = source_.last_number();
    return back_.end_of_input(last, diags, jump, source_.file()) && source_.go(jump, last, diags);
  }
  const bool more = back_.process(line_, out, diags, jump);
  back_.keep_last_line();  // (line_ is read into next)
  const int number = line_.number;
  line_.trim();
  if (more && jump.seek && !source_.go(jump, number, diags)) return false;
  return more;
}

bool LineDriver::step_ahead(std::vector<Canon>& out, std::vector<Diagnostic>& diags) {
  if (batch_ == nullptr || next_ == batch_->count) {
    if (batch_ == nullptr || !batch_->eof) {  // (a released batch is the reader's again)
      back_.keep_last_line();
      if (batch_ != nullptr) ahead_->release();
      batch_ = &ahead_->acquire();
      next_ = 0;
    }
    if (next_ == batch_->count) {  // the input ended after the lines handed out
      const int last = batch_->last_number;
      back_.keep_last_line();
      batch_ = nullptr;
      ahead_.reset();
      FlowJump jump;
      return back_.end_of_input(last, diags, jump) && source_.go(jump, last, diags);
    }
  }
  ParsedLine& p = batch_->lines[next_++];
  FlowJump jump;
  const bool more = back_.process(p, out, diags, jump);
  if (more && jump.seek) {
    const int number = p.number;
    back_.keep_last_line();
    batch_ = nullptr;
    ahead_.reset();  // the reader stops; its batches are dropped
    return source_.go(jump, number, diags);
  }
  return more;
}

}  // namespace gm
