// Test helper: a per-process scratch directory under the system temp directory, removed at exit.
#pragma once

#include <unistd.h>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace gmtest {

/// `<tmp>/gmotion-<name>-<pid>`, created on first use; tests may leave files in it. Every
/// directory made here is removed with its contents when the test process exits normally.
inline std::filesystem::path scratch_dir(const std::string& name) {
  struct RemoveAtExit {
    std::vector<std::filesystem::path> dirs;
    ~RemoveAtExit() {
      for (const auto& d : dirs) {
        std::error_code ec;  // best effort: a failure to clean up must not fail the run
        std::filesystem::remove_all(d, ec);
      }
    }
  };
  static RemoveAtExit made;
  std::filesystem::path d = std::filesystem::temp_directory_path() /
                            ("gmotion-" + name + "-" + std::to_string(::getpid()));
  if (std::filesystem::create_directories(d)) made.dirs.push_back(d);
  return d;
}

}  // namespace gmtest
