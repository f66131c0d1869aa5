// The predefined parameters read from the interpreter's state, the system parameters exported
// to the store and written back from it, and the parameter file's load and save.
#include "interp/system_parameters.hpp"

#include "common/error_codes.hpp"
#include "interp/frame.hpp"

namespace gm {

bool StateParameters::predefined(std::string_view name, double& v) const {
  return axis_parameter(name, v) || mode_parameter(name, v) || ini_parameter(name, v);
}

// #<_ini[SECTION]NAME>: the machine INI's value (LinuxCNC's INI_VARS), read-only.
bool StateParameters::ini_parameter(std::string_view name, double& v) const {
  if (!name.starts_with("_ini[")) return false;
  const auto& vars = interp_.machine().ini_vars;
  const auto it = vars.find(name);
  if (it == vars.end()) return false;
  v = it->second;
  return true;
}

bool StateParameters::axis_parameter(std::string_view name, double& v) const {
  const ModalState& s = interp_.state();
  const double units = s.inch ? 25.4 : 1.0;
  static constexpr std::string_view kAxisNames[] = {"_x", "_y", "_z", "_a", "_b",
                                                    "_c", "_u", "_v", "_w"};
  static constexpr std::string_view kAbsAxes[] = {"_abs_x", "_abs_y", "_abs_z", "_abs_a", "_abs_b",
                                                  "_abs_c", "_abs_u", "_abs_v", "_abs_w"};
  for (int i = 0; i < 9; ++i) {
    if (name == kAxisNames[i]) {
      v = program_position(i);
      return true;
    }
    if (name == kAbsAxes[i]) {
      v = s.position_mm[i] / (axis_is_rotary(i) ? 1.0 : units);  // A, B, C: degrees
      return true;
    }
  }
  return false;
}

bool StateParameters::mode_parameter(std::string_view name, double& v) const {
  const ModalState& s = interp_.state();
  const double units = s.inch ? 25.4 : 1.0;
  struct Entry {
    std::string_view name;
    double value;
  };
  const Entry table[] = {
      {"_vmajor", 2.9},
      {"_vminor", 0.0},
      {"_line", static_cast<double>(line_)},
      {"_motion_mode", s.motion < 0 ? 800.0 : static_cast<double>(s.motion)},
      {"_plane", s.plane == Plane::XY   ? 170.0
                 : s.plane == Plane::XZ ? 180.0
                                        : 190.0},
      {"_ccomp", s.comp.side > 0   ? 410.0
                 : s.comp.side < 0 ? 420.0
                                   : 400.0},
      {"_metric", s.inch ? 0.0 : 1.0},
      {"_imperial", s.inch ? 1.0 : 0.0},
      {"_absolute", s.incremental ? 0.0 : 1.0},
      {"_incremental", s.incremental ? 1.0 : 0.0},
      {"_inverse_time", s.inverse_time ? 1.0 : 0.0},
      {"_units_per_minute", s.inverse_time || s.per_rev ? 0.0 : 1.0},
      {"_units_per_rev", s.per_rev ? 1.0 : 0.0},
      {"_coord_system",
       s.coord_system < 6 ? 540.0 + 10.0 * s.coord_system : 590.0 + (s.coord_system - 5)},
      {"_tool_offset", s.tool_offset_mm.isZero() ? 0.0 : 1.0},
      {"_retract_r_plane", s.retract_to_r ? 1.0 : 0.0},
      {"_retract_old_z", s.retract_to_r ? 0.0 : 1.0},
      {"_spindle_rpm_mode", s.css ? 0.0 : 1.0},
      {"_spindle_css_mode", s.css ? 1.0 : 0.0},
      {"_spindle_on", s.spindle_dir != 0 ? 1.0 : 0.0},
      {"_spindle_cw", s.spindle_dir > 0 ? 1.0 : 0.0},
      {"_mist", s.mist ? 1.0 : 0.0},
      {"_flood", s.flood ? 1.0 : 0.0},
      {"_speed_override", s.feed_override ? 1.0 : 0.0},
      {"_feed_override", s.feed_override ? 1.0 : 0.0},
      {"_adaptive_feed", 0.0},
      {"_feed_hold", 1.0},
      {"_ijk_absolute_mode", s.ijk_absolute ? 1.0 : 0.0},
      {"_lathe_diameter_mode", s.lathe_diameter ? 1.0 : 0.0},
      {"_lathe_radius_mode", s.lathe_diameter ? 0.0 : 1.0},
      {"_feed", s.feed_mm_min / units},
      {"_rpm", s.spindle_rpm},
      {"_current_tool", static_cast<double>(s.tool_in_spindle)},
      {"_selected_tool", static_cast<double>(s.tool_selected)},
      {"_task", 0.0},
      {"_remap_level", 0.0},
  };
  for (const Entry& e : table)
    if (e.name == name) {
      v = e.value;
      return true;
    }
  return false;
}

bool StateParameters::live(int n, double& v) const {
  if (n >= 5420 && n <= 5428) {
    v = program_position(n - 5420);
    return true;
  }
  if (n == 5400) {
    v = interp_.state().tool_in_spindle;
    return true;
  }
  if (n > 5400 && n <= 5413) {  // the spindle's tool data (machine units, mm)
    const int tool = interp_.state().spindle_slot_tool;
    const ToolEntry* e = tool == 0 ? nullptr : interp_.tables().tools.find(tool);
    if (e == nullptr) {
      v = 0.0;
    } else if (n <= 5409) {
      v = e->offset_mm[static_cast<std::size_t>(n - 5401)];
    } else {
      v = n == 5410   ? e->diameter_mm
          : n == 5411 ? e->front_angle_deg
          : n == 5412 ? e->back_angle_deg
                      : static_cast<double>(e->orientation);
    }
    return true;
  }
  return false;
}

double StateParameters::program_position(int i) const {
  const ModalState& s = interp_.state();
  // A, B and C are degrees in either unit mode (rs274).
  return Frame(s).to_program(s.position_mm)[i] / (s.inch && !axis_is_rotary(i) ? 25.4 : 1.0);
}

SystemParameters::SystemParameters(Interpreter& interp, ParameterStore& params, std::string file)
    : interp_(interp), params_(params), state_(interp), file_(std::move(file)) {
  params_.set_provider(&state_);
}

bool SystemParameters::load(Diagnostic& error) {
  if (file_.empty()) return true;
  if (!params_.load_var_file(file_, error)) return false;
  loaded_ = true;
  // LinuxCNC's DISABLE_G92_PERSISTENCE: the file's G92 offsets are read as 0 (and written so).
  if (!interp_.machine().g92_persistent)
    for (int n = 5210; n <= 5219; ++n) params_.set_system(n, 0.0);
  interp_.restore_system_parameters([this](int n) { return params_.get(n); });
  export_state();
  return true;
}

void SystemParameters::apply_program_writes() {
  for (const auto& [n, v] : params_.system_writes()) interp_.write_system_parameter(n, v);
  params_.clear_system_writes();
}

void SystemParameters::export_state() {
  const ModalState& s = interp_.state();
  params_.set_system(5210, s.g92_flag);
  params_.set_system(5220, static_cast<double>(s.coord_system + 1));
  if (interp_.tables_version() == tables_seen_) return;
  tables_seen_ = interp_.tables_version();
  const SystemTables& t = interp_.tables();
  for (int i = 0; i < 9; ++i) {
    params_.set_system(5161 + i, t.g28_mm[i]);
    params_.set_system(5181 + i, t.g30_mm[i]);
    params_.set_system(5211 + i, t.g92_saved_mm[i]);
    for (int k = 0; k < 9; ++k)
      params_.set_system(5221 + 20 * k + i, t.g5x_mm[static_cast<std::size_t>(k)][i]);
  }
  for (int k = 0; k < 9; ++k)
    params_.set_system(5230 + 20 * k, t.g5x_rotation_deg[static_cast<std::size_t>(k)]);
}

void SystemParameters::save(std::vector<Diagnostic>& diags) {
  if (file_.empty() || !loaded_ || saved_) return;
  saved_ = true;
  export_state();
  std::string error;
  if (!params_.save_var_file(file_, error))
    diags.push_back(Diagnostic{Severity::Error,
                               static_cast<int>(ErrorCode::ParameterFile),
                               SourceLoc{1, 1},
                               error,
                               {},
                               file_});
}

}  // namespace gm
