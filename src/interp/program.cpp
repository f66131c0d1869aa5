// The program driver: line reader -> grammar -> interpreter, with program-level rules
// (% delimiters, block delete, missing end) and diagnostics rendering.
#include "interp/program.hpp"
#include "interp/frame.hpp"

#include "common/batch_ring.hpp"

#include "common/diagnostic.hpp"
#include "common/status.hpp"
#include "grammar/parse.hpp"
#include "interp/codes.hpp"
#include "interp/dialect.hpp"
#include "interp/expression.hpp"
#include "interp/interpreter.hpp"
#include "interp/line_reader.hpp"
#include "interp/oword_flow.hpp"
#include "interp/parameters.hpp"
#include "interp/subroutine_path.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace gm {

/// rs274's LINELEN (255) less one: fgets filling this many bytes is LinuxCNC's "Command too long".
inline constexpr std::uint64_t kRs274LineBytes = 254;

/// One line as read and parsed: what the front half (reader + grammar) hands to the back half
/// (program rules + interpreter). Reused from line to line.
struct ParsedLine {
  int number = 0;                 ///< 1-based line number
  std::uint64_t offset = 0;       ///< byte offset of the line in the program
  std::uint64_t next_offset = 0;  ///< byte offset of the line after it
  bool truncated = false;         ///< longer than grammar::kMaxLineLength (not parsed)
  int file = 0;                   ///< 0: the program; > 0: a subroutine file
  std::string text;               ///< the line as read (diagnostics echo it)
  grammar::Block block;

  /// Gives back memory a hostile line made this slot grow (kept lines stay small).
  void trim() {
    if (text.capacity() > kKeepBytes) std::string().swap(text);
    if (block.words.capacity() > kKeepWords) std::vector<grammar::Word>().swap(block.words);
  }
  static constexpr std::size_t kKeepBytes = std::size_t{1} << 16;
  static constexpr std::size_t kKeepWords = 1024;
};

/// The front half: reads and parses lines. Holds no interpreter state, so it can run ahead on
/// another thread.
class LineParser {
 public:
  explicit LineParser(std::istream& in) : reader_(in, grammar::kMaxLineLength) {}
  /// Reads and parses the next line into `p`. False at end of input.
  bool next(ParsedLine& p) {
    if (!reader_.next(p.text)) return false;
    p.number = reader_.number();
    p.offset = reader_.line_offset();
    p.next_offset = reader_.next_offset();
    p.truncated = reader_.truncated();
    if (p.truncated) return true;
    if (!looped_) {  // a straight program: every line is parsed once
      parser_.parse(p.text, p.number, p.block);
      return true;
    }
    // Loops re-read their lines: a line parsed before (same offset, number and text) is copied
    // from the cache instead of being parsed again (the copy reuses p.block's storage).
    Cached& c = cache_[(p.offset * 0x9E3779B97F4A7C15ull) >> (64 - kCacheBits)];
    if (c.offset == p.offset && c.number == p.number && c.text == p.text) {
      p.block = c.block;
      return true;
    }
    parser_.parse(p.text, p.number, p.block);
    if (p.text.size() <= kCacheLineBytes) {
      c.offset = p.offset;
      c.number = p.number;
      c.text = p.text;
      c.block = p.block;
    }
    return true;
  }
  /// Number of the last line read (0 before the first).
  int last_number() const { return reader_.number(); }
  /// Continues at byte `offset`, the line there being numbered `line`. False if the input
  /// cannot seek. From then on parsed lines are cached.
  bool seek(std::uint64_t offset, int line) {
    if (!looped_) cache_.resize(std::size_t{1} << kCacheBits);
    looped_ = true;
    return reader_.restart(offset, line - 1);
  }

 private:
  /// 256 lines of at most 256 bytes each (LinuxCNC's own limit is 253): loop bodies fit, and a
  /// hostile program cannot make the cache hold more than about 256 × a parsed line.
  static constexpr int kCacheBits = 8;
  static constexpr std::size_t kCacheLineBytes = 256;
  struct Cached {
    std::uint64_t offset = ~std::uint64_t{0};
    int number = 0;
    std::string text;
    grammar::Block block;
  };
  LineReader reader_;
  grammar::BlockParser parser_;
  bool looped_ = false;
  std::vector<Cached> cache_;  ///< direct-mapped by offset; empty until the first seek
};

/// The subroutine files a program has called (`o<name> call` -> `name.ngc` on the path), each
/// read like the program: streamed, seeking for loops and returns. At most kMaxOpen are open at
/// once (each holds a read chunk); a file closed for room is opened again when a jump needs it.
class SubroutineFiles : public SubroutineFinder {
 public:
  static constexpr std::size_t kMaxOpen = 4;

  explicit SubroutineFiles(std::vector<std::string> dirs) : path_(std::move(dirs)) {}

  int find(const std::string& label) override {
    if (path_.empty()) return 0;
    const std::string path = path_.find(label);
    if (path.empty()) return 0;
    for (std::size_t i = 0; i < files_.size(); ++i)
      if (files_[i].path == path) return static_cast<int>(i) + 1;
    files_.push_back(File{path, nullptr, nullptr, 0});
    return static_cast<int>(files_.size());
  }
  std::string miss(const std::string& label) const override { return path_.describe_miss(label); }
  std::string file_name(int id) const override {
    return id > 0 && static_cast<std::size_t>(id) <= files_.size()
               ? files_[static_cast<std::size_t>(id) - 1].path
               : std::string();
  }

  /// The reader of file `id`, opened if needed; null if it cannot be opened.
  LineParser* parser(int id) {
    File& f = files_.at(static_cast<std::size_t>(id) - 1);
    f.used = ++clock_;
    if (f.parser) return f.parser.get();
    std::size_t open = 0;
    File* oldest = nullptr;
    for (File& g : files_)
      if (g.parser) {
        ++open;
        if (oldest == nullptr || g.used < oldest->used) oldest = &g;
      }
    if (open >= kMaxOpen && oldest != nullptr) {
      oldest->parser.reset();
      oldest->in.reset();
    }
    f.in = std::make_unique<std::ifstream>(f.path, std::ios::binary);
    if (!*f.in) {
      f.in.reset();
      return nullptr;
    }
    f.parser = std::make_unique<LineParser>(*f.in);
    return f.parser.get();
  }

 private:
  struct File {
    std::string path;
    std::unique_ptr<std::ifstream> in;
    std::unique_ptr<LineParser> parser;
    std::uint64_t used;  ///< clock_ at the last use
  };
  SubroutinePath path_;
  std::vector<File> files_;
  std::uint64_t clock_ = 0;
};

/// The predefined read-only parameters (#<_x>, #<_metric>, ..., #5420-#5428), read from the
/// interpreter's state when a program asks for them.
class StateParameters : public ParameterProvider {
 public:
  explicit StateParameters(const Interpreter& interp) : interp_(interp) {}
  void set_line(int line) { line_ = line; }

  bool predefined(std::string_view name, double& v) const override {
    const ModalState& s = interp_.state();
    const double units = s.inch ? 25.4 : 1.0;
    static constexpr std::string_view kAxisNames[] = {"_x", "_y", "_z", "_a", "_b",
                                                      "_c", "_u", "_v", "_w"};
    static constexpr std::string_view kAbsAxes[] = {
        "_abs_x", "_abs_y", "_abs_z", "_abs_a", "_abs_b", "_abs_c", "_abs_u", "_abs_v", "_abs_w"};
    for (int i = 0; i < 9; ++i) {
      if (name == kAxisNames[i]) {
        v = program_position(i);
        return true;
      }
      if (name == kAbsAxes[i]) {
        v = s.position_mm[i] / units;
        return true;
      }
    }
    struct Entry {
      std::string_view name;
      double value;
    };
    const Entry table[] = {
        {"_vmajor", 2.9},
        {"_vminor", 0.0},
        {"_line", static_cast<double>(line_)},
        {"_motion_mode", s.motion < 0 ? 800.0 : static_cast<double>(s.motion)},
        {"_plane", s.plane == Plane::XY   ? 170.0
                   : s.plane == Plane::XZ ? 180.0
                                          : 190.0},
        {"_ccomp", s.comp.side > 0   ? 410.0
                   : s.comp.side < 0 ? 420.0
                                     : 400.0},
        {"_metric", s.inch ? 0.0 : 1.0},
        {"_imperial", s.inch ? 1.0 : 0.0},
        {"_absolute", s.incremental ? 0.0 : 1.0},
        {"_incremental", s.incremental ? 1.0 : 0.0},
        {"_inverse_time", s.inverse_time ? 1.0 : 0.0},
        {"_units_per_minute", s.inverse_time || s.per_rev ? 0.0 : 1.0},
        {"_units_per_rev", s.per_rev ? 1.0 : 0.0},
        {"_coord_system",
         s.coord_system < 6 ? 540.0 + 10.0 * s.coord_system : 590.0 + (s.coord_system - 5)},
        {"_tool_offset", s.tool_offset_mm.isZero() ? 0.0 : 1.0},
        {"_retract_r_plane", s.retract_to_r ? 1.0 : 0.0},
        {"_retract_old_z", s.retract_to_r ? 0.0 : 1.0},
        {"_spindle_rpm_mode", s.css ? 0.0 : 1.0},
        {"_spindle_css_mode", s.css ? 1.0 : 0.0},
        {"_spindle_on", s.spindle_dir != 0 ? 1.0 : 0.0},
        {"_spindle_cw", s.spindle_dir > 0 ? 1.0 : 0.0},
        {"_mist", s.mist ? 1.0 : 0.0},
        {"_flood", s.flood ? 1.0 : 0.0},
        {"_speed_override", s.feed_override ? 1.0 : 0.0},
        {"_feed_override", s.feed_override ? 1.0 : 0.0},
        {"_adaptive_feed", 0.0},
        {"_feed_hold", 1.0},
        {"_ijk_absolute_mode", s.ijk_absolute ? 1.0 : 0.0},
        {"_lathe_diameter_mode", s.lathe_diameter ? 1.0 : 0.0},
        {"_lathe_radius_mode", s.lathe_diameter ? 0.0 : 1.0},
        {"_feed", s.feed_mm_min / units},
        {"_rpm", s.spindle_rpm},
        {"_current_tool", static_cast<double>(s.tool_in_spindle)},
        {"_selected_tool", static_cast<double>(s.tool_selected)},
        {"_task", 0.0},
        {"_remap_level", 0.0},
    };
    for (const Entry& e : table)
      if (e.name == name) {
        v = e.value;
        return true;
      }
    return false;
  }

  bool live(int n, double& v) const override {
    if (n >= 5420 && n <= 5428) {
      v = program_position(n - 5420);
      return true;
    }
    if (n == 5400) {
      v = interp_.state().tool_in_spindle;
      return true;
    }
    if (n > 5400 && n <= 5413) {  // the spindle's tool data (machine units, mm)
      const int tool = interp_.state().spindle_slot_tool;
      const ToolEntry* e = tool == 0 ? nullptr : interp_.tables().tools.find(tool);
      if (e == nullptr) {
        v = 0.0;
      } else if (n <= 5409) {
        v = e->offset_mm[static_cast<std::size_t>(n - 5401)];
      } else {
        v = n == 5410   ? e->diameter_mm
            : n == 5411 ? e->front_angle_deg
            : n == 5412 ? e->back_angle_deg
                        : static_cast<double>(e->orientation);
      }
      return true;
    }
    return false;
  }

 private:
  // Current position in the program's coordinate system and units (axis `i` in X..W order).
  double program_position(int i) const {
    const ModalState& s = interp_.state();
    return Frame(s).to_program(s.position_mm)[i] / (s.inch ? 25.4 : 1.0);
  }
  const Interpreter& interp_;
  int line_ = 0;
};

/// The back half: program-level rules (% delimiters, block delete, missing end) and the
/// interpreter, one parsed line at a time; shared by check_program and ProgramStream.
class ProgramRunner {
 public:
  ProgramRunner(std::string filename, const InterpreterOptions& opts)
      : filename_(std::move(filename)),
        machine_(opts.machine ? *opts.machine : default_machine_),
        block_delete_(opts.block_delete),
        interp_(machine_),
        state_params_(interp_),
        files_(opts.subroutine_path),
        flow_(params_, opts.max_iterations, &files_),
        parameter_file_(opts.parameter_file),
        dialect_(opts.dialect) {
    params_.set_provider(&state_params_);
    if (!parameter_file_.empty()) load_parameters();
    if (dialect_ == Dialect::Grbl) {  // grbl starts in G0: a first `X10` moves (rs274 refuses it)
      grammar::Block g0;
      g0.words.push_back(grammar::Word{'G', 0.0, SourceLoc{1, 1}});
      std::vector<Canon> none;
      InterpError err;
      interp_.execute(g0, none, err);
    }
  }
  ProgramRunner(const ProgramRunner&) = delete;
  ProgramRunner& operator=(const ProgramRunner&) = delete;

  /// Processes one parsed line. Appends canon to `out` and diagnostics to `diags`.
  /// Returns false when the program is over (end code or closing %).
  bool process(ParsedLine& p, std::vector<Canon>& out, std::vector<Diagnostic>& diags,
               FlowJump& jump) {
    if (start_failed(diags)) return false;
    const std::size_t first = diags.size();
    const bool more = process_line(p, out, diags, jump);
    if (p.file > 0)
      for (std::size_t i = first; i < diags.size(); ++i) diags[i].file = files_.file_name(p.file);
    return more;
  }

  SubroutineFiles& files() { return files_; }

  /// A subroutine file found on the path could not be opened when the program jumped to it.
  void cannot_open(int file, int line, int from_file, std::vector<Diagnostic>& diags) {
    diags.push_back(
        Diagnostic{Severity::Error,
                   static_cast<int>(ErrorCode::SubroutineFile),
                   SourceLoc{line, 1},
                   fmt::format("cannot read subroutine file {}", files_.file_name(file)),
                   {},
                   files_.file_name(from_file)});
    done_ = true;
  }

 private:
  bool process_line(ParsedLine& p, std::vector<Canon>& out, std::vector<Diagnostic>& diags,
                    FlowJump& jump) {
    jump.seek = false;
    if (done_) return false;
    const std::string& text = p.text;
    const int line = p.number;
    remember(text);
    // rs274 reads a line with fgets into 255 bytes and refuses one that fills 254 of them (line
    // end included), even on lines it passes over: "Command too long".
    if (dialect_ == Dialect::LinuxCNC && !p.truncated &&
        p.next_offset - p.offset >= kRs274LineBytes) {
      diags.push_back(Diagnostic{
          Severity::Error, static_cast<int>(ErrorCode::LineTooLong),
          SourceLoc{line, static_cast<int>(kRs274LineBytes) - 1},
          fmt::format("command too long: {} bytes with the line end, LinuxCNC reads at most {} "
                      "(--dialect fanuc has no such limit)",
                      p.next_offset - p.offset, kRs274LineBytes - 1),
          source_for(text)});
      return true;
    }
    if (flow_.skipping()) {  // passing over lines: only O-words matter, nothing else is checked
      InterpError err;       // a sub searched for past the closing '%' (rs274: not found)
      if (p.block.percent && opened_percent_ && p.file == 0 && !p.truncated &&
          !flow_.closing_percent(SourceLoc{line, static_cast<int>(text.find('%')) + 1}, err)) {
        diags.push_back(error_diagnostic(err, text));
        done_ = true;
        return false;
      }
      if (p.truncated || p.block.oword.kind == grammar::OKind::None) return true;
      return control(p, out, diags, jump);
    }
    if (dialect_ == Dialect::Grbl && !p.truncated && grbl_dollar_line(text)) {
      if (!dollar_warned_) {  // a grbl setting or command ($H, $$, $110=500): not G-code
        dollar_warned_ = true;
        diags.push_back(Diagnostic{Severity::Warning, 0, SourceLoc{line, 1},
                                   "grbl '$' setting and command lines are passed over (the "
                                   "first is here)",
                                   source_for(text)});
      }
      return true;
    }
    if (p.truncated) {
      diags.push_back(Diagnostic{Severity::Error,
                                 static_cast<int>(ErrorCode::LineTooLong),
                                 SourceLoc{line, 1},
                                 fmt::format("line longer than {} bytes", grammar::kMaxLineLength),
                                 {}});
      return true;
    }
    grammar::Block& block = p.block;
    // grbl passes over '/' and runs the line (protocol.c: block delete not supported)
    if (block.block_delete && block_delete_ && dialect_ != Dialect::Grbl) return true;
    if (block.percent_text && dialect_ == Dialect::Fanuc) {  // `% vfd enable`: a tape marker
      diags.push_back(Diagnostic{Severity::Warning, 0, block.errors[0].loc,
                                 "text after a '%' tape marker is passed over (--dialect fanuc)",
                                 source_for(text)});
      block.errors.clear();
    }
    if (block.has_errors()) {
      for (const auto& e : block.errors)
        diags.push_back(Diagnostic{Severity::Error, static_cast<int>(e.code), e.loc, e.message,
                                   source_for(text)});
      first_content_seen_ = true;
      return true;
    }
    if (dialect_ == Dialect::Grbl) {
      SourceLoc at;
      std::string why;
      if (!grbl_accepts(block, at, why)) {
        diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::NotInDialect), at,
                                   why + " (--dialect grbl)", source_for(text)});
        first_content_seen_ = true;
        return true;
      }
    }
    if (block.percent) {
      if (!first_content_seen_) {
        opened_percent_ = true;
        first_content_seen_ = true;
      } else {
        out.emplace_back(Event{line, EventKind::End, {}});
        done_ = true;
        return false;
      }
    }
    if (block.oword.kind == grammar::OKind::M99 && flow_.call_depth() == 0) {
      // M99 in the main program ends it as M2 does (rs274; LinuxCNC's task would loop).
      block.oword.kind = grammar::OKind::None;
      for (grammar::Word& w : block.words)
        if (w.letter == 'M' && w.value == 99.0) w.value = 2.0;
    }
    if (block.oword.kind != grammar::OKind::None) {
      first_content_seen_ = true;
      return control(p, out, diags, jump);
    }
    if (block.words.empty() && block.message_count == 0 && !block.needs_evaluation()) return true;
    first_content_seen_ = true;
    if (!block.words.empty()) ++blocks_;
    InterpError err;
    if (block.needs_evaluation()) {
      state_params_.set_line(line);
      if (!evaluator_.run(block, params_, err)) {
        diags.push_back(error_diagnostic(err, text));
        return true;
      }
      // A program that writes the offsets' parameters changes the interpreter's tables.
      for (const auto& [n, v] : params_.system_writes()) interp_.write_system_parameter(n, v);
      params_.clear_system_writes();
      for (std::size_t i = 0; i < block.directive_count; ++i)
        if (!directive(block.directives[i], text, diags)) return false;
      if (block.words.empty() && block.message_count == 0) return true;
    }
    if (dialect_ == Dialect::Fanuc && !fanuc_machine_codes(block, text, diags)) return true;
    if (g7x_base_ >= 0 && flow_.call_depth() > g7x_base_) {  // a G7x profile: read, not run
      if (!interp_.g7x_collect(block, err)) diags.push_back(error_diagnostic(err, text));
      return true;
    }
    if (!interp_.execute(block, out, err)) {
      diags.push_back(error_diagnostic(err, text));
      return true;
    }
    export_system_parameters();
    if (interp_.g7x_pending() && !start_g7x(p, diags, jump)) return false;
    if (interp_.state().input_waits != input_waits_seen_) {  // M66: #5399
      input_waits_seen_ = interp_.state().input_waits;
      params_.set_system(5399, interp_.state().input_result);
    }
    if (interp_.state().probes != probes_seen_) {  // G38.x: #5061-#5069 result, #5070 tripped
      probes_seen_ = interp_.state().probes;
      for (int i = 0; i < 9; ++i)
        params_.set_system(5061 + i, interp_.state().probe_result[static_cast<std::size_t>(i)]);
      params_.set_system(5070, 0.0);
    }
    if (interp_.state().ended) {
      done_ = true;
      return false;
    }
    return true;
  }

 public:
  /// The input (file `file`) ended after line `last_line` (0: empty input): reports a missing
  /// program end.
  void end_of_input(int last_line, std::vector<Diagnostic>& diags, int file = 0) {
    if (start_failed(diags) || done_) return;
    done_ = true;
    InterpError err;
    int err_file = 0;
    if (!flow_.at_end(last_line, err, err_file)) {
      diags.push_back(Diagnostic{Severity::Error,
                                 static_cast<int>(err.code),
                                 err.loc,
                                 err.message,
                                 {},
                                 files_.file_name(err_file)});
      return;
    }
    if (!interp_.state().ended && dialect_ == Dialect::Grbl) return;  // grbl streams: no end
    if (!interp_.state().ended && dialect_ == Dialect::Fanuc) {
      diags.push_back(Diagnostic{Severity::Warning, 0, SourceLoc{last_line > 0 ? last_line : 1, 1},
                                 "the program ends without M2/M30 (ended here, --dialect fanuc)",
                                 last_line_, files_.file_name(file)});
      return;
    }
    if (!interp_.state().ended) {
      const int last = last_line > 0 ? last_line : 1;
      diags.push_back(Diagnostic{
          Severity::Error, static_cast<int>(ErrorCode::MissingProgramEnd), SourceLoc{last, 1},
          opened_percent_ ? "missing program end: no closing '%' (or M2/M30)"
                          : "missing program end: the program must end with M2 or M30",
          last_line_, files_.file_name(file)});
    }
  }

  bool done() const { return done_; }

  /// Writes the parameters to the parameter file (if one is named and it was read), once.
  void save_parameters(std::vector<Diagnostic>& diags) {
    if (parameter_file_.empty() || !parameters_loaded_ || parameters_saved_) return;
    parameters_saved_ = true;
    export_system_parameters();
    std::string error;
    if (!params_.save_var_file(parameter_file_, error))
      diags.push_back(Diagnostic{Severity::Error,
                                 static_cast<int>(ErrorCode::ParameterFile),
                                 SourceLoc{1, 1},
                                 error,
                                 {},
                                 parameter_file_});
  }
  const std::string& filename() const { return filename_; }
  const ParameterStore& parameters() const { return params_; }
  const Machine& machine() const { return machine_; }
  std::int64_t blocks() const { return blocks_; }

 private:
  /// An interpreter error on the line whose text is `text`, as a diagnostic.
  static Diagnostic error_diagnostic(const InterpError& err, const std::string& text) {
    return Diagnostic{Severity::Error, static_cast<int>(err.code), err.loc, err.message,
                      source_for(text)};
  }
  static std::string source_for(const std::string& text) {
    // Very long lines are not echoed under the message (the location is still exact).
    return text.size() <= 512 ? text : std::string();
  }
  // An O-word line: control flow. An error there ends the program (the flow state is lost).
  bool control(ParsedLine& p, std::vector<Canon>& out, std::vector<Diagnostic>& diags,
               FlowJump& jump) {
    state_params_.set_line(p.number);
    InterpError err;
    const int depth = flow_.call_depth();
    const grammar::OKind kind = p.block.oword.kind;
    if ((kind == grammar::OKind::M98 || kind == grammar::OKind::M99) && !flow_.skipping() &&
        p.block.needs_evaluation() && !evaluator_.run(p.block, params_, err)) {
      diags.push_back(error_diagnostic(err, p.text));
      done_ = true;
      jump.seek = false;
      return false;
    }
    bool ok = flow_.handle(p.block, LinePos{p.offset, p.next_offset, p.number, p.file}, jump, err);
    // The interpreter keeps M70/M73 modes per call level (machine's, interp/saved_modes.cpp).
    if (ok && flow_.call_depth() > depth) interp_.enter_call(flow_.call_depth());
    if (ok && flow_.call_depth() < depth) ok = interp_.leave_call(depth, p.number, out, err);
    if (ok && g7x_base_ >= 0 && flow_.call_depth() == g7x_base_ && depth > g7x_base_) {
      g7x_base_ = -1;  // the profile subroutine returned: the cycle runs
      if (!interp_.g7x_finish(p.number, out, err)) {
        diags.push_back(error_diagnostic(err, p.text));
        return true;
      }
    }
    if (!ok) {
      diags.push_back(error_diagnostic(err, p.text));
      done_ = true;
      jump.seek = false;
      return false;
    }
    return true;
  }

  // A G70-G72 line ran: its profile subroutine is called as `O<q> call` from that line, and its
  // blocks are read (process_line) until it returns (control).
  bool start_g7x(ParsedLine& p, std::vector<Diagnostic>& diags, FlowJump& jump) {
    grammar::Block call;
    call.line = p.number;
    call.oword.kind = grammar::OKind::Call;
    call.oword.label = interp_.g7x().label;
    call.oword.loc = interp_.g7x().loc;
    interp_.g7x_started();
    const int depth = flow_.call_depth();
    g7x_base_ = depth;
    InterpError err;
    bool ok = flow_.handle(call, LinePos{p.offset, p.next_offset, p.number, p.file}, jump, err);
    if (ok && flow_.call_depth() > depth) interp_.enter_call(flow_.call_depth());
    if (!ok) {
      g7x_base_ = -1;
      diags.push_back(error_diagnostic(err, p.text));
      done_ = true;
      jump.seek = false;
      return false;
    }
    return true;
  }

 public:
  /// The driver could not seek where the control flow asked (the input is a pipe).
  void cannot_seek(int line, std::vector<Diagnostic>& diags) {
    diags.push_back(Diagnostic{
        Severity::Error,
        static_cast<int>(ErrorCode::NotSeekable),
        SourceLoc{line, 1},
        "loops and subroutine calls re-read the program, which cannot seek here (a pipe?): "
        "give it as a file",
        {}});
    done_ = true;
  }

 private:
  // ABORT ends the program with a located error; LOG comments write nothing (no log directory
  // is configured), LOGOPEN/LOGAPPEND say so once. False when the program is over.
  bool directive(const grammar::Message& m, const std::string& text,
                 std::vector<Diagnostic>& diags) {
    using grammar::CommentKind;
    if (m.kind == CommentKind::Abort) {
      diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::CommentAbort), m.loc,
                                 fmt::format("program aborted: {}", m.text), source_for(text)});
      done_ = true;
      aborted_ = true;
      return false;
    }
    if ((m.kind == CommentKind::LogOpen || m.kind == CommentKind::LogAppend) && !log_warned_) {
      log_warned_ = true;
      diags.push_back(Diagnostic{Severity::Warning, 0, m.loc,
                                 fmt::format("log file '{}' not written: no log directory is "
                                             "allowed (LOG comments are ignored)",
                                             m.text),
                                 source_for(text)});
    }
    return true;
  }
  void remember(const std::string& text) {
    if (text.size() <= 512)
      last_line_ = text;
    else
      last_line_.clear();
  }

  std::string filename_;
  Machine default_machine_;
  const Machine& machine_;
  bool block_delete_;
  Interpreter interp_;
  StateParameters state_params_;
  ParameterStore params_;
  LineEvaluator evaluator_;
  SubroutineFiles files_;
  OwordFlow flow_;
  std::string last_line_;
  bool aborted_ = false;
  bool log_warned_ = false;
  bool done_ = false;
  bool opened_percent_ = false;
  int probes_seen_ = 0;
  int g7x_base_ = -1;  ///< G70-G72: the call depth of the cycle's line while its profile is read
  int input_waits_seen_ = 0;
  std::uint64_t tables_seen_ = 1;  // the tables as the interpreter starts: left to the store

  // The interpreter's system parameters in machine units (mm): G28 #5161-#5169, G30
  // #5181-#5189, G92 #5210-#5219, the coordinate system #5220, G54..G59.3 #5221+20k (machine's;
  // a program that writes them does not move the interpreter's offsets yet).
  void export_system_parameters() {
    const ModalState& s = interp_.state();
    params_.set_system(5210, s.g92_applied ? 1.0 : 0.0);
    params_.set_system(5220, static_cast<double>(s.coord_system + 1));
    if (interp_.tables_version() == tables_seen_) return;
    tables_seen_ = interp_.tables_version();
    const SystemTables& t = interp_.tables();
    for (int i = 0; i < 9; ++i) {
      params_.set_system(5161 + i, t.g28_mm[i]);
      params_.set_system(5181 + i, t.g30_mm[i]);
      params_.set_system(5211 + i, t.g92_saved_mm[i]);
      for (int k = 0; k < 9; ++k)
        params_.set_system(5221 + 20 * k + i, t.g5x_mm[static_cast<std::size_t>(k)][i]);
    }
    for (int k = 0; k < 9; ++k)
      params_.set_system(5230 + 20 * k, t.g5x_rotation_deg[static_cast<std::size_t>(k)]);
  }
  bool first_content_seen_ = false;
  std::int64_t blocks_ = 0;

  // The parameter file: read before the first line (its offsets apply, LinuxCNC Interp::init);
  // an error there is reported with the first line processed and stops the program.
  void load_parameters() {
    Diagnostic d;
    if (!params_.load_var_file(parameter_file_, d)) {
      start_error_.push_back(std::move(d));
      return;
    }
    parameters_loaded_ = true;
    interp_.restore_system_parameters([this](int n) { return params_.get(n); });
    export_system_parameters();
  }
  bool start_failed(std::vector<Diagnostic>& diags) {
    if (start_error_.empty()) return false;
    for (Diagnostic& d : start_error_) diags.push_back(std::move(d));
    start_error_.clear();
    done_ = true;
    return true;
  }
  // --dialect fanuc: M codes of Fanuc/Haas machines that LinuxCNC does not have (M19 orient,
  // M31 chip conveyor, M88 through-spindle coolant, ...) are passed over with one warning per
  // code; M97 (Haas local subprogram call) is refused. False when nothing is left to execute.
  bool fanuc_machine_codes(grammar::Block& block, const std::string& text,
                           std::vector<Diagnostic>& diags) {
    auto& words = block.words;
    for (std::size_t i = 0; i < words.size();) {
      const grammar::Word& w = words[i];
      const long m = std::lround(w.value);
      if (w.letter != 'M' || std::abs(w.value - static_cast<double>(m)) > 1e-6 || m < 0 || m > 99 ||
          find_code('M', static_cast<int>(10 * m)) != nullptr) {
        ++i;
        continue;
      }
      if (m == 97) {
        diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::NotInDialect),
                                   w.loc,
                                   "M97 (Haas local subprogram call to line N) is not supported: "
                                   "use M98 with an O-numbered subprogram",
                                   source_for(text)});
        return false;
      }
      if (m < static_cast<long>(fanuc_warned_.size()) &&
          !fanuc_warned_[static_cast<std::size_t>(m)]) {
        fanuc_warned_[static_cast<std::size_t>(m)] = true;
        diags.push_back(Diagnostic{Severity::Warning, 0, w.loc,
                                   fmt::format("M{} is a machine function LinuxCNC does not have: "
                                               "passed over (--dialect fanuc; warned once)",
                                               m),
                                   source_for(text)});
      }
      words.erase(words.begin() + static_cast<std::ptrdiff_t>(i));
    }
    return !(words.empty() && block.message_count == 0);
  }

  std::string parameter_file_;
  Dialect dialect_;
  bool dollar_warned_ = false;
  std::array<bool, 100> fanuc_warned_{};
  std::vector<Diagnostic> start_error_;
  bool parameters_loaded_ = false;
  bool parameters_saved_ = false;
};

/// Where the serial driver reads: the program, or a subroutine file after a call jumped there.
class LineSource {
 public:
  LineSource(LineParser& program, ProgramRunner& back) : program_(program), back_(back) {}
  /// The next line of the current file (tagged with it). False at its end.
  bool next(ParsedLine& p) {
    if (!current().next(p)) return false;
    p.file = file_;
    return true;
  }
  int last_number() { return current().last_number(); }
  int file() const { return file_; }
  /// Continues where `jump` says; false (with the error reported) if that is impossible.
  bool go(const FlowJump& jump, int from_line, std::vector<Diagnostic>& diags) {
    LineParser* target = &program_;
    if (jump.file > 0) target = back_.files().parser(jump.file);
    if (target == nullptr) {
      back_.cannot_open(jump.file, from_line, file_, diags);
      return false;
    }
    const int from_file = file_;
    file_ = jump.file;
    if (!target->seek(jump.offset, jump.line)) {
      back_.cannot_seek(from_line, diags);
      if (from_file > 0) diags.back().file = back_.files().file_name(from_file);
      return false;
    }
    return true;
  }

 private:
  LineParser& current() {
    if (file_ == 0) return program_;
    LineParser* p = back_.files().parser(file_);  // open: go() opened it
    return p != nullptr ? *p : program_;
  }
  LineParser& program_;
  ProgramRunner& back_;
  int file_ = 0;
};

/// Reading and parsing on a second thread, in batches, ahead of the interpreter on this one.
/// Same diagnostics, in the same order, and the same summary as the serial check: the front
/// half has no state the back half changes. A batch closes at kBatchLines lines or kBatchBytes
/// bytes of text, so at most kBatches batches of bounded size are in memory. The hand-over is
/// the run's own queue type, BatchRing.
class ParallelFront {
 public:
  static constexpr std::size_t kBatches = 3;
  static constexpr std::size_t kBatchLines = 1024;
  static constexpr std::size_t kBatchBytes = std::size_t{1} << 20;

  struct Batch {
    std::vector<ParsedLine> lines = std::vector<ParsedLine>(kBatchLines);
    std::size_t count = 0;
    bool eof = false;     ///< the input ends after these lines
    int last_number = 0;  ///< with eof: the last line number read
  };

  explicit ParallelFront(std::istream& in) : front_(in), thread_([this] { produce(); }) {}
  ~ParallelFront() {
    ring_.stop();
    thread_.join();
  }
  ParallelFront(const ParallelFront&) = delete;
  ParallelFront& operator=(const ParallelFront&) = delete;

  /// Waits for the next batch; rethrows what the reader thread threw. The consumer stops
  /// asking after the batch marked eof, so a batch always comes.
  Batch& acquire() {
    taken_ = ring_.begin_take();
    return *taken_;
  }
  /// Hands the batch returned by acquire() back for refilling.
  void release() {
    for (std::size_t i = 0; i < taken_->count; ++i) taken_->lines[i].trim();
    ring_.end_take();
  }

 private:
  void produce() {
    try {
      while (Batch* b = ring_.begin_fill()) {
        fill(*b);
        const bool eof = b->eof;
        ring_.end_fill();
        if (eof) return;
      }
    } catch (...) {
      ring_.fail(std::current_exception());
    }
  }
  void fill(Batch& b) {
    b.count = 0;
    b.eof = false;
    std::size_t bytes = 0;
    while (b.count < kBatchLines && bytes < kBatchBytes) {
      ParsedLine& p = b.lines[b.count];
      if (!front_.next(p)) {
        b.eof = true;
        b.last_number = front_.last_number();
        return;
      }
      bytes += p.text.size();
      ++b.count;
    }
  }

  LineParser front_;
  BatchRing<Batch, kBatches> ring_;
  Batch* taken_ = nullptr;  ///< the consumer's batch between acquire() and release()
  std::thread thread_;      ///< last: starts once everything above is constructed
};

/// Both halves, what ProgramStream pulls a line at a time: on one thread, or with read-ahead
/// (InterpreterOptions::read_ahead) the lines read and parsed on a second thread (ParallelFront)
/// until the program first jumps (a loop or a call re-reads it: the reader stops and the rest is
/// read here, seeking as asked). The same lines reach the interpreter either way.
class SerialRunner {
 public:
  SerialRunner(std::istream& in, std::string filename, const InterpreterOptions& opts)
      : front_(in), back_(std::move(filename), opts), source_(front_, back_) {
    if (opts.read_ahead) ahead_ = std::make_unique<ParallelFront>(in);  // front_ reads nothing yet
  }
  /// Reads, parses and interprets one line; false when the program is over.
  bool step(std::vector<Canon>& out, std::vector<Diagnostic>& diags) {
    if (back_.done()) return false;
    if (ahead_) return step_ahead(out, diags);
    if (!source_.next(line_)) {
      back_.end_of_input(source_.last_number(), diags, source_.file());
      return false;
    }
    FlowJump jump;
    const bool more = back_.process(line_, out, diags, jump);
    const int number = line_.number;
    line_.trim();
    if (more && jump.seek && !source_.go(jump, number, diags)) return false;
    return more;
  }
  const ProgramRunner& back() const { return back_; }
  /// The program is over: writes the parameter file (once).
  void finish(std::vector<Diagnostic>& diags) { back_.save_parameters(diags); }

 private:
  /// step() on the reader thread's lines (file 0, the program).
  bool step_ahead(std::vector<Canon>& out, std::vector<Diagnostic>& diags) {
    if (batch_ == nullptr || next_ == batch_->count) {
      if (batch_ == nullptr || !batch_->eof) {  // (a released batch is the reader's again)
        if (batch_ != nullptr) ahead_->release();
        batch_ = &ahead_->acquire();
        next_ = 0;
      }
      if (next_ == batch_->count) {  // the input ended after the lines handed out
        const int last = batch_->last_number;
        batch_ = nullptr;
        ahead_.reset();
        back_.end_of_input(last, diags);
        return false;
      }
    }
    ParsedLine& p = batch_->lines[next_++];
    FlowJump jump;
    const bool more = back_.process(p, out, diags, jump);
    if (more && jump.seek) {
      const int number = p.number;
      batch_ = nullptr;
      ahead_.reset();  // the reader stops; its batches are dropped
      return source_.go(jump, number, diags);
    }
    return more;
  }

  LineParser front_;
  ProgramRunner back_;
  LineSource source_;
  ParsedLine line_;
  std::unique_ptr<ParallelFront> ahead_;   ///< read-ahead until the first jump, else null
  ParallelFront::Batch* batch_ = nullptr;  ///< the batch being interpreted
  std::size_t next_ = 0;                   ///< its next line
};

namespace {

// Adds what `out` holds to the summary's counts.
void account(const std::vector<Canon>& out, const Machine& machine, CheckSummary& sum) {
  for (const auto& c : out) {
    if (const auto* m = std::get_if<Motion>(&c)) {
      ++sum.moves;
      const double len = motion_length_mm(*m);
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
/// diagnostics and the errors are counted (what a run needs before it starts).
template <bool Summarise = true, typename Sink>
CheckSummary run_check(std::istream& in, std::string_view filename, const InterpreterOptions& opts,
                       CheckThreads threads, Sink&& sink) {
  CheckSummary sum;
  std::vector<Canon> out;
  std::vector<Diagnostic> diags;
  auto emit = [&](const Machine& machine) {
    for (const auto& d : diags) {
      sink(d);
      if (d.severity == Severity::Error) ++sum.errors;
    }
    if constexpr (Summarise) account(out, machine, sum);
    out.clear();
    diags.clear();
  };
  if (threads == CheckThreads::Single || std::thread::hardware_concurrency() < 2) {
    SerialRunner runner(in, std::string(filename), opts);
    bool more = true;
    while (more) {
      more = runner.step(out, diags);
      emit(runner.back().machine());
    }
    sum.blocks = runner.back().blocks();
    return sum;
  }
  ProgramRunner back(std::string(filename), opts);
  FlowJump jump;
  int jump_from = 0;
  {
    ParallelFront front(in);
    while (!back.done() && !jump.seek) {
      ParallelFront::Batch& b = front.acquire();
      for (std::size_t i = 0; i < b.count && !back.done() && !jump.seek; ++i) {
        back.process(b.lines[i], out, diags, jump);
        jump_from = b.lines[i].number;
        emit(back.machine());
      }
      if (b.eof && !back.done() && !jump.seek) {
        back.end_of_input(b.last_number, diags);
        emit(back.machine());
      }
      front.release();
    }
  }
  if (jump.seek && !back.done()) {
    // Control flow re-reads the program: the rest runs on this thread, seeking as asked.
    LineParser serial(in);
    LineSource source(serial, back);
    ParsedLine line;
    bool ok = source.go(jump, jump_from, diags);
    while (ok && !back.done()) {
      if (!source.next(line)) {
        back.end_of_input(source.last_number(), diags, source.file());
        emit(back.machine());
        break;
      }
      const bool more = back.process(line, out, diags, jump);
      line.trim();
      if (more && jump.seek && !source.go(jump, line.number, diags)) ok = false;
      emit(back.machine());
    }
    emit(back.machine());
  }
  sum.blocks = back.blocks();
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

ProgramStream::ProgramStream(std::istream& in, std::string filename, InterpreterOptions opts)
    : runner_(std::make_unique<SerialRunner>(in, std::move(filename), opts)),
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
