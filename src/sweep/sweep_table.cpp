// Sweep rows: read from a run's summary (local) or its summary JSON (merged cluster runs), written
// out.
#include "sweep/sweep_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace gm::sweep {
namespace {

// The number after the n-th `"key":` (optionally `{"value":`), or nullopt. The summary JSON is
// gmotion's own fixed format (src/trace/run_summary.cpp), so a key search suffices.
bool number_after(const std::string& j, std::size_t& pos, std::string_view key, double& out) {
  const std::string k = fmt::format("\"{}\":", key);
  const std::size_t at = j.find(k, pos);
  if (at == std::string::npos) return false;
  std::size_t p = at + k.size();
  if (j.compare(p, 9, "{\"value\":") == 0) p += 9;
  if (j.compare(p, 4, "null") == 0) {
    out = std::nan("");
  } else {
    char* end = nullptr;
    out = std::strtod(j.c_str() + p, &end);
    if (end == j.c_str() + p) return false;
  }
  pos = p;
  return true;
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string json_text(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\')
      q += '\\', q += c;
    else if (static_cast<unsigned char>(c) < 0x20)
      q += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
    else
      q += c;
  }
  return q + "\"";
}

std::string num(double v) {
  return std::isfinite(v) ? fmt::format("{:.9g}", v) : "";
}

}  // namespace

SweepRow row_setup(const SweepSpec& s, const RunPoint& r, const Machine& m) {
  SweepRow row;
  row.index = r.index;
  row.program = std::filesystem::path(s.programs[r.program]).filename().string();
  row.machine = s.machines[r.machine].label;
  row.profile = m.profile;
  row.tau_s = m.tau_s;
  row.period_s = m.period_s;
  row.override_ = s.overrides[r.override_].label();
  return row;
}

namespace {
// A summary value as --summary-json prints it (9 significant digits; null for NaN and infinity)
// and merge() reads it back.
double as_printed(double v) {
  return std::isfinite(v) ? std::strtod(fmt::format("{:.9g}", v).c_str(), nullptr) : std::nan("");
}
}  // namespace

void fill_from_summary(SweepRow& row, const RunSummary& summary, const Machine& m) {
  row.samples = summary.samples;
  row.cycle_time_s = as_printed(summary.cycle_time_s);
  row.program_time_s = as_printed(summary.program_time_s);
  row.contour_max_mm = as_printed(summary.contour_err_blu.value) * m.contour_blu_mm();
  row.contour_max_line = summary.contour_err_blu.line;
  row.contour_rms_mm = as_printed(summary.contour_rms_blu) * m.contour_blu_mm();
  row.following_max_mm = 0.0;
  for (int a = 0; a < m.axis_count(); ++a) {
    const auto i = static_cast<std::size_t>(a);
    row.following_max_mm =
        std::max(row.following_max_mm,
                 as_printed(summary.axes[i].following_err_blu.value) * m.axes[i].blu_mm);
  }
  row.status = summary.settled ? "ok" : "unsettled";
}

bool fill_from_summary_json(SweepRow& row, const std::string& j, const Machine& m) {
  std::size_t pos = 0;
  double samples = 0, line = 0, contour = 0, rms = 0;
  if (!number_after(j, pos, "samples", samples) ||
      !number_after(j, pos, "cycle_time_s", row.cycle_time_s) ||
      !number_after(j, pos, "program_time_s", row.program_time_s))
    return false;
  pos = 0;
  if (!number_after(j, pos, "contour_err_max_blu", contour)) return false;
  std::size_t line_pos = pos;
  if (!number_after(j, line_pos, "line", line)) return false;
  if (!number_after(j, pos, "contour_err_rms_blu", rms)) return false;
  row.samples = static_cast<std::int64_t>(samples);
  row.contour_max_mm = contour * m.contour_blu_mm();
  row.contour_max_line = static_cast<int>(line);
  row.contour_rms_mm = rms * m.contour_blu_mm();
  row.following_max_mm = 0.0;
  for (int a = 0; a < m.axis_count(); ++a) {
    double f = 0;
    if (!number_after(j, pos, "following_err_max_blu", f)) return false;
    row.following_max_mm =
        std::max(row.following_max_mm, f * m.axes[static_cast<std::size_t>(a)].blu_mm);
  }
  row.status = j.find("\"settled\":true") != std::string::npos ? "ok" : "unsettled";
  return true;
}

namespace {
constexpr const char* kColumns[] = {
    "index",          "program",          "machine",        "profile",
    "tau_s",          "period_s",         "override",       "status",
    "cycle_time_s",   "program_time_s",   "contour_max_mm", "contour_max_line",
    "contour_rms_mm", "following_max_mm", "samples",        "error"};

// The row's values in column order; texts flagged so JSON quotes them.
std::vector<std::pair<std::string, bool>> cells(const SweepRow& r) {
  return {{std::to_string(r.index), false},
          {r.program, true},
          {r.machine, true},
          {r.profile, true},
          {num(r.tau_s), false},
          {num(r.period_s), false},
          {r.override_, true},
          {r.status, true},
          {num(r.cycle_time_s), false},
          {num(r.program_time_s), false},
          {num(r.contour_max_mm), false},
          {std::to_string(r.contour_max_line), false},
          {num(r.contour_rms_mm), false},
          {num(r.following_max_mm), false},
          {std::to_string(r.samples), false},
          {r.error, true}};
}
}  // namespace

std::string to_csv(const std::vector<SweepRow>& rows) {
  std::string s;
  for (const char* c : kColumns) {
    if (!s.empty()) s += ',';  // appended in two steps: g++ 12 -O3 warns falsely on `a + b`
    s += c;
  }
  s += "\n";
  for (const SweepRow& r : rows) {
    std::string line;
    for (const auto& [v, is_text] : cells(r)) {
      if (!line.empty()) line += ',';
      line += csv_text(v);
    }
    s += line + "\n";
  }
  return s;
}

std::string to_json(const std::vector<SweepRow>& rows) {
  std::string s = "[";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    s += i ? ",\n {" : "\n {";
    const auto c = cells(rows[i]);
    for (std::size_t k = 0; k < c.size(); ++k)
      s += fmt::format(
          "{}\"{}\":{}", k ? "," : "", kColumns[k],
          c[k].second ? json_text(c[k].first) : (c[k].first.empty() ? "null" : c[k].first));
    s += "}";
  }
  return s + "\n]\n";
}

}  // namespace gm::sweep
