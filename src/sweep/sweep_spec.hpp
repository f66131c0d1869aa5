// A sweep specification (TOML): the lists whose product is the set of runs, in a fixed order.
#pragma once

#include "machine/machine.hpp"
#include "setup/run_settings.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gm::sweep {

/// One override setting: a constant feed override (percent) or a schedule file.
struct OverrideChoice {
  double percent = 100.0;
  std::string schedule;       ///< a schedule file (--override-file); empty: the constant percent
  std::string label() const;  ///< "100" or the schedule's file name
};

/// One machine of the sweep, read once.
struct SweepMachine {
  std::string file;   ///< as resolved (relative to the spec); empty: the built-in machine
  std::string label;  ///< the file's stem, or "builtin"
  Machine machine;
};

/// The spec: every list is a dimension; the runs are their product.
struct SweepSpec {
  std::filesystem::path source;
  std::vector<std::string> programs;                 ///< resolved paths
  std::vector<SweepMachine> machines;                ///< default: the built-in machine
  std::vector<std::optional<std::string>> profiles;  ///< nullopt: the machine's
  std::vector<std::optional<double>> taus_s;         ///< nullopt: the machine's
  std::vector<OverrideChoice> overrides;             ///< default: 100 %
  bool servo = true;
  double max_time_s = 3600.0;  ///< each run's stop rule (simulated seconds)
  /// `flags`: further `gmotion run` flags of every run (those the lists above do not give), paths
  /// in them made relative to the spec's directory; the machines are resolved with them.
  setup::RunSettings settings;
  int jobs = 0;  ///< 0: every core
};

/// One run: indices into the spec's lists.
struct RunPoint {
  std::size_t index = 0;
  std::size_t program = 0, machine = 0, profile = 0, tau = 0, override_ = 0;
};

/// Reads a spec; paths in it are relative to the spec's directory. Throws gm::InputError
/// "FILE:LINE: key 'k': ..." on a bad key or value.
SweepSpec load_sweep_spec(const std::filesystem::path& path);

/// The runs in their fixed order: program, then machine, profile, τ, override (innermost).
std::vector<RunPoint> expand(const SweepSpec& spec);

}  // namespace gm::sweep
