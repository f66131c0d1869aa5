// The sweep's table: one row per run, filled from the run's summary; written as CSV or JSON.
#pragma once

#include "measure/run_summary.hpp"
#include "sweep/sweep_spec.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace gm::sweep {

/// One run's row. Lengths in mm (BLU converted with the machine's BLU).
struct SweepRow {
  std::size_t index = 0;
  std::string program, machine, profile;
  double tau_s = 0.0, period_s = 0.0;
  std::string override_;  ///< percent, or the schedule's file name
  std::string status;     ///< "ok", "unsettled", "error" or "missing" (merge: no summary)
  double cycle_time_s = 0.0, program_time_s = 0.0;
  double contour_max_mm = 0.0;  ///< worst contour error of the actual position
  int contour_max_line = 0;     ///< its source line
  double contour_rms_mm = 0.0;
  double following_max_mm = 0.0;  ///< worst following error over the axes
  std::int64_t samples = 0;
  std::string error;  ///< why not "ok"
};

/// The row of run `r` with its set-up filled (machine after profile and τ), values zero.
SweepRow row_setup(const SweepSpec& s, const RunPoint& r, const Machine& m);

/// Fills the row's values from the summary of a run on machine `m` (a local run), each value as
/// `--summary-json` prints it, so that the row is the one merge() reads from that file.
void fill_from_summary(SweepRow& row, const RunSummary& summary, const Machine& m);
/// Fills the row's values from a `--summary-json` text of a run on machine `m` (a cluster run,
/// merged); false when the text lacks a field.
bool fill_from_summary_json(SweepRow& row, const std::string& json, const Machine& m);

/// The table as CSV (header line, one line per row; texts quoted when they need it).
std::string to_csv(const std::vector<SweepRow>& rows);
/// The table as a JSON array of objects with the CSV's column names.
std::string to_json(const std::vector<SweepRow>& rows);

}  // namespace gm::sweep
