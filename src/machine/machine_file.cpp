// TOML machine file reader/writer (toml++): every error names the key, the file and the line.
#include "machine/machine_file.hpp"
#include "accdec/taps.hpp"
#include "machine/linuxcnc_ini.hpp"

#include "common/path_list.hpp"
#include "common/position_limits.hpp"
#include "common/status.hpp"
#include "servo/discrete_plant.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>
#include <filesystem>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace gm {
namespace {

std::string fmt_double(double v) {
  return fmt::format("{}", v);
}  // shortest round-trip

// A TOML basic string: quotes, backslashes and control characters escaped (the reader gives
// back the same text; found by fuzz_machine: a name with backslashes did not round-trip).
std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || u == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(u));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    default:
      return "nothing";
  }
}

/// One TOML table being read: tracks which keys were consumed so leftovers are reported.
class Reader {
 public:
  Reader(const toml::table& t, std::string prefix, std::string source)
      : t_(t), prefix_(std::move(prefix)), source_(std::move(source)) {}

  [[noreturn]] void fail_at(const toml::source_region& r, const std::string& key,
                            const std::string& msg) const {
    throw InputError(fmt::format("{}:{}: key '{}': {}", source_, r.begin.line, key, msg));
  }
  std::string full(std::string_view k) const { return prefix_ + std::string(k); }

  const toml::node* get(std::string_view k, bool required) {
    seen_.insert(std::string(k));
    const toml::node* n = t_.get(k);
    if (n == nullptr && required) fail_at(t_.source(), full(k), "required key is missing");
    return n;
  }

  /// A finite number (integer or float); `check` returns "" or the violated condition.
  template <class Check>
  bool number(std::string_view k, double& out, bool required, Check check) {
    const toml::node* n = get(k, required);
    if (n == nullptr) return false;
    double v = 0.0;
    if (auto i = n->as_integer())
      v = static_cast<double>(i->get());
    else if (auto f = n->as_floating_point())
      v = f->get();
    else
      fail_at(n->source(), full(k), fmt::format("must be a number (got {})", type_name(*n)));
    if (!std::isfinite(v)) fail_at(n->source(), full(k), fmt::format("must be finite (got {})", v));
    if (std::string c = check(v); !c.empty())
      fail_at(n->source(), full(k), fmt::format("{} (got {})", c, fmt_double(v)));
    out = v;
    return true;
  }
  bool integer(std::string_view k, int& out, bool required, long long lo, long long hi) {
    const toml::node* n = get(k, required);
    if (n == nullptr) return false;
    auto i = n->as_integer();
    if (!i)
      fail_at(n->source(), full(k), fmt::format("must be an integer (got {})", type_name(*n)));
    const long long v = i->get();
    if (v < lo || v > hi)
      fail_at(n->source(), full(k), fmt::format("must be in {}..{} (got {})", lo, hi, v));
    out = static_cast<int>(v);
    return true;
  }
  bool boolean(std::string_view k, bool& out) {
    const toml::node* n = get(k, false);
    if (n == nullptr) return false;
    auto b = n->as_boolean();
    if (!b)
      fail_at(n->source(), full(k), fmt::format("must be true or false (got {})", type_name(*n)));
    out = b->get();
    return true;
  }
  /// The key a rotary axis may name in its own units instead of `linear` (both: an error).
  template <class Check>
  void number_or(std::string_view linear, std::string_view rotary, double& out, Check check) {
    if (const toml::node* n = t_.get(rotary); n && t_.get(linear))
      fail_at(n->source(), full(rotary),
              fmt::format("gives what '{}' gives: name one of them", full(linear)));
    if (!number(rotary, out, false, check)) number(linear, out, false, check);
  }
  bool string(std::string_view k, std::string& out, bool required) {
    const toml::node* n = get(k, required);
    if (n == nullptr) return false;
    auto s = n->as_string();
    if (!s) fail_at(n->source(), full(k), fmt::format("must be a string (got {})", type_name(*n)));
    if (s->get().empty()) fail_at(n->source(), full(k), "must not be empty");
    out = s->get();
    return true;
  }
  bool numbers(std::string_view k, std::vector<double>& out, bool required, std::size_t min_n,
               std::size_t max_n) {
    const toml::node* n = get(k, required);
    if (n == nullptr) return false;
    auto a = n->as_array();
    if (!a)
      fail_at(n->source(), full(k),
              fmt::format("must be an array of numbers (got {})", type_name(*n)));
    if (a->size() < min_n || a->size() > max_n)
      fail_at(n->source(), full(k),
              min_n == max_n
                  ? fmt::format("must have {} elements (got {})", min_n, a->size())
                  : fmt::format("must have {}..{} elements (got {})", min_n, max_n, a->size()));
    std::vector<double> v;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const toml::node& e = *a->get(i);
      double d = 0.0;
      if (auto in = e.as_integer())
        d = static_cast<double>(in->get());
      else if (auto f = e.as_floating_point())
        d = f->get();
      else
        fail_at(e.source(), fmt::format("{}[{}]", full(k), i),
                fmt::format("must be a number (got {})", type_name(e)));
      if (!std::isfinite(d))
        fail_at(e.source(), fmt::format("{}[{}]", full(k), i), "must be finite");
      v.push_back(d);
    }
    out = std::move(v);
    return true;
  }
  const toml::table* table(std::string_view k, bool required) {
    const toml::node* n = get(k, required);
    if (n == nullptr) return nullptr;
    auto t = n->as_table();
    if (!t) fail_at(n->source(), full(k), fmt::format("must be a table (got {})", type_name(*n)));
    return t;
  }
  /// Reports the first key that was never asked for (a typo or an unsupported key).
  void reject_unknown() const {
    for (auto&& [key, node] : t_) {
      if (seen_.count(std::string(key.str())) == 0) {
        const toml::source_region& r = key.source().begin.line != 0 ? key.source() : node.source();
        fail_at(r, full(key.str()), "unknown key");
      }
    }
  }
  const toml::table& tbl() const { return t_; }
  const std::string& source() const { return source_; }

 private:
  const toml::table& t_;
  std::string prefix_;
  std::string source_;
  std::set<std::string> seen_;
};

// "" when tau_s gives an Acc/Dec filter of 1..kMaxAccDecTaps taps at period_s, else the rule.
std::string tau_problem(double tau_s, double period_s) {
  if (!(tau_s >= period_s)) return "must be >= period_s (at least one tap)";
  if (tau_s / period_s > kMaxAccDecTaps + 0.5)
    return fmt::format("must be <= {} x period_s = {} s (tau/T = {:.6g} taps; at most {})",
                       kMaxAccDecTaps, fmt_double(kMaxAccDecTaps * period_s), tau_s / period_s,
                       kMaxAccDecTaps);
  return "";
}

// Smallest interpolation period (1 µs) and position-loop gain (a 1000 s time constant) a machine
// file may give: with both, every sample count a run derives (5/(kp·T)) fits its integers.
constexpr double kMinPeriod = 1e-6;
constexpr double kMinKp = 1e-3;

auto positive = [](double v) { return v > 0.0 ? "" : "must be > 0"; };
auto non_negative = [](double v) { return v >= 0.0 ? "" : "must be >= 0"; };
// A BLU finer than 1 nm would count positions of a program's range beyond int64.
auto blu_range = [](double v) {
  return v >= kMinBluMm
             ? ""
             : "must be >= 1e-6 mm (1 nm): positions up to ±1e12 mm must fit int64 counts";
};

void read_axis(Reader& r, AxisConfig& a, double machine_blu_mm, double period_s, bool path_axis) {
  a.blu_mm = machine_blu_mm;
  if (const toml::table* acc = r.table("accdec", false)) {
    if (path_axis)
      r.fail_at(acc->source(), r.full("accdec"),
                "X, Y and Z share the machine's [accdec] (the contour error and the tolerance "
                "planner assume one filter for the path); only the axes past them may have their "
                "own");
    Reader ar(*acc, r.full("accdec."), r.source());
    ar.string("profile", a.accdec_profile, false);
    ar.number("tau_s", a.accdec_tau_s, false,
              [period_s](double v) { return tau_problem(v, period_s); });
    ar.reject_unknown();
  }
  if (a.rotary) {  // degrees, torque, inertia: the rotary names, or the linear ones (same fields)
    r.number_or("blu_mm", "blu_deg", a.blu_mm, blu_range);
    r.number_or("v_max_mm_s", "v_max_deg_s", a.v_max_mm_s, positive);
    r.number_or("f_max_N", "torque_max_Nm", a.f_max_N, positive);
    r.number_or("mass_kg", "inertia_kg_m2", a.mass_kg, positive);
    r.number_or("damping_kg_s", "damping_Nm_s_rad", a.damping_kg_s, non_negative);
    r.boolean("wrapped_rotary", a.wrapped_rotary);
  } else {
    r.number("blu_mm", a.blu_mm, false, blu_range);
    r.number("v_max_mm_s", a.v_max_mm_s, false, positive);
    r.number("f_max_N", a.f_max_N, false, positive);
    r.number("mass_kg", a.mass_kg, false, positive);
    r.number("damping_kg_s", a.damping_kg_s, false, non_negative);
    if (const toml::node* w = r.tbl().get("wrapped_rotary"))
      r.fail_at(w->source(), r.full("wrapped_rotary"), "only a rotary axis (A, B, C) wraps");
  }
  r.number("p_max_W", a.p_max_W, false, positive);
  r.numbers("plant_num", a.plant_num, true, 1, DiscretePlant::kMaxOrder);
  r.numbers("plant_den", a.plant_den, true, 2, DiscretePlant::kMaxOrder + 1);
  r.number("kvp", a.kvp, true, non_negative);
  r.number("kvi", a.kvi, true, non_negative);
  // Five position-loop time constants (5/kp) are the servo lag a run counts in samples.
  r.number("kp_1_s", a.kp_1_s, true,
           [](double v) { return v >= kMinKp ? "" : "must be >= 0.001 1/s"; });
  r.number("ff1", a.ff1, false,
           [](double v) { return v >= -10.0 && v <= 10.0 ? "" : "must be in -10..10"; });
  r.number("ff2_s", a.ff2_s, false,
           [](double v) { return v >= -1.0 && v <= 1.0 ? "" : "must be in -1..1 s"; });
  if (r.numbers("mode_hz", a.mode_hz, false, 0, 4))
    for (double f : a.mode_hz)
      if (!(f > 0.0))
        r.fail_at(r.tbl().get("mode_hz")->source(), r.full("mode_hz"),
                  fmt::format("every frequency must be > 0 Hz (got {})", fmt_double(f)));
  if (r.numbers("mode_damping", a.mode_damping, false, 0, 4))
    for (double z : a.mode_damping)
      if (!(z >= 0.0))
        r.fail_at(r.tbl().get("mode_damping")->source(), r.full("mode_damping"),
                  fmt::format("every damping ratio must be >= 0 (got {})", fmt_double(z)));
  if (a.mode_hz.size() != a.mode_damping.size()) {
    const toml::node* n =
        r.tbl().get("mode_hz") ? r.tbl().get("mode_hz") : r.tbl().get("mode_damping");
    r.fail_at(n->source(), r.full("mode_damping"),
              fmt::format("needs one damping ratio per mode_hz ({} against {})",
                          a.mode_damping.size(), a.mode_hz.size()));
  }
  r.number("backlash_blu", a.backlash_blu, false, non_negative);
  r.number("coulomb_N", a.coulomb_N, false, non_negative);
  r.number("plant_blu_s_per_unit", a.plant_blu_s_per_unit, false, positive);
  r.number("kv_period_s", a.kv_period_s, false, positive);
  r.number("drive_N_per_unit", a.drive_N_per_unit, false, non_negative);
  std::string form;
  if (r.string("kv_form", form, false)) {
    if (form == "ip")
      a.kv_form = VelocityLoopForm::Ip;
    else if (form == "pi")
      a.kv_form = VelocityLoopForm::Pi;
    else
      r.fail_at(r.tbl().get("kv_form")->source(), r.full("kv_form"),
                fmt::format("must be \"ip\" or \"pi\" (got \"{}\")", form));
  }
  std::string site;
  if (r.string("encoder", site, false)) {
    if (site == "motor")
      a.encoder = EncoderSite::Motor;
    else if (site == "table")
      a.encoder = EncoderSite::Table;
    else
      r.fail_at(r.tbl().get("encoder")->source(), r.full("encoder"),
                fmt::format("must be \"motor\" or \"table\" (got \"{}\")", site));
  }
  // The plant must discretise; the drive mapping must be derivable.
  const toml::node* den = r.tbl().get("plant_den");
  try {
    DiscretePlant p(a.plant_num, a.plant_den, a.plant_blu_s_per_unit, 1e-3);
    if (a.drive_N_per_unit == 0.0 && p.accel_gain_blu_s2() == 0.0)
      r.fail_at(den->source(), r.full("drive_N_per_unit"),
                "required for a plant of relative degree > 1 (cannot derive it from mass_kg)");
    if (a.drive_N_per_unit == 0.0 && !(p.accel_gain_blu_s2() > 0.0))
      r.fail_at(den->source(), r.full("plant_num"), "high-frequency gain must be > 0");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind("plant: ", 0) != 0) throw;
    r.fail_at(den->source(), r.full("plant_den"), msg.substr(7));
  }
  r.reject_unknown();
}

// An optional "on" | "off" key into `flag` (left as it is when absent).
void read_on_off(Reader& r, const toml::table& root, const char* key, bool& flag) {
  std::string value;
  if (!r.string(key, value, false)) return;
  if (value != "off" && value != "on")
    r.fail_at(root.get(key)->source(), key,
              fmt::format("must be \"off\" or \"on\" (got \"{}\")", value));
  flag = value == "on";
}

// The top-level keys of the run: period, rates, override, tolerance, arc rule.
void read_run_keys(Reader& r, const toml::table& root, Machine& m) {
  r.string("name", m.name, true);
  r.number("period_s", m.period_s, true,
           [](double v) { return v >= kMinPeriod && v <= 1.0 ? "" : "must be in 1e-06..1 s"; });
  r.integer("servo_substeps", m.servo_substeps, false, 1, 1000);
  r.number("rapid_mm_min", m.rapid_mm_min, false, positive);
  double pct = m.max_override * 100.0;
  r.number("max_override_percent", pct, false,
           [](double v) { return v >= 100.0 && v <= 1000.0 ? "" : "must be in 100..1000"; });
  m.max_override = pct / 100.0;
  r.number("path_tolerance_mm", m.path_tolerance_mm, false,
           [](double v) { return v >= 0.0 && v <= 1000.0 ? "" : "must be in 0..1000"; });
  std::string rule;
  if (r.string("arc_rule", rule, false)) {
    if (rule == "linuxcnc")
      m.arc_rule = ArcRule::LinuxCnc;
    else if (rule == "grbl")
      m.arc_rule = ArcRule::Grbl;
    else if (rule == "g2core")
      m.arc_rule = ArcRule::G2core;
    else
      r.fail_at(root.get("arc_rule")->source(), "arc_rule",
                fmt::format("must be \"linuxcnc\", \"grbl\" or \"g2core\" (got \"{}\")", rule));
  }
  std::string tol_on;
  if (r.string("tolerance_on", tol_on, false)) {
    if (tol_on == "acc_dec")
      m.tolerance_on = ToleranceOn::AccDec;
    else if (tol_on == "encoder")
      m.tolerance_on = ToleranceOn::Encoder;
    else
      r.fail_at(root.get("tolerance_on")->source(), "tolerance_on",
                fmt::format("must be \"acc_dec\" or \"encoder\" (got \"{}\")", tol_on));
  }
  read_on_off(r, root, "arc_precompensation", m.arc_precompensation);
  read_on_off(r, root, "g61_arc_precompensation", m.g61_arc_precompensation);
  read_on_off(r, root, "private_arcs", m.private_arcs);
  read_on_off(r, root, "servo_matching", m.servo_matching);
}

// [accdec]: profile and τ; without tau_s the period must suit the default τ.
void read_accdec_table(Reader& r, const toml::table& root, const std::string& src, Machine& m) {
  const toml::table* acc = r.table("accdec", false);
  if (acc != nullptr) {
    Reader ar(*acc, "accdec.", src);
    ar.string("profile", m.profile, false);
    const double period = m.period_s;
    ar.number("tau_s", m.tau_s, false, [period](double v) { return tau_problem(v, period); });
    ar.reject_unknown();
  }
  if (acc == nullptr || acc->get("tau_s") == nullptr) {
    // tau_s keeps its default: the period must still suit it (the file never names tau_s).
    if (std::string c = tau_problem(m.tau_s, m.period_s); !c.empty())
      r.fail_at(root.get("period_s")->source(), "period_s",
                fmt::format("does not suit accdec.tau_s = {} s (the default): tau_s {} (got {})",
                            fmt_double(m.tau_s), c, fmt_double(m.period_s)));
  }
}

// [axes]: the letters, then one [axes.<letter>] table per axis.
void read_axes_table(Reader& r, const std::string& src, double blu_mm, Machine& m) {
  const toml::table* axes = r.table("axes", true);
  Reader axr(*axes, "axes.", src);
  if (std::string letters; axr.string("letters", letters, false)) {
    const std::optional<AxisLayout> l = AxisLayout::of(letters);
    if (!l)
      axr.fail_at(axes->get("letters")->source(), "axes.letters",
                  fmt::format("must be axis letters in the order XYZABCUVW, each at most once "
                              "(got \"{}\")",
                              letters));
    m.set_axes(*l, AxisConfig{});
  }
  for (int i = 0; i < m.axis_count(); ++i) {
    const char letter = static_cast<char>(m.layout.letter(i) - 'A' + 'a');
    const std::string k(1, letter);
    const toml::table* at = axr.table(k, true);
    Reader ar(*at, "axes." + k + ".", src);
    read_axis(ar, m.axes[static_cast<std::size_t>(i)], blu_mm, m.period_s, m.layout.program(i) < 3);
  }
  axr.reject_unknown();
}

// The top-level keys of the programs: tools, files and directories (relative to the machine
// file's directory, as LinuxCNC's are to the INI's), dialect, units, spindle, pause.
void read_program_keys(Reader& r, const toml::table& root, const std::string& src, Machine& m) {
  r.numbers("tools", m.tool_lengths_mm, false, 0, 100000);
  const auto beside = [&](const std::string& f) {
    const std::filesystem::path p(f);
    return p.is_absolute() ? f : (std::filesystem::path(src).parent_path() / p).string();
  };
  if (std::string tt; r.string("tool_table", tt, false)) m.tool_table = load_tool_table(beside(tt));
  if (std::string sp; r.string("subroutine_path", sp, false))
    for (const std::string& dir : split_path_list(sp)) m.subroutine_path.push_back(beside(dir));
  if (std::string pf; r.string("parameter_file", pf, false)) m.parameter_file = beside(pf);
  if (std::string d; r.string("dialect", d, false)) {
    if (d == "linuxcnc" || d == "fanuc" || d == "grbl" || d == "haas" || d == "mach3")
      m.dialect = d;
    else
      r.fail_at(root.get("dialect")->source(), "dialect",
                fmt::format("must be \"linuxcnc\", \"fanuc\", \"grbl\", \"haas\" or \"mach3\" "
                            "(got \"{}\")",
                            d));
  }
  if (std::string k; r.string("kind", k, false)) {
    if (k == "mill" || k == "lathe")
      m.lathe = k == "lathe";
    else
      r.fail_at(root.get("kind")->source(), "kind",
                fmt::format("must be \"mill\" or \"lathe\" (got \"{}\")", k));
  }
  if (std::string ud; r.string("user_mcode_dir", ud, false)) m.user_mcode_dir = beside(ud);
  if (std::string u; r.string("program_units", u, false)) {
    if (u == "mm" || u == "inch")
      m.program_inch = u == "inch";
    else
      r.fail_at(root.get("program_units")->source(), "program_units",
                fmt::format("must be \"mm\" or \"inch\" (got \"{}\")", u));
  }
  r.number("spindle_accel_rpm_s", m.spindle_accel_rpm_s, false,
           [](double v) { return v >= 0.0 && v <= 1e7 ? "" : "must be 0..1e7 rpm/s"; });
  r.number("pause_s", m.pause_s, false,
           [](double v) { return v >= 0.0 && v <= 1e6 ? "" : "must be 0..1e6 s"; });
}

// [work_offsets]: g54..g59 as [x, y, z] or more, in XYZABCUVW order (an axis the machine lacks
// must be 0).
void read_work_offsets_table(Reader& r, const std::string& src, Machine& m) {
  const toml::table* wo = r.table("work_offsets", false);
  if (wo == nullptr) return;
  Reader wr(*wo, "work_offsets.", src);
  for (int g = 0; g < 6; ++g) {
    std::vector<double> v;
    if (wr.numbers(fmt::format("g{}", 54 + g), v, false, 3, kMaxAxes))
      for (int a = 0; a < static_cast<int>(v.size()); ++a)
        m.work_offsets_mm[static_cast<std::size_t>(g)][a] = v[static_cast<std::size_t>(a)];
  }
  wr.reject_unknown();
}

// A TOML array of numbers.
std::string toml_list(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) s += ", ";  // appended in two steps: g++ 12 -O3 warns falsely on `a + b`
    s += fmt_double(v[i]);
  }
  return s + "]";
}

// The top-level keys machine_to_toml writes, up to the first table.
std::string toml_top_keys(const Machine& m) {
  const char* rule = m.arc_rule == ArcRule::Grbl     ? "grbl"
                     : m.arc_rule == ArcRule::G2core ? "g2core"
                                                     : "linuxcnc";
  std::string s;
  s += fmt::format("name = {}\nperiod_s = {}\nservo_substeps = {}\nrapid_mm_min = {}\n",
                   toml_string(m.name), fmt_double(m.period_s), m.servo_substeps,
                   fmt_double(m.rapid_mm_min));
  s += fmt::format("max_override_percent = {}\narc_rule = \"{}\"\nblu_mm = {}\n",
                   fmt_double(m.max_override * 100.0), rule, fmt_double(m.axes[0].blu_mm));
  if (m.path_tolerance_mm > 0.0)
    s += fmt::format("path_tolerance_mm = {}\n", fmt_double(m.path_tolerance_mm));
  if (m.tolerance_on == ToleranceOn::Encoder) s += "tolerance_on = \"encoder\"\n";
  if (!m.arc_precompensation) s += "arc_precompensation = \"off\"\n";
  if (m.g61_arc_precompensation) s += "g61_arc_precompensation = \"on\"\n";
  if (!m.private_arcs) s += "private_arcs = \"off\"\n";
  if (!m.servo_matching) s += "servo_matching = \"off\"\n";
  if (!m.subroutine_path.empty()) {
    std::string dirs;
    for (const std::string& d : m.subroutine_path) {
      if (!dirs.empty()) dirs += ':';
      dirs += d;
    }
    s += fmt::format("subroutine_path = {}\n", toml_string(dirs));
  }
  if (!m.parameter_file.empty())
    s += fmt::format("parameter_file = {}\n", toml_string(m.parameter_file));
  if (!m.dialect.empty()) s += fmt::format("dialect = {}\n", toml_string(m.dialect));
  if (m.lathe) s += "kind = \"lathe\"\n";
  if (!m.user_mcode_dir.empty())
    s += fmt::format("user_mcode_dir = {}\n", toml_string(m.user_mcode_dir));
  if (m.pause_s > 0.0) s += fmt::format("pause_s = {}\n", fmt_double(m.pause_s));
  if (m.program_inch) s += "program_units = \"inch\"\n";
  if (m.spindle_accel_rpm_s > 0.0)
    s += fmt::format("spindle_accel_rpm_s = {}\n", fmt_double(m.spindle_accel_rpm_s));
  s += "tools = " + toml_list(m.tool_lengths_mm) + "\n\n";
  return s;
}

// One [axes.<letter>] table, and its [axes.<letter>.accdec] when it has its own Acc/Dec.
std::string toml_axis_table(const AxisConfig& a, char letter) {
  std::string s = fmt::format("\n[axes.{}]\n", letter);
  if (a.rotary) {
    s += fmt::format("blu_deg = {}\nv_max_deg_s = {}\ntorque_max_Nm = {}\np_max_W = {}\n",
                     fmt_double(a.blu_mm), fmt_double(a.v_max_mm_s), fmt_double(a.f_max_N),
                     fmt_double(a.p_max_W));
    s += fmt::format("inertia_kg_m2 = {}\ndamping_Nm_s_rad = {}\n", fmt_double(a.mass_kg),
                     fmt_double(a.damping_kg_s));
    if (a.wrapped_rotary) s += "wrapped_rotary = true\n";
  } else {
    s += fmt::format("blu_mm = {}\nv_max_mm_s = {}\nf_max_N = {}\np_max_W = {}\n",
                     fmt_double(a.blu_mm), fmt_double(a.v_max_mm_s), fmt_double(a.f_max_N),
                     fmt_double(a.p_max_W));
    s += fmt::format("mass_kg = {}\ndamping_kg_s = {}\n", fmt_double(a.mass_kg),
                     fmt_double(a.damping_kg_s));
  }
  s += fmt::format("plant_num = {}\nplant_den = {}\n", toml_list(a.plant_num),
                   toml_list(a.plant_den));
  s += fmt::format("kvp = {}\nkvi = {}\nkp_1_s = {}\nbacklash_blu = {}\ncoulomb_N = {}\n",
                   fmt_double(a.kvp), fmt_double(a.kvi), fmt_double(a.kp_1_s),
                   fmt_double(a.backlash_blu), fmt_double(a.coulomb_N));
  // The feedforward only when set: files of machines without it read as before.
  if (a.ff1 != 0.0) s += fmt::format("ff1 = {}\n", fmt_double(a.ff1));
  if (a.ff2_s != 0.0) s += fmt::format("ff2_s = {}\n", fmt_double(a.ff2_s));
  if (!a.mode_hz.empty())
    s += fmt::format("mode_hz = {}\nmode_damping = {}\n", toml_list(a.mode_hz),
                     toml_list(a.mode_damping));
  if (a.encoder == EncoderSite::Table) s += "encoder = \"table\"\n";
  s += fmt::format(
      "plant_blu_s_per_unit = {}\nkv_period_s = {}\nkv_form = \"{}\"\ndrive_N_per_unit = {}\n",
      fmt_double(a.plant_blu_s_per_unit), fmt_double(a.kv_period_s),
      a.kv_form == VelocityLoopForm::Ip ? "ip" : "pi", fmt_double(a.drive_N_per_unit));
  if (!a.accdec_profile.empty() || a.accdec_tau_s > 0.0) {
    s += fmt::format("\n[axes.{}.accdec]\n", letter);
    if (!a.accdec_profile.empty())
      s += fmt::format("profile = {}\n", toml_string(a.accdec_profile));
    if (a.accdec_tau_s > 0.0) s += fmt::format("tau_s = {}\n", fmt_double(a.accdec_tau_s));
  }
  return s;
}

}  // namespace

Machine parse_machine_toml(std::string_view text, std::string_view source_name) {
  const std::string src(source_name);
  toml::table root;
  try {
    root = toml::parse(text, src);
  } catch (const toml::parse_error& e) {
    throw InputError(
        fmt::format("{}:{}: TOML syntax error: {}", src, e.source().begin.line, e.description()));
  }
  Machine m = default_machine();
  m.source = src;
  Reader r(root, "", src);
  read_run_keys(r, root, m);
  double blu_mm = 0.001;
  r.number("blu_mm", blu_mm, false, blu_range);
  read_accdec_table(r, root, src, m);
  read_axes_table(r, src, blu_mm, m);
  read_program_keys(r, root, src, m);
  read_work_offsets_table(r, src, m);
  r.reject_unknown();
  return m;
}

Machine load_machine_file(const std::filesystem::path& path) {
  if (is_linuxcnc_ini(path)) return load_linuxcnc_ini(path).machine;  // docs/linuxcnc-ini.md
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open machine file", path.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_machine_toml(ss.str(), path.string());
}

std::string machine_to_toml(const Machine& m) {
  std::string s = toml_top_keys(m);
  s += fmt::format("[accdec]\nprofile = {}\ntau_s = {}\n", toml_string(m.profile),
                   fmt_double(m.tau_s));
  if (!m.layout.is_xyz()) s += fmt::format("\n[axes]\nletters = \"{}\"\n", m.layout.letters());
  for (int i = 0; i < m.axis_count(); ++i)
    s += toml_axis_table(m.axes[static_cast<std::size_t>(i)],
                         static_cast<char>(m.layout.letter(i) - 'A' + 'a'));
  s += "\n[work_offsets]\n";
  for (int g = 0; g < 6; ++g) {
    const AxisVec& w = m.work_offsets_mm[static_cast<std::size_t>(g)];
    int n = kMaxAxes;
    while (n > 3 && w[n - 1] == 0.0) --n;  // [x, y, z] unless a later axis is offset
    s += fmt::format("g{} = {}\n", 54 + g, toml_list(std::vector<double>(w.data(), w.data() + n)));
  }
  return s;
}

}  // namespace gm
