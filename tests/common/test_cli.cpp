// The CLI's documented contract: --version, --help and usage-error exit codes.
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace {
struct Result {
  int code;
  std::string out;
};
// Runs the built gmotion with `args` (shell syntax), capturing stdout and stderr together.
Result run_gmotion(const std::string& args) {
  std::string cmd = std::string(GMOTION_BIN) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::string out;
  std::array<char, 4096> buf{};
  while (std::size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}
}  // namespace

TEST_CASE("gmotion --version prints the project version and exits 0") {
  auto r = run_gmotion("--version");
  CHECK(r.code == 0);
  CHECK(r.out == std::string("gmotion ") + GMOTION_VERSION + "\n");
}

TEST_CASE("gmotion --help lists every subcommand") {
  auto r = run_gmotion("--help");
  CHECK(r.code == 0);
  for (const char* sub : {"run", "check", "moves", "design", "analyze"}) {
    INFO(sub);
    CHECK(r.out.find(std::string("\n  ") + sub) != std::string::npos);
  }
}

TEST_CASE("usage errors exit 2") {
  CHECK(run_gmotion("").code == 2);
  CHECK(run_gmotion("no-such-command").code == 2);
  CHECK(run_gmotion("run --no-such-flag").code == 2);
}
