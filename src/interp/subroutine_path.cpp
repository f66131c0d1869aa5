// The subroutine search path: name checks (no escape from the directories) and the file lookup.
#include "interp/subroutine_path.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

namespace gm {

bool SubroutinePath::safe_name(std::string_view label) {
  if (label.empty() || label.size() > 200 || label.front() == '.') return false;
  for (const char c : label) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

std::string SubroutinePath::find(std::string_view label) const {
  if (!safe_name(label)) return {};
  for (const std::string& dir : dirs_) {
    std::filesystem::path p = std::filesystem::path(dir) / (std::string(label) + ".ngc");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec)) continue;
    std::ifstream probe(p, std::ios::binary);
    if (probe) return p.string();
  }
  return {};
}

std::string SubroutinePath::describe_miss(std::string_view label) const {
  if (dirs_.empty())
    return "no subroutine path is set (--subroutine-path DIR or the machine key "
           "subroutine_path)";
  if (!safe_name(label))
    return fmt::format(
        "the name is not looked up on the subroutine path (only letters, digits, "
        "'_', '-' and '.' not first)");
  std::string dirs;
  for (const std::string& d : dirs_) {
    if (!dirs.empty()) dirs += ':';  // appended in two steps: g++ 12 -O3 warns on `a + b`
    dirs += d;
  }
  return fmt::format("no file '{}.ngc' in {}", label, dirs);
}

}  // namespace gm
