// The tool steps: T (select), M6 (change), M61 (set the tool number), G43/G43.1/G43.2/G49 (tool
// length offsets) and G10 L1/L10/L11 (tool table entries), as LinuxCNC 2.9 runs them.
#include "interp/steps.hpp"

namespace gm {

namespace {

Pos9 offsets_of(const ToolEntry& e) {
  Pos9 p;
  for (int i = 0; i < kProgramAxes; ++i) p[i] = e.offset_mm[static_cast<std::size_t>(i)];
  return p;
}

// A word that names a tool: a non-negative integer (T, H, M61 Q, G10 L1 P).
bool tool_number(BlockCtx& ctx, const grammar::Word& w, int& tool) {
  double t = 0;
  if (!near_integer(w.value, t) || t < 0)
    return ctx.fail(ErrorCode::BadCodeNumber, w.loc,
                    fmt::format("{}{:g} is not a tool number", w.letter, w.value));
  if (t > kMaxToolNumber)
    return ctx.fail(w.letter == 'T' ? ErrorCode::ValueOutOfRange : ErrorCode::ToolNumberOutOfRange,
                    w.loc,
                    fmt::format("{}{:g}: tool numbers go up to {:g}", w.letter, t, kMaxToolNumber));
  tool = static_cast<int>(t);
  return true;
}

// rs274: "Requested tool N not found in the tool table". Tool 0 (no tool) always exists.
bool tool_in_table(BlockCtx& ctx, const grammar::Word& w, int tool) {
  if (tool == 0 || ctx.tables().tools.find(tool)) return true;
  return ctx.fail(
      ErrorCode::ToolNumberOutOfRange, w.loc,
      fmt::format("tool {} is not in the tool table ({})", tool, ctx.tables().tools.source));
}

// The offsets of tool `tool` (zero for tool 0).
Pos9 tool_offsets(const BlockCtx& ctx, int tool) {
  const ToolEntry* e = tool == 0 ? nullptr : ctx.tables().tools.find(tool);
  return e ? offsets_of(*e) : Pos9::Zero();
}

}  // namespace

bool step_tool_select(BlockCtx& ctx) {
  const auto* tw = ctx.w['T'];
  int t = 0;
  if (!tool_number(ctx, *tw, t) || !tool_in_table(ctx, *tw, t)) return false;
  ctx.s.tool_selected = t;
  emit_io(ctx, EventKind::ToolSelect, t, 0.0);
  return true;
}

bool run_tool_change(BlockCtx& ctx, const Code&) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::MToolChange), "change tools")) return false;
  // LinuxCNC stops the spindle for the change (no TOOL_CHANGE_WITH_SPINDLE_ON in its sims).
  ctx.s.spindle_dir = 0;
  emit_io(ctx, EventKind::SpindleStop, 0, 0.0);
  emit_io(ctx, EventKind::ToolChange, ctx.s.tool_selected, 0.0);
  ctx.s.tool_in_spindle = ctx.s.tool_selected;
  // rs274: T0 M6 leaves the spindle's tool data as it was (G43 without H still uses it).
  if (ctx.s.tool_selected != 0) ctx.s.spindle_slot_tool = ctx.s.tool_selected;
  return true;
}

bool run_m61(BlockCtx& ctx, const Code&) {
  if (!ctx.w.has('Q'))
    return ctx.fail(ErrorCode::MissingWord, ctx.loc_of(Group::MToolChange),
                    "M61 without Q (the tool number)");
  int t = 0;
  if (!tool_number(ctx, *ctx.w['Q'], t) || !tool_in_table(ctx, *ctx.w['Q'], t)) return false;
  ctx.s.tool_in_spindle = t;  // rs274: the spindle's tool data stays what M6 loaded
  emit_io(ctx, EventKind::ToolNumber, t, 0.0);
  return true;
}

bool run_tool_length(BlockCtx& ctx, const Code& c) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::ToolLength), "change the tool length offset"))
    return false;
  Pos9& off = ctx.s.tool_offset_mm;
  ctx.s.tool_length_code = c.number10;
  switch (c.number10) {
    case 490:  // G49
      off.setZero();
      return true;
    case 431:  // G43.1: the axis words are the offsets (other axes keep theirs)
      for (int i = 0; i < kProgramAxes; ++i)
        if (const auto* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]])
          off[i] = aw->value * (axis_is_rotary(i) ? 1.0 : ctx.scale());
      return true;
    default:
      break;
  }
  int tool = ctx.s.spindle_slot_tool;
  if (const auto* hw = ctx.w['H']) {
    if (!tool_number(ctx, *hw, tool) || !tool_in_table(ctx, *hw, tool)) return false;
  } else if (c.number10 == 432) {
    return ctx.fail(ErrorCode::MissingWord, ctx.loc_of(Group::ToolLength),
                    "G43.2 without H (the tool whose offsets are added)");
  }
  if (tool == 0) tool = ctx.s.spindle_slot_tool;  // rs274: H0 is the spindle's tool data
  if (c.number10 == 432)
    off += tool_offsets(ctx, tool);
  else
    off = tool_offsets(ctx, tool);
  return true;
}

bool run_g10_tool(BlockCtx& ctx, int l) {
  const auto* pw = ctx.w['P'];
  int tool = 0;
  if (!tool_number(ctx, *pw, tool)) return false;
  const ToolEntry* old = ctx.tables().tools.find(tool);
  if (!old)
    return ctx.fail(ErrorCode::ToolNumberOutOfRange, pw->loc,
                    fmt::format("G10 L{}: tool {} is not in the tool table ({})", l, tool,
                                ctx.tables().tools.source));
  ToolEntry e = *old;
  const Pos9& pos = ctx.s.position_mm;
  const auto& t = ctx.tables();
  for (int i = 0; i < kProgramAxes; ++i) {
    const auto* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]];
    if (!aw) continue;
    const double v = aw->value * (axis_is_rotary(i) ? 1.0 : ctx.scale());
    double& o = e.offset_mm[static_cast<std::size_t>(i)];
    if (l == 1)
      o = v;
    else if (l == 10)  // the current point gets coordinate v with this offset applied
      o = pos[i] - t.g5x_mm[static_cast<std::size_t>(ctx.s.coord_system)][i] - ctx.s.g92_mm[i] - v;
    else  // L11: as L10 in G59.3 without G92
      o = pos[i] - t.g5x_mm[8][i] - v;
  }
  if (const auto* rw = ctx.w['R']) e.diameter_mm = 2.0 * rw->value * ctx.scale();
  ctx.tables_w().tools.set(e);
  return true;
}

}  // namespace gm
