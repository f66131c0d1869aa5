// The run settings' table of names, their parsing and checks, and the machine and options of a run.
#include "setup/run_settings.hpp"

#include "accdec/accel_limit.hpp"
#include "accdec/profiles.hpp"
#include "common/position_limits.hpp"
#include "common/status.hpp"
#include "interp/subroutine_path.hpp"
#include "machine/linuxcnc_ini.hpp"
#include "machine/machine_file.hpp"
#include "override/override_schedule.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace gm::setup {
namespace {

constexpr unsigned kCheckMachine = kProgramGroup | kMachineGroup;

using S = RunSettings;

SettingRow row(std::string flag, std::string help, SettingField field, unsigned groups) {
  SettingRow r;
  r.flag = std::move(flag);
  r.help = std::move(help);
  r.field = field;
  r.groups = groups;
  return r;
}

SettingRow must_be_positive(SettingRow r) {
  r.check = SettingCheck::Positive;
  return r;
}

SettingRow one_of(SettingRow r, std::vector<std::string> choices, bool ignore_case) {
  r.check = SettingCheck::OneOf;
  r.choices = std::move(choices);
  r.ignore_case = ignore_case;
  return r;
}

// The machine choice.
void add_machine_rows(std::vector<SettingRow>& rows) {
  rows.push_back(row("--machine",
                     "Machine file (TOML, or a LinuxCNC .ini: docs/linuxcnc-ini.md); "
                     "default: the built-in 3-axis machine",
                     &S::machine_file, kCheckMachine));
  rows.push_back(row("--axes",
                     "Machine axes, a subsequence of XYZABCUVW (e.g. XYZA; A B C "
                     "rotary, degrees); default: the machine's (built-in: XYZ)",
                     &S::axes, kCheckMachine));
  rows.push_back(row("--wrapped-rotary",
                     "Rotary axes that wrap (LinuxCNC's WRAPPED_ROTARY), e.g. A: an absolute "
                     "angle is a position modulo 360, turned to by its sign; default: the "
                     "machine's",
                     &S::wrapped_rotary, kCheckMachine));
  rows.push_back(row("--profile",
                     "Acc/Dec profile: " + profile_forms(" | ") + " (C = cutoff or max)",
                     &S::profile, kMachineGroup));
  rows.push_back(
      row("--tau", "Acc/Dec time constant tau = (N+1)T, seconds", &S::tau_s, kMachineGroup));
  rows.push_back(row("--period", "Interpolation period T, seconds", &S::period_s, kMachineGroup));
  rows.push_back(row("--blu", "Basic length unit of every axis, mm", &S::blu_mm, kMachineGroup));
  rows.push_back(row("--no-servo", "Ideal axes: the encoder reads the Acc/Dec output", &S::no_servo,
                     kMachineGroup));
  rows.push_back(
      row("--block-delete", "Skip blocks that start with '/'", &S::block_delete, kCheckMachine));
  rows.push_back(row("--lathe",
                     "The machine is a lathe (as kind = \"lathe\"): with --dialect fanuc, "
                     "Fanuc/Haas lathe words (X diameter, U/W, T0101, G50, G71/G70, G76); "
                     "docs/dialects.md",
                     &S::lathe, kCheckMachine));
  rows.push_back(row("--tool-table",
                     "LinuxCNC tool table (T1 P1 Z50 D6 ;comment), mm; default: "
                     "the machine's",
                     &S::tool_table, kCheckMachine));
  rows.push_back(row("--user-mcode-dir",
                     "Directory where M100..M199 are found (a file named "
                     "M101 makes M101 known; recorded, never run); default: the machine's "
                     "user_mcode_dir",
                     &S::user_mcode_dir, kCheckMachine));
  rows.push_back(row("--pause-s",
                     "Seconds an M0/M1 program stop holds the run; default: the "
                     "machine's pause_s (0)",
                     &S::pause_s, kMachineGroup));
}

// How the program is read.
void add_language_rows(std::vector<SettingRow>& rows) {
  rows.push_back(row("--subroutine-path",
                     "directories (DIR[:DIR...]) where 'o<name> call' finds "
                     "name.ngc, searched before the machine's subroutine_path",
                     &S::subroutine_path, kLanguageGroup));
  rows.push_back(must_be_positive(row("--max-iterations",
                                      "loop iterations and subroutine calls before "
                                      "the program is stopped",
                                      &S::max_iterations, kLanguageGroup)));
  rows.push_back(one_of(row("--dialect",
                            "what the program is written for: linuxcnc (default: "
                            "rs274's rules), fanuc (Fanuc posts), haas (Haas mill posts), "
                            "grbl (grbl 1.1), mach3 (Mach3 posts); docs/dialects.md",
                            &S::dialect, kLanguageGroup),
                        {"linuxcnc", "fanuc", "grbl", "haas", "mach3"}, true));
  rows.push_back(row("--parameter-file",
                     "LinuxCNC .var parameter file read before the program "
                     "and written after it (run, moves; check only reads), instead of the "
                     "machine's",
                     &S::parameter_file, kLanguageGroup));
  SettingRow no_pf = row("--no-parameter-file",
                         "neither read nor write a parameter file, not "
                         "even the one the machine names",
                         &S::no_parameter_file, kLanguageGroup);
  no_pf.excludes = "--parameter-file";
  rows.push_back(std::move(no_pf));
}

// The run itself.
void add_run_rows(std::vector<SettingRow>& rows) {
  rows.push_back(
      must_be_positive(row("--decimate", "Write every K-th sample", &S::decimate, kRunGroup)));
  rows.push_back(row("--override", "Feed override at the start, percent (default 100)",
                     &S::override_pct, kRunGroup));
  rows.push_back(row("--rapid-override", "Rapid override at the start, percent (default 100)",
                     &S::rapid_override_pct, kRunGroup));
  rows.push_back(row("--override-file",
                     "Override schedule: lines t_s,percent | line:N,percent | "
                     "t_s,rapid=percent; # comments",
                     &S::override_file, kRunGroup));
  rows.push_back(row("--max-time", "Stop the run (exit 1) when simulated time passes this, s",
                     &S::max_time_s, kRunGroup));
  rows.push_back(row("--tolerance",
                     "Contour tolerance under G64 without P, mm (the machine's "
                     "path_tolerance_mm; 0 = unbounded)",
                     &S::tolerance_mm, kRunGroup));
  rows.push_back(row("--check-tolerance",
                     "Exit 1 when any sample's contour error exceeds the "
                     "tolerance in force",
                     &S::check_tolerance, kRunGroup));
  rows.push_back(one_of(row("--tolerance-on",
                            "Plan the tolerance for the Acc/Dec output "
                            "(acc_dec, default) or for the table through the servo model too "
                            "(encoder; the machine's tolerance_on)",
                            &S::tolerance_on, kRunGroup),
                        {"acc_dec", "encoder"}, false));
}

std::string lower(std::string_view text) {
  std::string t(text);
  for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return t;
}

template <typename T>
T number(const SettingRow& row, std::string_view text) {
  T v{};
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || p != end || text.empty())
    throw InputError(fmt::format("{} {}: not a number", row.flag, text));
  return v;
}

bool switch_value(const SettingRow& row, std::string_view text) {
  const std::string t = lower(text);
  if (t == "true" || t == "1" || t.empty()) return true;
  if (t == "false" || t == "0") return false;
  throw InputError(fmt::format("{} {}: give true or false", row.flag, text));
}

// The row's own check of a text value (CLI11's checks, for the other front ends).
std::string checked(const SettingRow& row, std::string_view text) {
  if (row.check != SettingCheck::OneOf) return std::string(text);
  for (const std::string& c : row.choices)
    if (row.ignore_case ? lower(text) == c : text == c) return c;
  std::string list;
  for (const std::string& c : row.choices) list += (list.empty() ? "" : ", ") + c;
  throw InputError(fmt::format("{} {} is not one of {}", row.flag, text, list));
}

// Splits a flag string at white space; single or double quotes keep spaces in a word.
std::vector<std::string> words(std::string_view text) {
  std::vector<std::string> out;
  std::string w;
  bool in_word = false;
  char quote = 0;
  for (const char c : text) {
    if (quote != 0) {
      if (c == quote)
        quote = 0;
      else
        w += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_word = true;
    } else if (std::isspace(static_cast<unsigned char>(c)) != 0) {
      if (in_word) out.push_back(std::move(w));
      w.clear();
      in_word = false;
    } else {
      w += c;
      in_word = true;
    }
  }
  if (quote != 0) throw InputError(fmt::format("an unclosed quote {}", quote));
  if (in_word) out.push_back(std::move(w));
  return out;
}

void positive(const char* flag, double v) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw InputError(
        fmt::format("{} must be a positive number of seconds or mm (got {})", flag, v));
}

void apply_machine_settings(const RunSettings& s, Machine& m) {
  if (!s.tool_table.empty()) m.tool_table = load_tool_table(s.tool_table);
  if (!s.user_mcode_dir.empty()) m.user_mcode_dir = s.user_mcode_dir;
  if (s.lathe) m.lathe = true;
  if (s.pause_s) {
    if (!(*s.pause_s >= 0.0) || *s.pause_s > 1e6)
      throw InputError(fmt::format("--pause-s {} is outside 0..1e6 s", *s.pause_s));
    m.pause_s = *s.pause_s;
  }
  if (s.profile) m.profile = *s.profile;
  if (s.tau_s) positive("--tau", *s.tau_s), m.tau_s = *s.tau_s;
  if (s.period_s) positive("--period", *s.period_s), m.period_s = *s.period_s;
  if (s.blu_mm) {
    positive("--blu", *s.blu_mm);
    if (*s.blu_mm < kMinBluMm)
      throw InputError(
          fmt::format("--blu {} is finer than 1e-6 mm (1 nm): positions up "
                      "to ±1e12 mm would not fit int64 counts",
                      *s.blu_mm));
    for (auto& a : m.axes) a.blu_mm = *s.blu_mm;
  }
}

}  // namespace

std::string SettingRow::keyword() const {
  std::string k = flag.substr(flag.find_first_not_of('-'));
  std::replace(k.begin(), k.end(), '-', '_');
  return k;
}

const std::vector<SettingRow>& setting_rows() {
  static const std::vector<SettingRow> rows = [] {
    std::vector<SettingRow> all;
    add_machine_rows(all);
    add_language_rows(all);
    add_run_rows(all);
    return all;
  }();
  return rows;
}

const SettingRow* find_setting(std::string_view flag) {
  for (const SettingRow& r : setting_rows())
    if (r.flag == flag) return &r;
  return nullptr;
}

void set_from_text(RunSettings& s, const SettingRow& row, std::string_view text) {
  std::visit(
      [&](auto member) {
        auto& field = s.*member;
        using T = std::remove_reference_t<decltype(field)>;
        if constexpr (std::is_same_v<T, bool>) {
          field = switch_value(row, text);
        } else if constexpr (std::is_same_v<T, std::string> ||
                             std::is_same_v<T, std::optional<std::string>>) {
          field = checked(row, text);
        } else if constexpr (std::is_same_v<T, std::optional<double>>) {
          field = number<double>(row, text);
        } else {
          field = number<T>(row, text);
          if (row.check == SettingCheck::Positive && !(field > 0))
            throw InputError(fmt::format("{} {}: must be positive", row.flag, text));
        }
      },
      row.field);
}

void parse_flags(RunSettings& s, std::string_view flags, unsigned groups) {
  const std::vector<std::string> w = words(flags);
  std::vector<std::string> given;
  for (std::size_t i = 0; i < w.size(); ++i) {
    const std::size_t eq = w[i].find('=');
    const std::string flag = w[i].substr(0, eq);
    const SettingRow* row = find_setting(flag);
    if (row == nullptr || (row->groups & groups) == 0)
      throw InputError(fmt::format("{}: not a flag here", w[i]));
    if (eq != std::string::npos) {
      set_from_text(s, *row, std::string_view(w[i]).substr(eq + 1));
    } else if (row->is_switch()) {
      set_from_text(s, *row, "true");
    } else {
      if (i + 1 == w.size()) throw InputError(fmt::format("{} needs a value", flag));
      set_from_text(s, *row, w[++i]);
    }
    given.push_back(flag);
  }
  for (const SettingRow& r : setting_rows())
    if (!r.excludes.empty() && std::count(given.begin(), given.end(), r.flag) > 0 &&
        std::count(given.begin(), given.end(), r.excludes) > 0)
      throw InputError(fmt::format("{} excludes {}", r.flag, r.excludes));
}

std::vector<std::string> flags_of(const RunSettings& s, unsigned groups) {
  static const RunSettings defaults;
  std::vector<std::string> out;
  for (const SettingRow& row : setting_rows()) {
    if ((row.groups & groups) == 0) continue;
    std::visit(
        [&](auto member) {
          const auto& v = s.*member;
          if (v == defaults.*member) return;
          out.push_back(row.flag);
          using T = std::remove_cvref_t<decltype(v)>;
          if constexpr (std::is_same_v<T, std::string>)
            out.push_back(v);
          else if constexpr (std::is_same_v<T, std::optional<std::string>>)
            out.push_back(*v);
          else if constexpr (std::is_same_v<T, std::optional<double>>)
            out.push_back(fmt::format("{}", *v));
          else if constexpr (!std::is_same_v<T, bool>)
            out.push_back(fmt::format("{}", v));
        },
        row.field);
  }
  return out;
}

std::string flag_names(unsigned groups) {
  std::string names;
  for (const SettingRow& r : setting_rows())
    if ((r.groups & groups) != 0) names += (names.empty() ? "" : " ") + r.flag;
  return names;
}

double validate(const RunSettings& s, const Machine& m) {
  if (s.tolerance_mm && (!(*s.tolerance_mm >= 0.0) || *s.tolerance_mm > 1000.0))
    throw InputError(fmt::format("--tolerance {} is outside 0..1000 mm", *s.tolerance_mm));
  const double max_pct = m.max_override * 100.0;
  for (auto [flag, v] : {std::pair{"--override", s.override_pct},
                         std::pair{"--rapid-override", s.rapid_override_pct}})
    if (!(v >= 0.0) || v > max_pct + 1e-9)
      throw InputError(fmt::format("{} {} is outside 0..{} % (the machine's maximum override)",
                                   flag, v, max_pct));
  if (s.decimate < 1) throw InputError(fmt::format("--decimate {} is below 1", s.decimate));
  if (s.max_iterations <= 0)
    throw InputError(fmt::format("--max-iterations {} is not positive", s.max_iterations));
  if (s.no_parameter_file && !s.parameter_file.empty())
    throw InputError("--parameter-file and --no-parameter-file exclude each other");
  for (const char* flag : {"--dialect", "--tolerance-on"}) {
    const SettingRow& row = *find_setting(flag);
    const std::string& v = s.*std::get<std::string RunSettings::*>(row.field);
    if (!v.empty()) checked(row, v);
  }
  return max_pct;
}

void apply_axes(Machine& m, const std::string& letters) {
  if (letters.empty()) return;
  const std::optional<AxisLayout> l = AxisLayout::of(letters);
  if (!l)
    throw InputError(fmt::format(
        "--axes {}: give axis letters in the order XYZABCUVW, each at most once", letters));
  m.set_axes(*l, default_machine().axes[0]);
}

void apply_wrapped_rotary(Machine& m, const std::string& letters) {
  if (letters.empty()) return;
  for (AxisConfig& a : m.axes) a.wrapped_rotary = false;
  for (const char c : letters) {
    const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    int found = -1;
    for (int i = 0; i < m.axis_count(); ++i)
      if (m.layout.letter(i) == letter) found = i;
    if (found < 0 || !axis_is_rotary(m.layout.program(found)))
      throw InputError(
          fmt::format("--wrapped-rotary {}: {} is not a rotary axis (A, B, C) of the "
                      "machine (axes {})",
                      letters, c, m.layout.letters()));
    m.axes[static_cast<std::size_t>(found)].wrapped_rotary = true;
  }
}

Machine resolve_machine(const RunSettings& s, IniNotes notes) {
  std::optional<IniImport> ini;
  if (!s.machine_file.empty() && is_linuxcnc_ini(s.machine_file)) {
    ini = load_linuxcnc_ini(s.machine_file);
    if (!ini->warnings.empty() && notes == IniNotes::Print) {
      std::string list;
      for (const std::string& w : ini->warnings) list += "\n  " + w;
      fmt::print(stderr, "gmotion: {}: not mapped from the LinuxCNC INI:{}\n", s.machine_file,
                 list);
    }
  }
  Machine m = ini                      ? ini->machine
              : s.machine_file.empty() ? default_machine()
                                       : load_machine_file(s.machine_file);
  apply_axes(m, s.axes);
  apply_wrapped_rotary(m, s.wrapped_rotary);
  apply_machine_settings(s, m);
  // An INI's τ follows its limits, the profile and T: suggested again for the settings' ones.
  if (ini && !s.tau_s && s.axes.empty() && (s.profile || s.period_s))
    m.tau_s = tau_for_accel_limit(m, ini->a_max_mm_s2, m.tau_s);
  return m;
}

InterpreterOptions interpreter_options(const RunSettings& s, const Machine& machine) {
  InterpreterOptions opts;
  opts.machine = &machine;
  opts.block_delete = s.block_delete;
  opts.subroutine_path = SubroutinePath::split(s.subroutine_path);
  for (const std::string& dir : machine.subroutine_path) opts.subroutine_path.push_back(dir);
  opts.max_iterations = s.max_iterations;
  opts.fanuc_subs_disabled = machine.fanuc_subs_disabled;
  opts.parameter_file = s.no_parameter_file         ? std::string()
                        : !s.parameter_file.empty() ? s.parameter_file
                                                    : machine.parameter_file;
  const std::string& d = s.dialect.empty() ? machine.dialect : s.dialect;
  if (!d.empty()) parse_dialect(d, opts.dialect);  // both checked when read
  return opts;
}

RunOptions run_options(const RunSettings& s, Machine machine) {
  RunOptions o;
  o.config.machine = std::move(machine);
  o.config.servo = !s.no_servo;
  const double max_pct = validate(s, o.config.machine);
  if (s.tolerance_mm) o.config.machine.path_tolerance_mm = *s.tolerance_mm;
  if (!s.tolerance_on.empty())
    o.config.machine.tolerance_on =
        s.tolerance_on == "encoder" ? ToleranceOn::Encoder : ToleranceOn::AccDec;
  if (!s.override_file.empty()) o.schedule = OverrideSchedule::load(s.override_file, max_pct);
  o.feed_override_pct = s.override_pct;
  o.rapid_override_pct = s.rapid_override_pct;
  o.max_time_s = s.max_time_s;
  o.decimate = s.decimate;
  return o;
}

}  // namespace gm::setup
