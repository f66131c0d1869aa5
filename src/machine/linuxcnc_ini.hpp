// A LinuxCNC INI configuration read as a gmotion machine, and a machine written as INI sections.
#pragma once

#include "machine/machine.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// What reading an INI gives: the machine, the per-axis acceleration limits it named (machine
/// axis order, mm/s^2 or deg/s^2; 0 where none) and, once, what it could not map.
struct IniImport {
  Machine machine;
  std::vector<double> a_max_mm_s2;
  std::vector<std::string> warnings;  ///< one line each: "[SECTION]KEY: why it is not used"
};

/// True when `path` names a LinuxCNC INI (its extension is .ini, any case).
bool is_linuxcnc_ini(const std::filesystem::path& path);

/// Reads a LinuxCNC INI (with its #INCLUDE files, relative to the INI's directory, at most 8
/// deep). Maps [EMCMOT]SERVO_PERIOD to T; [TRAJ]COORDINATES to the axes, LINEAR_UNITS and
/// ANGULAR_UNITS to the conversion into mm and degrees, MAX_LINEAR_VELOCITY to the rapid rate;
/// [AXIS_L]/[JOINT_n] MAX_VELOCITY, MAX_ACCELERATION (the smaller of the two), INPUT_SCALE
/// (BLU) and BACKLASH; [DISPLAY]MAX_FEED_OVERRIDE; [EMCIO]TOOL_TABLE; [RS274NGC]SUBROUTINE_PATH
/// and PARAMETER_FILE (paths relative to the INI's directory). τ is suggested from the limits
/// (tau_for_accel_limit, accdec/accel_limit.hpp). Throws gm::InputError "FILE:LINE: [SECTION]KEY:
/// ..." on a value it needs and cannot read.
IniImport load_linuxcnc_ini(const std::filesystem::path& path);

/// τ from the acceleration limits (accdec's tau_for_accel_limit) for machine m's profile, period
/// and axis speed limits.
double tau_for_accel_limit(const Machine& m, const std::vector<double>& a_max_mm_s2,
                           double fallback_s);

/// The INI sections a LinuxCNC configuration needs for this machine's axes: [EMCMOT]
/// SERVO_PERIOD, [TRAJ] (COORDINATES, units mm/degree, MAX_LINEAR_VELOCITY), [KINS] JOINTS,
/// [DISPLAY] MAX_FEED_OVERRIDE and per axis [AXIS_L] and [JOINT_n] with MAX_VELOCITY,
/// MAX_ACCELERATION = c·V/τ (c = profile_peak_factor, so that reading it back suggests the
/// machine's τ), INPUT_SCALE = 1/BLU and BACKLASH.
std::string machine_to_linuxcnc_ini(const Machine& m);

}  // namespace gm
