// The `check` entry points: a whole program's diagnostics and its summary (moves, path length,
// time), read serially or with the reading and parsing on a second thread.
#include "interp/program.hpp"

#include "interp/program_runner.hpp"

#include <thread>

namespace gm {

namespace {

// The move's length, motion_length_mm's bits: a line moving X, Y or Z takes the same operations
// on the three differences alone (not the nine-axis difference first).
double summary_length_mm(const Motion& m) {
  if (m.kind != MotionKind::Arc) {
    const Vec3 xyz = m.end_mm.head<3>() - m.start_mm.head<3>();
    if (xyz != Vec3::Zero()) return xyz.norm();
  }
  return motion_length_mm(m);
}

// Adds what `out` holds to the summary's counts.
void account(const std::vector<Canon>& out, const Machine& machine, CheckSummary& sum) {
  for (const auto& c : out) {
    if (const auto* m = std::get_if<Motion>(&c)) {
      ++sum.moves;
      const double len = summary_length_mm(*m);
      sum.path_length_mm += len;
      if (m->kind == MotionKind::Rapid)
        sum.time_at_feed_s += machine.rapid_mm_min > 0 ? len / machine.rapid_mm_min * 60.0 : 0.0;
      else if (m->inverse_time_s > 0)
        sum.time_at_feed_s += m->inverse_time_s;
      else if (m->feed_mm_min > 0)
        sum.time_at_feed_s += len / m->feed_mm_min * 60.0;
    } else if (const auto* d = std::get_if<Dwell>(&c)) {
      sum.time_at_feed_s += d->seconds;
    }
  }
}

/// `Summarise`: the moves, path length and time are added up (check); otherwise only the
/// diagnostics and the errors are counted (what a run needs before it starts). With two or more
/// cores (CheckThreads::Auto) the lines are read and parsed on a second thread until the program
/// first jumps, as ProgramStream's read-ahead: the same diagnostics, in the same order.
template <bool Summarise = true, typename Sink>
CheckSummary run_check(std::istream& in, std::string_view filename, const InterpreterOptions& opts,
                       CheckThreads threads, Sink&& sink) {
  InterpreterOptions options = opts;
  options.read_ahead = threads == CheckThreads::Auto && std::thread::hardware_concurrency() >= 2;
  options.check_all = true;
  LineDriver driver(in, std::string(filename), options);
  CheckSummary sum;
  std::vector<Canon> out;
  std::vector<Diagnostic> diags;
  bool more = true;
  while (more) {
    more = driver.step(out, diags);
    for (const auto& d : diags) {
      sink(d);
      if (d.severity == Severity::Error) ++sum.errors;
    }
    if constexpr (Summarise) account(out, driver.back().machine(), sum);
    out.clear();
    diags.clear();
  }
  sum.blocks = driver.back().blocks();
  return sum;
}

}  // namespace

CheckSummary check_program(std::istream& in, std::string_view filename,
                           const InterpreterOptions& opts, std::ostream& diag_out,
                           CheckThreads threads) {
  return run_check(in, filename, opts, threads,
                   [&](const Diagnostic& d) { diag_out << format_diagnostic(filename, d); });
}

int count_program_errors(std::istream& in, std::string_view filename,
                         const InterpreterOptions& opts, std::ostream& diag_out) {
  return run_check<false>(in, filename, opts, CheckThreads::Auto,
                          [&](const Diagnostic& d) { diag_out << format_diagnostic(filename, d); })
      .errors;
}

CheckSummary check_program_diagnostics(std::istream& in, std::string_view filename,
                                       const InterpreterOptions& opts,
                                       std::vector<Diagnostic>& diagnostics, CheckThreads threads) {
  return run_check(in, filename, opts, threads,
                   [&](const Diagnostic& d) { diagnostics.push_back(d); });
}

}  // namespace gm
