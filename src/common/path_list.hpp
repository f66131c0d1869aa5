// Colon-separated directory lists ("DIR[:DIR...]"), as LinuxCNC's SUBROUTINE_PATH writes them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// Splits "DIR[:DIR...]" at its colons, in order; empty entries are dropped.
std::vector<std::string> split_path_list(std::string_view colon_list);

}  // namespace gm
