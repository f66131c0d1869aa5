// The encoder-trace logger: one row per servo sample, CSV or compact binary, written atomically.
#pragma once

#include "common/axis.hpp"
#include "motion/block_sink.hpp"
#include "motion/sample_record.hpp"
#include "trace/trace_schema.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>

namespace gm {

struct SampleBlock;

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
  std::string axes = "XYZ";                ///< the machine's axis letters, its order
  MachineVec blu_mm = MachineVec::Zero();  ///< per axis, in that order
  bool servo = true;
  int decimate = 1;
  /// --keep-partial: a `# status:` line of fixed width right after the first line, saying
  /// "partial, run in progress" until finish() or keep_partial() overwrites it in place.
  bool status_line = false;
  /// The optional columns written (trace_schema.hpp): kTraceModes adds the tool tip per axis.
  TraceColumnSet columns = kTraceAlways;
};

/// Width in bytes of the `# status: ...` header line, without its '\n'.
inline constexpr std::size_t kTraceStatusWidth = 120;

/// The `#` header lines (shared by CSV and binary) and the column line, each ending in '\n'.
std::string trace_header(const TraceMeta& meta);

/// `# status: TEXT` cut or padded with spaces to exactly kTraceStatusWidth bytes, then '\n'.
/// Line breaks in `text` become spaces; a cut text ends in "..." and keeps UTF-8 characters whole.
std::string trace_status_line(std::string_view text);

/// Writes a trace to `path` ("-" = stdout; an existing device or FIFO is written in place). A
/// file is written as `path.partial` and renamed to `path` only by finish(), so an interrupted
/// run never leaves a file that looks complete; a writer destroyed without finish() or
/// keep_partial() removes its partial file. Throws gm::InputError when the path cannot be opened
/// or written (the message names it and the reason), and when meta.status_line is asked for a
/// trace written in place (see written_in_place()).
class TraceWriter final : public BlockSink {
 public:
  TraceWriter(std::string path, TraceFormat format, const TraceMeta& meta);
  ~TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  /// Appends rows first..count-1 of block `b` that fall on the decimation grid
  /// (k % decimate == 0), each row's SampleRecord (SampleBlock::record() and the contour columns)
  /// read from the block's columns in place; `period_s` is the T of record(). No allocation once
  /// the buffer has grown to its working size.
  void write_block(const SampleBlock& b, int first, double period_s);
  /// write_block() with the header's period.
  void consume(const SampleBlock& b, int first) override { write_block(b, first, period_s_); }
  /// Flushes, closes and renames the file into place; with a status line, first overwrites it
  /// with "complete". Throws gm::InputError on a write error; with a status line the file then
  /// stays open, for keep_partial().
  void finish();
  /// The end of a run: finish(), unless the run is unsettled and the trace has a status line
  /// (the caller keeps it partial then, keep_partial()).
  void finish(const RunEnd& end) override {
    if (end.settled || !status_line_) finish();
  }
  /// For a failed run, with meta.status_line and before finish() has succeeded: writes out the rows
  /// written so far, overwrites the status line with "partial: REASON" and closes the file, which
  /// stays at `path.partial` and ends after its last whole row. Returns that path, or "" when not
  /// even the header could be written (nothing is left then). Without a status line it does
  /// nothing and returns "". Never throws.
  std::string keep_partial(std::string_view reason) noexcept;
  /// True until finish() has succeeded or keep_partial() has closed the file.
  bool open() const { return file_ != nullptr; }

  std::int64_t rows() const { return rows_; }
  /// Samples k with k % decimate() == 0 are written.
  int decimate() const { return decimate_; }

  /// True when `path` would be written in place, so cannot be kept partial: "-" (stdout) or an
  /// existing device or FIFO. False for a directory (the constructor refuses it on its own).
  static bool written_in_place(const std::string& path);

 private:
  void flush_buffer();
  void count_whole_rows(std::size_t n);  ///< after a short write of n bytes of buf_
  void patch_status(std::string_view text);
  template <int N, TraceColumnSet Set>
  void write_rows(const SampleBlock& b, int first, double period_s);
  /// Row `s` (a SampleRecord or a BlockRow) of `axes` axis blocks at p; returns its end.
  /// "{:.6g}" of pct, kept from the last call while pct is the same (the override changes rarely).
  std::string_view percent_text(double pct) {
    if (!(pct == last_pct_ && std::signbit(pct) == std::signbit(last_pct_))) [[unlikely]]
      format_percent(pct);
    return {last_pct_text_.data(), last_pct_size_};
  }
  void format_percent(double pct);  ///< sets last_pct_ and last_pct_text_
  template <TraceColumnSet Set, typename Row, typename Axes>
  char* put_csv_row(char* p, const Row& s, Axes axes);
  template <TraceColumnSet Set, typename Row, typename Axes>
  char* put_binary_row(char* p, const Row& s, Axes axes) const;

  std::string path_, tmp_path_;
  TraceFormat format_;
  int decimate_;
  double period_s_;
  std::FILE* file_ = nullptr;
  bool to_stdout_ = false;
  bool direct_ = false;                    ///< an existing device or FIFO: written in place
  bool status_line_ = false;               ///< the header has a `# status:` line (--keep-partial)
  int axes_ = 3;                           ///< axis blocks per row
  TraceColumnSet columns_ = kTraceAlways;  ///< the optional columns written
  std::int64_t binary_row_ = 0;            ///< bytes of a binary row
  std::int64_t status_offset_ = 0;         ///< its byte offset in the file
  std::int64_t header_bytes_ = 0;  ///< magic, length and header: the file before the first row
  std::int64_t written_ = 0;       ///< bytes of whole rows (and header) written to the file
  fmt::memory_buffer buf_;
  std::int64_t rows_ = 0;
  /// Room for a row and the 8 (16 for the override) bytes a number's store may write past
  /// its text. CSV, nine axes: 38 integers of up to 20 characters, t_s and contour_err up to
  /// 350 each (fmt's "%.6f" of DBL_MAX), the override up to 13, 42 separators: 1,555; with the
  /// tool tip (fixed3, up to 350 each) nine more: 4,714. Binary: 308, 380 with the tool tip.
  static constexpr std::size_t kMaxRowBytes = 6144;
  double last_pct_ = std::numeric_limits<double>::quiet_NaN();  ///< override of the cached text
  /// "{:.6g}" of last_pct_ (at most 13 characters, "-1.23457e+308"), in a buffer a row copies
  /// 16 bytes of at once.
  std::array<char, 32> last_pct_text_{};
  std::size_t last_pct_size_ = 0;
};

}  // namespace gm
