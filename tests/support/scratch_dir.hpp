// Test helper: a per-process scratch directory under the system temp directory.
#pragma once

#include <filesystem>
#include <string>
#include <unistd.h>

namespace gmtest {

/// `<tmp>/gmotion-<name>-<pid>`, created on first use; tests may leave files in it.
inline std::filesystem::path scratch_dir(const std::string& name) {
  std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("gmotion-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace gmtest
