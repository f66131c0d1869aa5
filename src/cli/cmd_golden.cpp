// gmotion golden record|verify SUITE: golden trace tests over a suite of programs (src/golden/).
#include "cli/commands.hpp"
#include "common/status.hpp"
#include "golden/case_run.hpp"
#include "golden/golden_runner.hpp"
#include "golden/junit.hpp"
#include "golden/suite.hpp"
#include "setup/run_settings.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace gm::cli {
namespace {

struct GoldenFlags {
  std::string suite;
  std::string junit;
  std::string pictures;
  bool update = false;
  int jobs = 0;
  std::vector<std::string> cases;
};

void print_result(const golden::CaseResult& r) {
  fmt::print("{:<9} {}{}{}\n", golden::outcome_word(r.outcome), r.name,
             r.headline.empty()                   ? ""
             : r.outcome == golden::Outcome::Pass ? " "
                                                  : ": ",
             r.headline);
  for (const std::string& d : r.details) {
    std::size_t a = 0;
    while (a <= d.size()) {  // a multi-line detail (program errors) keeps its indent
      std::size_t b = d.find('\n', a);
      if (b == std::string::npos) b = d.size();
      fmt::print("          {}\n", d.substr(a, b - a));
      a = b + 1;
    }
  }
  std::fflush(stdout);
}

int golden_cmd(golden::Mode mode, const GoldenFlags& f) {
  const auto t0 = std::chrono::steady_clock::now();
  const golden::Suite suite = golden::load_suite(f.suite);
  golden::RunnerOptions o;
  o.mode = mode;
  o.jobs = f.jobs;
  o.only = f.cases;
  o.pictures_dir = f.pictures;
  const std::vector<golden::CaseResult> results = golden::run_suite(suite, o, print_result);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int counts[6] = {};
  for (const golden::CaseResult& r : results) ++counts[static_cast<int>(r.outcome)];
  using golden::Outcome;
  auto n = [&](Outcome x) { return counts[static_cast<int>(x)]; };
  if (mode == golden::Mode::Verify)
    fmt::print("{} case{}: {} passed, {} failed, {} errors\n", results.size(),
               results.size() == 1 ? "" : "s", n(Outcome::Pass), n(Outcome::Fail),
               n(Outcome::Error));
  else
    fmt::print("{} case{}: {} recorded, {} changed, {} unchanged, {} errors (goldens in {})\n",
               results.size(), results.size() == 1 ? "" : "s", n(Outcome::Recorded),
               n(Outcome::Changed), n(Outcome::Unchanged), n(Outcome::Error), suite.store.string());
  std::fflush(stdout);
  fmt::print(stderr, "gmotion golden: {} cases in {:.2f} s\n", results.size(), seconds);
  if (!f.junit.empty()) {
    std::ofstream x(f.junit, std::ios::trunc);
    x << golden::junit_xml(suite.name, results, seconds);
    if (!x) throw InputError(fmt::format("cannot write --junit '{}'", f.junit));
  }
  const bool failed = n(Outcome::Fail) + n(Outcome::Error) > 0;
  return failed ? static_cast<int>(ExitCode::InputError) : 0;
}

void add_common(CLI::App* sub, GoldenFlags& f) {
  sub->add_option("suite", f.suite,
                  "Suite folder: suite.toml with [[case]] entries, or a folder of programs")
      ->required();
  sub->add_option("-j,--jobs", f.jobs, "Cases run at once (default: every core)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--case", f.cases, "Only the cases of this name (glob; repeatable)");
}

}  // namespace

void add_golden(CLI::App& app, Context& ctx) {
  auto* g =
      app.add_subcommand("golden", "Golden trace tests over a suite: record, then verify in CI");
  g->require_subcommand(1);
  g->footer(fmt::format(
      "A case's `flags` in suite.toml takes these `gmotion run` flags: {}.\nSee docs/golden.md.",
      setup::flag_names()));

  auto rec = std::make_shared<GoldenFlags>();
  auto* r = g->add_subcommand(
      "record",
      "Run every case and store its trace (binary, zstd), summary, gmotion version and "
      "set-up hash; a run that does not complete is refused");
  add_common(r, *rec);
  r->callback([rec, &ctx] { ctx.exit_code = golden_cmd(golden::Mode::Record, *rec); });

  auto ver = std::make_shared<GoldenFlags>();
  auto* v = g->add_subcommand(
      "verify",
      "Run every case again and compare with its golden: one line per case, the first "
      "divergence and the largest difference per column of each failure");
  add_common(v, *ver);
  v->add_option("--junit", ver->junit, "Write the results as JUnit XML to this file");
  v->add_option("--pictures", ver->pictures,
                "Draw each divergence as DIR/CASE.png (paths around it, difference vs time)");
  v->add_flag(
      "--update", ver->update,
      "Re-record the cases that changed (after a deliberate change) and print what changed");
  v->footer(
      "Exit 0 when every case passes, 1 otherwise (with --update: 1 only when a case could "
      "not run).");
  v->callback([ver, &ctx] {
    ctx.exit_code = golden_cmd(ver->update ? golden::Mode::Update : golden::Mode::Verify, *ver);
  });
}

}  // namespace gm::cli
