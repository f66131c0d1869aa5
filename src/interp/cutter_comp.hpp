// Cutter radius compensation (G40, G41, G42, G41.1, G42.1) as LinuxCNC 2.9 runs it: the state a
// block carries, and the steps that offset straight moves and arcs by the tool radius.
#pragma once

#include "interp/program_axes.hpp"
#include "motion/canon.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace gm {

struct BlockCtx;
struct Code;
struct SourceLoc;

/// One command held back under compensation: a move whose end point the next move may still
/// change (LinuxCNC's queued canon), or a dwell queued behind it.
struct CompQueued {
  bool is_motion = true;
  Motion mo;                        ///< kind, line, feed, arc sense and turns, plane, path mode
  Pos9 end_mm = Pos9::Zero();       ///< end point (machine coordinates, nine axes)
  Pos9 center_mm = Pos9::Zero();    ///< arcs: the centre (in-plane components)
  double dir_a = 0.0, dir_b = 0.0;  ///< straight moves: the programmed direction in the plane
  double sweep_rad = 0.0;           ///< arcs: the sweep as enqueued (0: not checked)
  bool inverse_time = false;        ///< G93: inverse_time_s is set when it leaves the queue
  Canon held;                       ///< when !is_motion: a dwell or an event
};

/// The held-back commands, oldest first: appended to and cleared, never changed in place. The
/// interpreter copies its modal state for every block (a block that fails leaves it as it was),
/// so a copy keeps what the two queues share and copies only the rest: each command pushed gets a
/// number no other push gets, and two queues holding the same number at the same place hold the
/// same commands up to it. (A full copy made a block under compensation cost as much as the
/// queue was long: 8,000 moves along Z held back took 1 s, quadratically more with more.)
class CompQueue {
 public:
  CompQueue() = default;
  CompQueue(const CompQueue&) = default;
  CompQueue(CompQueue&&) noexcept = default;
  CompQueue& operator=(CompQueue&&) noexcept = default;
  CompQueue& operator=(const CompQueue& o);
  ~CompQueue() = default;

  bool empty() const { return items_.empty(); }
  std::size_t size() const { return items_.size(); }
  const CompQueued& front() const { return items_.front(); }
  std::vector<CompQueued>::const_iterator begin() const { return items_.begin(); }
  std::vector<CompQueued>::const_iterator end() const { return items_.end(); }
  void push_back(CompQueued q);
  void clear() {
    items_.clear();
    ids_.clear();
  }

 private:
  std::vector<CompQueued> items_;
  std::vector<std::uint64_t> ids_;  ///< each item's push, unique in the process
};

/// Compensation state (LinuxCNC's cutter_comp_side/radius/firstmove, program_x/y/z, the queue).
/// Positions are machine coordinates in mm; `a`, `b` are the plane's two axes (plane_axes()).
struct CutterComp {
  int side = 0;                       ///< +1 left (G41), -1 right (G42), 0 off (G40)
  double radius_mm = 0.0;             ///< tool radius, >= 0 (a negative D swaps the side)
  int orientation = 0;                ///< lathe tool orientation (G18 only), 0 = mill
  bool first_move = true;             ///< no move made since compensation was turned on
  double prog_a = 0.0, prog_b = 0.0;  ///< the programmed (uncompensated) point in the plane
  bool arc_not_allowed = false;       ///< the move after G40 must be straight
  CompQueue queue;                    ///< held-back commands, oldest first
  Pos9 emitted_mm = Pos9::Zero();     ///< where the last command that left the queue ended
  double end_a = 0.0, end_b = 0.0;    ///< start of the queued moves (LinuxCNC's endpoint)
  bool end_valid = false;
  /// After G40 the interpreter's point is the programmed one while the tool is still where the
  /// last compensated move left it: the next move starts from `emitted_mm`.
  bool detached = false;
  /// Fanuc, Haas: G41/G42 with compensation on starts it again (a new side or D) from the next
  /// move, as G40 then G41/G42 would; LinuxCNC refuses it.
  bool reissue = false;

  bool on() const { return side != 0; }
  bool active() const { return side != 0 && radius_mm > 0.0; }
};

/// G40 G41 G42 G41.1 G42.1 (the cutter compensation step of the order of execution).
bool run_cutter_comp(BlockCtx& ctx, const Code& c);
/// A straight move (G0/G1) to the programmed `target_mm` under active compensation.
bool comp_straight(BlockCtx& ctx, MotionKind kind, const Pos9& target_mm);
/// An arc (G2/G3) to the programmed `target_mm` under active compensation (XY or XZ plane);
/// its centre from the block's words, or `centre_mm` when given (G70's profile arcs).
bool comp_arc(BlockCtx& ctx, const Code& c, const Pos9& target_mm, int turns,
              const Pos9* centre_mm = nullptr);
/// Sends every held-back command on with the last move ending where the tool is (M0/M1/M2/M30).
bool comp_flush(BlockCtx& ctx);
/// Appends a non-motion command behind the held-back moves, or to the output if none is held.
void emit_in_order(BlockCtx& ctx, Canon c);
/// The error LinuxCNC gives when `what` is done with compensation on; true if it is off.
bool comp_forbids(BlockCtx& ctx, SourceLoc loc, std::string_view what);
/// Where the axis words of a move start from: the programmed point under compensation (after
/// its first move), else the tool's position (LinuxCNC find_ends).
Pos9 comp_program_point(const BlockCtx& ctx);
/// Where the next emitted move starts (the tool, which differs from the interpreter's point
/// right after G40).
const Pos9& motion_start(const BlockCtx& ctx);

}  // namespace gm
