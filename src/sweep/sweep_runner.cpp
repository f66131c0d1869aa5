// Sweep execution: a thread pool over the runs (as golden verify's), or commands for a scheduler.
#include "sweep/sweep_runner.hpp"

#include "common/status.hpp"
#include "pipeline/run.hpp"
#include "setup/program_input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

namespace gm::sweep {
namespace {

std::string shell_quote(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                        "0123456789_-./:=@%+,") == std::string::npos)
    return s;
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

SweepRow run_one(const SweepSpec& s, const RunPoint& r) {
  Machine m = run_machine(s, r);
  SweepRow row = row_setup(s, r, m);
  try {
    const setup::RunSettings settings = run_settings(s, r);
    RunOptions o = setup::run_options(settings, m);
    setup::ProgramInput program(s.programs[r.program]);
    // The machine's language keys apply as in `run`; its parameter file is read, never written
    // (the runs are parallel).
    const InterpreterOptions opts = setup::interpreter_options(settings, o.config.machine);
    std::ostringstream diag;
    const CheckSummary chk =
        check_program(program.rewind(), program.name(), opts, diag, CheckThreads::Single);
    if (chk.errors > 0) {
      std::string text = diag.str();
      throw InputError(text.substr(0, text.find('\n')));
    }
    o.program_name = program.name();
    o.consumer_thread = false;  // the runs themselves fill the cores
    Run run(std::move(o), program.rewind(), opts);
    RunStatus st;
    while ((st = run.advance()) == RunStatus::Working) {
    }
    fill_from_summary(row, run.summary(), m);
    if (st != RunStatus::Finished) row.status = "unsettled", row.error = run.unsettled_reason();
  } catch (const std::exception& e) {
    row.status = "error";
    row.error = e.what();
  }
  return row;
}

}  // namespace

Machine run_machine(const SweepSpec& s, const RunPoint& r) {
  Machine m = s.machines[r.machine].machine;
  if (const auto& p = s.profiles[r.profile]) m.profile = *p;
  if (const auto& t = s.taus_s[r.tau]) m.tau_s = *t;
  return m;
}

setup::RunSettings run_settings(const SweepSpec& s, const RunPoint& r) {
  setup::RunSettings settings = s.settings;
  settings.machine_file = s.machines[r.machine].file;
  settings.profile = s.profiles[r.profile];
  settings.tau_s = s.taus_s[r.tau];
  const OverrideChoice& ov = s.overrides[r.override_];
  settings.override_pct = ov.percent;
  settings.override_file = ov.schedule;
  settings.no_servo = !s.servo;
  settings.max_time_s = s.max_time_s;
  return settings;
}

std::vector<SweepRow> run_local(const SweepSpec& s, int jobs,
                                const std::function<void(const SweepRow&)>& done) {
  const std::vector<RunPoint> points = expand(s);
  std::vector<std::optional<SweepRow>> results(points.size());
  std::mutex mu;
  std::condition_variable cv;
  std::atomic<std::size_t> next{0};
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const int want = jobs > 0 ? jobs : s.jobs > 0 ? s.jobs : static_cast<int>(cores);
  const std::size_t n_threads =
      std::min<std::size_t>(points.size(), static_cast<std::size_t>(want));
  auto loop = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < points.size();) {
      SweepRow row = run_one(s, points[i]);
      const std::lock_guard<std::mutex> lock(mu);
      results[i] = std::move(row);
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t j = 0; n_threads > 1 && j < n_threads; ++j) pool.emplace_back(loop);
  if (n_threads <= 1) loop();
  std::vector<SweepRow> rows;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::unique_lock<std::mutex> lock(mu);
    cv.wait(lock, [&] { return results[i].has_value(); });
    SweepRow row = std::move(*results[i]);
    lock.unlock();
    if (done) done(row);
    rows.push_back(std::move(row));
  }
  for (std::thread& t : pool) t.join();
  return rows;
}

std::string summary_path(const std::string& out_dir, const RunPoint& r) {
  return fmt::format("{}/run-{:05}.json", out_dir, r.index);
}

std::string run_command(const SweepSpec& s, const RunPoint& r, const std::string& gmotion,
                        const std::string& out_dir) {
  const Machine m = run_machine(s, r);
  std::string c = shell_quote(gmotion) + " run " + shell_quote(s.programs[r.program]);
  if (!s.machines[r.machine].file.empty())
    c += " --machine " + shell_quote(s.machines[r.machine].file);
  c += " --profile " + shell_quote(m.profile) + fmt::format(" --tau {}", m.tau_s);
  const OverrideChoice& ov = s.overrides[r.override_];
  if (ov.schedule.empty())
    c += fmt::format(" --override {}", ov.percent);
  else
    c += " --override-file " + shell_quote(ov.schedule);
  if (!s.servo) c += " --no-servo";
  c += fmt::format(" --max-time {}", s.max_time_s);
  for (const std::string& word : setup::flags_of(s.settings)) c += " " + shell_quote(word);
  c += " --summary-json " + shell_quote(summary_path(out_dir, r)) + " >/dev/null";
  return c;
}

std::vector<SweepRow> merge(const SweepSpec& s, const std::string& out_dir) {
  std::vector<SweepRow> rows;
  for (const RunPoint& r : expand(s)) {
    const Machine m = run_machine(s, r);
    SweepRow row = row_setup(s, r, m);
    std::ifstream in(summary_path(out_dir, r), std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in || !fill_from_summary_json(row, text.str(), m)) {
      row.status = "missing";
      row.error = fmt::format("no summary at {}", summary_path(out_dir, r));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace gm::sweep
