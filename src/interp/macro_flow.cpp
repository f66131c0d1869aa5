// Fanuc Macro B's control flow (--dialect fanuc) in OwordFlow: IF [...] GOTO n, GOTO n, WHILE
// [...] DO m ... END m, DO m ... END m and G65 macro calls, over the same stack, skip state and
// seeks as the O-words.
#include "interp/macro_variables.hpp"
#include "interp/oword_flow.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

namespace {

using grammar::OKind;

// Argument specification I (FANUC 16i/18i-MB operator's manual B-63534EN, II-15.6.1): the local
// variable each letter sets; 0 for G, L, N, O, P, which are not arguments.
constexpr int kMacroArgument[26] = {1, 2, 3, 7,  8,  9,  0,  11, 4,  5,  6,  0,  13,
                                    0, 0, 0, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26};

// Argument specification II (Haas 96-8000 "Local Variables", its table of variables, addresses
// and alternates; FANUC B-63684EN p. 278 "Mixture of argument specifications I and II"): A, B,
// C once each set #1-#3 as in I, and the n-th I, J, K (n = 1..10) set #(3n+1), #(3n+2),
// #(3n+3), so that I1 J1 K1 are #4-#6 (specification I's I J K) and I10 J10 K10 #31-#33.
constexpr int kMaxArgumentSets = 10;
constexpr int argument_ii_variable(char letter, int n) {
  return 3 * n + 1 + (letter - 'I');
}
static_assert(argument_ii_variable('I', 1) == 4 && argument_ii_variable('K', 10) == 33);

void macro_seek(FlowJump& jump, const LinePos& p, bool after) {
  jump.seek = true;
  jump.offset = after ? p.next : p.offset;
  jump.line = after ? p.line + 1 : p.line;
  jump.file = p.file;
}

}  // namespace

void OwordFlow::set_macro(MacroVariables* m) {
  macro_ = m;
  eval_.set_macro(m);
}

bool OwordFlow::condition(const grammar::Block& b, bool& holds, InterpError& err) {
  double v = 0.0;
  if (!evaluate_arg(b, 0, v, err)) return false;
  holds = !vacant(v) && v != 0.0;
  return true;
}

bool OwordFlow::macro_statement(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                                InterpError& err) {
  bool holds = false;
  switch (b.oword.kind) {
    case OKind::IfGoto:  // B-63534EN II-15.5.2: IF [condition] GOTO n
      if (!condition(b, holds, err)) return false;
      return !holds || macro_goto(b, 1, pos, jump, err);
    case OKind::Goto:  // II-15.5.1
      return macro_goto(b, 0, pos, jump, err);
    case OKind::WhileDo:  // II-15.5.3
    case OKind::MacroDo:
      return macro_loop(b, pos, jump, err);
    case OKind::EndDo:
      return macro_end(b, pos, jump, err);
    case OKind::G65:  // II-15.6.1
      return g65(b, pos, jump, err);
    default:  // IF ... THEN: its setting is the runner's (ProgramRunner::control)
      return true;
  }
}

bool OwordFlow::macro_goto(const grammar::Block& b, std::size_t arg, const LinePos& pos,
                           FlowJump& /*jump*/, InterpError& err) {
  const grammar::OWord& o = b.oword;
  double v = 0.0;
  if (!evaluate_arg(b, arg, v, err)) return false;
  const double n = std::round(vacant(v) ? -1.0 : v);
  if (!(std::fabs(v - n) < 1e-4) || n < 1 || n > 99999)
    return fail(err, ErrorCode::BadOWord, o.loc,
                fmt::format("GOTO {}: the target is a sequence number 1-99999", v));
  if (!count_iteration(o.loc, err)) return false;
  // Search forward for N n to the program's end, then from its start (the lines between are
  // passed over, not run).
  skip_ = SkipState{};
  skip_.mode = Skip::FindSequence;
  skip_.sequence = static_cast<long>(n);
  skip_.from = pos;
  skip_.started = o.loc;
  skip_.started_kind = o.kind;
  skip_.started_file = skip_.file = pos.file;
  skip_.shown = fmt::format("GOTO {}", skip_.sequence);
  return true;
}

LinePos OwordFlow::program_start() const {
  for (auto f = stack_.rbegin(); f != stack_.rend(); ++f) {
    if (f->kind != Frame::Call) continue;
    if (!f->label.empty() && f->label[0] == 'N') continue;  // M97: the caller's program
    const auto it = subs_.find(f->label);
    if (it == subs_.end()) break;
    const LinePos& d = it->second.pos;
    return LinePos{d.next, d.next, d.line + 1, d.file};
  }
  return LinePos{0, 0, 1, 0};
}

int OwordFlow::sequence_line(long n, const LinePos& pos, InterpError& err) {
  if (pos.file == skip_.file && n == skip_.sequence) {
    skip_ = SkipState{};
    // A GOTO may leave loops (not enter them): the loops of this level the target is outside
    // of are closed.
    while (!stack_.empty() && stack_.back().kind == Frame::MacroLoop) {
      const Open& f = stack_.back();
      const bool inside = f.pos.file == pos.file && pos.offset >= f.pos.offset &&
                          (f.end == 0 || pos.offset <= f.end);
      if (inside) break;
      stack_.pop_back();
    }
    return 1;
  }
  if (skip_.wrapped && pos.file == skip_.from.file && pos.offset >= skip_.from.offset) {
    fail(err, ErrorCode::ControlMismatch, skip_.started,
         fmt::format("{}: no block N{} in this program (searched to its end and from its "
                     "start)",
                     skip_.shown, skip_.sequence));
    return -1;
  }
  return 0;
}

bool OwordFlow::sequence_end(FlowJump& jump, InterpError& err) {
  if (!skip_.wrapped) {
    skip_.wrapped = true;
    macro_seek(jump, program_start(), false);
    return true;
  }
  return fail(err, ErrorCode::ControlMismatch, skip_.started,
              fmt::format("{}: no block N{} in this program", skip_.shown, skip_.sequence));
}

// O-word lines met while passing over lines for a false WHILE or a GOTO's search.
bool OwordFlow::macro_skipped(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                              InterpError& err) {
  const grammar::OWord& o = b.oword;
  if (skip_.mode == Skip::MacroLoopEnd) {
    if (o.kind == OKind::EndDo && o.label == skip_.label) skip_ = SkipState{};
    return true;
  }
  if (o.kind == OKind::EndDo) {  // the search leaves this loop: its extent is now known
    for (auto f = stack_.rbegin(); f != stack_.rend() && f->kind != Frame::Call; ++f)
      if (f->kind == Frame::MacroLoop && f->label == o.label && f->end == 0 &&
          f->pos.file == pos.file && f->pos.offset < pos.offset) {
        f->end = pos.offset;
        break;
      }
    return true;
  }
  // The next program's `O` line ends this program: the search goes on from its start.
  if (o.kind == OKind::Program && !skip_.wrapped) return sequence_end(jump, err);
  return true;
}

bool OwordFlow::macro_loop(const grammar::Block& b, const LinePos& pos, FlowJump& /*jump*/,
                           InterpError& err) {
  const grammar::OWord& o = b.oword;
  const bool again = !stack_.empty() && stack_.back().kind == Frame::MacroLoop &&
                     stack_.back().label == o.label && stack_.back().pos.offset == pos.offset &&
                     stack_.back().pos.file == pos.file;
  if (!again) {
    for (auto f = stack_.rbegin(); f != stack_.rend() && f->kind != Frame::Call; ++f)
      if (f->kind == Frame::MacroLoop && f->label == o.label)
        return fail(err, ErrorCode::ControlMismatch, o.loc,
                    fmt::format("DO{} inside the loop DO{} of line {}: nested loops take "
                                "different numbers (1, 2, 3)",
                                o.label, o.label, f->pos.line));
    stack_.push_back(Open{Frame::MacroLoop, o.label, pos});
  }
  if (o.kind != OKind::WhileDo) return true;  // DO m without WHILE: endless (bounded)
  bool holds = false;
  if (!condition(b, holds, err)) return false;
  if (!holds) {  // to the line after END m
    stack_.pop_back();
    skip_ = SkipState{};
    skip_.mode = Skip::MacroLoopEnd;
    skip_.label = o.label;
    skip_.shown = "DO" + o.label;
    skip_.started = o.loc;
    skip_.started_kind = o.kind;
    skip_.started_file = skip_.file = pos.file;
  }
  return true;
}

bool OwordFlow::macro_end(const grammar::Block& b, const LinePos& pos, FlowJump& jump,
                          InterpError& err) {
  const grammar::OWord& o = b.oword;
  const Open* open = nullptr;  // the innermost loop DO m of this level
  for (auto f = stack_.rbegin(); f != stack_.rend() && f->kind != Frame::Call; ++f)
    if (f->kind == Frame::MacroLoop && f->label == o.label) {
      open = &*f;
      break;
    }
  if (stack_.empty() || stack_.back().kind != Frame::MacroLoop || stack_.back().label != o.label) {
    if (open != nullptr && stack_.back().kind == Frame::MacroLoop)
      return fail(err, ErrorCode::ControlMismatch, o.loc,
                  fmt::format("END{} closes DO{} (line {}) while DO{} (line {}) inside it is "
                              "open: loops nest, they do not overlap",
                              o.label, o.label, open->pos.line, stack_.back().label,
                              stack_.back().pos.line));
    return fail(err, ErrorCode::ControlMismatch, o.loc,
                fmt::format("END{} without WHILE [...] DO{}", o.label, o.label));
  }
  Open& f = stack_.back();
  if (f.end == 0) f.end = pos.offset;
  if (!count_iteration(o.loc, err)) return false;
  macro_seek(jump, f.pos, false);  // the WHILE line again: its condition decides
  return true;
}

bool OwordFlow::g65(const grammar::Block& b, const LinePos& pos, FlowJump& jump, InterpError& err) {
  const grammar::OWord& o = b.oword;
  pending_locals_.fill(kVacant);
  std::array<bool, 26> given{};    // letters of specification I (each once)
  std::array<int, 3> ijk_count{};  // I, J, K so far (specification II: up to 10 each)
  const grammar::Word* p = nullptr;
  const grammar::Word* l = nullptr;
  bool g65_seen = false;
  for (const grammar::Word& w : b.words) {
    const char c = w.letter;
    if (c == 'N') continue;
    if (c == 'G' && w.value == 65.0 && !g65_seen) {
      g65_seen = true;
      continue;
    }
    if (c == 'P' && p == nullptr) {
      p = &w;
      continue;
    }
    if (c == 'L' && l == nullptr) {
      l = &w;
      continue;
    }
    int var = c >= 'A' && c <= 'Z' ? kMacroArgument[c - 'A'] : 0;
    if (var == 0)
      return fail(err, ErrorCode::SubprogramMisused, w.loc,
                  fmt::format("{}{} on a G65 line: a macro call takes P (program), L (repeats) "
                              "and the arguments A-Z but G, L, N, O, P",
                              c, w.value));
    if (c == 'I' || c == 'J' || c == 'K') {  // specification II: the n-th I, J, K
      const int n = ++ijk_count[static_cast<std::size_t>(c - 'I')];
      if (n > kMaxArgumentSets)
        return fail(err, ErrorCode::SubprogramMisused, w.loc,
                    fmt::format("{} given {} times: argument specification II takes I, J, K up "
                                "to {} times (#4-#33)",
                                c, n, kMaxArgumentSets));
      var = argument_ii_variable(c, n);
    } else if (given[static_cast<std::size_t>(c - 'A')]) {
      return fail(err, ErrorCode::SubprogramMisused, w.loc,
                  fmt::format("argument {} given twice: only I, J and K repeat (argument "
                              "specification II)",
                              c));
    }
    given[static_cast<std::size_t>(c - 'A')] = true;
    // A variable two arguments name (I2 and D: #7) takes the one given later.
    pending_locals_[static_cast<std::size_t>(var - 1)] = w.value;
  }
  if (p == nullptr)
    return fail(err, ErrorCode::SubprogramMisused, o.loc,
                "G65 needs P, the number of the macro program (O1234 ... M99) to call");
  const double pn = std::floor(p->value + 1e-4);
  if (std::abs(p->value - pn) > 1e-4 || pn < 0 || pn > 99999999)
    return fail(err, ErrorCode::SubprogramMisused, p->loc,
                fmt::format("G65 P must be a program number, not {}", p->value));
  pending_macro_ = true;
  return fanuc_call(o, fmt::format("{}", static_cast<long>(pn)), l, pos, jump, err);
}

double OwordFlow::program_number(long main_program) const {
  for (auto f = stack_.rbegin(); f != stack_.rend(); ++f)
    if (f->kind == Frame::Call && (f->label.empty() || f->label[0] != 'N'))  // M97: the caller's
      return f->fanuc ? std::strtod(f->label.c_str(), nullptr) : kVacant;
  return main_program < 0 ? kVacant : static_cast<double>(main_program);
}

}  // namespace gm
