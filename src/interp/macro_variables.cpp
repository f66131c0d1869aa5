// Fanuc Macro B's variable numbering and system variables over the parameter store.
#include "interp/macro_variables.hpp"

#include <fmt/format.h>

namespace gm {

namespace {

constexpr const char* kMacroKnown =
    "locals #1-#33, commons #100-#999, system variables #3000, #3901, #3902, #4001-#4022, #4109, "
    "#4114, #4115, #4119, #4120, #5001-#5006, #5021-#5026, #5041-#5046, #5061-#5066, G54-G59 "
    "offsets #5221-#5346";

bool macro_local_or_common(int n) {
  return (n >= 1 && n <= ParameterStore::kMacroLocals) || (n >= 100 && n <= 999);
}
/// Haas's tool feed timers: tools 1-100, seconds (Haas mill operator's manual, macro system
/// variables table).
bool haas_feed_timer(int n) {
  return n >= 5401 && n <= 5500;
}
bool macro_work_offset(int n) {
  return n >= 5221 && n <= 5346 && (n - 5221) % 20 < 6;
}

}  // namespace

void MacroVariables::start() {
  for (int n = 1; n <= ParameterStore::kMacroLocals; ++n) params_.set_system(n, kVacant);
  for (int n = 100; n <= 499; ++n) params_.set_system(n, kVacant);
  for (int n = 500; n <= 999; ++n)
    if (!params_.from_file(n)) params_.set_system(n, kVacant);
  params_.set_system(3901, 0.0);
  params_.set_system(3902, 0.0);
  params_.keep_in_file(500, 999);
}

bool MacroVariables::number(double v, SourceLoc loc, int& n, InterpError& err) {
  if (vacant(v)) v = 0.0;
  const double r = std::round(v);
  if (!(std::fabs(v - r) < 1e-4) || r < 0 || r > 99999)
    return fail(err, ErrorCode::ParameterOutOfRange, loc,
                fmt::format("variable number {} is not a Fanuc variable number (0-99999)", v));
  n = static_cast<int>(r);
  return true;
}

double MacroVariables::named(std::string_view name) const {
  double v = kVacant;
  if (!params_.get_named(name, v)) return kVacant;
  return v;
}

// #4001-#4022: the G code of each modal group in effect (B-63534EN II-15.2, "Modal
// information"); groups gmotion does not model (G22/G23, G61-G64, groups 18-22) read vacant.
bool MacroVariables::modal(int n, double& v) const {
  const double motion = named("_motion_mode");  // G code x 10
  switch (n) {
    case 4001:  // G00-G03, G33; LinuxCNC keeps canned cycles and G80 in the motion group
      v = motion == 0 || motion == 10 || motion == 20 || motion == 30 || motion == 330
              ? motion / 10.0
              : 80.0;
      return true;
    case 4002:
      v = named("_plane") / 10.0;
      return true;
    case 4003:
      v = named("_absolute") != 0.0 ? 90.0 : 91.0;
      return true;
    case 4005:
      v = named("_inverse_time") != 0.0 ? 93.0 : named("_units_per_rev") != 0.0 ? 95.0 : 94.0;
      return true;
    case 4006:
      v = named("_imperial") != 0.0 ? 20.0 : 21.0;
      return true;
    case 4007:
      v = named("_ccomp") / 10.0;
      return true;
    case 4008:
      v = named("_tool_offset") != 0.0 ? 43.0 : 49.0;
      return true;
    case 4009:
      v = motion >= 730 && motion <= 890 ? motion / 10.0 : 80.0;
      return true;
    case 4010:
      v = named("_retract_r_plane") != 0.0 ? 99.0 : 98.0;
      return true;
    case 4011:  // scaling (G51, interp/fanuc_modal.hpp)
      v = scaling_ ? 51.0 : 50.0;
      return true;
    case 4012:  // no modal macro call (G66)
      v = 67.0;
      return true;
    case 4013:
      v = named("_spindle_css_mode") != 0.0 ? 96.0 : 97.0;
      return true;
    case 4014:
      v = named("_coord_system") / 10.0;
      return true;
    case 4016:  // coordinate rotation (G68)
      v = rotation_ ? 68.0 : 69.0;
      return true;
    case 4017:  // polar coordinate command (G16)
      v = polar_ ? 16.0 : 15.0;
      return true;
    case 4109:
      v = named("_feed");
      return true;
    case 4114:
      v = sequence_ < 0 ? kVacant : static_cast<double>(sequence_);
      return true;
    case 4115:
      v = program_;
      return true;
    case 4119:
      v = named("_rpm");
      return true;
    case 4120:
      v = named("_selected_tool");
      return true;
    default:
      if (n >= 4001 && n <= 4022) {
        v = kVacant;
        return true;
      }
      return false;
  }
}

// #5001-#5006 block end point and #5041-#5046 current position (work coordinates: the same
// between blocks), #5021-#5026 machine coordinates (B-63534EN II-15.2, "Current position").
bool MacroVariables::position(int n, double& v) const {
  static constexpr std::string_view kWork[] = {"_x", "_y", "_z", "_a", "_b", "_c"};
  static constexpr std::string_view kMachine[] = {"_abs_x", "_abs_y", "_abs_z",
                                                  "_abs_a", "_abs_b", "_abs_c"};
  for (int base : {5001, 5041})
    if (n >= base && n < base + 6) {
      v = named(kWork[n - base]);
      return true;
    }
  if (n >= 5021 && n < 5027) {
    v = named(kMachine[n - 5021]);
    return true;
  }
  return false;
}

bool MacroVariables::read(int n, SourceLoc loc, double& v, InterpError& err) const {
  if (n == 0 || n == 3000) {
    v = kVacant;
    return true;
  }
  if (macro_local_or_common(n) || n == 3901 || n == 3902 || macro_work_offset(n) ||
      (n >= 5061 && n <= 5066)) {
    v = params_.get(n);
    return true;
  }
  if (modal(n, v) || position(n, v)) return true;
  if (haas_ && haas_feed_timer(n)) {  // a fresh machine: no tool has fed yet
    v = 0.0;
    return true;
  }
  return fail(
      err, ErrorCode::ParameterOutOfRange, loc,
      n < 1000
          ? fmt::format("#{} is not a Fanuc variable (--dialect fanuc reads {})", n, kMacroKnown)
          : fmt::format("unknown system variable #{} (--dialect fanuc reads {})", n, kMacroKnown));
}

bool MacroVariables::writable(int n, SourceLoc loc, InterpError& err) const {
  if (macro_local_or_common(n) || n == 3000 || n == 3901 || n == 3902 || macro_work_offset(n))
    return true;
  if (n == 0)
    return fail(err, ErrorCode::ParameterReadOnly, loc,
                "#0 is always vacant: it cannot be set (write #i = #0 to make #i vacant)");
  double v = 0.0;
  if (modal(n, v) || position(n, v) || (n >= 5061 && n <= 5066) || (haas_ && haas_feed_timer(n)))
    return fail(err, ErrorCode::ParameterReadOnly, loc,
                fmt::format("system variable #{} is read-only", n));
  return read(n, loc, v, err);  // the error naming an unknown variable
}

bool MacroVariables::write(int n, double v, std::string_view remark, SourceLoc loc,
                           InterpError& err) {
  if (n == 3000) {  // B-63534EN II-15.2 "Alarms": #3000 = n (message) stops with alarm 3000 + n
    const long alarm = vacant(v) ? 0 : std::lround(v);
    return fail(err, ErrorCode::CommentAbort, loc,
                fmt::format("alarm {}: {} (#3000 = {})", 3000 + alarm,
                            remark.empty() ? std::string_view("(no message)") : remark, alarm));
  }
  if (macro_work_offset(n) && vacant(v)) v = 0.0;
  params_.set(n, v);
  return true;
}

}  // namespace gm
