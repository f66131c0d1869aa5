// Reads a gmotion trace (CSV or binary, detected by its magic) one row at a time.
#pragma once

#include "trace/trace_schema.hpp"

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace gm {

/// A trace opened for reading: its header and columns, then rows as numbers. Constant memory.
class TraceReader {
 public:
  /// Opens `path`; throws gm::InputError when it cannot be read or is not a gmotion trace.
  explicit TraceReader(const std::string& path);
  ~TraceReader();
  TraceReader(const TraceReader&) = delete;
  TraceReader& operator=(const TraceReader&) = delete;

  /// Reads the next row into `values` (one per column); false at the end. Throws on a malformed
  /// row, naming the file and the row's line (CSV) or record number (binary). In a partial trace
  /// an incomplete last row (no '\n', or a short record) ends the rows instead: see dropped_tail().
  bool next(std::vector<double>& values);

  const std::vector<std::string>& columns() const { return columns_; }
  /// The `# key: value` header lines, without the leading "# ".
  const std::vector<std::string>& header() const { return header_; }
  /// The value of header line `key` ("machine", "profile", ...), or "" when absent.
  std::string header_value(const std::string& key) const;
  /// The `# status:` line of a trace written with `run --keep-partial`, without its padding:
  /// "complete", "partial, run in progress" (the run never got to say more: killed, or still
  /// running) or "partial: REASON"; "" when the trace has no status line.
  std::string status() const;
  /// True when status() starts with "partial".
  bool partial() const { return partial_; }
  /// True when next() has met an incomplete last row in a partial trace and left it out.
  bool dropped_tail() const { return dropped_tail_; }
  bool binary() const { return binary_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
  bool binary_ = false;
  std::vector<std::string> header_;
  std::vector<std::string> columns_;
  std::string line_;
  std::vector<char> record_;      ///< one binary record
  std::vector<TraceKind> kinds_;  ///< per column, from the schema
  bool partial_ = false;
  bool dropped_tail_ = false;
  std::int64_t row_ = 0;
  std::int64_t line_no_ = 0;
  double period_s_ = 0.0;
};

}  // namespace gm
