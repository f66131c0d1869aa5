// The spindle and I/O steps: S, M3/M4/M5/M19, M7/M8/M9, M62..M68 and the user codes M100..M199,
// each emitting the canonical command LinuxCNC 2.9's interpreter gives (nothing is executed).
#include "interp/steps.hpp"

#include "common/units.hpp"

#include <cmath>
#include <filesystem>
#include <system_error>

namespace gm {

void emit_io(BlockCtx& ctx, EventKind kind, int index, double value) {
  Event e;
  e.line = ctx.block.line;
  e.kind = kind;
  e.index = index;
  e.value = value;
  emit_in_order(ctx, Canon(std::in_place_type<Event>, std::move(e)));
}

// The surface speed of G96 S in mm/min: S m/min (G21) or ft/min (G20), in the units in force when
// it is set (LinuxCNC's SPINDLE_SPEED_: css_factor from the canon's length units then).
static double surface_mm_min(const ModalState& s) {
  return s.spindle_rpm * (s.inch ? 12.0 * units::kMmPerInch : 1000.0);
}

bool run_spindle_mode(BlockCtx& ctx, const Code& c) {
  ctx.s.css = c.number10 == 960;
  ctx.s.css_max_rpm = !ctx.s.css ? 0.0 : ctx.w.has('D') ? std::fabs(ctx.w.get('D')) : 1e30;
  ctx.s.css_surface_mm_min = ctx.s.css ? surface_mm_min(ctx.s) : 0.0;
  return true;
}

bool step_speed(BlockCtx& ctx) {
  ctx.s.spindle_rpm = ctx.w['S']->value;  // negative S is refused when the block is checked
  if (ctx.s.css) ctx.s.css_surface_mm_min = surface_mm_min(ctx.s);
  emit_io(ctx, EventKind::SpindleSpeed, 0, ctx.s.spindle_rpm);
  return true;
}

bool run_spindle(BlockCtx& ctx, const Code& c) {
  ctx.s.spindle_dir = c.number10 == 30 ? 1 : c.number10 == 40 ? -1 : 0;
  if (ctx.s.spindle_dir == 0)
    emit_io(ctx, EventKind::SpindleStop, 0, 0.0);
  else
    emit_io(ctx, EventKind::SpindleStart, ctx.s.spindle_dir, ctx.s.spindle_rpm);
  return true;
}

// M19 [R<angle>] [P<direction mode>] [Q<timeout>]: the spindle stops turning; ORIENT_SPINDLE only
// with R or P, at R plus the machine's orient offset (LinuxCNC's ORIENT_OFFSET), the wait only
// with Q > 0.
bool run_orient(BlockCtx& ctx, const Code&) {
  const auto& w = ctx.w;
  if (w.has('Q') && !(w['Q']->value > 0.0))
    return ctx.fail(ErrorCode::ValueOutOfRange, w['Q']->loc,
                    fmt::format("M19 Q{:g}: Q (the timeout) must be more than 0", w['Q']->value));
  ctx.s.spindle_dir = 0;
  if (w.has('R') || w.has('P'))
    emit_io(ctx, EventKind::SpindleOrient, static_cast<int>(std::lround(w.get('P'))),
            w.get('R') + ctx.machine.orient_offset_deg);
  if (w.has('Q')) emit_io(ctx, EventKind::OrientWait, 0, w['Q']->value);
  return true;
}

bool run_coolant(BlockCtx& ctx, const Code& c) {
  if (c.number10 == 70) {
    ctx.s.mist = true;
    emit_io(ctx, EventKind::Mist, 1, 0.0);
  } else if (c.number10 == 80) {
    ctx.s.flood = true;
    emit_io(ctx, EventKind::Flood, 1, 0.0);
  } else {  // M9: both off, printed whatever they were
    ctx.s.mist = ctx.s.flood = false;
    emit_io(ctx, EventKind::Mist, 0, 0.0);
    emit_io(ctx, EventKind::Flood, 0, 0.0);
  }
  return true;
}

namespace {

// A word naming a pin or channel: rounded to an integer as LinuxCNC does (round_to_int).
int pin_of(const grammar::Word& w) {
  return static_cast<int>(std::lround(w.value));
}

}  // namespace

// M62/M63 (with motion) and M64/M65 (at once) P<pin>: set or clear a digital output.
bool run_digital_out(BlockCtx& ctx, const Code& c) {
  const std::string name = code_name(c);
  if (!comp_forbids(ctx, ctx.loc_of(Group::MIo), fmt::format("set outputs ({})", name)))
    return false;
  if (!ctx.w.has('P'))
    return ctx.fail(ErrorCode::MissingWord, ctx.loc_of(Group::MIo),
                    fmt::format("{} without P (the output number)", name));
  if (!within(ctx.w['P']->value, 1e9))
    return ctx.fail(ErrorCode::ValueOutOfRange, ctx.w['P']->loc,
                    fmt::format("{} P{:g}: no such output", name, ctx.w['P']->value));
  Event e;
  e.line = ctx.block.line;
  e.kind = EventKind::DigitalOut;
  e.index = pin_of(*ctx.w['P']);
  e.value = c.number10 == 620 || c.number10 == 640 ? 1.0 : 0.0;
  e.sync = c.number10 == 620 || c.number10 == 630;
  ctx.out.emplace_back(std::in_place_type<Event>, std::move(e));
  return true;
}

// M67 (with motion) / M68 (at once) E<channel> Q<value>: set an analog output.
bool run_analog_out(BlockCtx& ctx, const Code& c) {
  const std::string name = code_name(c);
  if (!comp_forbids(ctx, ctx.loc_of(Group::MIo), fmt::format("set outputs ({})", name)))
    return false;
  const auto* ew = ctx.w['E'];
  if (!ew || !within(ew->value, 1e9) || pin_of(*ew) < 0)
    return ctx.fail(ErrorCode::MissingWord, ew ? ew->loc : ctx.loc_of(Group::MIo),
                    fmt::format("invalid analog index with {} (E0 or more)", name));
  Event e;
  e.line = ctx.block.line;
  e.kind = EventKind::AnalogOut;
  e.index = pin_of(*ew);
  e.value = ctx.w.get('Q');
  e.sync = c.number10 == 670;
  ctx.out.emplace_back(std::in_place_type<Event>, std::move(e));
  return true;
}

// M66 P<digital>|E<analog> [L<mode>] [Q<timeout>]: wait for an input. No input is modelled: the
// wait is recorded and takes no time.
bool run_wait_input(BlockCtx& ctx, const Code&) {
  const auto& w = ctx.w;
  const SourceLoc loc = ctx.loc_of(Group::MIo);
  const double l = w.get('L');
  const int mode = within(l, 1e9) ? static_cast<int>(std::lround(l)) : -1;
  if (w.has('P') && w.has('E'))
    return ctx.fail(ErrorCode::BadPWord, w['E']->loc,
                    "M66: both a digital (P) and an analog (E) input selected");
  if (w.has('L') && mode > 0 && w.get('Q') <= 0.0)
    return ctx.fail(ErrorCode::ValueOutOfRange, w.has('Q') ? w['Q']->loc : loc,
                    "M66: zero timeout (Q) with a wait that is not immediate (L > 0)");
  if (w.has('E') && w.has('L') && mode != 0)
    return ctx.fail(ErrorCode::BadLWord, w['L']->loc,
                    "M66: an analog input (E) can only be read immediately (L0)");
  const auto* iw = w.has('P') ? w['P'] : w['E'];
  if (!iw || !within(iw->value, 1e9) || pin_of(*iw) < 0)
    return ctx.fail(ErrorCode::MissingWord, iw ? iw->loc : loc,
                    "M66: invalid or missing P and E words (the input to wait for)");
  if (mode < 0 || mode > 4)
    return ctx.fail(ErrorCode::BadLWord, w['L']->loc, fmt::format("M66 L{:g}: L must be 0..4", l));
  if (!comp_forbids(ctx, loc, "wait for an input (M66)")) return false;
  Event e;
  e.line = ctx.block.line;
  e.kind = EventKind::WaitInput;
  e.index = pin_of(*iw);
  e.analog = w.has('E');
  e.mode = mode;
  e.value = w.has('Q') && w['Q']->value > 0.0 ? w['Q']->value : 0.0;
  // A simulation's inputs read 0 (digital low): a wait for a rise, a fall or a high level runs
  // to its timeout (the interpolator waits Q), after which LinuxCNC gives #5399 = -1.
  ctx.results.add(5399, mode >= 1 && mode <= 3 ? -1.0 : 0.0);
  ctx.out.emplace_back(std::in_place_type<Event>, std::move(e));
  return true;
}

// M100..M199 P Q: a user code is known when the machine's user M-code directory holds a file of
// its name (M101); it is recorded, never run. Without one it is rs274's "unknown M code" error.
bool run_user_mcode(BlockCtx& ctx, const Code& c) {
  const std::string name = code_name(c);
  const std::string& dir = ctx.machine.user_mcode_dir;
  std::error_code ec;
  if (dir.empty() || !std::filesystem::is_regular_file(std::filesystem::path(dir) / name, ec))
    return ctx.fail(
        ErrorCode::UnknownMCode, ctx.loc_of(Group::MUser),
        dir.empty() ? fmt::format("unknown M code used: {} (no user M-code directory; "
                                  "--user-mcode-dir DIR with a file {})",
                                  name, name)
                    : fmt::format("unknown M code used: {} (no file {} in {})", name, name, dir));
  Event e;
  e.line = ctx.block.line;
  e.kind = EventKind::UserMcode;
  e.index = c.number10 / 10;
  e.value = ctx.w.get('P');
  e.value2 = ctx.w.get('Q');
  emit_in_order(ctx, Canon(std::in_place_type<Event>, std::move(e)));
  return true;
}

}  // namespace gm
