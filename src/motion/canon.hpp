// Canonical commands: what the interpreter hands the interpolator, in mm, mm/min and seconds,
// in machine coordinates (units converted, work offsets, G92 and tool length applied).
#pragma once

#include "common/axis.hpp"

#include <cstdint>
#include <string>
#include <variant>

namespace gm {

enum class Plane { XY, XZ, YZ };  ///< G17, G18, G19

/// How the block ends (LinuxCNC's meanings): exact stop (G61.1, or G9 for one block), exact path
/// (G61) and continuous (G64). With the Acc/Dec after interpolation a path is followed exactly
/// only if the filter drains at each block end, so the interpolator holds the next block until
/// the Acc/Dec output has settled in both exact modes; continuous mode runs blocks back to back
/// and lets the filter blend the corners. Exact path passes a tangent join as LinuxCNC's does:
/// the tolerance planner hands such a block on as Continuous, the join planned within the BLU
/// rounding (docs/tolerance.md, "G61: exact path"); the interpreter's canon keeps ExactPath.
enum class PathMode { ExactStop, ExactPath, Continuous };

enum class MotionKind { Rapid, Line, Arc };

/// Which of LinuxCNC's canonical calls a Line is: STRAIGHT_FEED, RIGID_TAP (G33.1, in and out)
/// or STRAIGHT_PROBE (G38.2..G38.5, the probe move and its back-off). It names the move in
/// `gmotion moves`; every stage moves a Line the same way whatever it is.
enum class LineCanon : std::uint8_t { Feed, RigidTap, Probe };

/// One motion block. `start_mm` is where the previous block ended.
struct Motion {
  int line = 0;  ///< 1-based source line of the block
  MotionKind kind = MotionKind::Line;
  AxisVec start_mm = AxisVec::Zero();
  AxisVec end_mm = AxisVec::Zero();
  /// Programmed feed in mm/min (G94). Unused for rapids (the machine's rapid rate applies).
  double feed_mm_min = 0.0;
  /// G93 inverse time: the move takes this long at 100 % override (seconds); 0 = not G93.
  double inverse_time_s = 0.0;
  // Arcs only -------------------------------------------------------------------------------
  AxisVec center_mm = AxisVec::Zero();  ///< centre; its normal-axis component equals start's
  bool ccw = false;                     ///< G3 (counter-clockwise seen from +normal) vs G2
  /// A move the operator makes by hand (G88's retract during its program stop), not one of the
  /// program's canonical moves. (Here, in the padding after `ccw`, to keep Motion's size.)
  bool by_operator = false;
  LineCanon canon = LineCanon::Feed;  ///< Lines only (also in that padding)
  int turns = 1;                      ///< LinuxCNC P: 1 = the ordinary arc, K adds K-1 full turns
  Plane plane = Plane::XY;
  // Block end -------------------------------------------------------------------------------
  PathMode path_mode = PathMode::Continuous;  ///< G9 in the block forces ExactStop
  /// Contour tolerance in force (G64 P, or the machine's path_tolerance_mm under G64 without P),
  /// mm; 0 = unbounded (the filter blends freely). Set under G64 (a G9 block keeps it along its
  /// path, its end an exact stop); 0 under G61 and G61.1.
  double path_tolerance_mm = 0.0;
  double naive_cam_tolerance_mm = 0.0;  ///< G64 Q, mm; 0 = none (carried, not yet applied)
  // Fed by the spindle (G95 feed per revolution, G33 synchronised) ---------------------------
  /// mm along the path per spindle revolution (G95 F, G33 K); 0 = fed in mm/min (or G93). The
  /// spindle runs at `spindle_rpm`, or under G96 at SpindleFeed::rpm_at(x); feed_mm_min is
  /// the feed where the move starts.
  double mm_per_rev = 0.0;
  bool spindle_synced = false;  ///< G33: the feed override does not act (LinuxCNC)
  double spindle_rpm = 0.0;     ///< G97: the programmed S
  /// G96 constant surface speed (mm/min of surface; 0 = G97), its D cap (rpm) and the machine X
  /// of the spindle axis (program X = 0: LinuxCNC's xoffset, work and tool offsets).
  double css_surface_mm_min = 0.0;
  double css_max_rpm = 0.0;
  double css_axis_x_mm = 0.0;

  /// The spindle speed with the tool at machine X `x_mm`, rpm (LinuxCNC motion's CSS rule:
  /// surface / (2 pi r), at most D; on the axis itself, D).
  double spindle_rpm_at(double x_mm) const {
    if (css_surface_mm_min <= 0.0) return spindle_rpm;
    const double r = x_mm > css_axis_x_mm ? x_mm - css_axis_x_mm : css_axis_x_mm - x_mm;
    const double rpm =
        r > 0.0 ? css_surface_mm_min / (2.0 * 3.14159265358979323846 * r) : css_max_rpm;
    return rpm < css_max_rpm ? rpm : css_max_rpm;
  }
  // Set by the tolerance planner (src/planner/) ----------------------------------------------
  /// Largest path speed the interpolator may use in this block, mm/s, whatever the override;
  /// 0 = no cap.
  double speed_cap_mm_s = 0.0;
  /// Arcs: > 0 when the arc is pre-compensated (interpolator/arc_compensation.hpp): commanded on
  /// radius R + c so that the Acc/Dec output lies on R, its speed ramped; the speed its blend
  /// and ramp were planned for, mm/s. 0 = commanded on its programmed radius.
  double comp_speed_mm_s = 0.0;
  /// Pre-compensated arcs: the command stops on the arc's end point (a dwell, a pause, an exact
  /// stop or the program's end follows) or nearly (the next block crawls at under a tenth of
  /// the arc's speed), so its end takes the rows for a stop.
  bool comp_stops_at_end = false;
  /// Pre-compensated arcs the planner found private (nothing else within its filter's reach:
  /// TolerancePlanner::arc_is_private): its moving ends take the end rows fitted for the
  /// distance from the path (ArcEndRows::Way::MovingDistance).
  bool comp_private = false;
  /// The lines within a window before a private arc (comp_private): a change of the feed
  /// override takes at most this change of speed per sample (the arc's ramp), mm/s, instead of
  /// acting at once; 0 = at once. The arc's rows for the distance hold for such speeds only.
  double override_ramp_mm_s = 0.0;
  /// Pre-compensated arcs cut at zone boundaries into pieces of the same centre: how far this
  /// piece starts from the whole arc's start and the whole arc's length, mm of path (length 0:
  /// the piece is the whole arc). The correction, its end rows and its ramp are the whole arc's.
  double comp_arc_from_mm = 0.0;
  double comp_arc_length_mm = 0.0;
  /// Pre-compensated pieces: the path speed the arc's ramp must be down to at this piece's end
  /// (the next piece's cap), mm/s; 0 = none.
  double comp_exit_speed_mm_s = 0.0;
  /// A piece of a block the planner cut at zone boundaries, not its last: the block goes on to
  /// `block_end_mm` (its programmed end) along the same line or circle. The contour measurement
  /// measures to the rest of the block, so that a table ahead of the command (a servo's
  /// overshoot after a step down in speed) is not taken for a path error past the piece's end.
  bool rest_of_block = false;
  AxisVec block_end_mm = AxisVec::Zero();
};

/// The move's kind as `gmotion moves` names it: rapid, line, arc, rigid_tap or probe.
inline const char* motion_kind_name(const Motion& m) {
  if (m.kind == MotionKind::Rapid) return "rapid";
  if (m.kind == MotionKind::Arc) return "arc";
  return m.canon == LineCanon::RigidTap ? "rigid_tap"
         : m.canon == LineCanon::Probe  ? "probe"
                                        : "line";
}

/// G4: zero velocity for `seconds`. Also M0/M1 when the run pauses there (`pause`: the
/// machine's pause_s, CLI --pause-s).
struct Dwell {
  int line = 0;
  double seconds = 0.0;
  bool pause = false;  ///< an M0/M1 program stop held for `seconds`, not a G4
};

/// Non-motion events the downstream stages care about.
enum class EventKind {
  Pause,            ///< M0 (program stop); recorded, the simulation continues
  OptionalPause,    ///< M1
  End,              ///< M2 / M30
  OverrideEnable,   ///< M48, or M50 P1 / M50 alone: feed override takes effect
  OverrideDisable,  ///< M49, or M50 P0: feed override is 100 %
  Message,          ///< (MSG, text)
  // Spindle and I/O (LinuxCNC's canon calls; no effect on motion yet) ---------------------
  SpindleSpeed,   ///< S: SET_SPINDLE_SPEED(value = rpm)
  SpindleStart,   ///< M3/M4: START_SPINDLE_(COUNTER)CLOCKWISE(index = +1 cw, -1 ccw)
  SpindleStop,    ///< M5, M6, M19, M2/M30, cycles: STOP_SPINDLE_TURNING
  SpindleOrient,  ///< M19 R P: ORIENT_SPINDLE(value = angle deg, index = P direction mode)
  OrientWait,     ///< M19 Q: WAIT_ORIENT_SPINDLE_COMPLETE(value = timeout s)
  Mist,           ///< M7 (index 1), M9 (index 0): MIST_ON / MIST_OFF
  Flood,          ///< M8 (index 1), M9 (index 0): FLOOD_ON / FLOOD_OFF
  ToolSelect,     ///< T: SELECT_TOOL(index = tool)
  ToolChange,     ///< M6: CHANGE_TOOL (index = the tool now in the spindle)
  ToolNumber,     ///< M61 Q: CHANGE_TOOL_NUMBER (index = tool)
  DigitalOut,     ///< M62..M65: index = P, value = 1 set / 0 clear, sync = with motion
  AnalogOut,      ///< M67/M68: index = E, value = Q, sync = with motion
  WaitInput,      ///< M66: index = P or E, analog, mode = L, value = Q timeout s
  UserMcode,      ///< M100..M199: index = the number, value = P, value2 = Q (never executed)
};

struct Event {
  int line = 0;
  EventKind kind = EventKind::End;
  std::string text;     ///< message text for EventKind::Message
  int index = 0;        ///< tool, pin, channel, direction or M number (see EventKind)
  double value = 0.0;   ///< rpm, angle, output value, timeout or P (see EventKind)
  double value2 = 0.0;  ///< UserMcode: Q
  int mode = 0;         ///< WaitInput: L (0 immediate, 1 rise, 2 fall, 3 high, 4 low)
  bool sync = false;    ///< DigitalOut/AnalogOut: with motion (M62/M63/M67) vs at once
  bool analog = false;  ///< WaitInput: E (analog) rather than P (digital)
};

using Canon = std::variant<Motion, Dwell, Event>;

struct MotionGeometry;  // motion/geometry.hpp

/// A pull source of canonical commands (the interpreter over a program stream, or a list in tests).
class CanonSource {
 public:
  virtual ~CanonSource() = default;
  /// Writes the next command into `out`; false when the stream has ended.
  virtual bool next(Canon& out) = 0;
  /// When the last next() wrote a Motion whose geometry the source built on the way, that
  /// geometry (equal to MotionGeometry::of(the motion)), so the reader need not build it again;
  /// else nullptr. Valid until the next call of next().
  virtual const MotionGeometry* geometry() const { return nullptr; }
};

}  // namespace gm
