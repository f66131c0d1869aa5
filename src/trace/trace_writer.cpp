// CSV and binary encoder traces with a metadata header; temp file + rename for integrity.
#include "trace/trace_writer.hpp"

#include "trace/block_row.hpp"
#include "trace/csv_number.hpp"
#include "trace/trace_row.hpp"
#include "trace/trace_schema.hpp"

#include "common/status.hpp"

#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <iterator>

namespace gm {
namespace {

constexpr std::size_t kFlushBytes = 1u << 20;
constexpr char kBinaryMagic[8] = {'G', 'M', 'T', 'R', 'A', 'C', 'E', '1'};

// Bytes of a binary row (the schema's fields of the set, the axis columns once per axis).
constexpr std::int64_t binary_row_bytes(int axes, TraceColumnSet set) {
  std::int64_t n = 0;
  for (const TraceColumn& c : kTraceColumns)
    if (c.in(set))
      n += static_cast<std::int64_t>(trace_binary_bytes(c.kind)) *
           (c.section == TraceSection::Axis ? axes : 1);
  return n;
}

template <typename T>
void put_raw(fmt::memory_buffer& buf, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));  // little-endian on every machine we build for
  buf.append(bytes, bytes + sizeof(T));
}

template <typename T>
char* put_raw(char* p, T v) {
  std::memcpy(p, &v, sizeof(T));  // little-endian on every machine we build for
  return p + sizeof(T);
}

}  // namespace

std::string trace_header(const TraceMeta& m) {
  std::string h;
  auto out = std::back_inserter(h);
  fmt::format_to(out, "# gmotion {} trace v1\n", GMOTION_VERSION);
  if (m.status_line) h += trace_status_line("partial, run in progress");
  fmt::format_to(out, "# program: {}\n", m.program);
  fmt::format_to(out, "# machine: {} ({})\n", m.machine_name, m.machine_source);
  fmt::format_to(out, "# profile: {} taps={} tau_s={}\n", m.profile, m.taps, m.tau_s);
  fmt::format_to(out, "# period_s: {}\n", m.period_s);
  fmt::format_to(out, "# blu_mm: {}\n",
                 fmt::join(m.blu_mm.data(), m.blu_mm.data() + m.axes.size(), ","));
  fmt::format_to(out, "# servo: {}\n", m.servo ? "on" : "off (encoder reads the Acc/Dec output)");
  fmt::format_to(out, "# decimate: {}\n", m.decimate);
  fmt::format_to(out, "# units: {}\n", trace_units_text(m.columns));
  fmt::format_to(out, "{}\n", fmt::join(trace_column_names(m.axes, m.columns), ","));
  return h;
}

std::string trace_status_line(std::string_view text) {
  constexpr std::string_view kPrefix = "# status: ";
  constexpr std::string_view kCut = "...";
  const std::size_t room = kTraceStatusWidth - kPrefix.size();
  std::size_t n = text.size();
  if (n > room) {
    n = room - kCut.size();
    while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0) == 0x80) --n;  // not mid-character
  }
  std::string line(kPrefix);
  for (std::size_t i = 0; i < n; ++i) line += text[i] == '\n' || text[i] == '\r' ? ' ' : text[i];
  if (n < text.size()) line += kCut;
  line.resize(kTraceStatusWidth, ' ');
  line += '\n';
  return line;
}

bool TraceWriter::written_in_place(const std::string& path) {
  struct stat st {};
  return path == "-" ||
         (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode));
}

TraceWriter::TraceWriter(std::string path, TraceFormat format, const TraceMeta& meta)
    : path_(std::move(path)),
      format_(format),
      decimate_(meta.decimate < 1 ? 1 : meta.decimate),
      period_s_(meta.period_s),
      status_line_(meta.status_line),
      axes_(static_cast<int>(meta.axes.size())),
      columns_(meta.columns),
      binary_row_(binary_row_bytes(axes_, meta.columns)) {
  struct stat st {};
  const bool special = path_ != "-" && ::stat(path_.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
  if (status_line_ && written_in_place(path_))
    throw InputError(
        fmt::format("cannot keep a partial trace of '{}': it is written in place, not as a file",
                    path_ == "-" ? "<stdout>" : path_));
  if (path_ == "-") {
    to_stdout_ = true;
    file_ = stdout;
  } else if (special) {
    // A device or FIFO (/dev/null, /dev/full, a pipe): written in place, never renamed over.
    if (S_ISDIR(st.st_mode))
      throw InputError(fmt::format("cannot write trace '{}': it is a directory", path_));
    file_ = std::fopen(path_.c_str(), "wb");
    if (file_ == nullptr)
      throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(errno)));
    direct_ = true;
  } else {
    tmp_path_ = path_ + ".partial";
    file_ = std::fopen(tmp_path_.c_str(), "wb");
    if (file_ == nullptr)
      throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(errno)));
    // Unbuffered: buf_ is the only buffer, so what fwrite() took is in the file and
    // keep_partial() can cut the file back to its last whole row.
    if (status_line_) std::setvbuf(file_, nullptr, _IONBF, 0);
  }
  const std::string header = trace_header(meta);
  if (format_ == TraceFormat::Binary) {
    buf_.append(kBinaryMagic, kBinaryMagic + 8);
    put_raw(buf_, static_cast<std::uint32_t>(header.size()));
  }
  status_offset_ = static_cast<std::int64_t>(buf_.size() + header.find('\n') + 1);
  buf_.append(header.data(), header.data() + header.size());
  header_bytes_ = static_cast<std::int64_t>(buf_.size());
  buf_.reserve(kFlushBytes + (kBlockSamples + 1) * kMaxRowBytes);
}

TraceWriter::~TraceWriter() {
  if (file_ != nullptr && !to_stdout_) {
    std::fclose(file_);
    if (!direct_)
      std::remove(tmp_path_.c_str());  // incomplete: leave nothing that looks like a trace
  }
}

void TraceWriter::write_block(const SampleBlock& b, int first, double period_s) {
  with_axis_count(axes_, [&](auto n) {
    if (columns_ & kTraceModes)
      write_rows<decltype(n)::value, kTraceModes>(b, first, period_s);
    else
      write_rows<decltype(n)::value, kTraceAlways>(b, first, period_s);
  });
}

template <int N, TraceColumnSet Set>
void TraceWriter::write_rows(const SampleBlock& b, int first, double period_s) {
  if (first >= b.count) return;
  // The first row on the grid, then every decimate_-th.
  const auto off = static_cast<int>((b.k0 + first) % decimate_);
  first += off == 0 ? 0 : decimate_ - off;
  if (first >= b.count) return;  // no row of this block is on the grid
  const std::size_t at = buf_.size();
  buf_.resize(at + static_cast<std::size_t>(b.count - first + 1) * kMaxRowBytes);
  char* p = buf_.data() + at;
  constexpr std::integral_constant<int, N> axes;
  if (format_ == TraceFormat::Csv) {
    for (int i = first; i < b.count; i += decimate_)
      p = put_csv_row<Set>(p, BlockRow(b, i, period_s), axes);
  } else {
    for (int i = first; i < b.count; i += decimate_)
      p = put_binary_row<Set>(p, BlockRow(b, i, period_s), axes);
  }
  if (first < b.count) rows_ += (b.count - 1 - first) / decimate_ + 1;
  buf_.resize(static_cast<std::size_t>(p - buf_.data()));
  if (buf_.size() >= kFlushBytes) flush_buffer();
}

void TraceWriter::format_percent(double pct) {
  last_pct_ = pct;
  const auto r = fmt::format_to_n(last_pct_text_.data(), last_pct_text_.size(), "{:.6g}", pct);
  last_pct_size_ = std::min(r.size, last_pct_text_.size());
}

template <TraceColumnSet Set, typename Row, typename Axes>
char* TraceWriter::put_csv_row(char* p, const Row& s, Axes axes) {
  // The schema's columns (trace_columns.def), each followed by ','; the last ',' becomes '\n'.
  // Same text as fmt "{:.6f}" (time), "{}" (line, count), "{:.3f}" (fixed3), "{:.6g}" (percent),
  // written by hand in place (put_int/put_fixed are exact; see csv_number.hpp).
  visit_trace_row<Set>(s, axes, [&](auto kind, auto value) {
    if constexpr (kind() == TraceKind::Time) {
      p = put_fixed_n<6>(p, value);
    } else if constexpr (kind() == TraceKind::Line || kind() == TraceKind::Count) {
      p = put_int(p, value);
    } else if constexpr (kind() == TraceKind::Fixed3) {
      p = put_fixed_n<3>(p, value);
    } else {
      static_assert(kind() == TraceKind::Percent);
      const std::string_view text = percent_text(value);
      std::memcpy(p, text.data(), 16);  // one fixed-size move; the text is shorter
      if (text.size() > 16) std::memcpy(p, text.data(), text.size());
      p += text.size();
    }
    *p++ = ',';
  });
  p[-1] = '\n';
  return p;
}

// Binary row: the schema's fields in row order, little-endian, no padding (trace_columns.def:
// time as the int64 sample index k, line int32, count int64, fixed3 and percent float64).
template <TraceColumnSet Set, typename Row, typename Axes>
char* TraceWriter::put_binary_row(char* p, const Row& s, Axes axes) const {
  visit_trace_row<Set>(s, axes, [&](auto kind, auto value) {
    if constexpr (kind() == TraceKind::Time)
      p = put_raw(p, static_cast<std::int64_t>(s.k));
    else if constexpr (kind() == TraceKind::Line)
      p = put_raw(p, static_cast<std::int32_t>(value));
    else if constexpr (kind() == TraceKind::Count)
      p = put_raw(p, static_cast<std::int64_t>(value));
    else
      p = put_raw(p, static_cast<double>(value));
  });
  return p;
}

void TraceWriter::flush_buffer() {
  if (buf_.size() == 0) return;
  const std::size_t n = std::fwrite(buf_.data(), 1, buf_.size(), file_);
  if (n != buf_.size()) {
    const int err = errno;
    if (status_line_) count_whole_rows(n);
    throw InputError(fmt::format("cannot write trace '{}': {}", to_stdout_ ? "<stdout>" : path_,
                                 std::strerror(err)));
  }
  written_ += static_cast<std::int64_t>(buf_.size());
  buf_.clear();
}

void TraceWriter::count_whole_rows(std::size_t n) {
  // buf_ starts at file offset written_ and holds whole rows (after the header, the first time).
  const std::int64_t end = written_ + static_cast<std::int64_t>(n);
  std::int64_t good = 0;  // whole rows (and header) among the n bytes written
  if (end >= header_bytes_) {
    if (format_ == TraceFormat::Binary) {
      good = header_bytes_ + (end - header_bytes_) / binary_row_ * binary_row_ - written_;
    } else {
      const std::size_t nl = std::string_view(buf_.data(), n).rfind('\n');
      good = nl == std::string_view::npos ? 0 : static_cast<std::int64_t>(nl) + 1;
      if (written_ + good < header_bytes_) good = 0;
    }
  }
  written_ += good;
  const std::size_t rest = buf_.size() - static_cast<std::size_t>(good);
  std::memmove(buf_.data(), buf_.data() + good, rest);
  buf_.resize(rest);
}

void TraceWriter::patch_status(std::string_view text) {
  const std::string line = trace_status_line(text);
  if (::pwrite(fileno(file_), line.data(), line.size(), status_offset_) !=
      static_cast<ssize_t>(line.size()))
    throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(errno)));
}

std::string TraceWriter::keep_partial(std::string_view reason) noexcept {
  if (file_ == nullptr || !status_line_) return "";
  bool kept = false;
  try {
    // Rows after a failed write are dropped: write from the end of the last whole row.
    if (::fseeko(file_, written_, SEEK_SET) == 0) flush_buffer();
  } catch (...) {  // the rows not written are dropped
  }
  if (written_ >= header_bytes_ && ::ftruncate(fileno(file_), written_) == 0) {
    kept = true;
    try {
      patch_status(fmt::format("partial: {}", reason));
    } catch (...) {  // it still says "partial, run in progress"
    }
  }
  std::fclose(file_);
  file_ = nullptr;
  if (!kept) {
    std::remove(tmp_path_.c_str());
    return "";
  }
  return tmp_path_;
}

void TraceWriter::finish() {
  flush_buffer();
  if (status_line_) {
    // Any failure before the rename leaves the file open, for keep_partial().
    patch_status("complete");
    if (std::rename(tmp_path_.c_str(), path_.c_str()) != 0)
      throw InputError(
          fmt::format("cannot move trace into place at '{}': {}", path_, std::strerror(errno)));
    const bool closed = std::fclose(file_) == 0;
    const int err = errno;
    file_ = nullptr;
    if (!closed) {
      std::remove(path_.c_str());
      throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(err)));
    }
    return;
  }
  if (direct_) {
    const bool ok = std::fflush(file_) == 0;
    const int err = errno;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed)
      throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(err)));
    return;
  }
  if (to_stdout_) {
    if (std::fflush(stdout) != 0)
      throw InputError(fmt::format("cannot write trace to stdout: {}", std::strerror(errno)));
    file_ = nullptr;
    return;
  }
  const bool ok = std::fflush(file_) == 0;
  const int err = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed) {
    std::remove(tmp_path_.c_str());
    throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(err)));
  }
  if (std::rename(tmp_path_.c_str(), path_.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp_path_.c_str());
    throw InputError(
        fmt::format("cannot move trace into place at '{}': {}", path_, std::strerror(e)));
  }
}

}  // namespace gm
