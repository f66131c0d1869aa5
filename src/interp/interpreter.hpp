// The modal G-code interpreter: validates a parsed block whole, then commits it and emits canon.
#pragma once

#include "common/axis.hpp"
#include "common/diagnostic.hpp"
#include "common/error_codes.hpp"
#include "grammar/parse.hpp"
#include "interp/canon.hpp"
#include "machine/machine.hpp"

#include <string>
#include <vector>

namespace gm {

/// A located interpreter error.
struct InterpError {
  ErrorCode code = ErrorCode::None;
  SourceLoc loc;
  std::string message;
};

/// The modal state (grbl's parser_state_t): everything that persists from block to block.
/// Positions are machine coordinates in mm; offsets in mm.
struct ModalState {
  int motion = -1;  ///< 0,1,2,3 = G0..G3; -1 none yet (LinuxCNC starts without one)
  Plane plane = Plane::XY;
  bool inch = false;          ///< G20
  bool incremental = false;   ///< G91
  bool ijk_absolute = false;  ///< G90.1 (default G91.1)
  bool inverse_time = false;  ///< G93
  PathMode path_mode = PathMode::Continuous;
  double path_tolerance_mm = -1.0;      ///< G64 P in mm; < 0: G64 without P (the machine's)
  double naive_cam_tolerance_mm = 0.0;  ///< G64 Q in mm
  int coord_system = 0;                 ///< 0..5 = G54..G59
  double feed_mm_min = 0.0;             ///< G94 feed; 0 = none yet
  AxisVec g92_mm = AxisVec::Zero();
  double tool_length_mm = 0.0;            ///< G43 length, applied to Z
  int tool_selected = 0;                  ///< T
  int tool_in_spindle = 0;                ///< after M6
  AxisVec position_mm = AxisVec::Zero();  ///< machine coordinates
  bool ended = false;                     ///< M2/M30 or closing % seen
};

/// Interprets blocks one at a time (grbl gcode.c STEP 1-4): copy the state, import the words,
/// check everything, then commit. A block with an error changes nothing.
class Interpreter {
 public:
  /// `machine` supplies tool lengths, work offsets and the arc rule; it must outlive this.
  explicit Interpreter(const Machine& machine);

  /// Interprets `block` (which must have no syntax errors). On success appends its canonical
  /// commands to `out` (in mm, mm/min, s, machine coordinates) and returns true; on failure
  /// sets `err` and returns false with the state unchanged.
  bool execute(const grammar::Block& block, std::vector<Canon>& out, InterpError& err);

  const ModalState& state() const { return state_; }
  /// Sum of all offsets from program to machine coordinates under the current state, mm.
  AxisVec total_offset_mm() const;

 private:
  const Machine& machine_;
  ModalState state_;
};

/// Length of a motion's path, mm (helical length for arcs, including extra turns).
double motion_length_mm(const Motion& m);
/// Signed sweep angle of an arc in radians (positive CCW), turns included.
double arc_sweep_rad(const Motion& m);

}  // namespace gm
