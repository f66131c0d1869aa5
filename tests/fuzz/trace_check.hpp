// What a run's trace must hold: one row per sample, in order, every column as the run's blocks had
// it, read back from the file the run wrote (CSV within its printing resolution, binary exactly).
#pragma once

#include "motion/block_sink.hpp"
#include "trace/block_row.hpp"
#include "trace/trace_reader.hpp"
#include "trace/trace_row.hpp"
#include "trace/trace_schema.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace fuzz {

/// A run's sink, added after its trace writer: keeps every row's trace columns as the schema
/// defines them (visit_trace_row over the block in place, as the writer reads it) and checks
/// that the samples come whole and in order, with finite table positions and contour errors.
/// error() is "" or the first broken promise.
class TraceExpect final : public gm::BlockSink {
 public:
  /// `keep_values`: keep the rows' values for compare_trace (else only check them); `columns`:
  /// the trace's column set (the tool tip's columns when the run's machine has modes).
  TraceExpect(int axes, double period_s, bool keep_values,
              gm::TraceColumnSet columns = gm::kTraceAlways)
      : axes_(axes), period_s_(period_s), keep_(keep_values), columns_(columns) {}

  void consume(const gm::SampleBlock& b, int first) override {
    for (int i = first; i < b.count; ++i) {
      const gm::BlockRow r(b, i, period_s_);
      if (r.k != rows_ && error_.empty())
        error_ = fmt::format("sample {} handed on where {} was due", r.k, rows_);
      ++rows_;
      bool finite = std::isfinite(r.contour_err_blu) && std::isfinite(r.feed_scale);
      for (int a = 0; a < axes_; ++a) finite = finite && std::isfinite(b.table_blu.v[a][i]);
      if (!finite && error_.empty()) error_ = fmt::format("sample {} has a non-finite value", r.k);
      if (!keep_) continue;
      const auto keep = [this](auto, auto v) { values_.push_back(static_cast<double>(v)); };
      if (columns_ & gm::kTraceModes)
        gm::visit_trace_row<gm::kTraceModes>(r, axes_, keep);
      else
        gm::visit_trace_row(r, axes_, keep);
    }
  }

  std::int64_t rows() const { return rows_; }
  gm::TraceColumnSet columns() const { return columns_; }
  const std::vector<double>& values() const { return values_; }
  const std::string& error() const { return error_; }

 private:
  int axes_;
  double period_s_;
  bool keep_;
  gm::TraceColumnSet columns_;
  std::int64_t rows_ = 0;
  std::vector<double> values_;  ///< rows × columns, row after row
  std::string error_;
};

/// How far a CSV value may be from the value written: half a unit of its last printed digit.
inline double csv_resolution(gm::TraceKind kind, double v) {
  const double eps = 4 * std::numeric_limits<double>::epsilon() * std::abs(v);
  switch (kind) {
    case gm::TraceKind::Time:  // %.6f
      return 5e-7 + eps;
    case gm::TraceKind::Fixed3:  // %.3f
      return 5e-4 + eps;
    case gm::TraceKind::Percent:  // %.6g
      return 5e-6 * std::abs(v) + eps;
    case gm::TraceKind::Line:
    case gm::TraceKind::Count:
      return 0.0;
  }
  return 0.0;
}

/// Reads the trace at `path` and compares it with what `e` kept: the columns of `axis_letters`,
/// as many rows as samples, every value. "" when they agree, else the first difference.
inline std::string compare_trace(const std::string& path, const std::string& axis_letters,
                                 const TraceExpect& e) {
  gm::TraceReader reader(path);
  const std::vector<std::string> names = gm::trace_column_names(axis_letters, e.columns());
  if (reader.columns() != names) return "the trace's columns are not the schema's";
  std::vector<gm::TraceKind> kinds;
  for (const std::string& n : names) kinds.push_back(gm::find_trace_column(n)->kind);
  const std::size_t cols = names.size();
  if (e.values().size() != static_cast<std::size_t>(e.rows()) * cols)
    return "the rows kept do not have the schema's columns";
  std::vector<double> row;
  std::int64_t k = 0;
  while (reader.next(row)) {
    if (k >= e.rows()) return fmt::format("the trace has more rows than the {} samples", e.rows());
    const double* want = e.values().data() + static_cast<std::size_t>(k) * cols;
    for (std::size_t c = 0; c < cols; ++c) {
      const double tol = reader.binary() ? 0.0 : csv_resolution(kinds[c], want[c]);
      if (!(std::abs(row[c] - want[c]) <= tol))
        return fmt::format("row {} column {}: read {} where {} was written", k, names[c], row[c],
                           want[c]);
    }
    ++k;
  }
  if (k != e.rows()) return fmt::format("the trace has {} rows for {} samples", k, e.rows());
  if (reader.partial() || reader.dropped_tail()) return "a finished trace reads as partial";
  return "";
}

}  // namespace fuzz
