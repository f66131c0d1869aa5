// Row-by-row comparison of a golden and a fresh trace over the pinned columns.
#include "golden/trace_compare.hpp"

#include "trace/trace_schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace gm::golden {

bool glob_match(std::string_view p, std::string_view s) {
  // Iterative matcher with one backtrack point (the last '*').
  std::size_t pi = 0, si = 0, star = std::string_view::npos, mark = 0;
  while (si < s.size()) {
    if (pi < p.size() && p[pi] == '*') {
      star = pi++;
      mark = si;
    } else if (pi < p.size() && p[pi] == s[si]) {
      ++pi, ++si;
    } else if (star != std::string_view::npos) {
      pi = star + 1;
      si = ++mark;
    } else {
      return false;
    }
  }
  while (pi < p.size() && p[pi] == '*') ++pi;
  return pi == p.size();
}

namespace {

double column_tolerance(const PinSpec& pins, const std::string& name) {
  double tol = pins.tolerance_blu;
  for (const auto& [pattern, t] : pins.tolerances)
    if (glob_match(pattern, name)) {
      tol = t;
      break;
    }
  const TraceColumn* c = find_trace_column(name);
  return std::max(tol, c != nullptr ? c->csv_resolution : 0.0);
}

}  // namespace

CompareResult compare_traces(TraceReader& golden, TraceReader& fresh, const PinSpec& pins) {
  CompareResult r;
  r.columns = golden.columns();
  if (fresh.columns() != golden.columns()) {
    r.problem = fmt::format("the columns differ: golden has {}, now {}",
                            fmt::join(golden.columns(), ","), fmt::join(fresh.columns(), ","));
    return r;
  }
  const std::size_t n = r.columns.size();
  r.pinned.resize(n);
  r.tolerance.resize(n);
  r.max_diff.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    r.pinned[i] = std::any_of(pins.columns.begin(), pins.columns.end(),
                              [&](const std::string& p) { return glob_match(p, r.columns[i]); });
    r.tolerance[i] = column_tolerance(pins, r.columns[i]);
  }
  std::vector<double> g, f;
  for (;;) {
    const bool hg = golden.next(g), hf = fresh.next(f);
    if (!hg || !hf) {
      r.golden_rows = r.rows + (hg ? 1 : 0);
      r.fresh_rows = r.rows + (hf ? 1 : 0);
      TraceReader* longer = hg ? &golden : hf ? &fresh : nullptr;
      if (longer != nullptr) {
        std::vector<double> tmp;
        std::int64_t& count = hg ? r.golden_rows : r.fresh_rows;
        while (longer->next(tmp)) ++count;
        ++r.beyond;
      }
      break;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!r.pinned[i]) continue;
      const double d = std::abs(f[i] - g[i]);
      if (d > r.max_diff[i]) r.max_diff[i] = d;
      if (d > r.tolerance[i] + 1e-12) {
        if (!r.first)
          r.first = Divergence{r.rows + 1, g[0], static_cast<int>(g[1]), r.columns[i], g[i], f[i]};
        ++r.beyond;
      }
    }
    ++r.rows;
  }
  return r;
}

std::string largest_differences(const CompareResult& r) {
  std::string out;
  for (std::size_t i = 0; i < r.columns.size(); ++i)
    if (r.pinned[i] && r.max_diff[i] > 0.0)
      out += fmt::format("{}{}={:.6g}", out.empty() ? "" : " ", r.columns[i], r.max_diff[i]);
  return out.empty() ? "none" : out;
}

std::string describe_first(const CompareResult& r) {
  if (!r.problem.empty()) return r.problem;
  if (r.first) {
    const Divergence& d = *r.first;
    return fmt::format("t = {:.6f} s, line {}, column {}: golden {}, now {} (row {})", d.t_s,
                       d.line, d.column, d.golden, d.fresh, d.row);
  }
  if (r.golden_rows != r.fresh_rows)
    return fmt::format("the run now has {} rows, the golden {} (equal for the first {})",
                       r.fresh_rows, r.golden_rows, r.rows);
  return "none";
}

}  // namespace gm::golden
