// What a program fuzz target asserts: checked whole and then streamed, the two agree on whether
// the program is valid and on its moves, and every move handed on is finite.
#pragma once

#include "common/diagnostic.hpp"
#include "common/status.hpp"
#include "interp/interpreter.hpp"
#include "interp/program.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace fuzz {

// Loop iterations and calls one input may run (the interpreter's --max-iterations; a run's
// default is 10^7). An input is at most 4,096 bytes (libFuzzer's length for these seeds), so at
// most about 2,000 lines run per iteration, and check + stream run it twice (four times with
// '/'): 400 iterations bound an input to about a million executed lines, well under a second
// under the sanitizers. At the default, a `while` whose condition never changes ran 10^7
// iterations: 5.8 s in a release build and past libFuzzer's 10 s limit under ASan+UBSan. The
// longest loop of the seeds runs 300 times (tests/diff/lang/loop_arith.ngc); at 1,000, the
// mutants whose loop never ends (an error in the line that counts: the check reads on after it)
// took a fifth of the fuzzer's time, 0.2-0.9 s each under ASan+UBSan.
inline constexpr std::int64_t kMaxIterations = 400;

// Checks the program, then streams it: both must agree on whether it is valid and on the moves.
// `opts` gives what else the interpreter is run with (a parameter file). The number of moves of
// a valid program, -1 for an invalid one.
inline std::int64_t check_and_stream(const std::string& text, bool block_delete,
                                     gm::Dialect dialect = gm::Dialect::LinuxCNC,
                                     gm::InterpreterOptions opts = {}) {
  opts.block_delete = block_delete;
  opts.max_iterations = kMaxIterations;
  opts.dialect = dialect;

  std::istringstream check_in(text);
  std::vector<gm::Diagnostic> diags;
  // The check's read-ahead thread (CheckThreads::Auto on two cores) allocates three batches of
  // 1,024 parsed lines per check, which under ASan cost more than the small programs the fuzzer
  // makes: one input in eight takes it (chosen by content, so a replay takes the same path).
  const gm::CheckThreads threads =
      std::hash<std::string>{}(text) % 8 == 0 ? gm::CheckThreads::Auto : gm::CheckThreads::Single;
  const gm::CheckSummary sum =
      gm::check_program_diagnostics(check_in, "fuzz.nc", opts, diags, threads);
  for (const gm::Diagnostic& d : diags) (void)gm::format_diagnostic("fuzz.nc", d);

  std::istringstream stream_in(text);
  gm::ProgramStream stream(stream_in, "fuzz.nc", opts);
  gm::Canon canon;
  std::int64_t moves = 0;
  try {
    while (stream.next(canon)) {
      if (const auto* m = std::get_if<gm::Motion>(&canon)) {
        ++moves;
        // What the interpolator is handed must be finite (it converts positions to integers).
        if (!m->start_mm.allFinite() || !m->end_mm.allFinite() || !m->center_mm.allFinite() ||
            !std::isfinite(m->feed_mm_min) || !std::isfinite(m->inverse_time_s) ||
            !std::isfinite(gm::motion_length_mm(*m))) {
          std::fprintf(stderr, "fuzz: line %d: a motion with a non-finite value\n", m->line);
          std::abort();
        }
      } else if (const auto* d = std::get_if<gm::Dwell>(&canon); d && !std::isfinite(d->seconds)) {
        std::fprintf(stderr, "fuzz: line %d: a dwell of %g s\n", d->line, d->seconds);
        std::abort();
      }
    }
  } catch (const gm::InputError&) {
    if (sum.errors == 0) {
      std::fputs("fuzz: the stream threw on a program check_program accepted\n", stderr);
      std::abort();
    }
    return -1;
  }
  if (sum.errors > 0) {
    std::fputs("fuzz: the stream ran to its end through a program check_program refused\n", stderr);
    std::abort();
  }
  if (moves != sum.moves) {
    std::fprintf(stderr, "fuzz: check counted %lld moves, the stream gave %lld\n",
                 static_cast<long long>(sum.moves), static_cast<long long>(moves));
    std::abort();
  }
  return moves;
}

}  // namespace fuzz
