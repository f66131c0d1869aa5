// Where `o<name> call` finds a subroutine that is not in the program: `name.ngc` on a search path.
#pragma once

#include "common/path_list.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// The directories `o<name> call` searches (LinuxCNC's [RS274NGC]SUBROUTINE_PATH), in order.
/// A name is looked up as `DIR/name.ngc` with the label as LinuxCNC reads it (lower case, spaces
/// removed). A program is untrusted input: only names made of letters, digits, '_', '-' and '.'
/// (not starting with '.') are looked up, so no name escapes the directories the user gave.
class SubroutinePath {
 public:
  SubroutinePath() = default;
  explicit SubroutinePath(std::vector<std::string> dirs) : dirs_(std::move(dirs)) {}

  /// Splits "DIR[:DIR...]" (empty entries dropped): split_path_list.
  static std::vector<std::string> split(std::string_view colon_list) {
    return split_path_list(colon_list);
  }

  bool empty() const { return dirs_.empty(); }
  const std::vector<std::string>& dirs() const { return dirs_; }

  /// True if `label` may name a file (see the class comment).
  static bool safe_name(std::string_view label);

  /// The first `DIR/label.ngc` that is a readable regular file, or "" (also for unsafe names).
  std::string find(std::string_view label) const;

  /// Why `label` was not found, for the error message ("no file 'x.ngc' in a:b", ...).
  std::string describe_miss(std::string_view label) const;

 private:
  std::vector<std::string> dirs_;
};

}  // namespace gm
