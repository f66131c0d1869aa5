// The modal G-code interpreter: validates a parsed block whole, then commits it and emits canon.
#pragma once

#include "common/axis.hpp"
#include "common/diagnostic.hpp"
#include "common/error_codes.hpp"
#include "grammar/parse.hpp"
#include "interp/cutter_comp.hpp"
#include "interp/lathe_profile.hpp"
#include "interp/program_axes.hpp"
#include "interp/spline.hpp"
#include "machine/machine.hpp"
#include "machine/tool_table.hpp"
#include "motion/canon.hpp"
#include "motion/geometry.hpp"  // motion_length_mm, arc_sweep_rad, plane_axes

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace gm {

/// A located interpreter error.
struct InterpError {
  ErrorCode code = ErrorCode::None;
  SourceLoc loc;
  std::string message;
};

/// Fills `err` and returns false, so that a failing step reads `return fail(err, code, loc, msg);`.
inline bool fail(InterpError& err, ErrorCode code, SourceLoc loc, std::string msg) {
  err.code = code;
  err.loc = loc;
  err.message = std::move(msg);
  return false;
}

/// The modes M70/M73 save and M72 restores (LinuxCNC's saved_g_codes/m_codes/settings of a call
/// level): modal G codes, F and S in the program units they were set in, spindle, override.
struct SavedModes {
  bool valid = false;              ///< M70/M73 saved here; M71 clears it
  bool restore_on_return = false;  ///< M73: restored when the subroutine returns
  bool inch = false;
  bool incremental = false, ijk_absolute = false, inverse_time = false, retract_to_r = true;
  bool per_rev = false;
  Plane plane = Plane::XY;
  int comp_code = 400;         ///< G40 G41 G42 (x 10)
  int tool_length_code = 490;  ///< G43 G43.1 G43.2 G49 (x 10)
  int coord_system = 0;
  PathMode path_mode = PathMode::Continuous;
  double path_tolerance_mm = -1.0, naive_cam_tolerance_mm = 0.0;
  double feed_units = 0.0;  ///< F in the units in force when saved
  double speed_rpm = 0.0;
  int spindle_dir = 0;
  bool mist = false, flood = false;
  bool feed_override = true;
};
inline constexpr int kCallLevels = 10;  ///< call levels 0 (the program) .. 9 (kMaxCallDepth)

/// The values a block rarely changes (LinuxCNC's system parameters #5161..#5389: stored G28/G30
/// positions, coordinate systems). Kept here until the parameter store holds them; a block that
/// changes them works on a copy (BlockCtx::tables_w) that is committed with the block.
struct SystemTables {
  std::array<Pos9, 9> g5x_mm{};  ///< work offsets of G54..G59, G59.1..G59.3 (machine units, mm)
  std::array<double, 9> g5x_rotation_deg{};  ///< their XY rotations (G10 L2 R), degrees ccw
  Pos9 g28_mm = Pos9::Zero();                ///< G28.1 position, machine coordinates
  Pos9 g30_mm = Pos9::Zero();                ///< G30.1 position, machine coordinates
  Pos9 g92_saved_mm = Pos9::Zero();          ///< G92 offsets as stored: G92.2 keeps, G92.3 restores
  ToolTable tools;                           ///< the tool table (G10 L1/L10/L11 change it)
  std::array<SavedModes, kCallLevels> saved_modes{};  ///< M70/M73 contexts by call level

  SystemTables() {
    for (auto& o : g5x_mm) o.setZero();
  }
};

/// The modal state (grbl's parser_state_t): everything that persists from block to block.
/// Positions are machine coordinates in mm on the nine program axes; offsets in mm.
struct ModalState {
  int motion = -1;  ///< motion code x 10 in effect (G0 = 0, G1 = 10, ...); -1 none yet
  Plane plane = Plane::XY;
  bool inch = false;                ///< G20
  bool incremental = false;         ///< G91
  bool ijk_absolute = false;        ///< G90.1 (default G91.1)
  bool lathe_diameter = false;      ///< G7: X words are diameters (default G8, radius)
  bool inverse_time = false;        ///< G93
  bool per_rev = false;             ///< G95: feed_mm_min holds the F in mm per spindle revolution
  bool css = false;                 ///< G96: S is a surface speed
  double css_surface_mm_min = 0.0;  ///< G96: the surface speed S, mm/min (m/min or ft/min x S)
  double css_max_rpm = 0.0;         ///< G96 D: the spindle's cap, rpm (no D: 1e30, as LinuxCNC)
  PathMode path_mode = PathMode::Continuous;
  double path_tolerance_mm = -1.0;      ///< G64 P in mm; < 0: G64 without P (the machine's)
  double naive_cam_tolerance_mm = 0.0;  ///< G64 Q in mm
  double feed_mm_min = 0.0;             ///< G94 feed; 0 = none yet
  int tool_selected = 0;                ///< T
  int tool_in_spindle = 0;              ///< after M6 or M61
  int spindle_slot_tool = 0;            ///< the tool whose data M6 loaded (G43 without H uses it)
  Pos9 position_mm = Pos9::Zero();      ///< machine coordinates
  int coord_system = 0;                 ///< 0..8 = G54..G59, G59.1..G59.3
  /// The active system's offsets and XY rotation as they were when it was selected (LinuxCNC
  /// copies them then: a program writing #5221.. changes them at the next selection or G10).
  Pos9 g5x_mm = Pos9::Zero();
  double g5x_rotation_deg = 0.0;
  Pos9 g92_mm = Pos9::Zero();  ///< G92/G52 axis offsets
  bool g92_applied = false;    ///< G92/G52/G92.3 on, G92.1/G92.2 off
  double g92_flag = 0.0;       ///< #5210: 1 or 0 as those set it, else the parameter file's value
  Pos9 tool_offset_mm = Pos9::Zero();  ///< G43 tool length offset
  int spindle_dir = 0;                 ///< M3 = 1, M4 = -1, M5 = 0
  double spindle_rpm = 0.0;            ///< S
  int tool_length_code = 490;          ///< G43/G43.1/G43.2/G49 in effect (x 10)
  bool feed_override = true;           ///< M48 (M50 P1) vs M49 (M50 P0)
  bool mist = false, flood = false;    ///< M7, M8 (M9 turns both off)
  // Canned cycles (program units, as LinuxCNC keeps them) --------------------------------------
  bool retract_to_r = true;   ///< G99 (LinuxCNC's initial retract mode); G98 = false
  int cycle_mode = -1;        ///< the cycle code x 10 of the previous cycle block, -1 none
  bool cycle_il_set = false;  ///< the initial level of this run of cycle blocks is known
  double cycle_il = 0.0;      ///< initial level (cycle axis, program units)
  double cycle_r = 0.0, cycle_bottom = 0.0, cycle_p = 0.0, cycle_q = 0.0;  ///< sticky R Z P Q
  std::array<double, 3> cycle_ijk{};                                       ///< G87's sticky I J K
  CutterComp comp;     ///< G40/G41/G42: side, radius, the held-back moves
  bool ended = false;  ///< M2/M30 or closing % seen

  /// mm per program length unit (25.4 under G20).
  double mm_per_unit() const;
};

/// The system parameters a block sets for the program to read (#5061-#5070 after G38.x, #5399
/// after M66): written to the parameter store when the block commits.
struct ResultParameters {
  static constexpr std::size_t kMax = 16;
  struct Set {
    int number;
    double value;
  };
  std::array<Set, kMax> set;  ///< the first `count` are valid (left unset: built every block)
  std::size_t count = 0;
  void add(int n, double v) {
    if (count < kMax) set[count++] = {n, v};
  }
};

class ParameterStore;

/// A lathe cycle G70-G72 between its line and the end of its profile subroutine (program
/// units, X as a radius).
struct G7xCycle {
  bool pending = false;  ///< the cycle's line ran: the driver calls the subroutine `label`
  int code10 = 0;
  SourceLoc loc;
  std::string label;
  double x = 0, z = 0, d = 0, e = 0, i = 1, p = 1, r = 0.5;
  bool incremental = false, ijk_absolute = false, diameter = false;
  int motion = -1;  ///< the profile's motion mode
  lathe::Pt at, start;
  Pos9 position_mm = Pos9::Zero();  ///< where the tool is when the profile is read
  std::vector<lathe::Seg> profile;
};

struct BlockWords;  // interp/steps.hpp

/// Interprets blocks one at a time (grbl gcode.c STEP 1-4): copy the state, import the words,
/// check everything, then commit. A block with an error changes nothing.
class Interpreter {
 public:
  /// `machine` supplies tool lengths, work offsets and the arc rule; it must outlive this.
  explicit Interpreter(const Machine& machine);
  const Machine& machine() const { return machine_; }

  /// Interprets `block` (which must have no syntax errors). On success appends its canonical
  /// commands to `out` (in mm, mm/min, s, machine coordinates) and returns true; on failure
  /// sets `err` and returns false with the state unchanged.
  bool execute(const grammar::Block& block, std::vector<Canon>& out, InterpError& err) {
    return execute(block, nullptr, out, err);
  }
  /// The same with the block's words already imported (import_words, interp/block_words.hpp;
  /// the read-ahead thread imports plain lines); null: imported here.
  bool execute(const grammar::Block& block, const BlockWords* imported, std::vector<Canon>& out,
               InterpError& err);

  const ModalState& state() const { return states_[cur_]; }
  /// The subroutine call level the next blocks run at (0 = the program); entering a level
  /// clears its saved modes (LinuxCNC enter_context).
  void enter_call(int level);
  /// A subroutine at `level` returned (endsub/return): modes saved there by M73 are restored
  /// (LinuxCNC leave_context). `line` is the returning line; false with `err` on an error.
  bool leave_call(int level, int line, std::vector<Canon>& out, InterpError& err);
  const SystemTables& tables() const { return tables_; }
  /// Starts from the persistent parameters of a .var file, as LinuxCNC's Interp::init does
  /// after reading it (interp/restore_parameters.cpp): G28/G30 positions, G54-G59.3
  /// offsets, the coordinate system #5220 (1-9, else G54) and G92's offsets, applied if #5210
  /// is set. `par(n)` is #n (mm, degrees).
  void restore_system_parameters(const std::function<double(int)>& par);
  /// A program wrote system parameter #n (G28 #5161.., G30 #5181.., G92 #5211.., G54-G59.3
  /// #5221..#5390, mm and degrees): the tables take it as LinuxCNC's parameters do; the active
  /// system's offsets follow at its next selection or G10. False if #n is none of those.
  bool write_system_parameter(int n, double v);
  /// Where a committed block's result parameters (#5061-#5070, #5399) are written; null: nowhere.
  void set_result_parameters(ParameterStore* params) { result_params_ = params; }
  /// Fanuc, Haas: G41/G42 with compensation on starts it again with the new D (CutterComp).
  void allow_comp_reissue() { state_mut().comp.reissue = true; }
  /// Adds `e` to the tool table (a dialect's zero-length tool for a number the table lacks).
  void add_tool(const ToolEntry& e) {
    tables_.tools.set(e);
    ++tables_version_;
  }
  /// Changes whenever a block changed the tables (so their parameters need writing again).
  std::uint64_t tables_version() const { return tables_version_; }

 private:
  // G70-G72 (steps_g7x.cpp), driven by G7xDriver (g7x_driver.hpp): true after the cycle's line
  // ran; the driver then calls its subroutine and hands the subroutine's blocks to
  // g7x_collect, then calls g7x_finish at its end.
  friend class G7xDriver;
  bool g7x_pending() const { return g7x_.pending; }
  const G7xCycle& g7x() const { return g7x_; }
  void g7x_started() { g7x_.pending = false; }
  /// One block of the profile subroutine: its motion is recorded, nothing is run.
  bool g7x_collect(const grammar::Block& block, InterpError& err);
  /// The subroutine returned at `line`: the cycle's moves; errors are located at `line`.
  bool g7x_finish(int line, std::vector<Canon>& out, InterpError& err);

  /// execute() once the block's words are imported (X halved in G7).
  bool execute_words(const grammar::Block& block, const BlockWords& w, std::vector<Canon>& out,
                     InterpError& err);
  /// execute() for a block whose steps LightUndo covers: run on the state itself.
  bool execute_light(const grammar::Block& block, const BlockWords& w, std::vector<Canon>& out,
                     InterpError& err);

  const Machine& machine_;
  /// The modal state and the copy a block executes on; a block that succeeds is committed by
  /// making its copy the state (no second copy), one that fails leaves the state as it was.
  std::array<ModalState, 2> states_{};
  int cur_ = 0;
  NurbsCurve nurbs_;   ///< the G5.2 control points so far (kept apart: a curve may be long)
  G7xCycle g7x_;       ///< the lathe cycle being read
  G7xCycle g7x_next_;  ///< the cycle a block starts (kept: not built and destroyed per block)
  ModalState& state_mut() { return states_[cur_]; }
  /// The scratch copy, set to the state: what execute() and leave_call() work on.
  ModalState& begin_block() {
    ModalState& s = states_[1 - cur_];
    s = states_[cur_];
    return s;
  }
  void commit_block() { cur_ = 1 - cur_; }
  SystemTables tables_;
  int call_level_ = 0;
  std::uint64_t tables_version_ = 1;
  ParameterStore* result_params_ = nullptr;
};

}  // namespace gm
