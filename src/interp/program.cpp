// The program driver: line reader -> grammar -> interpreter, with program-level rules
// (% delimiters, block delete, missing end) and diagnostics rendering.
#include "interp/program.hpp"

#include "common/diagnostic.hpp"
#include "common/status.hpp"
#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"
#include "interp/line_reader.hpp"

#include <fmt/format.h>

#include <vector>

namespace gm {

/// Reads, parses and interprets one line per step; shared by check_program and ProgramStream.
class ProgramRunner {
 public:
  ProgramRunner(std::istream& in, std::string filename, const InterpreterOptions& opts)
      : filename_(std::move(filename)),
        machine_(opts.machine ? *opts.machine : default_machine_),
        block_delete_(opts.block_delete),
        reader_(in, grammar::kMaxLineLength),
        interp_(machine_) {}

  /// Processes the next line. Appends canon to `out` and diagnostics to `diags`.
  /// Returns false when the program is over (end code, closing %, or end of input).
  bool step(std::vector<Canon>& out, std::vector<Diagnostic>& diags) {
    if (done_) return false;
    if (!reader_.next()) {
      done_ = true;
      if (!interp_.state().ended) {
        const int last = reader_.number() > 0 ? reader_.number() : 1;
        diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::MissingProgramEnd),
                                   SourceLoc{last, 1},
                                   opened_percent_ ? "missing program end: no closing '%' (or M2/M30)"
                                                   : "missing program end: the program must end with M2 or M30",
                                   last_line_});
      }
      return false;
    }
    const std::string& text = reader_.line();
    const int line = reader_.number();
    remember(text);
    if (reader_.truncated()) {
      diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::LineTooLong), SourceLoc{line, 1},
                                 fmt::format("line longer than {} bytes", grammar::kMaxLineLength), {}});
      return true;
    }
    parser_.parse(text, line, block_);
    if (block_.block_delete && block_delete_) return true;
    if (block_.has_errors()) {
      for (const auto& e : block_.errors)
        diags.push_back(Diagnostic{Severity::Error, static_cast<int>(e.code), e.loc, e.message, source_for(text)});
      first_content_seen_ = true;
      return true;
    }
    if (block_.percent) {
      if (!first_content_seen_) {
        opened_percent_ = true;
        first_content_seen_ = true;
      } else {
        out.emplace_back(Event{line, EventKind::End, {}});
        done_ = true;
        return false;
      }
    }
    if (block_.words.empty() && block_.message_count == 0) return true;
    first_content_seen_ = true;
    if (!block_.words.empty()) ++blocks_;
    InterpError err;
    if (!interp_.execute(block_, out, err)) {
      diags.push_back(Diagnostic{Severity::Error, static_cast<int>(err.code), err.loc, err.message, source_for(text)});
      return true;
    }
    if (interp_.state().ended) {
      done_ = true;
      return false;
    }
    return true;
  }

  const std::string& filename() const { return filename_; }
  const Machine& machine() const { return machine_; }
  std::int64_t blocks() const { return blocks_; }

 private:
  static std::string source_for(const std::string& text) {
    // Very long lines are not echoed under the message (the location is still exact).
    return text.size() <= 512 ? text : std::string();
  }
  void remember(const std::string& text) {
    if (text.size() <= 512) last_line_ = text;
    else last_line_.clear();
  }

  std::string filename_;
  Machine default_machine_;
  const Machine& machine_;
  bool block_delete_;
  LineReader reader_;
  grammar::BlockParser parser_;
  grammar::Block block_;
  Interpreter interp_;
  std::string last_line_;
  bool done_ = false;
  bool opened_percent_ = false;
  bool first_content_seen_ = false;
  std::int64_t blocks_ = 0;
};

namespace {

template <typename Sink>
CheckSummary run_check(std::istream& in, std::string_view filename, const InterpreterOptions& opts, Sink&& sink) {
  ProgramRunner runner(in, std::string(filename), opts);
  CheckSummary sum;
  std::vector<Canon> out;
  std::vector<Diagnostic> diags;
  bool more = true;
  while (more) {
    out.clear();
    diags.clear();
    more = runner.step(out, diags);
    for (const auto& d : diags) {
      sink(d);
      ++sum.errors;
    }
    for (const auto& c : out) {
      if (const auto* m = std::get_if<Motion>(&c)) {
        ++sum.moves;
        const double len = motion_length_mm(*m);
        sum.path_length_mm += len;
        if (m->kind == MotionKind::Rapid)
          sum.time_at_feed_s += runner.machine().rapid_mm_min > 0 ? len / runner.machine().rapid_mm_min * 60.0 : 0.0;
        else if (m->inverse_time_s > 0)
          sum.time_at_feed_s += m->inverse_time_s;
        else if (m->feed_mm_min > 0)
          sum.time_at_feed_s += len / m->feed_mm_min * 60.0;
      } else if (const auto* d = std::get_if<Dwell>(&c)) {
        sum.time_at_feed_s += d->seconds;
      }
    }
  }
  sum.blocks = runner.blocks();
  return sum;
}

}  // namespace

CheckSummary check_program(std::istream& in, std::string_view filename, const InterpreterOptions& opts,
                           std::ostream& diag_out) {
  return run_check(in, filename, opts, [&](const Diagnostic& d) { diag_out << format_diagnostic(filename, d); });
}

CheckSummary check_program_diagnostics(std::istream& in, std::string_view filename, const InterpreterOptions& opts,
                                       std::vector<Diagnostic>& diagnostics) {
  return run_check(in, filename, opts, [&](const Diagnostic& d) { diagnostics.push_back(d); });
}

ProgramStream::ProgramStream(std::istream& in, std::string filename, InterpreterOptions opts)
    : runner_(std::make_unique<ProgramRunner>(in, std::move(filename), opts)) {}

ProgramStream::~ProgramStream() = default;

bool ProgramStream::next(Canon& out) {
  while (head_ >= queue_.size()) {
    queue_.clear();
    head_ = 0;
    diags_.clear();
    const bool more = runner_->step(queue_, diags_);
    if (!diags_.empty()) {
      std::string msg;
      for (const auto& d : diags_) msg += format_diagnostic(runner_->filename(), d);
      if (!msg.empty() && msg.back() == '\n') msg.pop_back();
      throw InputError(msg);
    }
    if (!more && queue_.empty()) return false;
  }
  out = queue_[head_++];
  return true;
}

}  // namespace gm
