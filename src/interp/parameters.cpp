// The parameter store: numbered, named local/global and predefined parameters, the .var file.
#include "interp/parameters.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

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

void ParameterStore::push_frame() {
  Frame& f = frames_.emplace_back();
  for (int i = 0; i < kArgs; ++i) f.saved_args[static_cast<std::size_t>(i)] = numbered_[i + 1];
}

void ParameterStore::pop_frame() {
  if (frames_.size() <= 1) return;
  const Frame& f = frames_.back();
  for (int i = 0; i < kArgs; ++i) numbered_[i + 1] = f.saved_args[static_cast<std::size_t>(i)];
  frames_.pop_back();
}

bool ParameterStore::load_var_file(const std::string& path, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = fmt::format("cannot read parameter file '{}'", path);
    return false;
  }
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    if (line[first] < '0' || line[first] > '9') continue;  // LinuxCNC skips such lines
    std::istringstream ls(line);
    long n = 0;
    double v = 0.0;
    if (!(ls >> n >> v) || n < kFirst || n > kLast) {
      error = fmt::format("{}:{}: expected 'number value' with number 1-{}", path, line_no, kLast);
      return false;
    }
    numbered_[static_cast<std::size_t>(n)] = v;
    from_file_[static_cast<std::size_t>(n)] = true;
  }
  return true;
}

bool ParameterStore::save_var_file(const std::string& path, std::string& error) const {
  std::string text;
  for (int n = kFirst; n <= kLast; ++n)
    if (persistent(n) || from_file_[static_cast<std::size_t>(n)])
      text += fmt::format("{}\t{:.6f}\n", n, numbered_[static_cast<std::size_t>(n)]);
  std::ofstream out(path, std::ios::trunc);
  if (!out || !(out << text) || !out.flush()) {
    error = fmt::format("cannot write parameter file '{}'", path);
    return false;
  }
  return true;
}

}  // namespace gm
