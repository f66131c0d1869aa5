// The colon splitter of directory lists.
#include "common/path_list.hpp"

namespace gm {

std::vector<std::string> split_path_list(std::string_view colon_list) {
  std::vector<std::string> out;
  while (!colon_list.empty()) {
    const std::size_t colon = colon_list.find(':');
    const std::string_view dir = colon_list.substr(0, colon);
    if (!dir.empty()) out.emplace_back(dir);
    if (colon == std::string_view::npos) break;
    colon_list.remove_prefix(colon + 1);
  }
  return out;
}

}  // namespace gm
