// O-word control flow: a stack of open subs/ifs/loops, a skip state for passing over lines, and
// the positions of the subs seen so far; backward jumps are seeks the driver performs.
#include "interp/oword_flow.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

namespace {

using grammar::OKind;

std::string label_of(const grammar::OWord& o) {
  if (o.kind == OKind::M98 || o.kind == OKind::M99) return std::string(grammar::okind_name(o.kind));
  return o.named ? "o<" + o.label + ">" : "o" + o.label;
}

// Continue at the line `p` (`after`: at the line after it).
void seek_to(FlowJump& jump, const LinePos& p, bool after) {
  jump.seek = true;
  jump.offset = after ? p.next : p.offset;
  jump.line = after ? p.line + 1 : p.line;
  jump.file = p.file;
}

}  // namespace

bool OwordFlow::evaluate_arg(const grammar::Block& b, std::size_t i, double& v, InterpError& err) {
  const grammar::OWord& o = b.oword;
  if (i >= o.args.size())
    return fail(err, ErrorCode::BadOWord, o.loc,
                fmt::format("{} {} needs a [value]", label_of(o), grammar::okind_name(o.kind)));
  return eval_.evaluate(b, o.args[i], params_, v, err);
}

bool OwordFlow::count_iteration(SourceLoc loc, InterpError& err) {
  if (++iterations_ > max_iterations_)
    return fail(err, ErrorCode::TooManyIterations, loc,
                fmt::format("loops and calls ran past --max-iterations ({})", max_iterations_));
  return true;
}

void OwordFlow::skip(Skip mode, const std::string& label, const grammar::Block& b, int file) {
  skip_.mode = mode;
  skip_.started_file = file;
  skip_.file = file;
  skip_.label = label;
  skip_.shown = label_of(b.oword);
  skip_.started = b.oword.loc;
  skip_.started_kind = b.oword.kind;
}

int OwordFlow::find_loop(const std::string& label) const {
  for (int i = static_cast<int>(stack_.size()) - 1; i >= 0; --i) {
    const Open& f = stack_[static_cast<std::size_t>(i)];
    if (f.kind == Frame::Call) return -1;  // loops do not reach across a call
    // rs274 2.9: break and continue belong to while and do loops only (not repeat).
    if ((f.kind == Frame::While || f.kind == Frame::Do) && f.label == label) return i;
  }
  return -1;
}

bool OwordFlow::note_label(const grammar::OWord& o, Frame kind, const LinePos& pos,
                           InterpError& err) {
  label_key_.clear();
  for (auto f = stack_.rbegin(); f != stack_.rend(); ++f)
    if (f->kind == Frame::Call) {
      label_key_ = f->label;
      break;
    }
  label_key_ += '#';
  label_key_ += o.label;
  const auto it = labels_.find(label_key_);
  if (it == labels_.end()) {
    if (labels_.size() < kMaxLabels) labels_.emplace(label_key_, LabelUse{kind, pos.line});
    return true;
  }
  // rs274 compares line numbers only; a while may close a do of the same label.
  if (kind == Frame::Do || it->second.line == pos.line ||
      (kind == Frame::While && it->second.kind == Frame::Do))
    return true;
  constexpr const char* kNames[] = {"call", "if", "while", "do", "repeat", "DO"};
  return fail(err, ErrorCode::ControlMismatch, o.loc,
              fmt::format("duplicate O-word label {}: line {} already used it for a {} (LinuxCNC "
                          "needs its own label for each if, while, do and repeat)",
                          label_of(o), it->second.line, kNames[static_cast<int>(it->second.kind)]));
}

bool OwordFlow::handle(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                       InterpError& err) {
  if (b.oword.label_expr) {
    // O[#2*10], o#<name>: rs274 2.9 evaluates the number whenever it reads the line, passed over
    // or not; inside a sub's definition a name not yet set reads as 0.
    double v = 0.0;
    if (!eval_.evaluate(b, b.oword.args[0], params_, v, err)) {
      if (skip_.mode != Skip::SubBody || err.code != ErrorCode::UndefinedParameter) return false;
      err = InterpError{};
      v = 0.0;
    }
    const double n = std::round(v);
    if (!(std::fabs(v - n) < 1e-4) || n < 0 || n > 99999999)
      return fail(
          err, ErrorCode::BadOWord, b.oword.loc,
          fmt::format("O[...] gives {}: an O-word number is a whole number 0..99999999", v));
    grammar::Block numbered = b;
    numbered.oword.label_expr = false;
    numbered.oword.label = fmt::format("{}", static_cast<long>(n));
    numbered.oword.args.erase(numbered.oword.args.begin());
    return skipping() ? skipped(numbered, pos, jump, err) : normal(numbered, pos, jump, err);
  }
  return skipping() ? skipped(b, pos, jump, err) : normal(b, pos, jump, err);
}

bool OwordFlow::enter_sub(const std::string& label, const LinePos& body, SourceLoc loc,
                          FlowJump& jump, bool seek, InterpError& err) {
  if (calls_ >= kMaxCallDepth)
    return fail(
        err, ErrorCode::CallTooDeep, loc,
        fmt::format("too many nested subroutine calls (LinuxCNC allows {})", kMaxCallDepth));
  if (!count_iteration(loc, err)) return false;
  Open call{Frame::Call, label, pending_return_};
  call.fanuc = pending_fanuc_;
  call.again = pending_again_;
  call.macro = pending_macro_;
  stack_.push_back(call);
  if (pending_macro_) {  // G65: #1-#33 its own, vacant but for the arguments
    params_.push_frame(true, ParameterStore::kMacroLocals);
    for (int i = 0; i < ParameterStore::kMacroLocals; ++i)
      params_.set_system(i + 1, pending_locals_[static_cast<std::size_t>(i)]);
  } else {
    params_.push_frame(!pending_fanuc_);  // M98: #1-#30 stay global
  }
  // An O-call starts #1-#30 from its arguments and 0 for those it does not pass (rs274).
  for (std::size_t i = 0; i < static_cast<std::size_t>(ParameterStore::kArgs); ++i)
    if (!pending_macro_ && (i < pending_args_.size() || !pending_fanuc_))
      params_.set(static_cast<int>(i) + 1, i < pending_args_.size() ? pending_args_[i] : 0.0);
  ++calls_;
  if (seek) seek_to(jump, body, true);
  return true;
}

bool OwordFlow::leave_sub(const grammar::Block& b, FlowJump& jump, InterpError& err) {
  const grammar::OWord& o = b.oword;
  int at = -1;
  for (int i = static_cast<int>(stack_.size()) - 1; i >= 0; --i)
    if (stack_[static_cast<std::size_t>(i)].kind == Frame::Call) {
      at = i;
      break;
    }
  if (at < 0)
    return fail(
        err, ErrorCode::ControlMismatch, o.loc,
        fmt::format("{} {} outside a called subroutine", label_of(o), grammar::okind_name(o.kind)));
  if (macro_ != nullptr && o.kind == OKind::M99)  // Fanuc's M99 P n returns to N n: not read
    for (const grammar::Word& w : b.words)
      if (w.letter == 'P')
        return fail(err, ErrorCode::NotInDialect, w.loc,
                    "M99 P (return to a sequence number of the caller) is not read: return to "
                    "the block after the call");
  // rs274 returns from the current call whatever the label of `return`/`endsub` (its
  // sample retval.ngc returns from o1000 with `o1010 return`).
  const Open call = stack_[static_cast<std::size_t>(at)];
  // LinuxCNC does not mix the styles: M98's `O1234` ends with M99, `o1234 sub` with endsub.
  if (call.fanuc && o.kind != OKind::M99)
    return fail(err, ErrorCode::SubprogramMisused, o.loc,
                fmt::format("subprogram O{} was called with M98: it must end with M99, not {} {}",
                            call.label, label_of(o), grammar::okind_name(o.kind)));
  if (!call.fanuc && o.kind == OKind::M99)
    return fail(err, ErrorCode::SubprogramMisused, o.loc,
                fmt::format("M99 in subroutine o{}: an 'o... sub' ends with 'endsub' or 'return'",
                            call.label));
  double value = 0.0;
  const bool has_value = o.kind != OKind::M99 && !o.args.empty();
  if (has_value && !evaluate_arg(b, 0, value, err)) return false;
  stack_.resize(static_cast<std::size_t>(at));
  params_.pop_frame();
  params_.set_returned(value, has_value);
  --calls_;
  seek_to(jump, call.pos, !call.again);  // M98 L: the call line runs again
  return true;
}

namespace {

// M98's words: P, the subprogram number, as its label; L (repeats), when given. Besides them
// only M98 itself and N may be written.
bool m98_words(const grammar::Block& b, std::string& label, const grammar::Word*& l,
               InterpError& err) {
  const grammar::Word* p = nullptr;
  l = nullptr;
  bool m98_seen = false;
  for (const grammar::Word& w : b.words) {
    if (w.letter == 'M' && w.value == 98.0 && !m98_seen) {
      m98_seen = true;
    } else if (w.letter == 'P' && p == nullptr) {
      p = &w;
    } else if (w.letter == 'L' && l == nullptr) {
      l = &w;
    } else if (w.letter != 'N') {
      return fail(err, ErrorCode::SubprogramMisused, w.loc,
                  fmt::format("M98 takes P (the subprogram number) and L (repeats) only, not {}",
                              w.letter));
    }
  }
  if (p == nullptr)
    return fail(err, ErrorCode::SubprogramMisused, b.oword.loc,
                "M98 needs P, the number of the subprogram (O1234 ... M99) to call");
  const double pn = std::floor(p->value + 1e-4);
  if (std::abs(p->value - pn) > 1e-4 || pn < 0 || pn > 99999999)
    return fail(err, ErrorCode::SubprogramMisused, p->loc,
                fmt::format("M98 P must be a subprogram number, not {}", p->value));
  label = fmt::format("{}", static_cast<long>(pn));
  return true;
}

}  // namespace

bool OwordFlow::m98(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err) {
  std::string label;
  const grammar::Word* l = nullptr;
  if (!m98_words(b, label, l, err)) return false;
  pending_macro_ = false;
  return fanuc_call(b.oword, label, l, pos, jump, err);
}

// LinuxCNC: the caller's frame counts an M98 (or M97) L's repeats down; while some are left, the
// return comes back to the call line, which calls again. False for `L0`: nothing is called.
bool OwordFlow::count_repeat(const grammar::Word* l) {
  pending_again_ = false;
  if (l == nullptr) return true;
  int& left = m98_loops_[static_cast<std::size_t>(calls_)];
  if (left == -1) left = static_cast<int>(std::lround(l->value));
  --left;
  if (left > 0)
    pending_again_ = true;
  else
    left = -1;
  return l->value != 0.0;
}

bool OwordFlow::fanuc_call(const grammar::OWord& o, const std::string& label,
                           const grammar::Word* l, const LinePos& pos, FlowJump& jump,
                           InterpError& err) {
  if (!count_repeat(l)) return true;
  pending_args_.clear();
  pending_return_ = pos;
  pending_fanuc_ = true;
  grammar::OWord shown = o;
  shown.named = false;
  shown.label = label;
  if (const auto it = subs_.find(label); it != subs_.end()) {
    if (!it->second.fanuc)
      return fail(err, ErrorCode::SubprogramMisused, o.loc,
                  fmt::format("{} P{} calls o{} sub (line {}): an 'o... sub' is called with "
                              "'o... call'; {} calls a bare O{} ... M99",
                              grammar::okind_name(o.kind), label, label, it->second.pos.line,
                              grammar::okind_name(o.kind), label));
    return enter_sub(label, it->second.pos, o.loc, jump, true, err);
  }
  if (calls_ >= kMaxCallDepth) return enter_sub(label, pos, o.loc, jump, false, err);
  skip_.mode = Skip::FindSub;
  skip_.started_file = pos.file;
  skip_.file = pos.file;
  skip_.label = label;
  skip_.shown = "O" + label;
  skip_.started = o.loc;
  skip_.started_kind = o.kind;
  skip_.fanuc = true;
  if (const int file = finder_ != nullptr ? finder_->find(label) : 0; file > 0) {
    skip_.file = file;
    seek_to(jump, LinePos{0, 0, 1, file}, false);
  }
  return true;
}

// FindSub reached the definition `o` at `pos`: enter it (the styles must match).
bool OwordFlow::found_sub(const grammar::OWord& o, const LinePos& pos, FlowJump& jump,
                          InterpError& err) {
  const bool fanuc = o.kind == OKind::Program;
  if (fanuc != skip_.fanuc)
    return fail(
        err, ErrorCode::SubprogramMisused, o.loc,
        fanuc
            ? fmt::format("O{} is a Fanuc-style subprogram: call it with M98 P{}", o.label, o.label)
            : fmt::format("{} sub is called with '{} call', not M98", label_of(o), label_of(o)));
  subs_[o.label] = SubDef{pos, fanuc};
  skip_.mode = Skip::None;
  skip_.fanuc = false;
  return enter_sub(o.label, pos, o.loc, jump, false, err);
}

// An O-word line outside any skip: one function per kind of construct.
bool OwordFlow::normal(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                       InterpError& err) {
  const grammar::OWord& o = b.oword;
  switch (o.kind) {
    case OKind::Sub:
      return define_sub(b, pos, err);
    case OKind::EndSub:
    case OKind::Return:
      return leave_sub(b, jump, err);
    case OKind::Call:
      return call_sub(b, pos, jump, err);
    case OKind::If:
    case OKind::ElseIf:
    case OKind::Else:
    case OKind::EndIf:
      return if_line(b, pos, err);
    case OKind::Do:
      if (!note_label(o, Frame::Do, pos, err)) return false;
      stack_.push_back(Open{Frame::Do, o.label, pos});
      return true;
    case OKind::While:
    case OKind::EndWhile:
      return while_line(b, pos, jump, err);
    case OKind::Repeat:
    case OKind::EndRepeat:
      return repeat_line(b, pos, jump, err);
    case OKind::Break:
    case OKind::Continue:
      return leave_loop(b, pos, jump, err);
    case OKind::M98:
      return m98(b, pos, jump, err);
    case OKind::M99:
      return leave_sub(b, jump, err);
    case OKind::IfGoto:
    case OKind::IfThen:
    case OKind::Goto:
    case OKind::WhileDo:
    case OKind::MacroDo:
    case OKind::EndDo:
    case OKind::G65:
      return macro_statement(b, pos, jump, err);
    case OKind::Program:  // reached in the flow, not by M98: LinuxCNC runs on into it
    case OKind::None:
      break;
  }
  return true;
}

bool OwordFlow::mismatch(const grammar::OWord& o, const char* opens, InterpError& err) const {
  return fail(err, ErrorCode::ControlMismatch, o.loc,
              fmt::format("{} {} without {} {}", label_of(o), grammar::okind_name(o.kind),
                          label_of(o), opens));
}

bool OwordFlow::top_is(const grammar::OWord& o, Frame k) const {
  return !stack_.empty() && stack_.back().kind == k && stack_.back().label == o.label;
}

// `o... sub`: records the definition and passes over its body.
bool OwordFlow::define_sub(const grammar::Block& b, const LinePos& pos, InterpError& err) {
  const grammar::OWord& o = b.oword;
  // Reached while a sub runs (called forward, or from its file): the definition is inside that
  // sub's body. rs274 2.9 would run its body in line and return at its endsub.
  for (auto f = stack_.rbegin(); f != stack_.rend(); ++f) {
    if (f->kind != Frame::Call) continue;
    const bool number = f->label.find_first_not_of("0123456789") == std::string::npos;
    const std::string caller = f->fanuc ? "O" + f->label
                               : number ? "o" + f->label
                                        : "o<" + f->label + ">";
    return fail(err, ErrorCode::ControlMismatch, o.loc,
                fmt::format("nested subroutine definition: {} sub inside the body of the called "
                            "subroutine {}; a sub is defined outside every other sub",
                            label_of(o), caller));
  }
  const auto [it, added] = subs_.emplace(o.label, SubDef{pos, false});
  // The flow reaches a definition it has seen at this very line: a call's search found it
  // further down (or a loop came back to it), so the program runs on into its own subs.
  if (!added && it->second.pos.file == pos.file && it->second.pos.offset == pos.offset)
    return fail(err, ErrorCode::ControlMismatch, o.loc,
                fmt::format("{} sub found in illegal location: the program runs into the "
                            "definition of a subroutine it has already called or defined (end "
                            "the main program with M2 or M30 before its subroutines)",
                            label_of(o)));
  if (!added)
    return fail(err, ErrorCode::SubroutineRedefined, o.loc,
                fmt::format("redefining subroutine {}: already defined at {}line {}", label_of(o),
                            it->second.pos.file > 0 && finder_ != nullptr
                                ? finder_->file_name(it->second.pos.file) + " "
                                : std::string(),
                            it->second.pos.line));
  it->second = SubDef{pos, false};
  skip(Skip::SubBody, o.label, b, pos.file);
  return true;
}

// `o... call [args]`: enters a sub already seen, else searches for it.
bool OwordFlow::call_sub(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                         InterpError& err) {
  const grammar::OWord& o = b.oword;
  double v = 0.0;
  pending_args_.clear();
  for (std::size_t i = 0; i < o.args.size() && i < ParameterStore::kArgs; ++i) {
    if (!evaluate_arg(b, i, v, err)) return false;
    pending_args_.push_back(v);
  }
  pending_return_ = pos;
  pending_fanuc_ = false;
  pending_again_ = false;
  pending_macro_ = false;
  skip_.fanuc = false;
  const auto it = subs_.find(o.label);
  if (it != subs_.end()) {
    if (it->second.fanuc)
      return fail(err, ErrorCode::SubprogramMisused, o.loc,
                  fmt::format("O{} (line {}) is a Fanuc-style subprogram: call it with M98 P{}",
                              o.label, it->second.pos.line, o.label));
    return enter_sub(o.label, it->second.pos, o.loc, jump, true, err);
  }
  if (calls_ >= kMaxCallDepth) return enter_sub(o.label, pos, o.loc, jump, false, err);
  // LinuxCNC's order: a sub already seen, then `name.ngc` on the subroutine path, then a
  // definition further down the current file.
  if (const int file = finder_ != nullptr ? finder_->find(o.label) : 0; file > 0) {
    skip(Skip::FindSub, o.label, b, pos.file);
    skip_.file = file;
    seek_to(jump, LinePos{0, 0, 1, file}, false);
    return true;
  }
  skip(Skip::FindSub, o.label, b, pos.file);  // defined further down: search forward
  return true;
}

// if, elseif, else, endif (a false branch is passed over by the skip state).
bool OwordFlow::if_line(const grammar::Block& b, const LinePos& pos, InterpError& err) {
  const grammar::OWord& o = b.oword;
  if (o.kind == OKind::If) {
    double v = 0.0;
    if (!note_label(o, Frame::If, pos, err)) return false;
    if (!evaluate_arg(b, 0, v, err)) return false;
    stack_.push_back(Open{Frame::If, o.label, pos});
    if (v == 0.0) skip(Skip::IfBranch, o.label, b, pos.file);
    return true;
  }
  if (!top_is(o, Frame::If)) return mismatch(o, "if", err);
  if (o.kind == OKind::EndIf)
    stack_.pop_back();
  else
    skip(Skip::IfDone, o.label, b, pos.file);  // the branch that ran ends here
  return true;
}

// while (opening a while loop, or ending a do loop) and endwhile.
bool OwordFlow::while_line(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                           InterpError& err) {
  const grammar::OWord& o = b.oword;
  double v = 0.0;
  if (o.kind == OKind::EndWhile) {
    if (!top_is(o, Frame::While)) return mismatch(o, "while", err);
    if (!count_iteration(o.loc, err)) return false;
    seek_to(jump, stack_.back().pos, false);  // re-evaluate
    return true;
  }
  if (top_is(o, Frame::Do)) {  // the end of a do ... while loop
    if (!evaluate_arg(b, 0, v, err)) return false;
    if (v != 0.0 && !break_pending_) {
      if (!count_iteration(o.loc, err)) return false;
      seek_to(jump, stack_.back().pos, true);
    } else {
      stack_.pop_back();
      break_pending_ = false;
    }
    return true;
  }
  if (!(top_is(o, Frame::While) && stack_.back().pos.offset == pos.offset)) {
    if (!note_label(o, Frame::While, pos, err)) return false;
    stack_.push_back(Open{Frame::While, o.label, pos});
  }
  if (!evaluate_arg(b, 0, v, err)) return false;
  if (v == 0.0) {
    stack_.pop_back();
    skip(Skip::LoopEnd, o.label, b, pos.file);
  }
  return true;
}

// repeat [n] and endrepeat.
bool OwordFlow::repeat_line(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                            InterpError& err) {
  const grammar::OWord& o = b.oword;
  if (o.kind == OKind::Repeat) {
    double v = 0.0;
    if (!note_label(o, Frame::Repeat, pos, err)) return false;
    if (!evaluate_arg(b, 0, v, err)) return false;
    if (v >= 1.0) {
      stack_.push_back(Open{Frame::Repeat, o.label, pos, v});
    } else {
      skip(Skip::LoopEnd, o.label, b, pos.file);
    }
    return true;
  }
  if (!top_is(o, Frame::Repeat)) return mismatch(o, "repeat", err);
  Open& f = stack_.back();
  f.remaining -= 1.0;
  if (f.remaining >= 1.0) {
    if (!count_iteration(o.loc, err)) return false;
    seek_to(jump, f.pos, true);
  } else {
    stack_.pop_back();
  }
  return true;
}

// break and continue, in the innermost loop with their label.
bool OwordFlow::leave_loop(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                           InterpError& err) {
  const grammar::OWord& o = b.oword;
  const int at = find_loop(o.label);
  if (at < 0) return mismatch(o, "while or do", err);
  const Open loop = stack_[static_cast<std::size_t>(at)];
  if (o.kind == OKind::Break) {
    break_pending_ = true;
    stack_.resize(static_cast<std::size_t>(at));
    skip(Skip::LoopEnd, o.label, b, pos.file);
    return true;
  }
  stack_.resize(static_cast<std::size_t>(at) + 1);
  if (loop.kind == Frame::Do) {
    // rs274 2.9: `continue` in a do loop goes to its `while` line as if that opened a
    // while loop (the do is forgotten): a true condition runs on past the loop.
    stack_.pop_back();
    skip(Skip::ToLoopEnd, o.label, b, pos.file);
    return true;
  }
  if (loop.kind == Frame::While) {
    if (!count_iteration(o.loc, err)) return false;
    seek_to(jump, loop.pos, false);
  } else {
    skip(Skip::ToLoopEnd, o.label, b, pos.file);
  }
  return true;
}

bool OwordFlow::skipped(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                        InterpError& err) {
  const grammar::OWord& o = b.oword;
  if (skip_.mode == Skip::MacroLoopEnd || skip_.mode == Skip::FindSequence)
    return macro_skipped(b, pos, jump, err);
  // rs274 2.9 (read_o): a `sub` while a definition is open is "Nested subroutine definition".
  if (o.kind == OKind::Sub && skip_.mode == Skip::SubBody)
    return fail(err, ErrorCode::ControlMismatch, o.loc,
                fmt::format("nested subroutine definition: {} sub inside {} sub (line {}); a sub "
                            "is defined outside every other sub",
                            label_of(o), skip_.shown, skip_.started.line));
  if (o.kind == OKind::Sub && skip_.mode != Skip::FindSub)
    subs_.emplace(o.label, SubDef{pos, false});
  if (o.label != skip_.label) return true;
  double v = 0.0;
  switch (skip_.mode) {
    case Skip::SubBody:
      if (o.kind == OKind::EndSub) skip_.mode = Skip::None;
      return true;
    case Skip::FindSub:
      if (o.kind != OKind::Sub && o.kind != OKind::Program) return true;
      return found_sub(o, pos, jump, err);
    case Skip::IfBranch:
      if (o.kind == OKind::ElseIf) {
        if (!evaluate_arg(b, 0, v, err)) return false;
        if (v != 0.0) skip_.mode = Skip::None;
      } else if (o.kind == OKind::Else) {
        skip_.mode = Skip::None;
      } else if (o.kind == OKind::EndIf) {
        skip_.mode = Skip::None;
        if (!stack_.empty()) stack_.pop_back();
      }
      return true;
    case Skip::IfDone:
      if (o.kind == OKind::EndIf) {
        skip_.mode = Skip::None;
        if (!stack_.empty()) stack_.pop_back();
      }
      return true;
    case Skip::LoopEnd:
      if (o.kind == OKind::EndWhile || o.kind == OKind::EndRepeat || o.kind == OKind::While)
        skip_.mode = Skip::None;
      if (o.kind == OKind::While) break_pending_ = false;  // the while ending a do: rs274 runs it
      return true;
    case Skip::ToLoopEnd:
      if (o.kind == OKind::EndRepeat || o.kind == OKind::While) {
        skip_.mode = Skip::None;
        return normal(b, pos, jump, err);
      }
      return true;
    case Skip::MacroLoopEnd:
    case Skip::FindSequence:
    case Skip::None:
      break;
  }
  return true;
}

bool OwordFlow::closing_percent(SourceLoc at, InterpError& err) const {
  if (skip_.mode != Skip::FindSub) return true;
  return fail(err, ErrorCode::UndefinedSubroutine, at,
              fmt::format("subroutine {} (called at line {}) is not defined before the "
                          "program's closing '%': nothing after it is read",
                          skip_.shown, skip_.started.line));
}

bool OwordFlow::drop_missing_call(FlowJump& jump) {
  if (skip_.mode != Skip::FindSub) return false;
  skip_ = SkipState{};
  pending_args_.clear();
  pending_fanuc_ = pending_again_ = pending_macro_ = false;
  m98_loops_[static_cast<std::size_t>(calls_)] = -1;
  seek_to(jump, pending_return_, true);
  return true;
}

bool OwordFlow::at_end(int last_line, InterpError& err, int& err_file) const {
  const std::string label = skip_.label;
  err_file = skip_.started_file;
  if (skip_.mode == Skip::FindSub) {
    if (skip_.file != skip_.started_file && finder_ != nullptr)
      return fail(err, ErrorCode::UndefinedSubroutine, skip_.started,
                  fmt::format("subroutine {} is not defined in its file {}", skip_.shown,
                              finder_->file_name(skip_.file)));
    return fail(err, ErrorCode::UndefinedSubroutine, skip_.started,
                fmt::format("subroutine {} is not defined in the program, and {}", skip_.shown,
                            finder_ != nullptr ? finder_->miss(label)
                                               : std::string("no subroutine path is set")));
  }
  if (skip_.mode != Skip::None)
    return fail(err, ErrorCode::UnterminatedControl, skip_.started,
                fmt::format("the program ends inside this {} (line {} is the last)",
                            grammar::okind_name(skip_.started_kind), last_line));
  if (!stack_.empty()) {
    const Open& f = stack_.back();
    err_file = f.pos.file;
    constexpr const char* kNames[] = {"call", "if", "while", "do", "repeat", "DO"};
    if (f.kind == Frame::MacroLoop)
      return fail(err, ErrorCode::UnterminatedControl, SourceLoc{f.pos.line, 1},
                  fmt::format("the program ends inside the loop DO{} (no END{}; line {} is the "
                              "last)",
                              f.label, f.label, last_line));
    return fail(err, ErrorCode::UnterminatedControl, SourceLoc{f.pos.line, 1},
                fmt::format("the program ends inside {} {} (line {} is the last)", f.label,
                            kNames[static_cast<int>(f.kind)], last_line));
  }
  return true;
}

}  // namespace gm
