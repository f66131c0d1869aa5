// Running a sweep: every run on a pool of local threads, or emitted as commands for a scheduler.
#pragma once

#include "setup/run_settings.hpp"
#include "sweep/sweep_table.hpp"

#include <functional>
#include <string>
#include <vector>

namespace gm::sweep {

/// The machine run `r` uses: the spec's machine with the run's profile and τ.
Machine run_machine(const SweepSpec& s, const RunPoint& r);

/// The run settings of run `r` (as its emitted `gmotion run` command gives them).
setup::RunSettings run_settings(const SweepSpec& s, const RunPoint& r);

/// Runs every point on `jobs` threads (0: the spec's jobs, else every core), each as `gmotion
/// run` would with --summary-json; a failed run is a row with status "error" and its message.
/// `done` (may be empty) is called on the calling thread with each row, in index order.
std::vector<SweepRow> run_local(const SweepSpec& s, int jobs,
                                const std::function<void(const SweepRow&)>& done);

/// The `gmotion run` command of run `r` (POSIX-shell quoted), writing its summary to
/// `out_dir`/run-NNNNN.json; `gmotion` is the executable to call.
std::string run_command(const SweepSpec& s, const RunPoint& r, const std::string& gmotion,
                        const std::string& out_dir);

/// Path of run `r`'s summary under `out_dir`.
std::string summary_path(const std::string& out_dir, const RunPoint& r);

/// The table from the summaries the emitted commands wrote (status "missing" where none is).
std::vector<SweepRow> merge(const SweepSpec& s, const std::string& out_dir);

}  // namespace gm::sweep
