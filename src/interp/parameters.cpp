// The parameter store: numbered, named local/global and predefined parameters, the .var file.
#include "interp/parameters.hpp"

#include "common/error_codes.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace gm {

ParameterStore::ParameterStore()
    : numbered_(static_cast<std::size_t>(kLast) + 1, 0.0),
      from_file_(static_cast<std::size_t>(kLast) + 1, false),
      frames_(1) {
  numbered_[5220] = 1.0;  // G54 (LinuxCNC's default)
}

double ParameterStore::get(int n) const {
  double v = 0.0;
  if (provider_ != nullptr && read_only(n) && provider_->live(n, v)) return v;
  return numbered_[static_cast<std::size_t>(n)];
}

bool ParameterStore::predefined(std::string_view name) const {
  if (name == "_value" || name == "_value_returned" || name == "_call_level") return true;
  double v = 0.0;
  return provider_ != nullptr && !name.empty() && name[0] == '_' && provider_->predefined(name, v);
}

bool ParameterStore::get_named(std::string_view name, double& value) const {
  if (!name.empty() && name[0] == '_') {
    if (name == "_value" || name == "_value_returned" || name == "_call_level") {
      value = name == "_value"            ? value_
              : name == "_value_returned" ? value_returned_
                                          : static_cast<double>(depth());
      return true;
    }
    if (provider_ != nullptr && provider_->predefined(name, value)) return true;
    const auto it = globals_.find(name);
    if (it == globals_.end()) return false;
    value = it->second;
    return true;
  }
  const NameMap& locals = frames_.back().locals;
  const auto it = locals.find(name);
  if (it == locals.end()) return false;
  value = it->second;
  return true;
}

bool ParameterStore::set_named(std::string_view name, double value) {
  if (predefined(name)) return false;
  NameMap& map = (!name.empty() && name[0] == '_') ? globals_ : frames_.back().locals;
  const auto it = map.find(name);
  if (it != map.end())
    it->second = value;
  else
    map.emplace(std::string(name), value);
  return true;
}

void ParameterStore::push_frame(bool save_args, int saved) {
  Frame& f = frames_.emplace_back();
  f.restores = save_args ? saved : 0;
  for (int i = 0; i < f.restores; ++i)
    f.saved_args[static_cast<std::size_t>(i)] = numbered_[static_cast<std::size_t>(i) + 1];
}

void ParameterStore::pop_frame() {
  if (frames_.size() <= 1) return;
  const Frame& f = frames_.back();
  for (int i = 0; i < f.restores; ++i)
    numbered_[static_cast<std::size_t>(i) + 1] = f.saved_args[static_cast<std::size_t>(i)];
  frames_.pop_back();
}

bool ParameterStore::load_var_file(const std::string& path, Diagnostic& error) {
  error = Diagnostic{};
  error.code = static_cast<int>(ErrorCode::ParameterFile);
  error.file = path;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) && !ec) return true;  // created at the first save
  std::ifstream in(path);
  if (!in) {
    error.loc = SourceLoc{1, 1};
    error.message = fmt::format("cannot read parameter file '{}': {}", path, std::strerror(errno));
    return false;
  }
  std::vector<double> values(numbered_.size(), 0.0);
  std::vector<bool> seen(numbered_.size(), false);
  std::string line;
  int line_no = 0;
  long last = 0;
  const auto fail = [&](std::size_t column, std::string message) {
    error.loc = SourceLoc{line_no, static_cast<int>(column) + 1};
    error.message = std::move(message);
    error.source_line = line.size() <= 512 ? line : std::string();
    return false;
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const char* begin = line.c_str();
    const char* p = begin;
    while (*p == ' ' || *p == '\t') ++p;
    const std::size_t number_col = static_cast<std::size_t>(p - begin);
    const bool sign = *p == '-' || *p == '+';
    if (!(std::isdigit(static_cast<unsigned char>(p[sign ? 1 : 0])) != 0))
      continue;  // not 'number value': LinuxCNC passes over it
    char* end = nullptr;
    errno = 0;
    const long n = std::strtol(p, &end, 10);
    if (errno != 0 || n < kFirst || n > kLast)
      return fail(number_col,
                  fmt::format("parameter number {} out of range 1-{} in the "
                              "parameter file",
                              std::string(p, static_cast<std::size_t>(end - p)), kLast));
    if (n <= last)
      return fail(number_col, fmt::format("parameter #{} out of order in the parameter file "
                                          "(numbers must increase; #{} came before)",
                                          n, last));
    p = end;
    while (*p == ' ' || *p == '\t') ++p;
    const std::size_t value_col = static_cast<std::size_t>(p - begin);
    errno = 0;
    const double v = std::strtod(p, &end);
    if (end == p || !std::isfinite(v))
      return fail(value_col, fmt::format("expected a number after parameter #{} in the "
                                         "parameter file",
                                         n));
    last = n;
    values[static_cast<std::size_t>(n)] = v;
    seen[static_cast<std::size_t>(n)] = true;
  }
  if (in.bad()) {
    error.loc = SourceLoc{line_no + 1, 1};
    error.message = fmt::format("cannot read parameter file '{}'", path);
    return false;
  }
  // Interp::restore_parameters: every numbered parameter not in the file is 0.
  for (std::size_t n = 1; n < numbered_.size(); ++n) {
    numbered_[n] = values[n];
    from_file_[n] = seen[n];
  }
  return true;
}

bool ParameterStore::save_var_file(const std::string& path, std::string& error) const {
  std::string text;
  for (int n = kFirst; n <= kLast; ++n)
    if ((persistent(n) || from_file_[static_cast<std::size_t>(n)] ||
         (n >= kept_first_ && n <= kept_last_)) &&
        !std::isnan(numbered_[static_cast<std::size_t>(n)]))
      text += fmt::format("{}\t{:.6f}\n", n, numbered_[static_cast<std::size_t>(n)]);
  std::ofstream out(path, std::ios::trunc);
  if (!out || !(out << text) || !out.flush()) {
    error = fmt::format("cannot write parameter file '{}': {}", path, std::strerror(errno));
    return false;
  }
  return true;
}

}  // namespace gm
