// Records, verifies or updates every case of a suite, in parallel on all cores, through Run.
#pragma once

#include "golden/suite.hpp"

#include <functional>
#include <string>
#include <vector>

namespace gm::golden {

enum class Mode { Record, Verify, Update };

/// How a case came out. Verify: Pass, Fail, Error. Record and update: Recorded, Unchanged,
/// Changed, Error.
enum class Outcome { Pass, Fail, Error, Recorded, Unchanged, Changed };

/// "PASS", "FAIL", "ERROR", "RECORDED", "UNCHANGED", "CHANGED".
const char* outcome_word(Outcome o);
/// True for the outcomes that make the command exit 1 (Fail, Error).
bool outcome_failed(Outcome o);

struct CaseResult {
  std::string name;
  Outcome outcome = Outcome::Error;
  std::string headline;  ///< after the name on the case's one line ("" for a plain pass)
  std::vector<std::string> details;  ///< further lines (first divergence, largest differences)
  std::string kind;      ///< JUnit failure type: divergence, setup, version, summary, run
  std::string picture;   ///< the PNG drawn for it (--pictures), or ""
  double seconds = 0.0;  ///< wall time of the case
};

struct RunnerOptions {
  Mode mode = Mode::Verify;
  int jobs = 0;                   ///< 0: every core
  std::vector<std::string> only;  ///< case names (globs) to run; empty: all
  std::string pictures_dir;       ///< verify: draw each divergence there as NAME.png
};

/// Runs the suite's cases (in parallel), calling `report` for each result in suite order as soon
/// as it and every case before it are done. Returns every result in suite order. Throws
/// gm::InputError when `only` names no case or the temporary folder cannot be made.
std::vector<CaseResult> run_suite(const Suite& suite, const RunnerOptions& options,
                                  const std::function<void(const CaseResult&)>& report);

/// The lines in which two set-up texts differ, as "[section] key: old -> new" (at most `max`).
std::vector<std::string> setup_changes(const std::string& before, const std::string& after,
                                       std::size_t max = 4);

}  // namespace gm::golden
