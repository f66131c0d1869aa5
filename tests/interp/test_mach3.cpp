// --dialect mach3 through the CLI: LinuxCNC's language as Mach3 reads it where Mach3 posts
// differ (G31, M47, machine M codes).
#include <catch2/catch.hpp>

#include "cli_moves.hpp"

#include <string>

namespace {
using gmtest::check_points;
using gmtest::cli_moves;
using gmtest::CliMoves;
}  // namespace

TEST_CASE("mach3: G31 is the straight probe G38.2, M47 ends the program, M codes passed over") {
  const std::string g31 = gmtest::scratch_program("mach3", "g31.nc",
                                                  "G21 G90\nG0 X5. Y5. Z10.\nG31 Z-10. F100.\n"
                                                  "M10\nG0 Z10.\nM47\nG0 X99.\n");
  const std::string g38 = gmtest::scratch_program("mach3", "g38.nc",
                                                  "G21 G90\nG0 X5. Y5. Z10.\nG38.2 Z-10. F100.\n"
                                                  "G0 Z10.\nM2\n");
  const CliMoves m = cli_moves(g31, "--dialect mach3");
  CHECK(m.code == 0);
  CHECK(m.out.find("warning: M47 (repeat the program from its first line) ends the program") !=
        std::string::npos);
  CHECK(m.out.find("warning: M10 is a machine function LinuxCNC does not have: passed over "
                   "(--dialect mach3") != std::string::npos);
  const CliMoves l = cli_moves(g38, "");
  REQUIRE(l.code == 0);
  check_points(m, m.ends, l.ends);  // G0 X99. after M47 is not run
  CHECK(m.kinds == l.kinds);
  CHECK(l.kinds[1] == "probe");
  // LinuxCNC has no G31 (rs274: G31 is not a G code it reads).
  CHECK(cli_moves(g31, "").code == 1);
}
