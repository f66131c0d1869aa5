// What a step of a block sees (the block's words and a copy of the state), and the step functions
// the code table names. Internal to the interpreter.
#pragma once

#include "common/position_limits.hpp"
#include "interp/block_words.hpp"
#include "interp/codes.hpp"
#include "interp/frame.hpp"
#include "interp/interpreter.hpp"
#include "interp/polar.hpp"
#include "interp/spline.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

namespace gm {

/// One block being executed: the machine, the block, its words and the state copy it changes.
struct BlockCtx {
  // (A constructor, not aggregate initialisation: the members without an initialiser of their
  // own are left unset rather than the whole context zeroed every block.)
  BlockCtx(const Machine& m, const grammar::Block& b, const BlockWords& words, ModalState& state,
           std::vector<Canon>& output, InterpError& error, const SystemTables& tables,
           std::unique_ptr<SystemTables> staged_tables)
      : machine(m),
        block(b),
        w(words),
        s(state),
        out(output),
        err(error),
        committed(tables),
        staged(std::move(staged_tables)) {}

  const Machine& machine;
  const grammar::Block& block;
  const BlockWords& w;
  ModalState& s;            ///< the copy; committed only if every step succeeds
  std::vector<Canon>& out;  ///< canonical commands of this block are appended
  InterpError& err;
  const SystemTables& committed;         ///< the tables as before this block
  std::unique_ptr<SystemTables> staged;  ///< this block's changes to them, if any
  int motion_to_be = -1;                 ///< the motion code x 10 this block executes, -1 none
  const Code* motion_code = nullptr;     ///< its code (set with it), null for none
  int call_level = 0;                    ///< subroutine call level (M70..M73 contexts)
  double inverse_f = 0.0;                ///< G93: this block's F (1/min)
  /// G76's I J K scale from a G7/G8 switch in this block (LinuxCNC rescales them then too).
  double lathe_ijk_switch = 1.0;
  int motion_before = -1;  ///< the motion mode before this block (G5.2 starts a new curve)
  const NurbsCurve* nurbs = nullptr;  ///< the G5.2 curve collected by earlier blocks
  NurbsEdit nurbs_edit{};             ///< this block's change to it (applied on commit)
  G7xCycle* g7x = nullptr;            ///< G70-G72: the cycle this block starts
  ResultParameters results;           ///< #5061-#5070, #5399 this block sets (on commit)

  /// Sets the error; returns false so a step can `return ctx.fail(...)`.
  bool fail(ErrorCode code, SourceLoc loc, std::string msg) {
    err.code = code;
    err.loc = loc;
    err.message = std::move(msg);
    return false;
  }
  /// Where the code of group `g` was written (the block start if it is not in the block).
  SourceLoc loc_of(Group g) const {
    const auto* wd = w.word_of(g);
    return wd ? wd->loc : SourceLoc{block.line, 1};
  }
  double scale() const { return s.mm_per_unit(); }
  /// The tables as this block sees them, and for writing (copied on first write).
  const SystemTables& tables() const { return staged ? *staged : committed; }
  SystemTables& tables_w() {
    if (!staged) staged = std::make_unique<SystemTables>(committed);
    return *staged;
  }
  /// Program and machine coordinates under the block's state (offsets, XY rotation).
  Frame frame() const { return Frame(s); }
  /// Sum of the offsets from program to machine coordinates under the block's state, mm.
  Pos9 offset() const { return frame().offset(); }
};

// Limits beyond which a run's integer counts would overflow (positions:
// common/position_limits.hpp).
inline constexpr double kMaxFeedMmMin = 1e12;
// The moves one block may expand to (a canned cycle's repeats and pecks, G7x roughing): what a
// block holds stays bounded (a Motion is a few hundred bytes).
inline constexpr std::size_t kMaxMovesPerBlock = 100000;
inline constexpr double kMaxToolNumber = 1e6;

inline bool within(double v, double limit) {
  return std::fabs(v) <= limit;
}  // false for NaN
inline bool near_integer(double v, double& rounded) {
  rounded = std::round(v);
  return std::fabs(v - rounded) < 1e-6;
}

// Steps of the value words (no code of their own) ----------------------------------------------
bool step_comment(BlockCtx&);
bool step_feed(BlockCtx&);
bool step_tool_select(BlockCtx&);
bool step_speed(BlockCtx&);

// Steps named by the code table -----------------------------------------------------------------
bool run_nothing(BlockCtx&, const Code&);  ///< accepted and recorded nowhere (M7, G9, ...)
bool run_feed_mode(BlockCtx&, const Code&);
bool run_tool_change(BlockCtx&, const Code&);
bool run_override(BlockCtx&, const Code&);
bool run_dwell(BlockCtx&, const Code&);
bool run_plane(BlockCtx&, const Code&);
bool run_units(BlockCtx&, const Code&);
bool run_tool_length(BlockCtx&, const Code&);
bool run_coord_system(BlockCtx&, const Code&);
bool run_path_control(BlockCtx&, const Code&);
bool run_distance(BlockCtx&, const Code&);
bool run_arc_distance(BlockCtx&, const Code&);
bool run_spindle_sync(BlockCtx&, const Code&);
bool run_spindle_mode(BlockCtx&, const Code&);
bool run_threading(BlockCtx&, const Code&);  ///< G76 (steps_threading.cpp)
bool run_g7x(BlockCtx&, const Code&);        ///< G70 G71 G71.1 G71.2 G72 G72.1 G72.2
bool run_rigid_tap(BlockCtx&, const Code&);  ///< G33.1
/// G95 and G33: `mo` is fed by the spindle, `mm_per_rev` along its path per revolution, at the
/// block's spindle speed (G97) or surface speed (G96); its feed_mm_min is the feed at its start
/// (mo.start_mm must be set; the compensation queue sets it again when it emits the move).
void set_spindle_feed(const BlockCtx& ctx, Motion& mo, double mm_per_rev);
/// G93's rate for a move of `length_mm` (LinuxCNC interp_inverse.cc: max(0.1, length × F) in
/// program units a minute), false with the error where it passes kMaxFeedMmMin. Compensated moves
/// take the rate of their programmed path (cutter_comp.cpp).
bool inverse_time_feed(BlockCtx& ctx, double length_mm, double& feed_mm_min);
bool run_lathe_mode(BlockCtx&, const Code&);
bool run_g92(BlockCtx&, const Code&);
bool run_g92_x(BlockCtx&, const Code&);  ///< G92.1 G92.2 G92.3
bool run_g52(BlockCtx&, const Code&);
bool run_g10(BlockCtx&, const Code&);       ///< L1 L10 L11 (tools), L2 L20 (coordinate systems)
bool run_home(BlockCtx&, const Code&);      ///< G28 G30
bool run_home_set(BlockCtx&, const Code&);  ///< G28.1 G30.1
bool run_m61(BlockCtx&, const Code&);
bool run_spindle(BlockCtx&, const Code&);       ///< M3 M4 M5
bool run_retract_mode(BlockCtx&, const Code&);  ///< G98 G99
bool run_cycle(BlockCtx&, const Code&);         ///< G73 G74 G81..G86 G89
bool run_g10_tool(BlockCtx&, int l);            ///< G10 L1/L10/L11 (from run_g10)
bool run_straight(BlockCtx&, const Code&);      ///< G0 G1
bool run_arc(BlockCtx&, const Code&);           ///< G2 G3
bool run_spline(BlockCtx&, const Code&);        ///< G5 G5.1 (steps_spline.cpp)
bool run_nurbs_point(BlockCtx&, const Code&);   ///< G5.2: one control point
bool run_nurbs_end(BlockCtx&, const Code&);     ///< G5.3: the curve collected since G5.2
bool run_stop(BlockCtx&, const Code&);
bool run_coolant(BlockCtx&, const Code&);      ///< M7 M8 M9
bool run_probe(BlockCtx&, const Code&);        ///< G38.2 G38.3 G38.4 G38.5
bool run_modes_save(BlockCtx&, const Code&);   ///< M70 M71 M72 M73
bool run_orient(BlockCtx&, const Code&);       ///< M19
bool run_digital_out(BlockCtx&, const Code&);  ///< M62 M63 M64 M65
bool run_analog_out(BlockCtx&, const Code&);   ///< M67 M68
bool run_wait_input(BlockCtx&, const Code&);   ///< M66
bool run_user_mcode(BlockCtx&, const Code&);   ///< M100..M199 (recorded, never executed)
/// Emits a spindle, coolant or tool event (EventKind) of this block, behind held-back moves.
void emit_io(BlockCtx& ctx, EventKind kind, int index, double value);
/// Restores saved modes as LinuxCNC does (units first, then one block of F, S and the modal
/// codes that differ, then the M codes).
bool restore_modes(BlockCtx& ctx, const SavedModes& m);

// Shared by the motion steps ---------------------------------------------------------------------
/// The machine-coordinate end point of the block's axis words from `from_mm` (G90/G91, offsets);
/// false with the error set if it is out of range.
bool axis_target(BlockCtx& ctx, const Pos9& from_mm, Pos9& target_mm);
/// The end point of a G53 block: the axis words are machine coordinates (mm after units).
bool machine_target(BlockCtx& ctx, Pos9& target_mm);
/// Emits a straight move (rapid or feed) from the current position to `target_mm` and moves
/// there; zero-length moves are not emitted. False with the error set for a target beyond
/// kMaxPositionMm or a block already holding kMaxMovesPerBlock moves (as emit_arc).
bool emit_straight(BlockCtx& ctx, MotionKind kind, const Pos9& target_mm, SourceLoc loc);
/// Emits a one-turn arc in the active plane from the current position to `target_mm` about
/// `centre_mm` (machine coordinates) at the block's feed, and moves there.
bool emit_arc(BlockCtx& ctx, const Pos9& target_mm, const Pos9& centre_mm, bool ccw);
/// A motion of this block's kind, line, plane and path mode (ends, feed and arc data unset).
Motion motion_template(const BlockCtx& ctx, MotionKind kind);
/// The centre of the block's arc (R or I/J/K words, G90.1/G91.1) from `start_mm` to `end_mm`,
/// machine coordinates (the in-plane components; the rest are start's); false with the error set.
bool arc_centre(BlockCtx& ctx, const Code& c, const Pos9& start_mm, const Pos9& end_mm,
                Pos9& centre_mm);
/// The feed checks of a feed motion (G93 F present and > 0, G94 feed > 0).
bool check_feed(BlockCtx& ctx, int code10, SourceLoc loc);

}  // namespace gm
