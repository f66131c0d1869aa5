// Streaming reader of CSV and binary (GMTRACE1) traces, for gmotion diff and the tools.
#include "trace/trace_reader.hpp"

#include "common/axis.hpp"
#include "common/status.hpp"
#include "trace/trace_schema.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

namespace gm {
namespace {

// Reads one line without its '\n'; `ended` tells whether the '\n' was there. False at the end.
bool read_line(std::FILE* f, std::string& out, bool& ended) {
  out.clear();
  ended = false;
  int c;
  while ((c = std::fgetc(f)) != EOF) {
    if (c == '\n') {
      ended = true;
      return true;
    }
    out += static_cast<char>(c);
  }
  return !out.empty();
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      parts.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  parts.push_back(cur);
  return parts;
}

}  // namespace

TraceReader::TraceReader(const std::string& path) : path_(path) {
  f_ = std::fopen(path.c_str(), "rb");
  if (f_ == nullptr)
    throw InputError(fmt::format("cannot read trace '{}': {}", path, std::strerror(errno)));
  char magic[8] = {};
  const std::size_t got = std::fread(magic, 1, 8, f_);
  std::string header_text;
  if (got == 8 && std::memcmp(magic, "GMTRACE1", 8) == 0) {
    binary_ = true;
    std::uint32_t len = 0;
    if (std::fread(&len, 4, 1, f_) != 1 || len > (1u << 20))
      throw InputError(fmt::format("{}: truncated or corrupt binary trace header", path));
    header_text.resize(len);
    if (std::fread(header_text.data(), 1, len, f_) != len)
      throw InputError(fmt::format("{}: truncated binary trace header", path));
  } else {
    std::rewind(f_);
    // CSV: '#' lines, then the column line.
    std::string l;
    bool ended = false;
    while (read_line(f_, l, ended)) {
      ++line_no_;
      header_text += l + "\n";
      if (l.empty() || l[0] != '#') break;
    }
  }
  std::istringstream hs(header_text);
  std::string l;
  while (std::getline(hs, l)) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    if (l.rfind("# ", 0) == 0) {
      header_.push_back(l.substr(2));
    } else if (!l.empty()) {
      columns_ = split(l, ',');
      break;
    }
  }
  if (columns_.size() < 2 || columns_[0] != "t_s" || header_.empty() ||
      header_[0].rfind("gmotion ", 0) != 0)
    throw InputError(
        fmt::format("{}: not a gmotion trace (no '# gmotion' header and t_s column line)", path));
  const std::string p = header_value("period_s");
  period_s_ = p.empty() ? 0.0 : std::strtod(p.c_str(), nullptr);
  if (binary_ && !(period_s_ > 0))
    throw InputError(
        fmt::format("{}: binary trace without a valid '# period_s:' header line", path));
  partial_ = status().rfind("partial", 0) == 0;
  // Each column's field as the schema defines it (trace_columns.def).
  std::size_t bytes = 0;
  for (const std::string& c : columns_) {
    const TraceColumn* col = find_trace_column(c);
    if (binary_ && col == nullptr)
      throw InputError(fmt::format("{}: binary trace with an unknown column '{}'", path, c));
    kinds_.push_back(col != nullptr ? col->kind : TraceKind::Fixed3);
    bytes += trace_binary_bytes(kinds_.back());
  }
  if (binary_) record_.resize(bytes);
}

TraceReader::~TraceReader() {
  if (f_ != nullptr) std::fclose(f_);
}

std::string TraceReader::header_value(const std::string& key) const {
  const std::string prefix = key + ": ";
  for (const std::string& h : header_)
    if (h.rfind(prefix, 0) == 0) return h.substr(prefix.size());
  return "";
}

std::string TraceReader::status() const {
  std::string s = header_value("status");
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

bool TraceReader::next(std::vector<double>& values) {
  values.resize(columns_.size());
  if (binary_) {
    const std::size_t got = std::fread(record_.data(), 1, record_.size(), f_);
    if (got == 0) return false;
    if (got < record_.size()) {
      dropped_tail_ = partial_;  // a record cut by the end of the run
      if (partial_) return false;
      throw InputError(fmt::format("{}: record {} is truncated", path_, row_ + 1));
    }
    const char* r = record_.data();
    for (std::size_t i = 0; i < columns_.size(); ++i) {
      switch (kinds_[i]) {
        case TraceKind::Time: {
          std::int64_t k = 0;
          std::memcpy(&k, r, 8);
          values[i] = static_cast<double>(k) * period_s_;
          break;
        }
        case TraceKind::Line: {
          std::int32_t v = 0;
          std::memcpy(&v, r, 4);
          values[i] = v;
          break;
        }
        case TraceKind::Count: {
          std::int64_t v = 0;
          std::memcpy(&v, r, 8);
          values[i] = static_cast<double>(v);
          break;
        }
        case TraceKind::Fixed3:
        case TraceKind::Percent:
          std::memcpy(&values[i], r, 8);
          break;
      }
      r += trace_binary_bytes(kinds_[i]);
    }
    ++row_;
    return true;
  }
  bool ended = false;
  if (!read_line(f_, line_, ended)) return false;
  if (!ended && partial_) {  // a row cut by the end of the run
    dropped_tail_ = true;
    return false;
  }
  ++line_no_;
  ++row_;
  const char* p = line_.data();
  const char* end = p + line_.size();
  if (end > p && end[-1] == '\r') --end;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    auto [q, ec] = std::from_chars(p, end, values[i]);
    if (ec != std::errc() || (i + 1 < columns_.size() ? (q == end || *q != ',') : q != end))
      throw InputError(fmt::format("{}:{}: malformed row (column {} '{}')", path_, line_no_, i + 1,
                                   columns_[i]));
    p = q + 1;
  }
  return true;
}

}  // namespace gm
