// Streaming a program's canonical commands (ProgramStream), line by line through the driver.
#include "interp/program.hpp"

#include "common/status.hpp"
#include "interp/program_runner.hpp"

#include <cstdio>

namespace gm {

namespace {

// A stream stops at the first error: it never reads on after one.
InterpreterOptions streamed(InterpreterOptions opts) {
  opts.check_all = false;
  return opts;
}

}  // namespace

ProgramStream::ProgramStream(std::istream& in, std::string filename, InterpreterOptions opts)
    : runner_(std::make_unique<LineDriver>(in, std::move(filename), streamed(opts))),
      save_parameters_(opts.save_parameters) {}

ProgramStream::~ProgramStream() {
  // A run stopped early (time limit, interrupt) still writes the parameters, as rs274 at exit.
  if (!save_parameters_) return;
  std::vector<Diagnostic> diags;
  runner_->finish(diags);
  for (const auto& d : diags)
    std::fputs(format_diagnostic(runner_->back().filename(), d).c_str(), stderr);
}

bool ProgramStream::next(Canon& out) {
  while (head_ >= queue_.size()) {
    queue_.clear();
    head_ = 0;
    diags_.clear();
    const bool more = runner_->step(queue_, diags_);
    bool error = false;
    for (const auto& d : diags_) error = error || d.severity == Severity::Error;
    if (save_parameters_ && (error || (!more && queue_.empty()))) runner_->finish(diags_);
    error = false;
    for (const auto& d : diags_) error = error || d.severity == Severity::Error;
    if (error) {
      std::string msg;
      for (const auto& d : diags_)
        if (d.severity == Severity::Error) msg += format_diagnostic(runner_->back().filename(), d);
      if (!msg.empty() && msg.back() == '\n') msg.pop_back();
      throw InputError(msg);
    }
    if (!more && queue_.empty()) return false;
  }
  out = queue_[head_++];
  return true;
}

}  // namespace gm
