// CSV and binary encoder traces with a metadata header; temp file + rename for integrity.
#include "trace/trace_writer.hpp"

#include "trace/csv_number.hpp"

#include "common/status.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <sys/stat.h>

namespace gm {
namespace {

constexpr std::size_t kFlushBytes = 1u << 20;
constexpr char kBinaryMagic[8] = {'G', 'M', 'T', 'R', 'A', 'C', 'E', '1'};

char lower(char c) { return static_cast<char>(c - 'A' + 'a'); }

template <typename T>
void put_raw(fmt::memory_buffer& buf, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));  // little-endian on every machine we build for
  buf.append(bytes, bytes + sizeof(T));
}

}  // namespace

std::string trace_header(const TraceMeta& m) {
  std::string h;
  auto out = std::back_inserter(h);
  fmt::format_to(out, "# gmotion {} trace v1\n", GMOTION_VERSION);
  fmt::format_to(out, "# program: {}\n", m.program);
  fmt::format_to(out, "# machine: {} ({})\n", m.machine_name, m.machine_source);
  fmt::format_to(out, "# profile: {} taps={} tau_s={}\n", m.profile, m.taps, m.tau_s);
  fmt::format_to(out, "# period_s: {}\n", m.period_s);
  fmt::format_to(out, "# blu_mm: {}\n", fmt::join(m.blu_mm.data(), m.blu_mm.data() + kAxes, ","));
  fmt::format_to(out, "# servo: {}\n", m.servo ? "on" : "off (encoder reads the Acc/Dec output)");
  fmt::format_to(out, "# decimate: {}\n", m.decimate);
  fmt::format_to(out,
                 "# units: t_s s; line source line; *_cmd interpolator BLU; *_ref Acc/Dec output BLU; "
                 "*_enc encoder counts; *_ferr following error ref-enc BLU; contour_err BLU (signed "
                 "radial on arcs, + outside); override percent\n");
  h += "t_s,line";
  for (char a : kAxisLetters)
    for (const char* col : {"_cmd", "_ref", "_enc", "_ferr"}) fmt::format_to(out, ",{}{}", lower(a), col);
  h += ",contour_err,override\n";
  return h;
}

TraceWriter::TraceWriter(std::string path, TraceFormat format, const TraceMeta& meta)
    : path_(std::move(path)), format_(format), decimate_(meta.decimate < 1 ? 1 : meta.decimate) {
  struct stat st {};
  const bool special = path_ != "-" && ::stat(path_.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
  if (path_ == "-") {
    to_stdout_ = true;
    file_ = stdout;
  } else if (special) {
    // A device or FIFO (/dev/null, /dev/full, a pipe): written in place, never renamed over.
    if (S_ISDIR(st.st_mode)) throw InputError(fmt::format("cannot write trace '{}': it is a directory", path_));
    file_ = std::fopen(path_.c_str(), "wb");
    if (file_ == nullptr)
      throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(errno)));
    direct_ = true;
  } else {
    tmp_path_ = path_ + ".partial";
    file_ = std::fopen(tmp_path_.c_str(), "wb");
    if (file_ == nullptr)
      throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(errno)));
  }
  const std::string header = trace_header(meta);
  if (format_ == TraceFormat::Binary) {
    buf_.append(kBinaryMagic, kBinaryMagic + 8);
    put_raw(buf_, static_cast<std::uint32_t>(header.size()));
  }
  buf_.append(header.data(), header.data() + header.size());
  buf_.reserve(kFlushBytes + 4096);
}

TraceWriter::~TraceWriter() {
  if (file_ != nullptr && !to_stdout_) {
    std::fclose(file_);
    if (!direct_) std::remove(tmp_path_.c_str());  // incomplete: leave nothing that looks like a trace
  }
}

void TraceWriter::write(const SampleRecord& s) {
  if (s.k % decimate_ != 0) return;
  if (format_ == TraceFormat::Csv)
    write_csv(s);
  else
    write_binary(s);
  ++rows_;
  if (buf_.size() >= kFlushBytes) flush_buffer();
}

void TraceWriter::write_csv(const SampleRecord& s) {
  // Same text as fmt "{:.6f},{}" + ",{},{},{},{}" per axis + ",{:.3f},{:.6g}\n", written by
  // hand into the buffer (put_int/put_fixed are exact; see csv_number.hpp).
  const std::size_t at = buf_.size();
  buf_.resize(at + kMaxCsvRow);
  char* p = buf_.data() + at;
  p = put_fixed(p, s.t_s, 6);
  *p++ = ',';
  p = put_int(p, s.line);
  for (int a = 0; a < kAxes; ++a) {
    for (std::int64_t v : {s.cmd_blu[a], s.ref_blu[a], s.enc_blu[a], s.ferr_blu[a]}) {
      *p++ = ',';
      p = put_int(p, v);
    }
  }
  *p++ = ',';
  p = put_fixed(p, s.contour_err_blu, 3);
  *p++ = ',';
  const double pct = s.feed_scale * 100.0;
  if (!(pct == last_pct_ && std::signbit(pct) == std::signbit(last_pct_))) {  // changes rarely
    last_pct_ = pct;
    last_pct_text_.clear();
    fmt::format_to(std::back_inserter(last_pct_text_), "{:.6g}", pct);
  }
  std::memcpy(p, last_pct_text_.data(), last_pct_text_.size());
  p += last_pct_text_.size();
  *p++ = '\n';
  buf_.resize(static_cast<std::size_t>(p - buf_.data()));
}

// Binary row: int64 k, int32 line, then per axis int64 cmd, ref, enc, ferr, then double
// contour_err (BLU) and double override (percent); little-endian, no padding.
void TraceWriter::write_binary(const SampleRecord& s) {
  put_raw(buf_, static_cast<std::int64_t>(s.k));
  put_raw(buf_, static_cast<std::int32_t>(s.line));
  for (int a = 0; a < kAxes; ++a) {
    put_raw(buf_, static_cast<std::int64_t>(s.cmd_blu[a]));
    put_raw(buf_, static_cast<std::int64_t>(s.ref_blu[a]));
    put_raw(buf_, static_cast<std::int64_t>(s.enc_blu[a]));
    put_raw(buf_, static_cast<std::int64_t>(s.ferr_blu[a]));
  }
  put_raw(buf_, s.contour_err_blu);
  put_raw(buf_, s.feed_scale * 100.0);
}

void TraceWriter::flush_buffer() {
  if (buf_.size() == 0) return;
  if (std::fwrite(buf_.data(), 1, buf_.size(), file_) != buf_.size())
    throw InputError(fmt::format("cannot write trace '{}': {}", to_stdout_ ? "<stdout>" : path_,
                                 std::strerror(errno)));
  buf_.clear();
}

void TraceWriter::finish() {
  flush_buffer();
  if (direct_) {
    const bool ok = std::fflush(file_) == 0;
    const int err = errno;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) throw InputError(fmt::format("cannot write trace '{}': {}", path_, std::strerror(err)));
    return;
  }
  if (to_stdout_) {
    if (std::fflush(stdout) != 0) throw InputError(fmt::format("cannot write trace to stdout: {}", std::strerror(errno)));
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
    throw InputError(fmt::format("cannot move trace into place at '{}': {}", path_, std::strerror(e)));
  }
}

}  // namespace gm
