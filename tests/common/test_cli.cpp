// The CLI's documented contract: --version, --help and usage-error exit codes.
#include <catch2/catch.hpp>

#include "support/run_command.hpp"

using gmtest::run_gmotion;

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
