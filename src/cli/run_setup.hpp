// What `run` and `compare` share: machine flags, resolving the machine, opening the program.
#pragma once

#include "interp/program.hpp"
#include "machine/machine.hpp"

#include <CLI/CLI.hpp>

#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gm::cli {

/// Flags that choose the machine and override parts of it.
struct MachineFlags {
  std::string machine_file;            ///< empty: the built-in default machine
  std::optional<std::string> profile;  ///< --profile NAME
  std::optional<double> tau_s;         ///< --tau S
  std::optional<double> period_s;      ///< --period S
  std::optional<double> blu_mm;        ///< --blu MM (every axis)
  bool no_servo = false;               ///< --no-servo: ideal axes
  bool block_delete = false;           ///< --block-delete: honour '/'
  std::string tool_table;              ///< --tool-table FILE (else the machine's table)
  std::string axes;                    ///< --axes LETTERS (else the machine's)
};

/// --axes LETTERS: gives `m` those axes (a subsequence of XYZABCUVW); an axis the machine
/// already has keeps its settings, a new one takes the built-in machine's X axis. No-op when
/// `letters` is empty. Throws gm::InputError on bad letters.
void apply_axes_flag(Machine& m, const std::string& letters);
/// The --axes option's help text.
inline constexpr const char* kAxesFlagHelp =
    "Machine axes, a subsequence of XYZABCUVW (e.g. XYZA; A B C rotary, degrees); default: the "
    "machine's (built-in: XYZ)";

/// Adds --machine, --axes, --profile, --tau, --period, --blu, --no-servo, --block-delete,
/// --tool-table to `sub`.
void add_machine_flags(CLI::App* sub, MachineFlags& flags);

/// The machine file (or the built-in machine) with the flags applied. Throws gm::InputError.
Machine resolve_machine(const MachineFlags& flags);

/// The run settings `run` and the golden cases share, checked against the machine: sets the
/// machine's path tolerance (--tolerance, 0..1000 mm) when given, and refuses a feed or rapid
/// override outside 0..the machine's maximum. Returns that maximum in percent. Throws
/// gm::InputError naming the flag.
double apply_run_limits(Machine& m, std::optional<double> tolerance_mm, double override_pct,
                        double rapid_override_pct);

/// A program opened for reading twice (validate, then run). `-` spools stdin to a temporary
/// file first, so the same bytes are checked and run.
class ProgramInput {
 public:
  explicit ProgramInput(const std::string& path);  ///< throws gm::InputError naming the path
  std::istream& rewind();                          ///< the stream, at the start
  const std::string& name() const { return name_; }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;
  std::string name_;
  std::vector<char> buffer_;  ///< the stream's buffer (set before open); declared before file_
  std::ifstream file_;
  std::string spool_path_;
};

/// Validates the program; prints its diagnostics to stderr. Returns true when it has no error.
bool validate_program(ProgramInput& program, const InterpreterOptions& opts);

}  // namespace gm::cli
