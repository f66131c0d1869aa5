// The `check` entry points: a whole program's diagnostics and its summary (moves, path length,
// time), read serially or with the reading and parsing on a second thread.
#include "interp/program.hpp"

#include "interp/move_tally.hpp"
#include "interp/program_runner.hpp"

#include <thread>

namespace gm {

namespace {

/// `Summarise`: the moves, path length and time are added up (check; MoveTally, on the reading
/// thread while it reads ahead); otherwise only the diagnostics and the errors are counted (what
/// a run needs before it starts). With two or more
/// cores (CheckThreads::Auto) the lines are read and parsed on a second thread until the program
/// first jumps, as ProgramStream's read-ahead: the same diagnostics, in the same order.
template <bool Summarise = true, typename Sink>
CheckSummary run_check(std::istream& in, std::string_view filename, const InterpreterOptions& opts,
                       CheckThreads threads, Sink&& sink) {
  InterpreterOptions options = opts;
  options.read_ahead = threads == CheckThreads::Auto && std::thread::hardware_concurrency() >= 2;
  options.check_all = true;
  MoveTally tally(opts.machine != nullptr ? opts.machine->rapid_mm_min : Machine{}.rapid_mm_min);
  LineDriver driver(in, std::string(filename), options, Summarise ? &tally : nullptr);
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
    if constexpr (Summarise) driver.tally(out);
    out.clear();
    diags.clear();
  }
  driver.stop_reading();
  sum.blocks = driver.back().blocks();
  sum.moves = tally.moves();
  sum.path_length_mm = tally.path_length_mm();
  sum.time_at_feed_s = tally.time_at_feed_s();
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
