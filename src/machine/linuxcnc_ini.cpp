// LinuxCNC INI -> Machine (limits, units, period, paths, suggested τ) and Machine -> INI sections.
#include "machine/linuxcnc_ini.hpp"

#include "accdec/accel_limit.hpp"
#include "common/path_list.hpp"
#include "common/position_limits.hpp"
#include "common/status.hpp"
#include "common/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>

namespace gm {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxIncludeDepth = 8;
// What one INI may read in all, its #INCLUDE files counted each time they are read: a file that
// includes itself ten times would otherwise be read 10^8 times.
constexpr int kMaxFilesRead = 256;
constexpr std::uintmax_t kMaxBytesRead = std::uintmax_t{64} << 20;  // 64 MiB

// Whether a path names a regular file or a folder; false, never an exception, for a name the
// system refuses (too long, a loop of links).
bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}
bool is_folder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

/// One `KEY = VALUE` line and where it was.
struct IniValue {
  std::string value;
  std::string file;
  int line = 0;
};

/// The INI as LinuxCNC's inifile reads it: `[SECTION]` headers, `KEY = VALUE`, whole-line
/// comments (# or ;), the first of repeated keys wins; #INCLUDE inserts a file in place.
class IniFile {
 public:
  void read(const fs::path& path, const fs::path& ini_dir, int depth, std::string section) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot open LinuxCNC INI file", path.string()));
    if (++files_read_ > kMaxFilesRead)
      throw InputError(fmt::format("{}: more than {} INI files read (#INCLUDE fanning out?)",
                                   path.string(), kMaxFilesRead));
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(path, ec);
    bytes_read_ += ec ? 0 : size;
    if (bytes_read_ > kMaxBytesRead)
      throw InputError(
          fmt::format("{}: more than {} MiB of INI text read", path.string(), kMaxBytesRead >> 20));
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      ++n;
      const std::string t = trim(line);
      if (t.rfind("#INCLUDE", 0) == 0) {
        const std::string name = trim(t.substr(8));
        if (depth >= kMaxIncludeDepth)
          throw InputError(fmt::format("{}:{}: #INCLUDE nested deeper than {}", path.string(), n,
                                       kMaxIncludeDepth));
        fs::path inc = name;
        if (name.rfind("~/", 0) == 0 && std::getenv("HOME") != nullptr)
          inc = fs::path(std::getenv("HOME")) / name.substr(2);
        else if (inc.is_relative())
          inc = ini_dir / inc;
        if (name.empty() || !is_file(inc)) {
          unreadable_includes.push_back(
              fmt::format("{}:{}: #INCLUDE {}: no such file", path.string(), n, name));
          continue;
        }
        read(inc, ini_dir, depth + 1, section);
        section = last_section_;
        continue;
      }
      if (t.empty() || t[0] == '#' || t[0] == ';') continue;
      if (t[0] == '[') {
        const auto close = t.find(']');
        section = t.substr(1, close == std::string::npos ? std::string::npos : close - 1);
        continue;
      }
      const auto eq = t.find('=');
      if (eq == std::string::npos) continue;
      const std::string key = trim(t.substr(0, eq));
      auto& sec = sections_[section];
      if (sec.count(key) == 0) sec[key] = IniValue{trim(t.substr(eq + 1)), path.string(), n};
    }
    last_section_ = section;
  }

  const IniValue* find(const std::string& section, const std::string& key) const {
    const auto s = sections_.find(section);
    if (s == sections_.end()) return nullptr;
    const auto k = s->second.find(key);
    return k == s->second.end() ? nullptr : &k->second;
  }

  /// The values that are whole numbers in LinuxCNC's reading (no hex, nothing after them),
  /// under upper-case sections and keys, as "_ini[section]key" in lower case: what a program
  /// reads as #<_ini[SECTION]KEY> (rs274 looks the upper-cased name up).
  std::map<std::string, double, std::less<>> ini_parameters() const {
    std::map<std::string, double, std::less<>> out;
    for (const auto& [section, keys] : sections_)
      for (const auto& [key, v] : keys) {
        if (upper(section) != section || upper(key) != key) continue;
        std::istringstream in(v.value);
        double d = 0.0;
        if ((in >> d) && in.eof() && std::isfinite(d))
          out.emplace("_ini[" + lower_case(section) + "]" + lower_case(key), d);
      }
    return out;
  }

  /// A number, or nullopt when absent; throws naming the key when it is not one.
  std::optional<double> number(const std::string& section, const std::string& key) const {
    const IniValue* v = find(section, key);
    if (v == nullptr) return std::nullopt;
    char* end = nullptr;
    const double d = std::strtod(v->value.c_str(), &end);
    if (end == v->value.c_str() || trim(end) != "" || !std::isfinite(d))
      throw InputError(fmt::format("{}:{}: [{}]{}: must be a number (got \"{}\")", v->file, v->line,
                                   section, key, v->value));
    return d;
  }
  [[noreturn]] void fail(const std::string& section, const std::string& key,
                         const std::string& msg) const {
    const IniValue* v = find(section, key);
    throw InputError(v ? fmt::format("{}:{}: [{}]{}: {}", v->file, v->line, section, key, msg)
                       : fmt::format("[{}]{}: {}", section, key, msg));
  }

  static std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
  }
  static std::string lower_case(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  }

  static std::string trim(std::string_view s) {
    std::size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
    return std::string(s.substr(b, e - b));
  }

  std::vector<std::string> unreadable_includes;

 private:
  std::map<std::string, std::map<std::string, IniValue>> sections_;
  std::string last_section_;
  int files_read_ = 0;
  std::uintmax_t bytes_read_ = 0;
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// mm per LINEAR_UNITS unit (LinuxCNC accepts the words below or a number of units per mm).
double linear_unit_mm(const IniFile& ini) {
  const IniValue* v = ini.find("TRAJ", "LINEAR_UNITS");
  if (v == nullptr) return 1.0;
  const std::string u = lower(v->value);
  if (u == "mm" || u == "metric" || u == "millimeter" || u == "millimetre") return 1.0;
  if (u == "inch" || u == "imperial" || u == "in") return 25.4;
  if (u == "cm" || u == "centimeter") return 10.0;
  const double per_mm = ini.number("TRAJ", "LINEAR_UNITS").value_or(0.0);
  if (per_mm > 0.0) return 1.0 / per_mm;
  ini.fail("TRAJ", "LINEAR_UNITS", "must be mm, inch, cm or units per mm");
}

// Degrees per ANGULAR_UNITS unit.
double angular_unit_deg(const IniFile& ini) {
  const IniValue* v = ini.find("TRAJ", "ANGULAR_UNITS");
  if (v == nullptr) return 1.0;
  const std::string u = lower(v->value);
  if (u == "degree" || u == "deg" || u == "degrees") return 1.0;
  if (u == "radian" || u == "rad" || u == "radians") return 180.0 / std::numbers::pi;
  if (u == "grad" || u == "gon") return 0.9;
  const double per_deg = ini.number("TRAJ", "ANGULAR_UNITS").value_or(0.0);
  if (per_deg > 0.0) return 1.0 / per_deg;
  ini.fail("TRAJ", "ANGULAR_UNITS", "must be degree, radian, grad or units per degree");
}

std::optional<double> min_of(std::optional<double> a, std::optional<double> b) {
  if (a && b) return std::min(*a, *b);
  return a ? a : b;
}

std::string ini_number(double v) {
  return fmt::format("{}", v);
}

using Warnings = std::vector<std::string>;

// The axes named in `coords`, each once, in the order XYZABCUVW.
std::string axis_letters(const std::string& coords) {
  std::string letters;
  for (const char l : std::string("XYZABCUVW"))
    if (coords.find(l) != std::string::npos) letters += l;
  return letters;
}

// A file the INI names, relative to the INI's directory.
std::string beside_ini(const fs::path& ini_dir, const std::string& f) {
  const fs::path p(f);
  return p.is_absolute() ? f : (ini_dir / p).lexically_normal().string();
}

// [EMCMOT]SERVO_PERIOD (ns) -> T.
void read_emcmot(const IniFile& ini, Machine& m, Warnings& warn) {
  if (const auto ns = ini.number("EMCMOT", "SERVO_PERIOD")) {
    if (!(*ns >= 1000.0 && *ns <= 1e9))
      ini.fail("EMCMOT", "SERVO_PERIOD", "must be in 1000..1e9 ns");
    m.period_s = *ns * 1e-9;
  } else {
    warn.push_back("[EMCMOT]SERVO_PERIOD: missing; T stays 0.004 s");
  }
}

// [TRAJ]COORDINATES: the joints' letters in joint order (trivkins: joint n drives the n-th
// letter); [KINS]KINEMATICS other than trivkins is only warned about.
std::string read_coordinates(const IniFile& ini, Warnings& warn) {
  std::string coords;
  if (const IniValue* v = ini.find("TRAJ", "COORDINATES")) {
    for (const char c : v->value)
      if (std::isalpha(static_cast<unsigned char>(c)))
        coords += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  } else {
    coords = "XYZ";
    warn.push_back("[TRAJ]COORDINATES: missing; the axes are XYZ");
  }
  for (const char c : coords)
    if (axis_index(c) < 0) ini.fail("TRAJ", "COORDINATES", fmt::format("'{}' is not an axis", c));
  if (coords.empty()) ini.fail("TRAJ", "COORDINATES", "names no axis");
  if (axis_letters(coords).size() != coords.size())
    warn.push_back(
        fmt::format("[TRAJ]COORDINATES = {}: an axis on several joints (gantry) is one "
                    "axis here, with the tightest joint limits",
                    ini.find("TRAJ", "COORDINATES")->value));
  if (const IniValue* k = ini.find("KINS", "KINEMATICS"); k && k->value.rfind("trivkins", 0) != 0)
    warn.push_back(
        fmt::format("[KINS]KINEMATICS = {}: not modelled; every axis is one joint "
                    "(trivkins)",
                    k->value));
  return coords;
}

// What [AXIS_L] and the [JOINT_n] that drive L give one axis (the tighter of axis and joints).
struct AxisLimits {
  std::optional<double> v, a, scale, backlash;
  std::optional<double> ff1, ff2;  ///< the pid's feedforward gains, of the first joint naming them
  std::string ff1_section, ff2_section;
  std::string scale_section;  ///< the joint INPUT_SCALE came from
  bool soft_limits = false;   ///< MIN_LIMIT or MAX_LIMIT named
};

AxisLimits axis_limits(const IniFile& ini, const std::string& coords, char letter) {
  const std::string axis_sec = fmt::format("AXIS_{}", letter);
  AxisLimits l;
  l.v = ini.number(axis_sec, "MAX_VELOCITY");
  l.a = ini.number(axis_sec, "MAX_ACCELERATION");
  for (std::size_t j = 0; j < coords.size(); ++j) {
    if (coords[j] != letter) continue;
    const std::string js = fmt::format("JOINT_{}", j);
    l.v = min_of(l.v, ini.number(js, "MAX_VELOCITY"));
    l.a = min_of(l.a, ini.number(js, "MAX_ACCELERATION"));
    if (!l.scale && (l.scale = ini.number(js, "INPUT_SCALE"))) l.scale_section = js;
    if (!l.backlash) l.backlash = ini.number(js, "BACKLASH");
    if (!l.ff1 && (l.ff1 = ini.number(js, "FF1"))) l.ff1_section = js;
    if (!l.ff2 && (l.ff2 = ini.number(js, "FF2"))) l.ff2_section = js;
    l.soft_limits = l.soft_limits || ini.find(js, "MIN_LIMIT") || ini.find(js, "MAX_LIMIT");
  }
  l.soft_limits =
      l.soft_limits || ini.find(axis_sec, "MIN_LIMIT") || ini.find(axis_sec, "MAX_LIMIT");
  return l;
}

// One axis from [AXIS_L]/[JOINT_n]: V_max, BLU (INPUT_SCALE), backlash; its A_max into a_max_mm_s2.
// Returns whether soft limits were named.
bool read_ini_axis(const IniFile& ini, const std::string& coords, double unit, Machine& m, int i,
                   double& a_max_mm_s2, Warnings& warn) {
  const char letter = m.layout.letter(i);
  const bool rotary = axis_is_rotary(m.layout.program(i));
  const std::string axis_sec = fmt::format("AXIS_{}", letter);
  const AxisLimits l = axis_limits(ini, coords, letter);
  AxisConfig& ac = m.axes[static_cast<std::size_t>(i)];
  if (l.v && *l.v > 0.0)
    ac.v_max_mm_s = *l.v * unit;
  else
    warn.push_back(fmt::format("[{}]MAX_VELOCITY: missing; {} keeps {} {}/s", axis_sec, letter,
                               ac.v_max_mm_s, rotary ? "deg" : "mm"));
  if (l.a && *l.a > 0.0)
    a_max_mm_s2 = *l.a * unit;
  else
    warn.push_back(
        fmt::format("[{}]MAX_ACCELERATION: missing; {} does not limit tau", axis_sec, letter));
  if (l.scale && *l.scale != 0.0) ac.blu_mm = unit / std::abs(*l.scale);
  if (ac.blu_mm < kMinBluMm)
    ini.fail(l.scale_section, "INPUT_SCALE",
             fmt::format("{:g} counts a unit: one count is {:g} {}, finer than 1e-6 (1 nm): "
                         "positions up to ±1e12 would not fit int64 counts",
                         *l.scale, ac.blu_mm, rotary ? "deg" : "mm"));
  if (l.backlash && *l.backlash > 0.0) ac.backlash_blu = std::round(*l.backlash * unit / ac.blu_mm);
  // WRAPPED_ROTARY, read as LinuxCNC's findBoolV reads it (1/0, TRUE/FALSE, YES/NO, ON/OFF).
  if (const IniValue* w = ini.find(axis_sec, "WRAPPED_ROTARY")) {
    std::string v = w->value;
    for (char& ch : v) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    const bool on = v == "1" || v == "TRUE" || v == "YES" || v == "ON";
    if (!on && v != "0" && v != "FALSE" && v != "NO" && v != "OFF")
      warn.push_back(
          fmt::format("[{}]WRAPPED_ROTARY = {}: not a boolean; taken as 0", axis_sec, w->value));
    if (on && !rotary)
      warn.push_back(
          fmt::format("[{}]WRAPPED_ROTARY: {} is linear; it does not wrap", axis_sec, letter));
    ac.wrapped_rotary = on && rotary;
  }
  // The pid's FF1 (output per unit/s) and FF2 (output per unit/s^2) with its output a velocity
  // in units/s, as the pid's manual takes it for a position loop: ff1 and ff2_s, whatever the
  // units (the ratios do not change with them).
  if (l.ff1) {
    if (!(std::abs(*l.ff1) <= 10.0)) ini.fail(l.ff1_section, "FF1", "must be in -10..10");
    ac.ff1 = *l.ff1;
  }
  if (l.ff2) {
    if (!(std::abs(*l.ff2) <= 1.0)) ini.fail(l.ff2_section, "FF2", "must be in -1..1 s");
    ac.ff2_s = *l.ff2;
  }
  return l.soft_limits;
}

// [AXIS_*]/[JOINT_*]: every axis of the machine, lengths in `lin` mm and angles in `ang` degrees.
void read_ini_axes(const IniFile& ini, const std::string& coords, double lin, double ang,
                   Machine& m, std::vector<double>& a_max_mm_s2, Warnings& warn) {
  a_max_mm_s2.assign(static_cast<std::size_t>(m.axis_count()), 0.0);
  bool soft_limits = false;
  for (int i = 0; i < m.axis_count(); ++i) {
    const double unit = axis_is_rotary(m.layout.program(i)) ? ang : lin;
    soft_limits =
        read_ini_axis(ini, coords, unit, m, i, a_max_mm_s2[static_cast<std::size_t>(i)], warn) ||
        soft_limits;
  }
  if (soft_limits)
    warn.push_back("[AXIS_*]/[JOINT_*]MIN_LIMIT, MAX_LIMIT: soft limits are not checked");
}

// [TRAJ]MAX_LINEAR_VELOCITY -> the rapid rate; without it, the fastest linear axis.
void read_rapid(const IniFile& ini, double lin, Machine& m) {
  if (const auto r = ini.number("TRAJ", "MAX_LINEAR_VELOCITY"); r && *r > 0.0) {
    m.rapid_mm_min = units::mm_s_to_mm_min(*r * lin);
    return;
  }
  double fastest = 0.0;
  for (int i = 0; i < m.axis_count(); ++i)
    if (!axis_is_rotary(m.layout.program(i)))
      fastest = std::max(fastest, m.axes[static_cast<std::size_t>(i)].v_max_mm_s);
  if (fastest > 0.0) m.rapid_mm_min = units::mm_s_to_mm_min(fastest);
}

// [DISPLAY]MAX_FEED_OVERRIDE and LATHE (a lathe: axis's lathe view; gmotion's machine kind).
void read_display(const IniFile& ini, Machine& m, Warnings& warn) {
  if (const auto l = ini.number("DISPLAY", "LATHE")) m.lathe = *l != 0.0;
  if (const auto o = ini.number("DISPLAY", "MAX_FEED_OVERRIDE")) {
    if (*o >= 1.0 && *o <= 10.0)
      m.max_override = *o;
    else
      warn.push_back(fmt::format("[DISPLAY]MAX_FEED_OVERRIDE = {}: gmotion needs 1..10; keeps {}",
                                 *o, m.max_override));
  }
}

// [EMCIO]TOOL_TABLE, its lengths in `lin` mm.
void read_emcio_tool_table(const IniFile& ini, const fs::path& dir, double lin, Machine& m) {
  const IniValue* t = ini.find("EMCIO", "TOOL_TABLE");
  if (t == nullptr) return;
  const std::string file = beside_ini(dir, t->value);
  if (!is_file(file))
    throw InputError(
        fmt::format("{}:{}: [EMCIO]TOOL_TABLE: cannot read {}", t->file, t->line, file));
  m.tool_table = load_tool_table(file);
  if (lin != 1.0)
    for (ToolEntry& e : m.tool_table.tools) {
      for (int k = 0; k < 9; ++k)
        if (!axis_is_rotary(k)) e.offset_mm[static_cast<std::size_t>(k)] *= lin;
      e.diameter_mm *= lin;
    }
}

// [RS274NGC]SUBROUTINE_PATH and PARAMETER_FILE (beside the INI); USER_M_PATH is only warned about.
void read_rs274ngc(const IniFile& ini, const fs::path& dir, Machine& m, Warnings& warn) {
  if (const IniValue* s = ini.find("RS274NGC", "SUBROUTINE_PATH"))
    for (const std::string& d : split_path_list(s->value)) {
      m.subroutine_path.push_back(beside_ini(dir, d));
      if (!is_folder(m.subroutine_path.back()))
        warn.push_back(fmt::format("[RS274NGC]SUBROUTINE_PATH: {} is not a directory",
                                   m.subroutine_path.back()));
    }
  if (const IniValue* p = ini.find("RS274NGC", "PARAMETER_FILE")) {
    const std::string file = beside_ini(dir, p->value);
    if (is_file(file))
      m.parameter_file = file;
    else
      warn.push_back(fmt::format("[RS274NGC]PARAMETER_FILE: {} does not exist; not used", file));
  }
  if (const auto d = ini.number("RS274NGC", "DISABLE_FANUC_STYLE_SUB"))
    m.fanuc_subs_disabled = *d != 0.0;
  // INI_VARS (rs274's default 1): the INI's numbers are #<_ini[SECTION]NAME> to programs.
  if (ini.number("RS274NGC", "INI_VARS").value_or(1.0) != 0.0) m.ini_vars = ini.ini_parameters();
  // DISABLE_G92_PERSISTENCE: the G92 offsets are not restored from the parameter file.
  m.g92_persistent = ini.number("RS274NGC", "DISABLE_G92_PERSISTENCE").value_or(0.0) == 0.0;
  // ORIENT_OFFSET: added to M19's R in ORIENT_SPINDLE.
  m.orient_offset_deg = ini.number("RS274NGC", "ORIENT_OFFSET").value_or(0.0);
  if (const IniValue* u = ini.find("RS274NGC", "USER_M_PATH"))
    warn.push_back(
        fmt::format("[RS274NGC]USER_M_PATH = {}: M100-M199 are recorded, never run", u->value));
}

// [TRAJ]LINEAR_UNITS -> the units a program starts in. LinuxCNC's INIT_CANON: units within 1e-3
// of 1/25.4 per mm are inches, 1 per mm is mm, and anything else starts the interpreter in mm
// with an error message.
void read_program_units(const IniFile& ini, double lin, Machine& m, Warnings& warn) {
  m.program_inch = std::abs(1.0 / lin - 1.0 / 25.4) < 1e-3;
  if (!m.program_inch && std::abs(1.0 / lin - 1.0) >= 1e-3)
    warn.push_back(
        fmt::format("[TRAJ]LINEAR_UNITS = {}: neither mm nor inch; converted to mm, and programs "
                    "start in G21 (LinuxCNC: \"non-standard length units, setting interpreter "
                    "to mm\")",
                    ini.find("TRAJ", "LINEAR_UNITS")->value));
}

}  // namespace

bool is_linuxcnc_ini(const std::filesystem::path& path) {
  return lower(path.extension().string()) == ".ini";
}

double tau_for_accel_limit(const Machine& m, const std::vector<double>& a_max_mm_s2,
                           double fallback_s) {
  std::vector<double> v_max_mm_s;
  for (const AxisConfig& a : m.axes) v_max_mm_s.push_back(a.v_max_mm_s);
  return tau_for_accel_limit(m.profile, m.period_s, v_max_mm_s, a_max_mm_s2, fallback_s);
}

IniImport load_linuxcnc_ini(const std::filesystem::path& path) {
  IniFile ini;
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  ini.read(path, dir, 0, "");
  IniImport out;
  Warnings& warn = out.warnings;
  for (const std::string& w : ini.unreadable_includes) warn.push_back(w + " (skipped)");

  Machine m = default_machine();
  m.source = path.string();
  if (const IniValue* v = ini.find("EMC", "MACHINE")) m.name = v->value;
  read_emcmot(ini, m, warn);
  const double lin = linear_unit_mm(ini);
  const double ang = angular_unit_deg(ini);
  const std::string coords = read_coordinates(ini, warn);
  m.set_axes(*AxisLayout::of(axis_letters(coords)), default_machine().axes[0]);
  read_ini_axes(ini, coords, lin, ang, m, out.a_max_mm_s2, warn);
  read_rapid(ini, lin, m);
  read_display(ini, m, warn);
  m.tau_s = tau_for_accel_limit(m, out.a_max_mm_s2, m.tau_s);
  read_emcio_tool_table(ini, dir, lin, m);
  read_rs274ngc(ini, dir, m, warn);
  read_program_units(ini, lin, m, warn);
  if (const IniValue* r = ini.find("EMCIO", "TOOL_CHANGE_POSITION"))
    warn.push_back(
        fmt::format("[EMCIO]TOOL_CHANGE_POSITION = {}: tool changes do not move", r->value));
  out.machine = std::move(m);
  return out;
}

std::string machine_to_linuxcnc_ini(const Machine& m) {
  const double c = profile_peak_factor(m.profile);
  std::string s;
  s += fmt::format("# LinuxCNC axis sections written by gmotion from machine '{}' ({})\n", m.name,
                   m.source);
  s += fmt::format("# MAX_ACCELERATION = c*V/tau with c = {} ({} taps' peak-to-mean), tau = {} s\n",
                   ini_number(c), m.profile, ini_number(m.tau_s));
  if (m.program_inch)
    s += "# program_units = inch: this INI is in mm, so LinuxCNC starts its programs in G21\n";
  s += fmt::format("\n[EMCMOT]\nSERVO_PERIOD = {}\n",
                   static_cast<long long>(std::llround(m.period_s * 1e9)));
  std::string coords;
  for (int i = 0; i < m.axis_count(); ++i) {
    if (i) coords += ' ';  // not `(i ? " " : "") + ...`: g++ 12 -O3 warns falsely (-Wrestrict)
    coords += m.layout.letter(i);
  }
  s += fmt::format("\n[DISPLAY]\nMAX_FEED_OVERRIDE = {}\n", ini_number(m.max_override));
  if (m.lathe) s += "LATHE = 1\n";
  s += fmt::format(
      "\n[TRAJ]\nCOORDINATES = {}\nLINEAR_UNITS = mm\nANGULAR_UNITS = degree\n"
      "MAX_LINEAR_VELOCITY = {}\n",
      coords, ini_number(units::mm_min_to_mm_s(m.rapid_mm_min)));
  s += fmt::format("\n[KINS]\nKINEMATICS = trivkins coordinates={}\nJOINTS = {}\n",
                   m.layout.letters(), m.axis_count());
  for (int i = 0; i < m.axis_count(); ++i) {
    const AxisConfig& a = m.axes[static_cast<std::size_t>(i)];
    const double acc = c * a.v_max_mm_s / m.tau_s;
    s += fmt::format("\n[AXIS_{}]\nMAX_VELOCITY = {}\nMAX_ACCELERATION = {}\n", m.layout.letter(i),
                     ini_number(a.v_max_mm_s), ini_number(acc));
    if (a.wrapped_rotary) s += "WRAPPED_ROTARY = 1\n";
    s += fmt::format(
        "\n[JOINT_{}]\nTYPE = {}\nMAX_VELOCITY = {}\nMAX_ACCELERATION = {}\nINPUT_SCALE = {}\n"
        "BACKLASH = {}\n",
        i, axis_is_rotary(m.layout.program(i)) ? "ANGULAR" : "LINEAR", ini_number(a.v_max_mm_s),
        ini_number(acc), ini_number(1.0 / a.blu_mm), ini_number(a.backlash_blu * a.blu_mm));
    if (a.ff1 != 0.0) s += fmt::format("FF1 = {}\n", ini_number(a.ff1));
    if (a.ff2_s != 0.0) s += fmt::format("FF2 = {}\n", ini_number(a.ff2_s));
  }
  return s;
}

}  // namespace gm
