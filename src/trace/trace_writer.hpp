// The encoder-trace logger: one row per servo sample, CSV or compact binary, written atomically.
#pragma once

#include "common/axis.hpp"
#include "pipeline/sample_record.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <limits>
#include <string>

namespace gm {

enum class TraceFormat { Csv, Binary };

/// What the header of a trace records, so a trace can be read and compared on its own.
struct TraceMeta {
  std::string program;
  std::string machine_name;
  std::string machine_source;
  std::string profile;
  int taps = 0;  ///< N+1
  double tau_s = 0.0;
  double period_s = 0.0;
  AxisVec blu_mm = AxisVec::Zero();
  bool servo = true;
  int decimate = 1;
};

/// The `#` header lines (shared by CSV and binary) and the column line, each ending in '\n'.
std::string trace_header(const TraceMeta& meta);

/// Writes a trace to `path` ("-" = stdout; an existing device or FIFO is written in place). A
/// file is written as `path.partial` and renamed to `path` only by finish(), so an interrupted run never leaves a file that looks complete; a
/// writer destroyed without finish() removes its partial file. Throws gm::InputError when the
/// path cannot be opened or written (the message names it and the reason).
class TraceWriter {
 public:
  TraceWriter(std::string path, TraceFormat format, const TraceMeta& meta);
  ~TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  /// Appends sample `s` if it falls on the decimation grid (k % decimate == 0). No allocation
  /// once the buffer has grown to its working size.
  void write(const SampleRecord& s);
  /// Flushes, closes and renames the file into place. Throws gm::InputError on a write error.
  void finish();

  std::int64_t rows() const { return rows_; }

 private:
  void flush_buffer();
  void write_csv(const SampleRecord& s);
  void write_binary(const SampleRecord& s);

  std::string path_, tmp_path_;
  TraceFormat format_;
  int decimate_;
  std::FILE* file_ = nullptr;
  bool to_stdout_ = false;
  bool direct_ = false;  ///< an existing device or FIFO: written in place
  fmt::memory_buffer buf_;
  std::int64_t rows_ = 0;
  static constexpr std::size_t kMaxCsvRow = 1200;  ///< 14 integers, 2 fixed-point, 1 %g, commas
  double last_pct_ = std::numeric_limits<double>::quiet_NaN();  ///< override of the cached text
  std::string last_pct_text_;                                   ///< "{:.6g}" of last_pct_ (SSO)
};

}  // namespace gm
