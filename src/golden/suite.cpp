// Reads suite.toml (or lists a folder's programs) into the cases of a golden suite.
#include "golden/suite.hpp"

#include "common/status.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <set>

namespace gm::golden {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail_at(const fs::path& file, const toml::node& n, const std::string& what) {
  throw InputError(fmt::format("{}:{}: {}", file.string(), n.source().begin.line, what));
}

// Every key of `t` must be one of `known`.
void check_keys(const fs::path& file, const toml::table& t,
                std::initializer_list<const char*> known, std::string_view where) {
  for (const auto& [k, v] : t) {
    const std::string_view key = k.str();  // clang 14 cannot capture a structured binding
    if (std::none_of(known.begin(), known.end(), [&](const char* s) { return key == s; }))
      fail_at(
          file, v,
          fmt::format("unknown key '{}' in {} (known: {})", key, where, fmt::join(known, ", ")));
  }
}

std::string get_string(const fs::path& file, const toml::table& t, const char* key,
                       const std::string& fallback) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return fallback;
  if (!n->is_string()) fail_at(file, *n, fmt::format("key '{}' must be a string", key));
  return std::string(*n->value<std::string>());
}

double get_number(const fs::path& file, const toml::node& n, const std::string& key) {
  const std::optional<double> v = n.value<double>();
  if (!v || !(*v >= 0.0)) fail_at(file, n, fmt::format("key '{}' must be a number >= 0", key));
  return *v;
}

// Applies the case keys of `t` (defaults or one case) onto `c`.
void apply(const fs::path& file, const toml::table& t, GoldenCase& c) {
  c.program = get_string(file, t, "program", c.program);
  c.name = get_string(file, t, "name", c.name);
  c.machine = get_string(file, t, "machine", c.machine);
  c.override_file = get_string(file, t, "override_file", c.override_file);
  c.flags = get_string(file, t, "flags", c.flags);
  if (const toml::node* n = t.get("decimate")) {
    const std::optional<std::int64_t> v = n->value<std::int64_t>();
    if (!v || *v < 1 || *v > 1'000'000) fail_at(file, *n, "key 'decimate' must be an integer >= 1");
    c.decimate = static_cast<int>(*v);
  }
  if (const toml::node* n = t.get("columns")) {
    const toml::array* a = n->as_array();
    if (a == nullptr || a->empty())
      fail_at(file, *n, "key 'columns' must be a non-empty array of column names or globs");
    c.pins.columns.clear();
    for (const toml::node& e : *a) {
      if (!e.is_string()) fail_at(file, e, "key 'columns': each entry must be a string");
      c.pins.columns.emplace_back(*e.value<std::string>());
    }
  }
  if (const toml::node* n = t.get("tolerance_blu"))
    c.pins.tolerance_blu = get_number(file, *n, "tolerance_blu");
  if (const toml::node* n = t.get("tolerances")) {
    const toml::table* tt = n->as_table();
    if (tt == nullptr) fail_at(file, *n, "key 'tolerances' must be a table: column glob = BLU");
    std::vector<std::pair<std::string, double>> own;
    for (const auto& [k, v] : *tt)
      own.emplace_back(std::string(k.str()),
                       get_number(file, v, "tolerances." + std::string(k.str())));
    // A case's own patterns are tried before the defaults'.
    own.insert(own.end(), c.pins.tolerances.begin(), c.pins.tolerances.end());
    c.pins.tolerances = std::move(own);
  }
  if (const toml::node* n = t.get("summary")) {
    if (!n->is_boolean()) fail_at(file, *n, "key 'summary' must be true or false");
    c.pin_summary = *n->value<bool>();
  }
}

constexpr std::initializer_list<const char*> kCaseKeys = {
    "name",     "program", "machine",       "override_file", "flags",
    "decimate", "columns", "tolerance_blu", "tolerances",    "summary"};

std::string stem_name(const std::string& program) {
  return fs::path(program).stem().string();
}

bool valid_name(const std::string& s) {
  return !s.empty() && s[0] != '.' && std::all_of(s.begin(), s.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '-' || ch == '_' || ch == '.';
  });
}

}  // namespace

Suite load_suite(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(fmt::format("suite '{}' is not a folder", dir.string()));
  Suite s;
  s.dir = dir;
  s.root = dir;
  s.store = dir / "golden";
  s.name = fs::weakly_canonical(dir, ec).filename().string();
  GoldenCase defaults;
  std::string pattern_list = "*.nc,*.ngc";
  const fs::path file = dir / "suite.toml";
  toml::table doc;
  const bool has_file = fs::exists(file, ec);
  if (has_file) {
    try {
      doc = toml::parse_file(file.string());
    } catch (const toml::parse_error& e) {
      throw InputError(
          fmt::format("{}:{}: {}", file.string(), e.source().begin.line, e.description()));
    }
    check_keys(file, doc, {"suite", "defaults", "case"}, "suite.toml");
    if (const toml::table* st = doc["suite"].as_table()) {
      check_keys(file, *st, {"name", "root", "store", "programs"}, "[suite]");
      s.name = get_string(file, *st, "name", s.name);
      s.root = dir / get_string(file, *st, "root", ".");
      s.store = dir / get_string(file, *st, "store", "golden");
      pattern_list = get_string(file, *st, "programs", pattern_list);
    }
    if (const toml::table* dt = doc["defaults"].as_table()) {
      check_keys(file, *dt, kCaseKeys, "[defaults]");
      if (dt->contains("name") || dt->contains("program"))
        fail_at(file, *dt, "[defaults] cannot set 'name' or 'program'");
      apply(file, *dt, defaults);
    }
  }
  const toml::array* cases = doc["case"].as_array();
  if (has_file && doc.contains("case") && cases == nullptr)
    fail_at(file, *doc.get("case"), "'case' must be an array of tables: [[case]]");
  if (cases != nullptr) {
    for (const toml::node& n : *cases) {
      const toml::table* t = n.as_table();
      if (t == nullptr) fail_at(file, n, "each [[case]] must be a table");
      check_keys(file, *t, kCaseKeys, "[[case]]");
      GoldenCase c = defaults;
      c.program.clear();
      apply(file, *t, c);
      if (c.program.empty()) fail_at(file, n, "[[case]] needs 'program'");
      if (c.name.empty()) c.name = stem_name(c.program);
      if (!valid_name(c.name))
        fail_at(
            file, n,
            fmt::format("case name '{}' may hold only letters, digits, '-', '_' and '.'", c.name));
      s.cases.push_back(std::move(c));
    }
  } else {
    // A folder of programs: every file matching one of the patterns, in name order.
    std::vector<std::string> patterns;
    for (std::size_t a = 0; a <= pattern_list.size();) {
      std::size_t b = pattern_list.find(',', a);
      if (b == std::string::npos) b = pattern_list.size();
      if (b > a) patterns.push_back(pattern_list.substr(a, b - a));
      a = b + 1;
    }
    std::vector<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(s.root, ec)) {
      const std::string fname = e.path().filename().string();
      if (e.is_regular_file() &&
          std::any_of(patterns.begin(), patterns.end(),
                      [&](const std::string& p) { return glob_match(p, fname); }))
        names.push_back(fname);
    }
    if (ec)
      throw InputError(fmt::format("cannot list suite '{}': {}", s.root.string(), ec.message()));
    std::sort(names.begin(), names.end());
    for (const std::string& fname : names) {
      GoldenCase c = defaults;
      c.program = fname;
      c.name = stem_name(fname);
      if (!valid_name(c.name)) continue;
      s.cases.push_back(std::move(c));
    }
  }
  std::set<std::string> seen;
  for (GoldenCase& c : s.cases) {
    if (!seen.insert(c.name).second)
      throw InputError(fmt::format("suite '{}': two cases are named '{}' (give one a 'name')",
                                   dir.string(), c.name));
    c.program_path = fs::path(c.program).is_absolute() ? fs::path(c.program) : s.root / c.program;
  }
  if (s.cases.empty())
    throw InputError(fmt::format("suite '{}' has no cases (no [[case]] in suite.toml, no programs)",
                                 dir.string()));
  return s;
}

}  // namespace gm::golden
