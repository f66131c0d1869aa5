// The machine description every stage reads: period, BLU, limits, plant, gains, Acc/Dec choice.
#pragma once

#include "common/axis.hpp"
#include "machine/tool_table.hpp"

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace gm {

/// Which controller's arc end-radius tolerance rule the interpreter applies.
enum class ArcRule { LinuxCnc, Grbl, G2core };

/// Structure of the digital velocity controller (both are "PI": proportional + integral).
/// Ip: u = Kvi*sum(e) - Kvp*y (proportional on the feedback only; no closed-loop zero; the
///     structure under which the paper's gains give 33 ms rise time and no overshoot).
/// Pi: u = Kvp*e + Kvi*sum(e) (proportional on the error; adds a zero, overshoots ~13-50 %).
enum class VelocityLoopForm { Ip, Pi };

/// What the contour tolerance (G64 P) is planned for: the Acc/Dec output, or the
/// whole linear chain FIR + servo, so that it holds for the table too (within one BLU more).
enum class ToleranceOn { AccDec, Encoder };

/// One axis: resolution, limits (Eq. 7 and 26 of the paper), plant and servo gains. On a rotary
/// axis (A, B, C) every `_mm` quantity is in degrees, and mass, damping and the force limit are
/// the rotary drive's inertia (kg·m²), damping (N·m·s/rad) and torque limit (N·m).
/// Where an axis's position encoder reads (AxisConfig::encoder).
enum class EncoderSite { Motor, Table };

struct AxisConfig {
  double blu_mm = 0.001;        ///< basic length unit: one encoder count, mm
  double v_max_mm_s = 1000.0;   ///< velocity limit V_max
  double f_max_N = 4000.0;      ///< force limit F_max (drive command saturates at it)
  double p_max_W = 500.0;       ///< power limit P_max
  double mass_kg = 500.0;       ///< equivalent mass m
  double damping_kg_s = 500.0;  ///< equivalent viscous damping c
  /// A, B or C (set from the machine's layout by Machine::set_axes): degrees, inertia, torque.
  bool rotary = false;
  /// LinuxCNC's [AXIS_n]WRAPPED_ROTARY (rotary axes only, key `wrapped_rotary`): an absolute
  /// angle is a position modulo 360°, reached in the direction of its sign.
  bool wrapped_rotary = false;
  /// Plant G(s) = num(s)/den(s) from drive command to motor velocity, highest power first.
  /// The paper's first-order plant b/(s+a) is num = {b}, den = {1, a}.
  std::vector<double> plant_num{33.518};
  std::vector<double> plant_den{1.0, 14.45};
  double kvp = 0.0422;        ///< velocity-loop proportional gain
  double kvi = 0.0094;        ///< velocity-loop integral gain
  double kp_1_s = 30.0;       ///< position-loop gain, 1/s
  double backlash_blu = 0.0;  ///< lost motion (off by default)
  double coulomb_N = 0.0;     ///< Coulomb friction (off by default)
  /// Velocity feedforward (LinuxCNC's pid FF1, its output a velocity in position units per
  /// second): the velocity command gets ff1 × the reference's velocity, its backward difference
  /// over T. 1 = the whole velocity (no velocity lag in a P loop); 0 (default) = the paper's loop.
  double ff1 = 0.0;
  /// Acceleration feedforward (LinuxCNC's pid FF2), s: the velocity command gets ff2_s × the
  /// reference's acceleration, its second backward difference over T. 0 by default.
  double ff2_s = 0.0;
  /// Structural modes between motor and table (two-mass oscillators in series, at most 4):
  /// natural frequency, Hz, and damping ratio of each; none by default. The table position (the
  /// tool tip: contour error, trace column `tip`) includes them (servo/flexible_modes.hpp).
  std::vector<double> mode_hz;
  std::vector<double> mode_damping;
  /// Where the position loop's encoder sits (key `encoder`): on the motor (semi-closed loop,
  /// default) or on the table (full-closed loop: a linear scale after the lost motion and the
  /// modes; the velocity loop keeps the motor's encoder).
  EncoderSite encoder = EncoderSite::Motor;
  /// The axis's own Acc/Dec ([axes.<letter>.accdec], axes past X, Y and Z only): profile spec and
  /// τ; "" and 0 take the machine's [accdec]. X, Y and Z share one filter, which the contour
  /// error and the tolerance planner assume.
  std::string accdec_profile;
  double accdec_tau_s = 0.0;

  // --- Unit mapping of the servo model (see src/servo/servo_axis.hpp and docs/servo.md). ---
  /// Motor velocity in BLU/s per unit of plant output (the plant's velocity unit is not given by
  /// the paper). With kv_period_s = 4 ms the velocity feedback gain is 34000*0.004 = 136 counts
  /// per sample per plant unit: the loop gain at which the paper's x and y gains are critically
  /// damped (136.28 and 136.22) with a 33 ms rise time.
  double plant_blu_s_per_unit = 34000.0;
  /// Velocity-loop gain reference period: the velocity feedback is measured in encoder counts per
  /// kv_period_s and Kvi multiplies the error summed once per kv_period_s (paper: T = 4 ms).
  double kv_period_s = 0.004;
  VelocityLoopForm kv_form = VelocityLoopForm::Ip;  ///< velocity controller structure
  /// Force per unit of drive command, N/unit (the drive command is in volts in the paper). 0 means
  /// derive it from the plant: mass_kg * (num[0]/den[0]) * plant_blu_s_per_unit * blu_mm * 1e-3
  /// (relative degree 1 only). The drive command saturates at +-f_max_N / drive_N_per_unit.
  double drive_N_per_unit = 0.0;
};

/// The whole machine. Defaults are the built-in default machine (3 axes XYZ, paper numbers).
struct Machine {
  std::string name = "default";
  std::string source = "<built-in>";  ///< file it was read from
  double period_s = 0.004;            ///< interpolation period T
  int servo_substeps = 1;             ///< servo period = T / servo_substeps
  double rapid_mm_min = 6000.0;       ///< G0 rate (path speed)
  double max_override = 2.0;          ///< largest feed override, 2.0 = 200 %
  std::string profile = "blackman";   ///< Acc/Dec profile spec (see accdec/profile_spec.hpp)
  double tau_s = 0.164;               ///< Acc/Dec time constant (N+1)T
  ArcRule arc_rule = ArcRule::LinuxCnc;
  /// Contour tolerance under G64 without P, mm (machine key path_tolerance_mm, CLI --tolerance);
  /// 0 = unbounded, the filter blends corners freely.
  double path_tolerance_mm = 0.0;
  /// Machine key tolerance_on ("acc_dec" or "encoder"), CLI --tolerance-on.
  ToleranceOn tolerance_on = ToleranceOn::AccDec;
  /// Machine key arc_precompensation ("on", the default, or "off"): arcs under a tolerance are
  /// commanded on R + c so that the Acc/Dec output lies on R (docs/tolerance.md,
  /// "Pre-compensated arcs").
  bool arc_precompensation = true;
  /// Machine key g61_arc_precompensation ("off", the default, or "on"): arcs under G61 (exact
  /// path, no tolerance) are commanded pre-compensated at their feed too, not slowed, so that
  /// their steady part lies on R instead of inside it (docs/tolerance.md, "G61: exact path").
  bool g61_arc_precompensation = false;
  /// Machine key private_arcs ("on", the default, or "off"): a pre-compensated arc with nothing
  /// else within its filter's reach but near-tangent corners takes end rows fitted for the
  /// distance from the path and is planned by that distance (docs/tolerance-arc-ends.md,
  /// "Private arcs"); "off": every arc as one that shares its windows.
  bool private_arcs = true;
  /// Machine key servo_matching ("on", the default, or "off"): with tolerance_on = encoder and
  /// the servo on, X, Y and Z servos that differ have their references shaped to respond as the
  /// planned chain's servo does (planner/servo_response's design_servo_match; docs/tolerance.md,
  /// "Servos matched").
  bool servo_matching = true;
  /// The machine's axes (key `axes.letters`, CLI --axes): a subsequence of XYZABCUVW. Rotary
  /// axes (A, B, C) count in degrees: their `_mm` quantities are degrees (blu_mm = degrees per
  /// count, v_max_mm_s = deg/s). Kinematics are trivial: each axis is one joint.
  AxisLayout layout{};
  std::vector<AxisConfig> axes = std::vector<AxisConfig>(3);  ///< one per axis, layout order
  std::vector<double> tool_lengths_mm;  ///< index = tool number (T0 = index 0); overrides table Z
  ToolTable tool_table = default_tool_table();  ///< key `tool_table` or --tool-table FILE
  /// Where `o<name> call` finds `name.ngc` (key `subroutine_path` "DIR[:DIR...]", relative to
  /// the machine file; LinuxCNC's [RS274NGC]SUBROUTINE_PATH); searched after --subroutine-path.
  std::vector<std::string> subroutine_path;
  /// LinuxCNC `.var` parameter file read at the start and written at the end of a run (key
  /// `parameter_file`, relative to the machine file); empty: none.
  std::string parameter_file;
  /// LinuxCNC's [RS274NGC]INI_VARS (on unless 0): the INI's numeric values, read-only to a
  /// program as `#<_ini[SECTION]NAME>`; keyed by the parameter's name in lower case
  /// ("_ini[section]name"). Empty for machine files.
  std::map<std::string, double, std::less<>> ini_vars;
  /// False: the parameter file's G92 offsets (#5210-#5219) are cleared when it is read
  /// (LinuxCNC's [RS274NGC]DISABLE_G92_PERSISTENCE = 1).
  bool g92_persistent = true;
  /// Added to M19's R, degrees (LinuxCNC's [RS274NGC]ORIENT_OFFSET).
  double orient_offset_deg = 0.0;
  /// What programs for this machine are written in (key `dialect`: "linuxcnc", "fanuc",
  /// "grbl"; docs/dialects.md); empty: linuxcnc. --dialect overrides it.
  std::string dialect;
  /// A lathe (key `kind = "lathe"`, default "mill"; LinuxCNC's [DISPLAY]LATHE = 1; --lathe):
  /// under --dialect fanuc the program is read with Fanuc/Haas lathe conventions (X a diameter,
  /// U/W incremental, T0101, G50, G71/G70, G76; docs/dialects.md "Fanuc/Haas lathe"). Under
  /// linuxcnc nothing changes (G7/G8 as rs274).
  bool lathe = false;
  /// Where M100..M199 are looked up (a file named M101 makes M101 known; it is recorded, never
  /// run): key `user_mcode_dir` or --user-mcode-dir; empty: every user M code is an error.
  std::string user_mcode_dir;
  /// LinuxCNC's [RS274NGC]DISABLE_FANUC_STYLE_SUB = 1 (INI only): M98, M99 in a subprogram and a
  /// bare `O1234` line are errors, as rs274's.
  bool fanuc_subs_disabled = false;
  /// The units a program starts in (key `program_units` "mm" or "inch"): false = G21, true = G20.
  /// LinuxCNC starts in its configuration's [TRAJ]LINEAR_UNITS; M2/M30 do not change them.
  bool program_inch = false;
  /// The spindle's acceleration, rpm/s (key `spindle_accel_rpm_s`); 0: at its commanded speed
  /// at once. Feeds per revolution follow the speed reached; G33/G76/G33.1 wait for it.
  double spindle_accel_rpm_s = 0.0;
  /// How long an M0/M1 program stop holds the run, s (key `pause_s`, CLI --pause-s); 0: none.
  double pause_s = 0.0;
  /// G54..G59 on the nine program axes (XYZABCUVW order), mm (degrees for A, B, C).
  std::array<AxisVec, 6> work_offsets_mm{AxisVec::Zero(), AxisVec::Zero(), AxisVec::Zero(),
                                         AxisVec::Zero(), AxisVec::Zero(), AxisVec::Zero()};

  int axis_count() const { return layout.count; }
  /// Some axis has structural modes (mode_hz): the trace gets the tool tip per axis and the
  /// summary the vibration at it.
  bool has_modes() const {
    for (int i = 0; i < layout.count; ++i)
      if (!axes[static_cast<std::size_t>(i)].mode_hz.empty()) return true;
    return false;
  }
  /// Per-axis BLU in the machine's axis order (0 past the count), mm (degrees on rotary axes).
  MachineVec blu_mm() const {
    MachineVec b = MachineVec::Zero();
    for (int i = 0; i < layout.count; ++i) b[i] = axes[static_cast<std::size_t>(i)].blu_mm;
    return b;
  }
  /// BLU of X, Y and Z (0 for an axis the machine lacks), mm: the contour's resolution.
  Eigen::Vector3d xyz_blu_mm() const {
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (int i = 0; i < layout.count; ++i)
      if (layout.program(i) < 3) b[layout.program(i)] = axes[static_cast<std::size_t>(i)].blu_mm;
    return b;
  }
  /// The BLU contour errors are expressed in: the smallest of the linear axes (of all axes when
  /// the machine has only rotary ones), mm.
  double contour_blu_mm() const {
    double lin = 0.0, any = 0.0;
    for (int i = 0; i < layout.count; ++i) {
      const double b = axes[static_cast<std::size_t>(i)].blu_mm;
      if (!axis_is_rotary(layout.program(i)) && (lin == 0.0 || b < lin)) lin = b;
      if (any == 0.0 || b < any) any = b;
    }
    return lin > 0.0 ? lin : any;
  }
  /// Gives the machine the axes `l`: an axis it already has keeps its settings, a new one
  /// takes `fresh` (a new rotary one: fresh's servo with rotary_axis_limits()).
  void set_axes(const AxisLayout& l, const AxisConfig& fresh) {
    std::vector<AxisConfig> next;
    for (int a = 0; a < l.count; ++a) {
      const AxisConfig* kept = nullptr;
      for (int b = 0; b < layout.count; ++b)
        if (layout.program(b) == l.program(a)) kept = &axes[static_cast<std::size_t>(b)];
      const bool rotary = axis_is_rotary(l.program(a));
      next.push_back(kept ? *kept : rotary ? rotary_axis_limits(fresh) : fresh);
      next.back().rotary = rotary;
    }
    layout = l;
    axes = std::move(next);
  }
  /// `servo` with a rotary drive's default limits and load: 360 °/s (60 rpm), 200 N·m, 750 W,
  /// inertia 0.5 kg·m², damping 1 N·m·s/rad (a 4th-axis table with its part, at the table).
  static AxisConfig rotary_axis_limits(const AxisConfig& servo) {
    AxisConfig a = servo;
    a.v_max_mm_s = 360.0;
    a.f_max_N = 200.0;
    a.p_max_W = 750.0;
    a.mass_kg = 0.5;
    a.damping_kg_s = 1.0;
    a.wrapped_rotary = false;
    return a;
  }
};

/// The built-in default machine (3 axes XYZ, the paper's numbers; y has the paper's y plant).
/// Needs no file; equal to programs/machines/default.toml.
Machine default_machine();

}  // namespace gm
