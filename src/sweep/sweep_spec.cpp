// Sweep spec reader (toml++): lists of programs, machines, profiles, τ and overrides.
#include "sweep/sweep_spec.hpp"

#include "common/status.hpp"
#include "setup/run_settings.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>

#include <algorithm>

namespace gm::sweep {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const SweepSpec& s, const toml::node& n, const std::string& key,
                       const std::string& msg) {
  throw InputError(
      fmt::format("{}:{}: key '{}': {}", s.source.string(), n.source().begin.line, key, msg));
}

const toml::array* list(const SweepSpec& s, const toml::table& t, const char* key) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return nullptr;
  const toml::array* a = n->as_array();
  if (a == nullptr || a->empty()) fail(s, *n, key, "must be a non-empty array");
  return a;
}

std::string text(const SweepSpec& s, const toml::node& n, const char* key) {
  const auto v = n.as_string();
  if (!v || v->get().empty()) fail(s, n, key, "each element must be a non-empty string");
  return v->get();
}

double number(const SweepSpec& s, const toml::node& n, const char* key) {
  if (auto i = n.as_integer()) return static_cast<double>(i->get());
  if (auto f = n.as_floating_point()) return f->get();
  fail(s, n, key, "must be a number");
}

// `flags`: the run flags every run takes. Those the spec's own keys give are refused.
template <typename Beside>
void read_flags(SweepSpec& s, const toml::node& n, const Beside& beside) {
  const auto v = n.as_string();
  if (!v) fail(s, n, "flags", "must be a string of `gmotion run` flags");
  setup::RunSettings& f = s.settings;
  try {
    setup::parse_flags(f, v->get());
  } catch (const InputError& e) {
    fail(s, n, "flags", e.what());
  }
  for (auto [flag, given] :
       {std::pair{"--machine", !f.machine_file.empty()},
        std::pair{"--profile", f.profile.has_value()}, std::pair{"--tau", f.tau_s.has_value()},
        std::pair{"--override", f.override_pct != 100.0},
        std::pair{"--override-file", !f.override_file.empty()}, std::pair{"--no-servo", f.no_servo},
        std::pair{"--max-time", f.max_time_s != 0.0}})
    if (given)
      fail(s, n, "flags",
           fmt::format("{}: the spec's machines, profiles, tau_s, overrides, servo and "
                       "max_time_s give it",
                       flag));
  for (std::string* path : {&f.tool_table, &f.parameter_file, &f.user_mcode_dir})
    if (!path->empty()) *path = beside(*path);
  std::string dirs;
  for (std::size_t at = 0; at < f.subroutine_path.size();) {
    const std::size_t colon = std::min(f.subroutine_path.find(':', at), f.subroutine_path.size());
    dirs += (dirs.empty() ? "" : ":") + beside(f.subroutine_path.substr(at, colon - at));
    at = colon + 1;
  }
  f.subroutine_path = dirs;
}

}  // namespace

std::string OverrideChoice::label() const {
  return schedule.empty() ? fmt::format("{}", percent) : fs::path(schedule).filename().string();
}

SweepSpec load_sweep_spec(const std::filesystem::path& path) {
  SweepSpec s;
  s.source = path;
  toml::table root;
  try {
    root = toml::parse_file(path.string());
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}: TOML syntax error: {}", path.string(),
                                 e.source().begin.line, e.description()));
  }
  const fs::path dir = path.parent_path();
  const auto beside = [&](const std::string& f) {
    return fs::path(f).is_absolute() ? f : (dir / f).lexically_normal().string();
  };
  for (auto&& [k, n] : root) {
    const std::string key(k.str());
    if (key != "programs" && key != "machines" && key != "profiles" && key != "tau_s" &&
        key != "overrides" && key != "servo" && key != "max_time_s" && key != "jobs" &&
        key != "flags")
      fail(s, n, key,
           "unknown key (programs, machines, profiles, tau_s, overrides, servo, "
           "max_time_s, jobs, flags)");
  }
  if (const toml::node* n = root.get("flags")) read_flags(s, *n, beside);
  const toml::array* programs = list(s, root, "programs");
  if (programs == nullptr)
    throw InputError(fmt::format("{}: key 'programs' is missing", path.string()));
  for (const toml::node& n : *programs) s.programs.push_back(beside(text(s, n, "programs")));

  if (const toml::array* a = list(s, root, "machines")) {
    for (const toml::node& n : *a) {
      const std::string f = text(s, n, "machines");
      SweepMachine m;
      m.file = f == "builtin" ? "" : beside(f);
      m.label = f == "builtin" ? "builtin" : fs::path(f).stem().string();
      s.machines.push_back(std::move(m));
    }
  } else {
    s.machines.push_back(SweepMachine{"", "builtin", {}});
  }
  for (SweepMachine& m : s.machines) {
    setup::RunSettings settings = s.settings;
    settings.machine_file = m.file;
    m.machine =
        setup::resolve_machine(settings);  // once per machine (an INI says once what it skips)
  }
  if (const toml::array* a = list(s, root, "profiles"))
    for (const toml::node& n : *a) s.profiles.emplace_back(text(s, n, "profiles"));
  else
    s.profiles.emplace_back(std::nullopt);
  if (const toml::array* a = list(s, root, "tau_s")) {
    for (const toml::node& n : *a) {
      const double t = number(s, n, "tau_s");
      if (!(t > 0.0)) fail(s, n, "tau_s", "each must be > 0 s");
      s.taus_s.emplace_back(t);
    }
  } else {
    s.taus_s.emplace_back(std::nullopt);
  }
  if (const toml::array* a = list(s, root, "overrides")) {
    for (const toml::node& n : *a) {
      OverrideChoice o;
      if (n.is_string())
        o.schedule = beside(text(s, n, "overrides"));
      else
        o.percent = number(s, n, "overrides");
      s.overrides.push_back(o);
    }
  } else {
    s.overrides.push_back(OverrideChoice{});
  }
  if (const toml::node* n = root.get("servo")) {
    if (!n->is_boolean()) fail(s, *n, "servo", "must be true or false");
    s.servo = n->as_boolean()->get();
  }
  if (const toml::node* n = root.get("max_time_s")) {
    s.max_time_s = number(s, *n, "max_time_s");
    if (!(s.max_time_s > 0.0)) fail(s, *n, "max_time_s", "must be > 0 s");
  }
  if (const toml::node* n = root.get("jobs")) {
    const auto i = n->as_integer();
    if (!i || i->get() < 0 || i->get() > 1024) fail(s, *n, "jobs", "must be an integer 0..1024");
    s.jobs = static_cast<int>(i->get());
  }
  return s;
}

std::vector<RunPoint> expand(const SweepSpec& s) {
  std::vector<RunPoint> runs;
  for (std::size_t p = 0; p < s.programs.size(); ++p)
    for (std::size_t m = 0; m < s.machines.size(); ++m)
      for (std::size_t f = 0; f < s.profiles.size(); ++f)
        for (std::size_t t = 0; t < s.taus_s.size(); ++t)
          for (std::size_t o = 0; o < s.overrides.size(); ++o)
            runs.push_back(RunPoint{runs.size(), p, m, f, t, o});
  return runs;
}

}  // namespace gm::sweep
