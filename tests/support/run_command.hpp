// Test helper: run a shell command (or the built gmotion) and capture its exit code and output.
#pragma once

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <string>

namespace gmtest {

struct CommandResult {
  int code;         ///< exit status, or -1 when killed by a signal
  std::string out;  ///< stdout (and stderr when the command redirects it)
};

/// Runs `cmd` through /bin/sh and captures its stdout.
inline CommandResult sh(const std::string& cmd) {
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::string out;
  std::array<char, 4096> buf{};
  while (std::size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// The built gmotion executable's path.
inline std::string gmotion_bin() {
  return GMOTION_BIN;
}

/// Runs the built gmotion with `args` (shell syntax), stdout and stderr together.
inline CommandResult run_gmotion(const std::string& args) {
  return sh(std::string(GMOTION_BIN) + " " + args + " 2>&1");
}

}  // namespace gmtest
