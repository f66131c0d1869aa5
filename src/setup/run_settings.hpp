// The settings of a run (machine choice, language, run), their one table of names, and the set-up.
#pragma once

#include "interp/program.hpp"
#include "machine/machine.hpp"
#include "pipeline/run.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace gm::setup {

/// Everything that changes a run (not its output files), as `gmotion run` takes it. Every
/// front end fills this one struct: the CLI from its flags, a golden case from its `flags`
/// string, a sweep from its spec, Python's run() from its keyword options.
struct RunSettings {
  // The machine choice.
  std::string machine_file;            ///< --machine (empty: the built-in machine)
  std::string axes;                    ///< --axes LETTERS (else the machine's)
  std::string wrapped_rotary;          ///< --wrapped-rotary LETTERS (else the machine's)
  std::optional<std::string> profile;  ///< --profile NAME
  std::optional<double> tau_s;         ///< --tau S
  std::optional<double> period_s;      ///< --period S
  std::optional<double> blu_mm;        ///< --blu MM (every axis)
  bool no_servo = false;               ///< --no-servo: ideal axes
  bool block_delete = false;           ///< --block-delete: honour '/'
  bool lathe = false;             ///< --lathe: the machine is a lathe (else the machine's kind)
  std::string tool_table;         ///< --tool-table FILE (else the machine's)
  std::string user_mcode_dir;     ///< --user-mcode-dir DIR (else the machine's)
  std::optional<double> pause_s;  ///< --pause-s S (else the machine's)
  // The language.
  std::string subroutine_path;               ///< --subroutine-path DIR[:DIR...], then the machine's
  std::int64_t max_iterations = 10'000'000;  ///< --max-iterations N
  std::string dialect;                       ///< --dialect (else the machine's)
  std::string parameter_file;                ///< --parameter-file FILE (else the machine's)
  bool no_parameter_file = false;            ///< --no-parameter-file: none read or written
  // The run.
  double override_pct = 100.0;         ///< --override (at the start)
  double rapid_override_pct = 100.0;   ///< --rapid-override (at the start)
  std::string override_file;           ///< --override-file (a schedule)
  std::optional<double> tolerance_mm;  ///< --tolerance (the machine's path_tolerance_mm)
  std::string tolerance_on;            ///< --tolerance-on acc_dec|encoder (else the machine's)
  bool check_tolerance = false;        ///< --check-tolerance: a sample over it fails the run
  double max_time_s = 0.0;             ///< --max-time (simulated seconds; 0: no limit)
  int decimate = 1;                    ///< --decimate (every K-th sample traced)
};

/// Where a setting is offered: the commands bind the rows of their groups.
enum SettingGroup : unsigned {
  kProgramGroup = 1,   ///< read by every command that interprets a program (check, moves)
  kMachineGroup = 2,   ///< chooses the machine (compare, machine export)
  kLanguageGroup = 4,  ///< how the program is read
  kRunGroup = 8,       ///< the run itself (run, report, golden cases, sweep, Python)
};
inline constexpr unsigned kAllSettings = kMachineGroup | kLanguageGroup | kRunGroup;

/// A RunSettings field a row sets.
using SettingField =
    std::variant<std::string RunSettings::*, std::optional<std::string> RunSettings::*,
                 double RunSettings::*, std::optional<double> RunSettings::*, bool RunSettings::*,
                 int RunSettings::*, std::int64_t RunSettings::*>;

/// What a setting's value must be, beyond its type (checked where the value is given).
enum class SettingCheck { None, Positive, OneOf };

/// One row of the table: a setting's flag name, help text, field and how its text is checked.
struct SettingRow {
  std::string flag;  ///< "--tau"; Python's keyword is the name without dashes, '-' as '_'
  std::string help;
  SettingField field;
  unsigned groups = 0;  ///< SettingGroup bits
  SettingCheck check = SettingCheck::None;
  std::vector<std::string> choices;  ///< SettingCheck::OneOf: the accepted words
  bool ignore_case = false;          ///< the choices in any case
  std::string excludes;              ///< a flag this one cannot be given with ("" none)
  bool is_switch() const { return std::holds_alternative<bool RunSettings::*>(field); }
  std::string keyword() const;  ///< the Python keyword: "tau", "no_servo"
};

/// Every run setting, in `gmotion run --help` order.
const std::vector<SettingRow>& setting_rows();
/// The row of `flag` ("--tau"), or null.
const SettingRow* find_setting(std::string_view flag);

/// Sets the row's field from text, as the flag's value ("0.1", "scurve2"; a switch takes "true"
/// or "false"), checked as the flag checks it. Throws gm::InputError naming the flag.
void set_from_text(RunSettings& s, const SettingRow& row, std::string_view text);

/// Parses a string of flags ("--profile scurve2 --tau 0.1 --no-servo") of the rows in `groups`
/// into `s`. Throws gm::InputError naming the first bad flag or value.
void parse_flags(RunSettings& s, std::string_view flags, unsigned groups = kAllSettings);
/// The flags that give `s` from the defaults, as words ("--tau", "0.1", "--no-servo"): the rows
/// of `groups` whose field differs from a default RunSettings, in the table's order.
std::vector<std::string> flags_of(const RunSettings& s, unsigned groups = kAllSettings);
/// The flags of `groups`, space-separated (for help texts).
std::string flag_names(unsigned groups = kAllSettings);

/// Checks the settings against the machine they run on: the path tolerance (0..1000 mm), the
/// feed and rapid overrides (0..the machine's maximum), decimate, the iteration bound, the
/// dialect, tolerance_on and the parameter file flags. Returns the machine's maximum override
/// in percent. Throws gm::InputError naming the flag.
double validate(const RunSettings& s, const Machine& m);

/// --axes LETTERS: gives `m` those axes (a subsequence of XYZABCUVW); an axis the machine
/// already has keeps its settings, a new one takes the built-in machine's X axis. No-op when
/// `letters` is empty. Throws gm::InputError on bad letters.
void apply_axes(Machine& m, const std::string& letters);

/// --wrapped-rotary LETTERS: those rotary axes of `m` wrap (LinuxCNC's WRAPPED_ROTARY), the
/// others not. No-op when `letters` is empty. Throws gm::InputError on a letter that is not a
/// rotary axis of `m`.
void apply_wrapped_rotary(Machine& m, const std::string& letters);

/// How resolve_machine reports the LinuxCNC INI keys it could not map.
enum class IniNotes { Print, Quiet };

/// The machine file (or the built-in machine) with the machine settings applied. Prints the
/// keys of a LinuxCNC INI it did not map to stderr (unless IniNotes::Quiet). Throws
/// gm::InputError.
Machine resolve_machine(const RunSettings& s, IniNotes notes = IniNotes::Print);

/// The interpreter options of a run on `machine` (kept by pointer): block delete, the subroutine
/// path (the settings', then the machine's), the bound, the parameter file (the settings', else
/// the machine's, none under no_parameter_file) and the dialect (the settings', else the
/// machine's). save_parameters stays false: the caller decides whether the file is written.
InterpreterOptions interpreter_options(const RunSettings& s, const Machine& machine);

/// The run options of a run on `machine`: validate()d, the tolerance and tolerance_on applied,
/// the overrides, the schedule (loaded), servo, max time and decimate. The outputs, the program
/// name and the threads are the caller's.
RunOptions run_options(const RunSettings& s, Machine machine);

}  // namespace gm::setup
