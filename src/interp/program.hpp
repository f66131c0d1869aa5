// Whole-program entry points: check (all diagnostics + summary) and the streaming canon source.
#pragma once

#include "common/diagnostic.hpp"
#include "interp/dialect.hpp"
#include "machine/machine.hpp"
#include "motion/canon.hpp"

#include <cstdint>
#include <istream>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

struct InterpreterOptions {
  const Machine* machine = nullptr;          ///< null: a default-constructed Machine
  bool block_delete = false;                 ///< honour '/' at line start (skip those lines)
  std::int64_t max_iterations = 10'000'000;  ///< loop iterations and calls before an error
  /// Directories where `o<name> call` finds `name.ngc` (LinuxCNC's SUBROUTINE_PATH); empty:
  /// no file is ever opened for a call.
  std::vector<std::string> subroutine_path{};
  /// LinuxCNC's parameter file (`.var`, the machine's `parameter_file`); empty: none. Read
  /// before the first line (a missing file is not an error); the offsets in it apply.
  std::string parameter_file{};
  /// ProgramStream writes the parameters back to `parameter_file` when the program is over
  /// (ended, stopped at an error, or the stream destroyed), as rs274 does at exit. check_program
  /// never writes.
  bool save_parameters = false;
  /// ProgramStream: lines are read and parsed on a second thread ahead of the interpreter (until
  /// the program first jumps); the same canon and diagnostics. check_program ignores it (it
  /// chooses with CheckThreads).
  bool read_ahead = false;
  /// What the program is written for (docs/dialects.md); LinuxCNC: rs274's rules exactly.
  Dialect dialect = Dialect::LinuxCNC;
  /// LinuxCNC's [RS274NGC]DISABLE_FANUC_STYLE_SUB: M98, M99 returning from a subprogram and a
  /// bare `O1234` line are errors (Machine::fanuc_subs_disabled).
  bool fanuc_subs_disabled = false;
  /// check_program: report every error in one pass. After a call whose subroutine is found
  /// nowhere the search is dropped and checking goes on after the call line; an error that
  /// leaves the control flow unknown ends checking with a note saying so. ProgramStream ignores
  /// it (it stops at the first error).
  bool check_all = false;
};

struct CheckSummary {
  std::int64_t blocks = 0;    ///< lines with at least one word that were interpreted
  std::int64_t moves = 0;     ///< canonical motions (zero-length lines/rapids are not emitted)
  double path_length_mm = 0;  ///< all motions, rapids included
  /// Feed moves at programmed F (G93: 60/F), rapids at Machine::rapid_mm_min, plus dwells.
  double time_at_feed_s = 0;
  int errors = 0;
};

/// How check_program uses threads: Auto = reading and parsing on a second thread when the
/// machine has two or more cores; Single = everything on the calling thread. Same results.
enum class CheckThreads { Auto, Single };

/// Validates a whole program, writing each diagnostic (formatted, file:line:col + caret) to
/// `diag_out`; returns the summary. Reads the stream once, line by line; with two or more
/// cores, reading and parsing run on a second thread ahead of the interpreter (same result).
CheckSummary check_program(std::istream& in, std::string_view filename,
                           const InterpreterOptions& opts, std::ostream& diag_out,
                           CheckThreads threads = CheckThreads::Auto);

/// As check_program, but returns only the number of errors: the moves are not added up (what
/// `gmotion run` checks before it starts). The same diagnostics, in the same order.
int count_program_errors(std::istream& in, std::string_view filename,
                         const InterpreterOptions& opts, std::ostream& diag_out);

/// As check_program, but hands back the diagnostics (with their ErrorCode in `code`) instead of
/// printing them (tests, tools).
CheckSummary check_program_diagnostics(std::istream& in, std::string_view filename,
                                       const InterpreterOptions& opts,
                                       std::vector<Diagnostic>& diagnostics,
                                       CheckThreads threads = CheckThreads::Auto);

class LineDriver;  // internal: reader + parser + interpreter, one line at a time

/// Streams canonical commands: each line is parsed, interpreted and handed on before the next
/// is read. Throws gm::InputError with the formatted diagnostic(s) at the first bad line.
/// Run check_program first if nothing may run when the program has an error.
class ProgramStream : public CanonSource {
 public:
  ProgramStream(std::istream& in, std::string filename, InterpreterOptions opts);
  ~ProgramStream() override;
  ProgramStream(const ProgramStream&) = delete;
  ProgramStream& operator=(const ProgramStream&) = delete;
  bool next(Canon& out) override;

 private:
  std::unique_ptr<LineDriver> runner_;
  std::vector<Canon> queue_;  ///< canon of the current line (reused)
  std::size_t head_ = 0;
  std::vector<Diagnostic> diags_;
  bool save_parameters_ = false;
};

}  // namespace gm
