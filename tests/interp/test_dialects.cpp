// --dialect fanuc|grbl through the CLI: each row of docs/dialects.md's table.
#include <catch2/catch.hpp>

#include "interp/codes.hpp"
#include "interp/dialect.hpp"
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace {
using gmtest::sh;

std::string src(const std::string& rel) {
  return std::string(GMOTION_TESTS_DIR) + "/../" + rel;
}
// The moves of `gmotion moves ARGS` without their line numbers (a dialect program and its
// LinuxCNC equivalent differ in numbering only).
std::string moves(const std::string& args) {
  const auto r =
      sh(gmtest::gmotion_bin() + " moves " + args + " 2>/dev/null | sed 's/\"line\":[0-9]*,//'");
  return r.code == 0 ? r.out : "exit " + std::to_string(r.code);
}
}  // namespace

TEST_CASE("dialect-cli: the CAM programs run as their LinuxCNC equivalents (checked with rs274)") {
  // tests/dialects/*.linuxcnc.ngc equal rs274 (diff:rs274-dialect-equivalents); G43 H01 adds
  // tool 1's length from the default table to Z
  const std::string haas = moves(src("programs/dialects/haas_bracket.nc") + " --dialect fanuc");
  CHECK(haas == moves(src("tests/dialects/haas_bracket.linuxcnc.ngc")));
  CHECK(haas.find("\"end\":[48,48,45.5],\"feed\":900,\"center\":[58,48,45.5]") !=
        std::string::npos);
  const std::string pcb = moves(src("programs/dialects/grbl_pcb_isolation.nc") + " --dialect grbl");
  CHECK(pcb == moves(src("tests/dialects/grbl_pcb_isolation.linuxcnc.ngc")));
  CHECK(pcb.rfind("{\"kind\":\"rapid\",\"end\":[0,0,5],\"feed\":0}", 0) == 0);  // bare Z5: G0
  CHECK(moves(src("programs/dialects/estlcam_engrave.nc") + " --dialect grbl") ==
        moves(src("tests/dialects/estlcam_engrave.linuxcnc.ngc")));
  // as LinuxCNC programs they are refused
  CHECK(sh(gmtest::gmotion_bin() + " check " + src("programs/dialects/haas_bracket.nc") +
           " 2>/dev/null")
            .code == 1);
  CHECK(sh(gmtest::gmotion_bin() + " check " + src("programs/dialects/grbl_pcb_isolation.nc") +
           " 2>/dev/null")
            .code == 1);
}

TEST_CASE("dialect-cli: missing end: error, fanuc warning, grbl silent") {
  const std::string prog = "printf 'G0 X1\\nG1 X2 F100\\n' | ";
  auto r = sh(prog + gmtest::gmotion_bin() + " check - 2>&1");
  CHECK(r.code == 1);
  CHECK(r.out.find("<stdin>:2:1: error: missing program end") != std::string::npos);
  r = sh(prog + gmtest::gmotion_bin() + " check - --dialect fanuc 2>&1");
  CHECK(r.code == 0);
  CHECK(r.out.find("<stdin>:2:1: warning: the program ends without M2/M30") != std::string::npos);
  r = sh(prog + gmtest::gmotion_bin() + " check - --dialect grbl 2>&1");
  CHECK(r.code == 0);
  CHECK(r.out.find("warning") == std::string::npos);
}

TEST_CASE("dialect-cli: fanuc machine M codes are passed over once each, M97 refused") {
  auto r = sh("printf 'M31\\nG0 X1 M88\\nM88\\nM2\\n' | " + gmtest::gmotion_bin() +
              " moves - --dialect fanuc 2>&1");
  CHECK(r.code == 0);
  CHECK(r.out.find("<stdin>:1:1: warning: M31 is a machine function") != std::string::npos);
  CHECK(r.out.find("<stdin>:2:7: warning: M88") != std::string::npos);
  CHECK(r.out.find("<stdin>:3:") == std::string::npos);  // warned once
  CHECK(r.out.find("{\"line\":2,\"kind\":\"rapid\",\"end\":[1,0,0],\"feed\":0}") !=
        std::string::npos);
  r = sh("printf 'M88\\nM2\\n' | " + gmtest::gmotion_bin() + " check - 2>&1");
  CHECK(r.code == 1);  // linuxcnc: not supported
  r = sh("printf 'M97 P100\\nM2\\n' | " + gmtest::gmotion_bin() + " check - --dialect fanuc 2>&1");
  CHECK(r.code == 1);
  CHECK(r.out.find("<stdin>:1:1: error: M97 (Haas local subprogram") != std::string::npos);
}

TEST_CASE("dialect-cli: grbl passes over $ lines, starts in G0, runs '/' lines") {
  auto r = sh("printf '$H\\n$110=500\\nX3\\n/Y4\\n' | " + gmtest::gmotion_bin() +
              " moves - --dialect grbl --block-delete 2>&1");
  CHECK(r.code == 0);
  CHECK(r.out.find("<stdin>:1:1: warning: grbl '$' setting") != std::string::npos);
  CHECK(r.out.find("<stdin>:2:") == std::string::npos);
  CHECK(r.out.find("{\"line\":3,\"kind\":\"rapid\",\"end\":[3,0,0],\"feed\":0}\n"
                   "{\"line\":4,\"kind\":\"rapid\",\"end\":[3,4,0],\"feed\":0}") !=
        std::string::npos);
  r = sh("printf 'X3\\nM2\\n' | " + gmtest::gmotion_bin() +
         " check - 2>&1");  // linuxcnc: no motion mode
  CHECK(r.code == 1);
}

TEST_CASE("dialect-cli: grbl refuses what grbl 1.1 does not have") {
  const auto refused = [](const std::string& line, const std::string& where_what) {
    const auto r =
        sh("printf '" + line + "\\n' | " + gmtest::gmotion_bin() + " check - --dialect grbl 2>&1");
    CHECK(r.code == 1);
    CHECK(r.out.find(where_what) != std::string::npos);
  };
  refused("G64 P0.01", "<stdin>:1:1: error: G64 is not in grbl 1.1");
  refused("G0 Z1\\nG81 X1 Y1 Z-1 R1 F100", "<stdin>:2:1: error: G81 is not in grbl 1.1");
  refused("G90.1", "error: G90.1 is not in grbl 1.1");
  refused("G43 H1", "<stdin>:1:1: error: G43 is not in grbl 1.1");
  refused("M6 T1", "<stdin>:1:1: error: M6 is not in grbl 1.1");
  refused("#1=5", "<stdin>:1:1: error: grbl 1.1 has no parameters");
  refused("G0 X[1+2]", "<stdin>:1:4: error: grbl 1.1 has no expressions");
  refused("o100 if [1]", "<stdin>:1:1: error: grbl 1.1 has no O-words");
  refused("O1234", "<stdin>:1:1: error: grbl 1.1 has no O-words");
  refused("M98 P100", "<stdin>:1:1: error: grbl 1.1 has no subprograms");
  refused("G0 A10", "<stdin>:1:4: error: grbl 1.1 has no A word");
  refused("G0 @1 ^2", "<stdin>:1:4: error: grbl 1.1 has no polar (@, ^) word");
  refused("G1 F100\\nG2 X1 I0.5 P2", "<stdin>:2:12: error: grbl 1.1 arcs take no P");
}

TEST_CASE("dialect-cli: the machine key dialect, and the flag over it") {
  const auto r =
      sh("d=$(mktemp -d) && sed 's/^\\[accdec\\]/dialect = \"grbl\"\\n[accdec]/' " +
         src("programs/machines/default.toml") +
         " > $d/m.toml && printf '$H\\nX1\\n' > $d/p.nc && " + gmtest::gmotion_bin() +
         " check $d/p.nc --machine $d/m.toml 2>/dev/null; echo \" $?\"; " + gmtest::gmotion_bin() +
         " check $d/p.nc --machine $d/m.toml --dialect linuxcnc 2>/dev/null; echo \" "
         "$?\"; sed -i 's/dialect = \"grbl\"/dialect = \"mach3\"/' $d/m.toml; " +
         gmtest::gmotion_bin() +
         " check $d/p.nc --machine $d/m.toml 2>&1 | grep -c 'dialect'; rm -r $d");
  CHECK(r.out.find(" 0\n") != std::string::npos);
  CHECK(r.out.find(" 1\n") != std::string::npos);
  CHECK(r.out.find("\n1\n") != std::string::npos);
}

TEST_CASE("M98/M99: the errors rs274 gives, located") {
  const auto error = [](const std::string& prog, const std::string& where_what) {
    const auto r = sh("printf '" + prog + "' | " + gmtest::gmotion_bin() + " check - 2>&1");
    CHECK(r.code == 1);
    CHECK(r.out.find(where_what) != std::string::npos);
  };
  // rs274: "Found 'm98' code with no P-word", "Fanuc 'O....' subroutine must be called with
  // 'M98'", "'O.... sub' subroutine must be called with 'O.... call'", "Unknown m code used"
  error("M98\\nM30\\n", "<stdin>:1:1: error: M98 needs P");
  error("o100 call\\nM30\\nO100\\nG0 X1\\nM99\\n", "<stdin>:3:1: error: O100 is a Fanuc-style");
  error("M98 P100\\nM30\\no100 sub\\nG0 X1\\no100 endsub\\n",
        "<stdin>:3:1: error: o100 sub is called with 'o100 call', not M98");
  error("G90 M98 P100\\nM30\\n", "<stdin>:1:5: error: M98 is not supported");
  error("M98 P100 X1\\nM30\\nO100\\nM99\\n", "<stdin>:1:10: error: M98 takes P");
  error("M98 P100\\nM30\\nO100\\no100 endsub\\n",
        "<stdin>:4:1: error: subprogram O100 was called "
        "with M98: it must end with M99");
}

TEST_CASE("dialect-cli: LinuxCNC line limit is 253 bytes with the line end, fanuc has none") {
  // rs274 (checked by hand and by diff:rs274-lang-errors): fgets into 255 bytes, refused when
  // 254 fill up, so 252 characters and '\n' pass and 253 do not; '\r' counts; a last line
  // without '\n' may have 253.
  const auto dir = gmtest::scratch_dir("line-limit");
  const auto check = [&](const std::string& text, const std::string& flags = "") {
    const auto path = (dir / "p.ngc").string();
    std::ofstream(path, std::ios::binary) << text;
    return sh(gmtest::gmotion_bin() + " check " + path + " " + flags + " 2>&1");
  };
  const auto line = [](std::size_t n) {  // a G1 with a comment, n characters in all
    const std::string g1 = "G1 X10 F300 (";
    return g1 + std::string(n - g1.size() - 1, 'c') + ")";
  };
  CHECK(check("G21\n" + line(252) + "\nM2\n").code == 0);
  auto r = check("G21\n" + line(253) + "\nM2\n");
  CHECK(r.code == 1);
  CHECK(r.out.find("p.ngc:2:253: error: command too long: 254 bytes with the line end, LinuxCNC "
                   "reads at most 253") != std::string::npos);
  CHECK(check("G21\r\n" + line(252) + "\r\nM2\r\n").code == 1);
  CHECK(check("G21\r\n" + line(251) + "\r\nM2\r\n").code == 0);
  const auto last = [](std::size_t n) { return "M2 (" + std::string(n - 5, 'c') + ")"; };
  CHECK(check("G21\n" + last(253)).code == 0);  // the last line, no '\n': 253 bytes
  CHECK(check("G21\n" + last(254)).code == 1);
  // also on a line passed over (a false if), as rs274 reads every line
  CHECK(check("o1 if [0]\n" + line(300) + "\no1 endif\nM2\n").code == 1);
  CHECK(check("G21\n" + line(5000) + "\nM2\n", "--dialect fanuc").code == 0);
}

TEST_CASE("dialects: grbl's codes are the code table's grbl column, M56 besides") {
  std::vector<int> g, m;
  for (const gm::Code& c : gm::code_table())
    if ((c.dialects & gm::kGrblBit) != 0) (c.letter == 'G' ? g : m).push_back(c.number10);
  std::sort(g.begin(), g.end());
  std::sort(m.begin(), m.end());
  // grbl 1.1's G-code (gnea/grbl README "G-code support", gcode.c), x 10.
  CHECK(g == std::vector<int>{0,   10,  20,  30,  40,  100, 170, 180, 190, 200, 210, 280, 281,
                              300, 301, 382, 383, 384, 385, 400, 431, 490, 530, 540, 550, 560,
                              570, 580, 590, 610, 800, 900, 910, 911, 920, 921, 930, 940});
  CHECK(m == std::vector<int>{0, 10, 20, 30, 40, 50, 70, 80, 90, 300});
  for (const gm::Code& c : gm::code_table()) CHECK((c.dialects & gm::kFanucBit) != 0);
  CHECK((gm::find_code('M', 1010)->dialects & gm::kGrblBit) == 0);  // user M codes
  gm::grammar::Block b;
  b.words.push_back(gm::grammar::Word{'M', 56.0, gm::SourceLoc{1, 1}});
  gm::SourceLoc at;
  std::string why;
  CHECK(gm::grbl_accepts(b, at, why));  // parking override: grbl's, refused later as unknown
  b.words.front().value = 6.0;
  CHECK_FALSE(gm::grbl_accepts(b, at, why));
}
