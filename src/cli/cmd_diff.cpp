// gmotion diff: compare two traces (CSV or binary) column by column, streaming.
#include "cli/commands.hpp"
#include "common/status.hpp"
#include "trace/trace_reader.hpp"
#include "trace/trace_schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gm::cli {
namespace {

struct DiffFlags {
  std::string a, b;
  double tol = 0.0;
  std::vector<std::string> columns;
};

// The printing resolution of a column in the CSV format (the schema's): differences below it
// are not real.
double resolution(const std::string& column) {
  const TraceColumn* c = find_trace_column(column);
  return c != nullptr ? c->csv_resolution : 0.0;
}

// Why a partial trace (`run --keep-partial`) stopped, from its status line.
std::string why_partial(const TraceReader& t) {
  const std::string s = t.status();
  if (s.rfind("partial: ", 0) == 0) return s.substr(9);
  return "its run never finished: killed, or still running";
}

int diff(const DiffFlags& f) {
  TraceReader a(f.a), b(f.b);
  // A partial trace is compared as far as it goes; its missing rows count as a difference.
  for (const TraceReader* t : {&a, &b})
    if (t->partial())
      fmt::print(stderr, "warning: {} = {} is a partial trace ({}); comparing the rows it has\n",
                 t == &a ? "A" : "B", t->path(), why_partial(*t));
  // Traces of different set-ups are not comparable: say which header line differs.
  for (const char* key : {"machine", "profile", "period_s", "blu_mm", "servo", "decimate"}) {
    if (a.header_value(key) != b.header_value(key))
      throw InputError(
          fmt::format("traces are of different set-ups: '{}' is '{}' in {} but '{}' in {}", key,
                      a.header_value(key), f.a, b.header_value(key), f.b));
  }
  if (a.columns() != b.columns())
    throw InputError(fmt::format("traces have different columns: {} has {}, {} has {}", f.a,
                                 fmt::join(a.columns(), ","), f.b, fmt::join(b.columns(), ",")));
  const std::vector<std::string>& cols = a.columns();
  std::vector<std::size_t> use;
  if (f.columns.empty()) {
    for (std::size_t i = 0; i < cols.size(); ++i) use.push_back(i);
  } else {
    for (const std::string& c : f.columns) {
      const auto it = std::find(cols.begin(), cols.end(), c);
      if (it == cols.end())
        throw InputError(
            fmt::format("--columns: no column '{}' (columns: {})", c, fmt::join(cols, ",")));
      use.push_back(static_cast<std::size_t>(it - cols.begin()));
    }
  }

  std::vector<double> va, vb, max_diff(cols.size(), 0.0);
  std::int64_t rows = 0, beyond = 0;
  std::string first;
  for (;;) {
    const bool ha = a.next(va), hb = b.next(vb);
    if (!ha || !hb) {
      if (ha != hb) {
        std::int64_t extra = 1;
        TraceReader& longer = ha ? a : b;
        std::vector<double> tmp;
        while (longer.next(tmp)) ++extra;
        if (first.empty())
          first = fmt::format("{} ends after {} rows; {} has {} more", ha ? f.b : f.a, rows,
                              ha ? f.a : f.b, extra);
        ++beyond;
      }
      break;
    }
    for (std::size_t i : use) {
      const double d = std::abs(va[i] - vb[i]);
      max_diff[i] = std::max(max_diff[i], d);
      if (d > std::max(f.tol, resolution(cols[i])) + 1e-12) {
        if (first.empty())
          first = fmt::format("row {} (t = {:.6f} s, line {}): column {}: {} in A, {} in B",
                              rows + 1, va[0], va[1], cols[i], va[i], vb[i]);
        ++beyond;
      }
    }
    ++rows;
  }
  for (const TraceReader* t : {&a, &b})
    if (t->dropped_tail())
      fmt::print(stderr, "warning: {} = {} ends in an incomplete row, not compared\n",
                 t == &a ? "A" : "B", t->path());

  fmt::print("A = {}\nB = {}\n{} rows compared, tolerance {}\n", f.a, f.b, rows, f.tol);
  fmt::print("largest difference per column:");
  for (std::size_t i : use)
    if (i > 1) fmt::print(" {}={:.6g}", cols[i], max_diff[i]);
  fmt::print("\n");
  if (beyond == 0) {
    fmt::print("traces agree within the tolerance\n");
    return 0;
  }
  fmt::print("first divergence: {}\n{} value{} beyond the tolerance\n", first, beyond,
             beyond == 1 ? "" : "s");
  return static_cast<int>(ExitCode::InputError);
}

}  // namespace

void add_diff(CLI::App& app, Context& ctx) {
  auto flags = std::make_shared<DiffFlags>();
  auto* sub = app.add_subcommand(
      "diff", "Compare two traces (CSV or binary): first divergence, largest differences");
  sub->add_option("a", flags->a, "First trace")->required();
  sub->add_option("b", flags->b, "Second trace")->required();
  sub->add_option("--tol", flags->tol,
                  "Largest allowed difference per value (BLU for positions; default 0)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--columns", flags->columns, "Only these columns (comma-separated)")
      ->delimiter(',');
  sub->footer(
      "Exit 0 when every compared value is within the tolerance, 1 when one is not or the traces\n"
      "are of different machines, profiles, periods, BLU or columns. A partial trace (header line\n"
      "'# status: partial...', from run --keep-partial) is compared as far as it goes, after a\n"
      "warning on stderr naming it and why it stopped; rows the other trace has beyond it are a\n"
      "difference.");
  sub->callback([flags, &ctx] { ctx.exit_code = diff(*flags); });
}

}  // namespace gm::cli
