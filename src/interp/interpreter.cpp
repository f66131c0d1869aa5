// Block interpretation in grbl's four steps: import the words, check them against a copy of the
// modal state, run the block's steps in LinuxCNC's order of execution on the copy, commit.
#include "interp/interpreter.hpp"

#include "interp/frame.hpp"
#include "interp/parameters.hpp"

#include "common/units.hpp"
#include "interp/steps.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace gm {

namespace {

// STEP 3: the checks that need the whole block: who uses the axis words, which code uses each
// value word. Sets ctx.motion_to_be.
bool check_block(BlockCtx& ctx) {
  const BlockWords& w = ctx.w;
  const Code* motion = w.in(Group::Motion);
  const Code* axis_user = nullptr;
  for (std::size_t i = 0; i < w.code_count; ++i)
    if (w.codes[i]->uses_axes) axis_user = w.codes[i];
  const bool has_axes = w.first_axis != nullptr;

  if (motion)
    ctx.motion_to_be = motion->number10;
  else if (has_axes && !axis_user)
    ctx.motion_to_be = ctx.s.motion;
  if (ctx.motion_to_be == 800) {  // G80 (cycles off) is the absence of a motion mode
    if (has_axes && motion)
      return ctx.fail(ErrorCode::AxisWordsWithoutMotion, w.first_axis->loc,
                      fmt::format("axis word {} with G80, which uses none", w.first_axis->letter));
    ctx.motion_to_be = -1;
  }

  // rs274: @ and ^ belong to motions; G10/G28/G30 refuse them, G92/G52 find no axis in them.
  if (w.polar.any() && axis_user)
    return ctx.fail(ErrorCode::PolarMisused, w.polar.first()->loc,
                    axis_user->number10 == 920 || axis_user->number10 == 520
                        ? fmt::format("{} takes axis words, not polar coordinates (@, ^)",
                                      code_name(*axis_user))
                        : fmt::format("polar coordinates (@, ^) can only be used for motion, "
                                      "not with {}",
                                      code_name(*axis_user)));
  if (has_axes && axis_user && motion)
    return ctx.fail(ErrorCode::ModalGroupViolation, w.word_of(Group::Motion)->loc,
                    fmt::format("{} and {} both use the axis words", code_name(*axis_user),
                                code_name(*motion)));
  if (has_axes && !axis_user && ctx.motion_to_be < 0)
    return ctx.fail(ErrorCode::AxisWordsWithoutMotion, w.first_axis->loc,
                    fmt::format("axis word {} with no motion mode (G0-G3) or G92 to use it",
                                w.first_axis->letter));

  // Every value word some code owns must be used by a code of this block (or its motion mode):
  // the letters as bits; the first unused word in the block's order is the error.
  ctx.motion_code = ctx.motion_to_be < 0 ? nullptr
                    : motion && motion->number10 == ctx.motion_to_be
                        ? motion  // (the table's row)
                        : find_code('G', ctx.motion_to_be);
  if (const std::uint32_t owned = w.letters & code_word_mask()) {
    std::uint32_t used = ctx.motion_code ? ctx.motion_code->word_mask : 0;
    for (std::size_t i = 0; i < w.code_count; ++i) used |= w.codes[i]->word_mask;
    if (owned & ~used)
      for (const grammar::Word& word : ctx.block.words) {
        const char c = word.letter;
        if (c < 'A' || c > 'Z' || c == 'G' || c == 'M') continue;
        if ((owned & ~used) & (std::uint32_t{1} << (c - 'A')))
          return ctx.fail(ErrorCode::UnusedWord, word.loc,
                          fmt::format("{} word with no {} to use it", c, codes_using(c)));
      }
  }
  constexpr std::uint32_t kCounts = letter_mask("HST");
  if (w.letters & kCounts)
    for (char c : {'S', 'T', 'H'})
      if (w.has(c) && w[c]->value < 0)
        return ctx.fail(ErrorCode::NegativeValue, w[c]->loc,
                        fmt::format("{}{:g} is negative", c, w[c]->value));
  return true;
}

// One thing a block does, at its place in the order of execution.
struct Action {
  Step step;
  bool (*word_step)(BlockCtx&);  // a value word's step, or
  const Code* code;              // a code's
};

// The block's actions in LinuxCNC's order of execution (a stable insertion sort of at most a
// few entries: the value words' steps, one code per group, the motion).
std::size_t plan_block(const BlockCtx& ctx, std::array<Action, kGroupCount + 4>& plan) {
  std::size_t n = 0;
  auto add = [&](Action a) {
    std::size_t k = n++;
    for (; k > 0 && plan[k - 1].step > a.step; --k) plan[k] = plan[k - 1];
    plan[k] = a;
  };
  if (ctx.block.message_count > 0) add({Step::Comment, step_comment, nullptr});
  if (ctx.w.has('F')) add({Step::Feed, step_feed, nullptr});
  if (ctx.w.has('S')) add({Step::Speed, step_speed, nullptr});
  if (ctx.w.has('T')) add({Step::Tool, step_tool_select, nullptr});
  for (std::size_t i = 0; i < ctx.w.code_count; ++i)
    if (const Code* c = ctx.w.codes[i]; c->group != Group::Motion) add({c->step, nullptr, c});
  if (ctx.w.in(Group::Motion) || ctx.motion_to_be >= 0) add({Step::Motion, nullptr, nullptr});
  return n;
}

// The motion step: the block's motion code becomes the mode; the mode moves if this block moves.
bool run_motion(BlockCtx& ctx) {
  if (const Code* m = ctx.w.in(Group::Motion)) {
    ctx.s.motion = m->number10;
    if (m->run != run_cycle) {  // a run of cycle blocks ends: the next one starts afresh
      ctx.s.cycle_mode = -1;
      ctx.s.cycle_il_set = false;
    }
  }
  if (ctx.motion_to_be < 0) return true;
  return ctx.motion_code->run(ctx, *ctx.motion_code);
}

// A light block: its steps are at most the F word's and a straight move or an arc without
// cutter compensation, which change only the fields below. It runs on the state itself with
// these fields saved, restored if a step fails (grbl's rule: an error leaves the state as it
// was), instead of on a copy of the whole state. A step added to light_block() must write no
// field outside LightUndo.
struct LightUndo {
  int motion;
  int cycle_mode;
  bool cycle_il_set;
  bool arc_not_allowed;
  bool detached;
  double feed_mm_min;
  Pos9 position_mm;

  explicit LightUndo(const ModalState& s)
      : motion(s.motion),
        cycle_mode(s.cycle_mode),
        cycle_il_set(s.cycle_il_set),
        arc_not_allowed(s.comp.arc_not_allowed),
        detached(s.comp.detached),
        feed_mm_min(s.feed_mm_min),
        position_mm(s.position_mm) {}
  void restore(ModalState& s) const {
    s.motion = motion;
    s.cycle_mode = cycle_mode;
    s.cycle_il_set = cycle_il_set;
    s.comp.arc_not_allowed = arc_not_allowed;
    s.comp.detached = detached;
    s.feed_mm_min = feed_mm_min;
    s.position_mm = position_mm;
  }
};

bool light_motion(const Code* c) {
  return c->run == run_straight || c->run == run_arc;
}

// True when every step of the block is one LightUndo covers: no comment, S or T word, every code
// G0-G3 (or none, the motion mode G0-G3 or none), cutter compensation off.
bool light_block(const grammar::Block& block, const BlockWords& w, const ModalState& s) {
  constexpr std::uint32_t kOwnSteps = letter_mask("ST");
  if (block.message_count > 0 || (w.letters & kOwnSteps) != 0 || s.comp.on()) return false;
  for (std::size_t i = 0; i < w.code_count; ++i)
    if (!light_motion(w.codes[i])) return false;
  if (w.code_count == 0 && s.motion >= 0 && w.first_axis != nullptr) {
    const Code* modal = find_code('G', s.motion);
    return modal != nullptr && light_motion(modal);
  }
  return true;
}

}  // namespace

double ModalState::mm_per_unit() const {
  return inch ? units::kMmPerInch : 1.0;
}

Interpreter::Interpreter(const Machine& machine) : machine_(machine) {
  for (ModalState& s : states_) s.inch = machine.program_inch;  // LinuxCNC: [TRAJ]LINEAR_UNITS
  for (std::size_t i = 0; i < machine.work_offsets_mm.size(); ++i)
    tables_.g5x_mm[i] = machine.work_offsets_mm[i];
  for (ModalState& s : states_) select_coord_system(s, tables_, 0);
  tables_.tools = machine.tool_table;
  // The machine file's `tools = [...]` lengths: tool i gets Z offset tools[i] (i >= 1).
  for (std::size_t i = 1; i < machine.tool_lengths_mm.size(); ++i) {
    ToolEntry e;
    if (const ToolEntry* old = tables_.tools.find(static_cast<int>(i))) e = *old;
    e.number = e.pocket = static_cast<int>(i);
    e.offset_mm[2] = machine.tool_lengths_mm[i];
    tables_.tools.set(e);
  }
}

bool Interpreter::execute(const grammar::Block& block, const BlockWords* imported,
                          std::vector<Canon>& out, InterpError& err) {
  // LinuxCNC reads X as a diameter in G7 (read_x halves it; a G7/G8 in the same block rescales
  // it), so the X word is halved when the block ends in diameter mode: X, G92 X, G10 X alike.
  const auto halves_x = [this](const BlockWords& w) {
    const Code* lathe = w.in(Group::LatheMode);
    return w.has('X') && (lathe ? lathe->number10 == 70 : state().lathe_diameter);
  };
  if (imported != nullptr && !halves_x(*imported)) return execute_words(block, *imported, out, err);
  BlockWords w;
  if (imported != nullptr)
    w = *imported;
  else if (!import_words(block, machine_.layout, w, err))
    return false;
  if (halves_x(w)) {
    w.x_radius = *w['X'];
    w.x_radius.value /= 2.0;
    w.value['X' - 'A'] = &w.x_radius;
  }
  return execute_words(block, w, out, err);
}

bool Interpreter::execute_words(const grammar::Block& block, const BlockWords& w,
                                std::vector<Canon>& out, InterpError& err) {
  if (light_block(block, w, state())) return execute_light(block, w, out, err);
  ModalState& s = begin_block();
  BlockCtx ctx{machine_, block, w, s, out, err, tables_, nullptr};
  ctx.call_level = call_level_;
  ctx.motion_before = s.motion;
  ctx.nurbs = &nurbs_;
  g7x_next_.pending = false;  // (a failed block may have left it set)
  ctx.g7x = &g7x_next_;
  if (!check_block(ctx)) return false;

  // STEP 4: execute on the copy, step by step in LinuxCNC's order ------------------------------
  std::array<Action, kGroupCount + 4> plan;
  const std::size_t n = plan_block(ctx, plan);
  const std::size_t out_mark = out.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Action& a = plan[i];
    const bool ok = a.word_step ? a.word_step(ctx)
                    : a.code    ? a.code->run(ctx, *a.code)
                                : run_motion(ctx);
    if (!ok) {
      out.resize(out_mark);
      return false;
    }
  }
  commit_block();
  if (ctx.staged) {
    tables_ = *ctx.staged;
    ++tables_version_;
  }
  const NurbsEdit& e = ctx.nurbs_edit;
  if (e.clear) nurbs_.points.clear();
  if (e.order > 0) nurbs_.order = e.order;
  for (int i = 0; i < e.added; ++i) nurbs_.points.push_back(e.add[static_cast<std::size_t>(i)]);
  if (g7x_next_.pending) {
    g7x_ = std::move(g7x_next_);
    g7x_next_.pending = false;
  }
  if (result_params_ != nullptr)
    for (std::size_t i = 0; i < ctx.results.count; ++i)
      result_params_->set_system(ctx.results.set[i].number, ctx.results.set[i].value);
  return true;
}

bool Interpreter::execute_light(const grammar::Block& block, const BlockWords& w,
                                std::vector<Canon>& out, InterpError& err) {
  ModalState& s = state_mut();
  BlockCtx ctx{machine_, block, w, s, out, err, tables_, nullptr};
  ctx.call_level = call_level_;
  ctx.motion_before = s.motion;
  ctx.nurbs = &nurbs_;
  ctx.g7x = &g7x_next_;
  if (!check_block(ctx)) return false;
  const LightUndo undo(s);
  const std::size_t out_mark = out.size();
  const bool ok = (!w.has('F') || step_feed(ctx)) &&
                  (!(w.in(Group::Motion) || ctx.motion_to_be >= 0) || run_motion(ctx));
  if (!ok) {
    undo.restore(s);
    out.resize(out_mark);
  }
  return ok;
}

void Interpreter::enter_call(int level) {
  call_level_ = std::clamp(level, 0, kCallLevels - 1);
  tables_.saved_modes[static_cast<std::size_t>(call_level_)] = SavedModes{};
}

bool Interpreter::leave_call(int level, int line, std::vector<Canon>& out, InterpError& err) {
  level = std::clamp(level, 0, kCallLevels - 1);
  call_level_ = std::max(0, level - 1);
  const SavedModes saved = tables_.saved_modes[static_cast<std::size_t>(level)];
  tables_.saved_modes[static_cast<std::size_t>(level)] = SavedModes{};
  if (!saved.valid || !saved.restore_on_return) return true;
  grammar::Block block;
  block.line = line;
  BlockWords w;
  ModalState& s = begin_block();
  BlockCtx ctx{machine_, block, w, s, out, err, tables_, nullptr};
  ctx.call_level = call_level_;
  const std::size_t mark = out.size();
  if (!restore_modes(ctx, saved)) {
    out.resize(mark);
    return false;
  }
  commit_block();
  if (ctx.staged) {
    tables_ = *ctx.staged;
    ++tables_version_;
  }
  return true;
}

}  // namespace gm
