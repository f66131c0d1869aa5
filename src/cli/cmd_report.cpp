// gmotion report: runs a program as `run` does and writes one self-contained HTML page about it.
#include "cli/commands.hpp"
#include "cli/run_flags.hpp"
#include "common/status.hpp"
#include "report/report_collector.hpp"
#include "report/report_page.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

namespace gm::cli {
namespace {

/// Longest source line text the page shows (a program is untrusted: a line may be huge).
constexpr std::size_t kMaxLineText = 240;

struct ReportFlags {
  RunFlags run;
  std::string output;
};

/// The texts of `lines` (sorted) in the program.
std::map<int, std::string> line_texts(ProgramInput& program, const std::vector<int>& lines) {
  std::map<int, std::string> texts;
  if (lines.empty()) return texts;
  std::istream& in = program.rewind();
  std::string text;
  for (int n = 1; std::getline(in, text) && n <= lines.back(); ++n) {
    if (!std::binary_search(lines.begin(), lines.end(), n)) continue;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.size() > kMaxLineText) text = text.substr(0, kMaxLineText) + " …";
    texts.emplace(n, text);
  }
  return texts;
}

void write_page(const ReportFlags& f, ProgramInput& program, const Run& run,
                const report::ReportCollector& collector) {
  const RunConfig& cfg = run.config();
  report::PageInput in;
  in.program_name = program.name();
  in.machine_name = cfg.machine.name;
  in.profile = cfg.machine.profile;
  in.tau_s = cfg.machine.tau_s;
  in.period_s = cfg.machine.period_s;
  in.servo = cfg.servo;
  in.summary_json = run.summary().json();
  in.summary_text = run.summary().text() + run.tolerance().text();
  in.status =
      run.summary().settled ? "the program finished and the axes settled" : run.unsettled_reason();
  in.taps = &run.pipeline().taps();
  in.line_texts = line_texts(program, collector.lines());
  in.vibration = run.summary().vibration();
  const std::string page = report::render_page(collector, in);
  std::ofstream out(f.output, std::ios::binary);
  out << page;
  out.close();
  if (!out) throw InputError(fmt::format("cannot write the report '{}'", f.output));
  fmt::print(stderr, "gmotion report: wrote {} ({} kB)\n", f.output, (page.size() + 1023) / 1024);
}

}  // namespace

void add_report(CLI::App& app, Context& ctx) {
  auto flags = std::make_shared<ReportFlags>();
  auto* sub = app.add_subcommand(
      "report",
      "Run a program as `run` does and write one self-contained HTML page: the XY path coloured "
      "by contour error, errors, override and per-axis motion against time, the summary, the "
      "profile's taps and response (docs/report.md)");
  add_run_flags(sub, flags->run);
  sub->add_option("-o,--output", flags->output, "The HTML page to write")->required();
  sub->callback([flags, &ctx] {
    validate_run_flags(flags->run);
    std::unique_ptr<report::ReportCollector> collector;
    RunHooks hooks;
    hooks.started = [&collector](Run& run) {
      collector = std::make_unique<report::ReportCollector>(run.config().machine);
      run.add_sink(*collector);  // fed block by block on the run's consumer thread
    };
    hooks.finished = [&](ProgramInput& program, const Run& run) {
      write_page(*flags, program, run, *collector);
    };
    ctx.exit_code = run_with_flags(flags->run, ctx, hooks);
  });
}

}  // namespace gm::cli
