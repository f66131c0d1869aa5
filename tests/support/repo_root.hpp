// Test helper: the repository's root folder (programs/, tests/golden/, ...), from the tests dir.
#pragma once

#include <filesystem>

namespace gm::test {

inline const std::filesystem::path kRepoRoot =
    std::filesystem::path(GMOTION_TESTS_DIR).parent_path();

}  // namespace gm::test
