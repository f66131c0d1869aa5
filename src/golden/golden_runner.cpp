// The suite engine: a pool of threads over the cases, each case run, compared and reported.
#include "golden/golden_runner.hpp"

#include "common/status.hpp"
#include "golden/case_run.hpp"
#include "golden/divergence_plot.hpp"
#include "golden/golden_store.hpp"
#include "golden/trace_compare.hpp"
#include "trace/trace_reader.hpp"

#include <fmt/format.h>

#include <stdlib.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

namespace gm::golden {
namespace {

namespace fs = std::filesystem;

// A private temporary folder, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string tmpl =
        std::string(base != nullptr && *base != '\0' ? base : "/tmp") + "/gmotion-golden-XXXXXX";
    if (mkdtemp(tmpl.data()) == nullptr)
      throw InputError(fmt::format("cannot create a temporary folder '{}'", tmpl));
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// "key = value" lines grouped by their "[section]" header.
std::map<std::string, std::string> setup_keys(const std::string& text) {
  std::map<std::string, std::string> keys;
  std::string section;
  std::size_t a = 0;
  while (a < text.size()) {
    std::size_t b = text.find('\n', a);
    if (b == std::string::npos) b = text.size();
    const std::string line = text.substr(a, b - a);
    a = b + 1;
    if (line.empty() || line[0] == '#') continue;
    if (line[0] == '[') {
      section = line;
      continue;
    }
    const std::size_t eq = line.find(" = ");
    const std::string key = eq == std::string::npos ? line : line.substr(0, eq);
    keys[section.empty() ? key : section + " " + key] =
        eq == std::string::npos ? "" : line.substr(eq + 3);
  }
  return keys;
}

// The first field in which two summary JSON texts differ.
std::string summary_difference(const std::string& before, const std::string& after) {
  auto fields = [](const std::string& s) {
    std::vector<std::string> out;
    std::size_t a = 0;
    while (a <= s.size()) {
      std::size_t b = s.find(',', a);
      if (b == std::string::npos) b = s.size();
      out.push_back(s.substr(a, b - a));
      a = b + 1;
    }
    return out;
  };
  const std::vector<std::string> x = fields(before), y = fields(after);
  for (std::size_t i = 0; i < std::max(x.size(), y.size()); ++i) {
    const std::string u = i < x.size() ? x[i] : "(nothing)", v = i < y.size() ? y[i] : "(nothing)";
    if (u != v) return fmt::format("golden {}, now {}", u, v);
  }
  return "whitespace";
}

struct Worker {
  const Suite& suite;
  const RunnerOptions& opt;
  const fs::path& tmp;

  CaseResult run(std::size_t index, const GoldenCase& c) const {
    CaseResult r;
    r.name = c.name;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      body(index, c, r);
    } catch (const std::exception& e) {
      r.outcome = Outcome::Error;
      r.kind = "run";
      r.headline = e.what();
    }
    std::error_code ec;
    fs::remove(tmp / fmt::format("{}.bin", index), ec);
    fs::remove(tmp / fmt::format("{}.golden.bin", index), ec);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }

  void body(std::size_t index, const GoldenCase& c, CaseResult& r) const {
    const std::string fresh_path = (tmp / fmt::format("{}.bin", index)).string();
    std::optional<StoredCase> stored;
    if (opt.mode != Mode::Record) stored = read_stored(suite.store, c.name);
    if (opt.mode == Mode::Verify && !stored) {
      r.outcome = Outcome::Error;
      r.kind = "missing";
      r.headline = fmt::format("no golden recorded in {} (run `gmotion golden record {}`)",
                               suite.store.string(), suite.dir.string());
      return;
    }
    const CaseOutput out = run_case(suite, c, fresh_path);
    if (!out.complete) {
      r.outcome = Outcome::Error;
      r.kind = "run";
      const std::size_t nl = out.error.find('\n');
      r.headline = fmt::format("the run did not complete{}: {}",
                               opt.mode == Mode::Verify ? "" : " (nothing recorded)",
                               out.error.substr(0, nl));
      if (nl != std::string::npos) r.details.push_back(out.error.substr(nl + 1));
      return;
    }
    StoredCase fresh;
    fresh.gmotion_version = GMOTION_VERSION;
    fresh.setup_hash = out.setup_hash;
    fresh.setup = out.setup;
    fresh.program = c.program;
    fresh.flags = c.flags;
    fresh.summary_json = out.summary_json;
    if (!stored) {
      const std::uintmax_t bytes = write_stored(suite.store, c.name, fresh_path, fresh);
      r.outcome = Outcome::Recorded;
      r.headline = fmt::format("recorded ({:.1f} KiB)", static_cast<double>(bytes) / 1024.0);
      return;
    }
    compare(index, c, *stored, fresh, fresh_path, r);
    if (opt.mode == Mode::Update) {
      if (r.outcome == Outcome::Pass && stored->setup == fresh.setup &&
          stored->gmotion_version == fresh.gmotion_version) {
        r.outcome = Outcome::Unchanged;
        r.headline.clear();
        r.details.clear();
        return;
      }
      write_stored(suite.store, c.name, fresh_path, fresh);
      r.outcome = r.outcome == Outcome::Pass ? Outcome::Unchanged : Outcome::Changed;
      r.headline = r.outcome == Outcome::Changed ? "re-recorded: " + r.headline
                                                 : "re-recorded (values unchanged) " + r.headline;
      r.picture.clear();
    }
  }

  void compare(std::size_t index, const GoldenCase& c, const StoredCase& stored,
               const StoredCase& fresh, const std::string& fresh_path, CaseResult& r) const {
    const std::string golden_path = (tmp / fmt::format("{}.golden.bin", index)).string();
    decompress_file(stored.trace_zst, golden_path);
    CompareResult cmp;
    {
      TraceReader g(golden_path), f(fresh_path);
      cmp = compare_traces(g, f, c.pins);
    }
    const bool summary_ok = !c.pin_summary || stored.summary_json == fresh.summary_json;
    const bool setup_ok = stored.setup_hash == fresh.setup_hash;
    const bool version_ok = stored.gmotion_version == fresh.gmotion_version;
    const std::string version_note = fmt::format("recorded with gmotion {}, this is {}",
                                                 stored.gmotion_version, fresh.gmotion_version);
    if (cmp.pass() && summary_ok && setup_ok) {
      r.outcome = Outcome::Pass;
      if (!version_ok) r.headline = "(" + version_note + ")";
      return;
    }
    r.outcome = Outcome::Fail;
    std::vector<std::string> why;
    if (!setup_ok) {
      const std::vector<std::string> ch = setup_changes(stored.setup, fresh.setup);
      why.push_back(fmt::format(
          "set-up changed since recorded (machine hash {:016x}, now {:016x}{}{})",
          stored.setup_hash, fresh.setup_hash, ch.empty() ? "" : ": ", fmt::join(ch, "; ")));
      r.kind = "setup";
    }
    if (!version_ok) {
      why.push_back(version_note);
      if (r.kind.empty()) r.kind = "version";
    }
    if (!cmp.pass()) {
      why.push_back(cmp.first              ? "first divergence " + describe_first(cmp)
                    : !cmp.problem.empty() ? "cannot compare the traces: " + cmp.problem
                                           : describe_first(cmp));
      if (r.kind.empty()) r.kind = "divergence";
      r.details.push_back("largest difference per column: " + largest_differences(cmp));
      r.details.push_back(fmt::format("{} value{} beyond the tolerance in {} rows", cmp.beyond,
                                      cmp.beyond == 1 ? "" : "s", cmp.rows));
    } else if (!summary_ok) {
      why.push_back("the trace agrees but the summary differs: " +
                    summary_difference(stored.summary_json, fresh.summary_json));
      if (r.kind.empty()) r.kind = "summary";
    }
    // The reason first, the divergence after: a set-up or version change explains the noise.
    r.headline = why.front();
    r.details.insert(r.details.begin(), why.begin() + 1, why.end());
    if (!opt.pictures_dir.empty() && opt.mode == Mode::Verify && cmp.first) {
      const fs::path png = fs::path(opt.pictures_dir) / (c.name + ".png");
      const std::string err = draw_divergence(golden_path, fresh_path, *cmp.first, c.name, png);
      if (err.empty()) {
        r.picture = png.string();
        r.details.push_back("picture: " + r.picture);
      } else {
        r.details.push_back("no picture: " + err);
      }
    }
  }
};

}  // namespace

const char* outcome_word(Outcome o) {
  switch (o) {
    case Outcome::Pass:
      return "PASS";
    case Outcome::Fail:
      return "FAIL";
    case Outcome::Error:
      return "ERROR";
    case Outcome::Recorded:
      return "RECORDED";
    case Outcome::Unchanged:
      return "UNCHANGED";
    case Outcome::Changed:
      return "CHANGED";
  }
  return "?";
}

bool outcome_failed(Outcome o) {
  return o == Outcome::Fail || o == Outcome::Error;
}

std::vector<std::string> setup_changes(const std::string& before, const std::string& after,
                                       std::size_t max) {
  const std::map<std::string, std::string> a = setup_keys(before), b = setup_keys(after);
  std::vector<std::string> out;
  std::size_t more = 0;
  auto add = [&](const std::string& key, const std::string& x, const std::string& y) {
    if (out.size() < max)
      out.push_back(
          fmt::format("{}: {} -> {}", key, x.empty() ? "(none)" : x, y.empty() ? "(none)" : y));
    else
      ++more;
  };
  for (const auto& [k, v] : a) {
    const auto it = b.find(k);
    const std::string now = it == b.end() ? "" : it->second;
    if (now != v) add(k, v, now);
  }
  for (const auto& [k, v] : b)
    if (a.find(k) == a.end()) add(k, "", v);
  if (more > 0) out.push_back(fmt::format("{} more", more));
  return out;
}

std::vector<CaseResult> run_suite(const Suite& suite, const RunnerOptions& options,
                                  const std::function<void(const CaseResult&)>& report) {
  std::vector<std::size_t> picked;
  for (std::size_t i = 0; i < suite.cases.size(); ++i)
    if (options.only.empty() ||
        std::any_of(options.only.begin(), options.only.end(),
                    [&](const std::string& p) { return glob_match(p, suite.cases[i].name); }))
      picked.push_back(i);
  if (picked.empty())
    throw InputError(fmt::format("no case of suite '{}' matches {}", suite.dir.string(),
                                 fmt::join(options.only, ", ")));
  if (!options.pictures_dir.empty()) {
    std::error_code ec;
    fs::create_directories(options.pictures_dir, ec);
    if (ec)
      throw InputError(fmt::format("cannot create --pictures folder '{}': {}", options.pictures_dir,
                                   ec.message()));
  }
  TempDir tmp;
  const Worker worker{suite, options, tmp.path()};
  std::vector<std::optional<CaseResult>> results(picked.size());
  std::mutex m;
  std::condition_variable done;
  std::atomic<std::size_t> next{0};
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t jobs = std::min<std::size_t>(
      picked.size(), options.jobs > 0 ? static_cast<std::size_t>(options.jobs) : cores);
  auto loop = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < picked.size();) {
      CaseResult r = worker.run(picked[i], suite.cases[picked[i]]);
      const std::lock_guard<std::mutex> lock(m);
      results[i] = std::move(r);
      done.notify_all();
    }
  };
  std::vector<std::thread> pool;
  // With one job this thread runs the cases itself; else it only reports, in suite order.
  for (std::size_t j = 0; jobs > 1 && j < jobs; ++j) pool.emplace_back(loop);
  std::vector<CaseResult> all;
  if (jobs <= 1) loop();
  for (std::size_t i = 0; i < picked.size(); ++i) {
    std::unique_lock<std::mutex> lock(m);
    done.wait(lock, [&] { return results[i].has_value(); });
    CaseResult r = std::move(*results[i]);
    lock.unlock();
    report(r);
    all.push_back(std::move(r));
  }
  for (std::thread& t : pool) t.join();
  return all;
}

}  // namespace gm::golden
