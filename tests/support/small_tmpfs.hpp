// Test helper: a 64 KiB tmpfs mounted for a test's scope, to make a file system run out of space.
#pragma once

#include "support/run_command.hpp"

#include <filesystem>
#include <string>

namespace gmtest {

/// Mounts a 64 KiB tmpfs at `dir` (created if missing). Needs root: mounted() says whether it
/// worked, so a test can skip. Unmounted by unmount() or at the end of the scope.
class SmallTmpfs {
 public:
  explicit SmallTmpfs(const std::filesystem::path& dir) : dir_(dir.string()) {
    std::filesystem::create_directories(dir);
    mounted_ = sh("mount -t tmpfs -o size=64k tmpfs " + dir_ + " 2>/dev/null").code == 0;
  }
  ~SmallTmpfs() { unmount(); }
  SmallTmpfs(const SmallTmpfs&) = delete;
  SmallTmpfs& operator=(const SmallTmpfs&) = delete;

  bool mounted() const { return mounted_; }
  void unmount() {
    if (mounted_) sh("umount " + dir_);
    mounted_ = false;
  }

 private:
  std::string dir_;
  bool mounted_ = false;
};

}  // namespace gmtest
