// Compares a golden trace with a fresh one: pinned columns, tolerances in BLU, first divergence.
#pragma once

#include "trace/trace_reader.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gm::golden {

/// Which columns are pinned and how far each may move. Column patterns are globs over the trace's
/// column names (`*` is any text: "*_enc" is every axis's encoder, "x_*" every column of X).
struct PinSpec {
  std::vector<std::string> columns{"*"};  ///< pinned columns; the others are not compared
  double tolerance_blu = 0.0;             ///< for every pinned column without its own
  std::vector<std::pair<std::string, double>> tolerances;  ///< pattern -> BLU; the first match wins
};

/// True when `name` matches `pattern` (`*` matches any run of characters, also none).
bool glob_match(std::string_view pattern, std::string_view name);

/// Where two traces first differ beyond the tolerance.
struct Divergence {
  std::int64_t row = 0;  ///< 1-based data row
  double t_s = 0.0;
  int line = 0;  ///< source line (of the golden row)
  std::string column;
  double golden = 0.0, fresh = 0.0;
};

struct CompareResult {
  std::vector<std::string> columns;
  std::vector<bool> pinned;
  std::vector<double> tolerance;  ///< per column, BLU (or the column's unit)
  std::vector<double> max_diff;   ///< per column, over the rows both traces have
  std::int64_t rows = 0;          ///< rows compared
  std::int64_t golden_rows = 0, fresh_rows = 0;
  std::int64_t beyond = 0;  ///< values beyond the tolerance (a missing row counts once)
  std::optional<Divergence> first;
  std::string problem;  ///< traces that cannot be compared row by row (different columns)
  bool pass() const { return problem.empty() && beyond == 0; }
};

/// Streams both traces to their ends (constant memory). A column's allowed difference is the
/// larger of its tolerance and its CSV printing resolution (trace_columns.def).
CompareResult compare_traces(TraceReader& golden, TraceReader& fresh, const PinSpec& pins);

/// "x_ref=6 x_enc=5": the pinned columns with a non-zero largest difference, "none" when none.
std::string largest_differences(const CompareResult& r);

/// "t = 0.412000 s, line 7, column x_ref: golden 1234, now 1240" (or the length or column problem).
std::string describe_first(const CompareResult& r);

}  // namespace gm::golden
