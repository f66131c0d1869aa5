// gmotion check / moves: exit codes, the JSON Lines format, stdin.
#include <catch2/catch.hpp>

#include "support/run_command.hpp"

#include <array>
#include <cstdio>
#include <fstream>
#include <string>

namespace {
using gmtest::sh;
}  // namespace

TEST_CASE("gmotion moves prints one JSON object per canonical move (mm, mm/min)") {
  const auto r = sh("printf 'G20 G0 X1\\nG21\\nG1 X10 F600\\nG2 X20 I5\\nG4 P0.5\\nM2\\n' | " +
                    gmtest::gmotion_bin() + " moves -");
  CHECK(r.code == 0);
  CHECK(r.out ==
        "{\"line\":1,\"kind\":\"rapid\",\"end\":[25.4,0,0],\"feed\":0}\n"
        "{\"line\":3,\"kind\":\"line\",\"end\":[10,0,0],\"feed\":600}\n"
        "{\"line\":4,\"kind\":\"arc\",\"end\":[20,0,0],\"feed\":600,\"center\":[15,0,0],\"dir\":"
        "\"cw\",\"turns\":1,"
        "\"plane\":\"XY\"}\n"
        "{\"line\":5,\"kind\":\"dwell\",\"seconds\":0.5}\n");
}

TEST_CASE("gmotion moves: G04 P in milliseconds under fanuc and haas, seconds under linuxcnc") {
  const std::string prog = "printf 'G04 P2000\\nG04 X1.5\\nG4 P2.5\\nM30\\n' | ";
  // Haas: P2000 is 2000 ms, X1.5 is 1.5 s, P2.5 (a decimal point) is 2.5 s.
  auto r = sh(prog + gmtest::gmotion_bin() + " moves - --dialect haas");
  CHECK(r.code == 0);
  CHECK(r.out ==
        "{\"line\":1,\"kind\":\"dwell\",\"seconds\":2}\n"
        "{\"line\":2,\"kind\":\"dwell\",\"seconds\":1.5}\n"
        "{\"line\":3,\"kind\":\"dwell\",\"seconds\":2.5}\n");
  // Fanuc: a decimal point in P is refused at the P (line 3 `G4 P2.5`, column 4).
  r = sh(prog + gmtest::gmotion_bin() + " check - --dialect fanuc 2>&1");
  CHECK(r.code == 1);
  CHECK(r.out.find(":3:4: error: G04 P2.5: Fanuc's P is milliseconds") != std::string::npos);
  // LinuxCNC: P in seconds.
  r = sh("printf 'G4 P2000\\nM2\\n' | " + gmtest::gmotion_bin() + " moves -");
  CHECK(r.out == "{\"line\":1,\"kind\":\"dwell\",\"seconds\":2000}\n");
}

TEST_CASE("gmotion moves prints nothing and exits 1 when any line is bad") {
  const auto r = sh("printf 'G1 X1 F100\\nG1 X[1/0]\\nM2\\n' | " + gmtest::gmotion_bin() +
                    " moves - 2>/dev/null");
  CHECK(r.code == 1);
  CHECK(r.out.empty());
}

TEST_CASE("gmotion check: summary on success, all errors with caret on failure") {
  auto r = sh("printf 'G1 X30 Y40 F600\\nM2\\n' | " + gmtest::gmotion_bin() + " check - 2>&1");
  CHECK(r.code == 0);
  // 50 mm at 600 mm/min = 5 s.
  CHECK(r.out.find("2 blocks, 1 moves, path 50.000 mm, 5.000 s") != std::string::npos);
  r = sh("printf 'G1 X1\\nG0 X1 X2\\n' | " + gmtest::gmotion_bin() + " check - 2>&1");
  CHECK(r.code == 1);
  CHECK(r.out.find("<stdin>:1:1: error: G1 with zero feed") != std::string::npos);
  CHECK(r.out.find("<stdin>:2:7: error: X appears twice") != std::string::npos);
  CHECK(r.out.find("\n        ^\n") != std::string::npos);
  CHECK(r.out.find("<stdin>:2:1: error: missing program end") != std::string::npos);
}

TEST_CASE("gmotion check --arc-rule selects the tolerance rule") {
  const std::string prog = "printf 'G1 F100\\nG2 X10 Y0 I5.01\\nM2\\n' | ";
  CHECK(sh(prog + gmtest::gmotion_bin() + " check - 2>/dev/null").code == 0);
  CHECK(sh(prog + gmtest::gmotion_bin() + " check - --arc-rule grbl 2>/dev/null").code == 1);
  CHECK(sh(prog + gmtest::gmotion_bin() + " check - --arc-rule nonsense 2>/dev/null").code == 2);
}

TEST_CASE("under G20 the current position of A, B and C stays in degrees (rs274)") {
  const auto r =
      sh("printf 'G20\\nG0 X1 A10 B20 C30\\n(DEBUG,#5420 #5423 #5424 #5425 #<_b> "
         "#<_abs_c>)\\nM2\\n' | " +
         gmtest::gmotion_bin() + " moves --axes XYZABC --messages - | grep message");
  CHECK(r.code == 0);
  CHECK(r.out ==
        "{\"line\":3,\"kind\":\"message\",\"text\":\"1.000000 10.000000 20.000000 30.000000 "
        "20.000000 30.000000\"}\n");
}
