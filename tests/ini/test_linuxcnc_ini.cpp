// LinuxCNC INI -> machine: units, limits, joints, paths, τ, warnings; sample configs run; export.
#include "machine/linuxcnc_ini.hpp"

#include "accdec/accel_limit.hpp"
#include "accdec/taps.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/run.hpp"
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using Catch::Detail::Approx;

namespace {

void write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

// What loading the INI throws, or "<no error>".
std::string load_error(const fs::path& p) {
  try {
    gm::load_linuxcnc_ini(p);
  } catch (const gm::InputError& e) {
    return e.what();
  }
  return "<no error>";
}

bool has_warning(const gm::IniImport& imp, const std::string& part) {
  return std::any_of(imp.warnings.begin(), imp.warnings.end(),
                     [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

// A gantry router in inches, the way a user writes one: Y on two joints, an A axis, an
// #INCLUDE'd axis file, paths relative to the INI.
fs::path router_dir() {
  const fs::path d = gmtest::scratch_dir("ini") / "router";
  fs::create_directories(d / "subs");
  write(d / "router.ini", R"([EMC]
MACHINE = test-router

[EMCMOT]
EMCMOT = motmod
SERVO_PERIOD = 500000

[TRAJ]
COORDINATES = X Y Y Z A
LINEAR_UNITS = inch
ANGULAR_UNITS = degree
MAX_LINEAR_VELOCITY = 4

[DISPLAY]
MAX_FEED_OVERRIDE = 1.5

[KINS]
KINEMATICS = trivkins coordinates=XYYZA kinstype=BOTH
JOINTS = 5

#INCLUDE axes.inc
#INCLUDE nosuch.inc

[JOINT_0]
TYPE = LINEAR
MAX_VELOCITY = 3
MAX_ACCELERATION = 30
INPUT_SCALE = 20000
BACKLASH = 0.001
[JOINT_1]
MAX_VELOCITY = 2.5
MAX_ACCELERATION = 25
[JOINT_2]
MAX_VELOCITY = 2.8
MAX_ACCELERATION = 20
[JOINT_3]
MAX_VELOCITY = 1.5
MAX_ACCELERATION = 15
[JOINT_4]
TYPE = ANGULAR
MAX_VELOCITY = 90
MAX_ACCELERATION = 720

[RS274NGC]
SUBROUTINE_PATH = subs:../shared-subs
USER_M_PATH = mcodes
PARAMETER_FILE = router.var

[EMCIO]
TOOL_TABLE = router.tbl
)");
  write(d / "axes.inc", R"(# included: the axis limits
[AXIS_X]
MAX_VELOCITY = 3.2
MAX_ACCELERATION = 40
MIN_LIMIT = -1
MAX_LIMIT = 40
[AXIS_Y]
MAX_VELOCITY = 3
MAX_ACCELERATION = 30
[AXIS_Z]
MAX_VELOCITY = 1.5
MAX_ACCELERATION = 15
[AXIS_A]
MAX_VELOCITY = 90
MAX_ACCELERATION = 720
)");
  write(d / "router.tbl", "T1 P1 Z1.5 D0.25 ;quarter-inch end mill\nT2 P2 Z2 D0.5\n");
  write(d / "router.var", "5220\t1.000000\n");
  return d;
}

const fs::path kSim = "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis";

bool have_sim(const std::string& ini) {
  if (fs::exists(kSim / ini)) return true;
  WARN("skipped: " << (kSim / ini).string()
                   << " is absent (the linuxcnc-uspace package ships it; tools/install-deps.sh)");
  return false;
}

// Runs `program` on `m` to its end; returns the summary (throws on a program error).
gm::RunSummary run_to_end(const gm::Machine& m, const fs::path& program, gm::RunStatus& st) {
  gm::RunOptions o;
  o.config.machine = m;
  o.program_name = program.string();
  o.consumer_thread = false;
  std::ifstream in(program);
  gm::InterpreterOptions opts;
  gm::Run run(std::move(o), in, opts);
  while ((st = run.step()) == gm::RunStatus::Working) {
  }
  return run.summary();
}

}  // namespace

TEST_CASE("ini: a gantry router in inches maps onto mm, the tightest joint and the INI's paths") {
  const fs::path d = router_dir();
  const gm::IniImport imp = gm::load_linuxcnc_ini(d / "router.ini");
  const gm::Machine& m = imp.machine;
  CHECK(m.name == "test-router");
  CHECK(m.period_s == Approx(0.0005));
  CHECK(m.layout.letters() == "XYZA");
  REQUIRE(m.axes.size() == 4);
  // X: the joint's 3 in/s is below the axis's 3.2; Y: the slower of its two joints.
  CHECK(m.axes[0].v_max_mm_s == Approx(3 * 25.4));
  CHECK(m.axes[1].v_max_mm_s == Approx(2.5 * 25.4));
  CHECK(m.axes[2].v_max_mm_s == Approx(1.5 * 25.4));
  CHECK(m.axes[3].v_max_mm_s == Approx(90.0));  // degrees stay degrees
  REQUIRE(imp.a_max_mm_s2.size() == 4);
  CHECK(imp.a_max_mm_s2[0] == Approx(30 * 25.4));
  CHECK(imp.a_max_mm_s2[1] == Approx(20 * 25.4));
  CHECK(imp.a_max_mm_s2[3] == Approx(720.0));
  // INPUT_SCALE 20000 counts/inch: 1.27 µm a count; BACKLASH 0.001 in = 20 counts.
  CHECK(m.axes[0].blu_mm == Approx(25.4 / 20000));
  CHECK(m.axes[0].backlash_blu == 20.0);
  CHECK(m.axes[1].blu_mm == 0.001);  // no INPUT_SCALE: gmotion's default
  CHECK(m.rapid_mm_min == Approx(4 * 25.4 * 60));
  CHECK(m.max_override == 1.5);
  CHECK_FALSE(m.lathe);  // no [DISPLAY]LATHE: a mill
  {                      // [DISPLAY]LATHE = 1: a lathe (the machine kind Fanuc lathe programs need)
    std::ifstream in(d / "router.ini");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("[DISPLAY]\n"), 10, "[DISPLAY]\nLATHE = 1\n");
    write(d / "router-lathe.ini", text);
    CHECK(gm::load_linuxcnc_ini(d / "router-lathe.ini").machine.lathe);
  }
  // The tool table is in inches like the INI.
  REQUIRE(m.tool_table.find(1) != nullptr);
  CHECK(m.tool_table.find(1)->offset_mm[2] == Approx(38.1));
  CHECK(m.tool_table.find(1)->diameter_mm == Approx(6.35));
  REQUIRE(m.subroutine_path.size() == 2);
  CHECK(m.subroutine_path[0] == (d / "subs").lexically_normal().string());
  CHECK(m.subroutine_path[1] == (d / ".." / "shared-subs").lexically_normal().string());
  CHECK(m.parameter_file == (d / "router.var").string());
  // Said once, each: what was not mapped.
  CHECK(has_warning(imp, "nosuch.inc"));
  CHECK(has_warning(imp, "gantry"));
  CHECK(has_warning(imp, "USER_M_PATH = mcodes"));
  CHECK(has_warning(imp, "shared-subs is not a directory"));
  CHECK(has_warning(imp, "soft limits"));
  CHECK(m.program_inch);                        // LINEAR_UNITS = inch: programs start in G20
  CHECK_FALSE(has_warning(imp, "KINEMATICS"));  // trivkins with parameters is trivkins
  // load_machine_file reads an .ini the same way (check, moves and the bindings use it).
  CHECK(gm::load_machine_file(d / "router.ini").layout.letters() == "XYZA");
}

namespace {

// The X and Y ends of the program's motions on machine `m`, mm.
std::vector<std::pair<double, double>> ends_xy(const gm::Machine& m, const std::string& text) {
  std::istringstream in(text);
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, "units.ngc", opts);
  std::vector<std::pair<double, double>> ends;
  gm::Canon c;
  while (stream.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c))
      ends.emplace_back(mo->end_mm[0], mo->end_mm[1]);
  return ends;
}

}  // namespace

TEST_CASE("ini: a program starts in the configuration's units, as LinuxCNC's INIT_CANON sets") {
  const fs::path d = gmtest::scratch_dir("ini") / "units";
  fs::create_directories(d);
  const auto machine = [&](const std::string& units) {
    write(d / "u.ini", "[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = " + units +
                           "\n[AXIS_X]\nMAX_VELOCITY = 1\nMAX_ACCELERATION = 10\n");
    return gm::load_linuxcnc_ini(d / "u.ini");
  };
  // No G20/G21 in the program: X1 is an inch on an inch machine until G21; M2 keeps the units.
  const std::string prog = "G0 X1 Y2\nG21 G0 X1\nG20\nM2\n";
  const auto inch = machine("inch");
  CHECK(inch.machine.program_inch);
  CHECK(ends_xy(inch.machine, prog) ==
        std::vector<std::pair<double, double>>{{25.4, 50.8}, {1.0, 50.8}});
  CHECK(machine("0.03937").machine.program_inch);  // units per mm within 1e-3 of 1/25.4
  const auto mm = machine("mm");
  CHECK_FALSE(mm.machine.program_inch);
  CHECK(ends_xy(mm.machine, prog) == std::vector<std::pair<double, double>>{{1.0, 2.0}});
  // cm: neither; LinuxCNC starts the interpreter in mm and says so, and so does gmotion.
  const auto cm = machine("cm");
  CHECK_FALSE(cm.machine.program_inch);
  CHECK(has_warning(cm, "neither mm nor inch"));
  CHECK_FALSE(has_warning(inch, "neither"));
}

TEST_CASE("ini: [RS274NGC]DISABLE_FANUC_STYLE_SUB = 1 makes M98 an error, as rs274's") {
  const fs::path d = gmtest::scratch_dir("ini") / "fanuc-subs";
  fs::create_directories(d);
  write(d / "f.ngc", "G0 X1\nM98 P100\nM2\nO100\nG0 X2\nM99\n");
  const auto check = [&](const std::string& value) {
    write(d / "f.ini",
          "[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = mm\n[AXIS_X]\nMAX_VELOCITY = 1\n"
          "MAX_ACCELERATION = 10\n[RS274NGC]\nDISABLE_FANUC_STYLE_SUB = " +
              value + "\n");
    CHECK(gm::load_linuxcnc_ini(d / "f.ini").machine.fanuc_subs_disabled == (value == "1"));
    return gmtest::run_gmotion("check " + (d / "f.ngc").string() + " --machine " +
                               (d / "f.ini").string());
  };
  const auto refused = check("1");
  CHECK(refused.code == 1);
  CHECK(refused.out.find("f.ngc:2:1: error: M98: Fanuc-style subprograms are disabled") !=
        std::string::npos);
  CHECK(refused.out.find("f.ngc: 1 error") != std::string::npos);
  CHECK(check("0").code == 0);
}

TEST_CASE("ini: [AXIS_A]WRAPPED_ROTARY wraps A as LinuxCNC's findBoolV reads it") {
  const fs::path d = gmtest::scratch_dir("ini") / "wrapped";
  fs::create_directories(d);
  write(d / "w.ngc", "G0 A300\nG0 A10\nM2\n");
  const auto machine_of = [&](const std::string& axis, const std::string& value) {
    write(d / "w.ini",
          "[TRAJ]\nCOORDINATES = X Y Z A\nLINEAR_UNITS = mm\nANGULAR_UNITS = degree\n[AXIS_" +
              axis + "]\nWRAPPED_ROTARY = " + value + "\n");
    return gm::load_linuxcnc_ini(d / "w.ini");
  };
  for (const char* on : {"1", "TRUE", "yes", "On"})
    CHECK(machine_of("A", on).machine.axes[3].wrapped_rotary);
  for (const char* off : {"0", "FALSE", "no"})
    CHECK_FALSE(machine_of("A", off).machine.axes[3].wrapped_rotary);
  const auto bad = machine_of("A", "maybe");
  CHECK_FALSE(bad.machine.axes[3].wrapped_rotary);
  CHECK(has_warning(bad, "WRAPPED_ROTARY = maybe: not a boolean"));
  const auto linear = machine_of("X", "1");
  CHECK_FALSE(linear.machine.axes[0].wrapped_rotary);
  CHECK(has_warning(linear, "X is linear; it does not wrap"));
  // A10 after A300 turns forward to 370 on the wrapped axis (rs274 with that INI does the same:
  // tests/diff/wrapped), and back to 10 on a plain one.
  machine_of("A", "1");
  const auto moves = gmtest::run_gmotion("moves " + (d / "w.ngc").string() + " --machine " +
                                         (d / "w.ini").string());
  CHECK(moves.out.find("\"A\":370") != std::string::npos);
  machine_of("A", "0");
  const auto plain = gmtest::run_gmotion("moves " + (d / "w.ngc").string() + " --machine " +
                                         (d / "w.ini").string());
  CHECK(plain.out.find("\"A\":10}") != std::string::npos);
}

TEST_CASE("ini: tau is the time a velocity step takes at the tightest V/A, by the profile's peak") {
  const gm::IniImport imp = gm::load_linuxcnc_ini(router_dir() / "router.ini");
  gm::Machine m = imp.machine;
  // Linear (box) taps: a step V ramps at V/tau, so tau = max V/A = 2.5/20 s (Y, and A: 90/720).
  m.profile = "linear";
  CHECK(gm::profile_peak_factor("linear") == Approx(1.0));
  CHECK(gm::tau_for_accel_limit(m, imp.a_max_mm_s2, 0.0) == Approx(0.125));
  // The default Blackman: its designed taps, applied to a step at each axis's V, stay within the
  // axis's A (the steepest sample is max h·V/T) to the rounding of c at 1000 taps.
  m.profile = "blackman";
  const double tau = imp.machine.tau_s;
  CHECK(tau == Approx(gm::tau_for_accel_limit(m, imp.a_max_mm_s2, 0.0)));
  const gm::Taps t = gm::design_taps("blackman", tau, m.period_s);
  const double hmax = *std::max_element(t.real.begin(), t.real.end());
  for (std::size_t i = 0; i < 4; ++i) {
    INFO("axis " << i);
    CHECK(hmax * m.axes[i].v_max_mm_s / m.period_s <= imp.a_max_mm_s2[i] * 1.01);
  }
  // ... and 20 periods shorter would not (Y binds).
  const gm::Taps shorter = gm::design_taps("blackman", tau - 0.01, m.period_s);
  CHECK(*std::max_element(shorter.real.begin(), shorter.real.end()) * m.axes[1].v_max_mm_s /
            m.period_s >
        imp.a_max_mm_s2[1]);
}

TEST_CASE("ini: a value that is not a number names the file, line, section and key") {
  const fs::path d = gmtest::scratch_dir("ini");
  write(d / "bad.ini", "[EMCMOT]\nSERVO_PERIOD = fast\n");
  CHECK(load_error(d / "bad.ini") ==
        (d / "bad.ini").string() + ":2: [EMCMOT]SERVO_PERIOD: must be a number (got \"fast\")");
}

TEST_CASE("ini: an INPUT_SCALE finer than 1 nm a count is refused by file, line and key") {
  // 1e10 counts an inch is 2.54e-9 mm a count: ±1e12 mm would be 4e20 counts, beyond int64.
  const fs::path d = gmtest::scratch_dir("ini");
  write(d / "fine.ini",
        "[KINS]\nKINEMATICS = trivkins coordinates=XYZ\nJOINTS = 3\n[TRAJ]\nLINEAR_UNITS = "
        "inch\n[JOINT_0]\nMAX_VELOCITY = 1\nMAX_ACCELERATION = 10\nINPUT_SCALE = -1e10\n");
  CHECK(load_error(d / "fine.ini") ==
        (d / "fine.ini").string() +
            ":9: [JOINT_0]INPUT_SCALE: -1e+10 counts a unit: one count is 2.54e-09 mm, finer "
            "than 1e-6 (1 nm): positions up to ±1e12 would not fit int64 counts");
  // 1e6 counts a mm is 1 nm: accepted.
  write(d / "nm.ini",
        "[KINS]\nKINEMATICS = trivkins coordinates=XYZ\nJOINTS = 3\n[TRAJ]\nLINEAR_UNITS = "
        "mm\n[JOINT_0]\nMAX_VELOCITY = 1\nMAX_ACCELERATION = 10\nINPUT_SCALE = 1e6\n");
  CHECK(gm::load_linuxcnc_ini(d / "nm.ini").machine.axes[0].blu_mm == 1e-6);
}

TEST_CASE("ini: [JOINT_n]FF1 and FF2 are the servo's ff1 and ff2_s, in any units") {
  // The pid's output for a position loop is a velocity in the joint's units per second: FF1
  // (output per unit/s) is a pure number and FF2 (output per unit/s²) seconds, in inches as in
  // mm. A joint without them keeps the paper's loop (0).
  const fs::path d = gmtest::scratch_dir("ini");
  write(d / "ff.ini",
        "[KINS]\nKINEMATICS = trivkins coordinates=XYZ\nJOINTS = 3\n[TRAJ]\nLINEAR_UNITS = "
        "inch\n[JOINT_0]\nMAX_VELOCITY = 1\nMAX_ACCELERATION = 10\nFF1 = 0.857\nFF2 = "
        "0.01431\n[JOINT_2]\nFF1 = 1\n");
  const gm::Machine m = gm::load_linuxcnc_ini(d / "ff.ini").machine;
  CHECK(m.axes[0].ff1 == 0.857);
  CHECK(m.axes[0].ff2_s == 0.01431);
  CHECK(m.axes[1].ff1 == 0.0);
  CHECK(m.axes[1].ff2_s == 0.0);
  CHECK(m.axes[2].ff1 == 1.0);
  CHECK(m.axes[2].ff2_s == 0.0);
  write(d / "ffbad.ini",
        "[KINS]\nKINEMATICS = trivkins coordinates=XYZ\nJOINTS = 3\n[JOINT_1]\nFF2 = 3\n");
  CHECK(load_error(d / "ffbad.ini") ==
        (d / "ffbad.ini").string() + ":5: [JOINT_1]FF2: must be in -1..1 s");
}

TEST_CASE("ini: #INCLUDE fan-out ends after 256 files read, not 10^8") {
  // f0 includes f1 ten times, f1 includes f2 ten times, ... f7: within the depth limit, 10^8
  // files read unbounded.
  const fs::path d = gmtest::scratch_dir("ini");
  for (int k = 0; k < 8; ++k) {
    std::string text = "[EMCMOT]\nSERVO_PERIOD = 1000000\n";
    if (k < 7)
      for (int i = 0; i < 10; ++i) text += "#INCLUDE f" + std::to_string(k + 1) + ".ini\n";
    write(d / ("f" + std::to_string(k) + ".ini"), text);
  }
  CHECK(load_error(d / "f0.ini") ==
        (d / "f7.ini").string() + ": more than 256 INI files read (#INCLUDE fanning out?)");
  // Found by fuzz_ini: an empty COORDINATES made an axis layout of nothing (UBSan: index out of
  // bounds).
  write(d / "none.ini", "[TRAJ]\nCOORDINATES = \n");
  CHECK_THROWS_WITH(gm::load_linuxcnc_ini(d / "none.ini"),
                    Catch::Contains("none.ini:2: [TRAJ]COORDINATES: names no axis"));
  // Found by fuzz_ini: an #INCLUDE name longer than the system allows made is_regular_file
  // throw, and the exception ended gmotion (std::terminate). Now it is a missing include.
  write(d / "long.ini",
        "#INCLUDE " + std::string(5000, 'x') + ".inc\n[EMCMOT]\nSERVO_PERIOD = 1000000\n");
  const gm::IniImport imp = gm::load_linuxcnc_ini(d / "long.ini");
  CHECK(imp.machine.period_s == 0.001);
  CHECK_THAT(imp.warnings.at(0), Catch::Contains("long.ini:1: #INCLUDE xxx"));
  CHECK_THAT(imp.warnings.at(0), Catch::EndsWith(".inc: no such file (skipped)"));
  // A file including itself meets the depth limit first.
  write(d / "once.ini", "#INCLUDE once.ini\n");
  CHECK_THROWS_WITH(gm::load_linuxcnc_ini(d / "once.ini"),
                    Catch::Contains("once.ini:1: #INCLUDE nested deeper than 8"));
}

TEST_CASE("ini: export writes the axis sections that read back to the same machine") {
  gm::Machine m = gm::default_machine();
  m.set_axes(*gm::AxisLayout::of("XYZA"), m.axes[0]);
  m.period_s = 0.001;
  m.tau_s = 0.2;
  m.rapid_mm_min = 9000;
  m.max_override = 1.2;
  m.axes[1].v_max_mm_s = 250;
  m.axes[3].v_max_mm_s = 720;
  m.axes[3].blu_mm = 0.0005;
  m.axes[2].backlash_blu = 3;
  m.axes[0].ff1 = 0.857;
  m.axes[0].ff2_s = 0.01431;
  m.axes[1].ff1 = 1.0;
  const fs::path p = gmtest::scratch_dir("ini") / "exported.ini";
  write(p, gm::machine_to_linuxcnc_ini(m));
  const gm::IniImport back = gm::load_linuxcnc_ini(p);
  const gm::Machine& b = back.machine;
  CHECK(b.layout.letters() == "XYZA");
  CHECK(b.period_s == Approx(m.period_s));
  CHECK(b.tau_s == Approx(m.tau_s));  // the accelerations were written to suggest it
  CHECK(b.rapid_mm_min == Approx(m.rapid_mm_min));
  CHECK(b.max_override == Approx(m.max_override));
  for (std::size_t i = 0; i < 4; ++i) {
    INFO("axis " << i);
    CHECK(b.axes[i].v_max_mm_s == Approx(m.axes[i].v_max_mm_s));
    CHECK(b.axes[i].blu_mm == Approx(m.axes[i].blu_mm));
    CHECK(b.axes[i].backlash_blu == m.axes[i].backlash_blu);
    CHECK(b.axes[i].ff1 == m.axes[i].ff1);  // [JOINT_n]FF1, FF2: the pid's feedforward
    CHECK(b.axes[i].ff2_s == m.axes[i].ff2_s);
  }
  CHECK(back.warnings.empty());
}

TEST_CASE("ini: the shipped axis_mm sim runs a square on its own limits") {
  if (!have_sim("axis_mm.ini")) return;
  const gm::IniImport imp = gm::load_linuxcnc_ini(kSim / "axis_mm.ini");
  const gm::Machine& m = imp.machine;
  CHECK(m.layout.letters() == "XYZ");
  CHECK(m.period_s == Approx(0.001));            // SERVO_PERIOD = 1000000 ns
  CHECK(m.axes[0].v_max_mm_s == Approx(30.48));  // mm config: no conversion
  CHECK(m.axes[0].blu_mm == Approx(1 / 157.48));
  CHECK(m.rapid_mm_min == Approx(53.34 * 60));
  CHECK(m.tool_table.tools.size() == 24);
  CHECK(has_warning(imp, "PARAMETER_FILE"));  // sim_mm.var is written by LinuxCNC, not shipped
  gm::RunStatus st{};
  const gm::RunSummary s =
      run_to_end(m, fs::path(GMOTION_TESTS_DIR) / ".." / "programs" / "square.nc", st);
  CHECK(st == gm::RunStatus::Finished);
  // 80 mm of feed at 1200 mm/min = 4 s, plus the plunge (1 mm at 300) and the rapid lift.
  CHECK(s.program_time_s > 4.2);
  CHECK(s.program_time_s < 4.2 + 3 * m.tau_s);
}

TEST_CASE("ini: the shipped lathe sim (X Z, inches) turns a shoulder") {
  if (!have_sim("lathe.ini")) return;
  const gm::IniImport imp = gm::load_linuxcnc_ini(kSim / "lathe.ini");
  const gm::Machine& m = imp.machine;
  CHECK(m.layout.letters() == "XZ");
  CHECK(m.lathe);  // its [DISPLAY]LATHE = 1
  CHECK(m.axes[0].v_max_mm_s == Approx(3.333333 * 25.4));
  CHECK(imp.a_max_mm_s2[1] == Approx(20 * 25.4));
  CHECK(m.tool_table.tools.size() == 10);
  gm::RunStatus st{};
  const gm::RunSummary s =
      run_to_end(m, fs::path(GMOTION_TESTS_DIR) / "ini" / "lathe-turn.ngc", st);
  CHECK(st == gm::RunStatus::Finished);
  // Ends at X1.1 Z0.1 in: both axes within a count of it.
  CHECK(std::abs(s.axes[0].final_enc_err_blu) <= 1);
  CHECK(std::abs(s.axes[1].final_enc_err_blu) <= 1);
}

TEST_CASE("ini: the shipped 9-axis sim moves all of X Y Z A B C U V W") {
  if (!have_sim("axis_9axis.ini")) return;
  const gm::IniImport imp = gm::load_linuxcnc_ini(kSim / "axis_9axis.ini");
  const gm::Machine& m = imp.machine;
  CHECK(m.layout.letters() == "XYZABCUVW");
  CHECK(m.axes[3].v_max_mm_s == Approx(90.0));        // A, degrees/s
  CHECK(m.axes[6].v_max_mm_s == Approx(1.2 * 25.4));  // U, inches/s in mm/s
  gm::RunStatus st{};
  const gm::RunSummary s = run_to_end(m, fs::path(GMOTION_TESTS_DIR) / "ini" / "nine-axis.ngc", st);
  CHECK(st == gm::RunStatus::Finished);
  // The C axis turns 45 degrees and back: its peak speed is its share of the coordinated feed.
  CHECK(s.axes[5].velocity_mm_s.value > 0.0);
  for (std::size_t i = 0; i < 9; ++i) CHECK(std::abs(s.axes[i].final_enc_err_blu) <= 1);
}

namespace {

// The diagnostics `gmotion check` gives the program on machine `m`.
std::vector<gm::Diagnostic> diagnostics(const gm::Machine& m, const std::string& text) {
  std::istringstream in(text);
  gm::InterpreterOptions opts;
  opts.machine = &m;
  std::vector<gm::Diagnostic> out;
  gm::check_program_diagnostics(in, "ini.ngc", opts, out);
  return out;
}

}  // namespace

TEST_CASE("ini: #<_ini[SECTION]NAME> reads the INI's numbers, read-only, as rs274 (INI_VARS)") {
  const fs::path d = gmtest::scratch_dir("ini") / "ini-vars";
  fs::create_directories(d);
  const std::string body =
      "[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = mm\n"
      "[PROBE]\nSAFE_Z = 12.5\nCLEAR = 1e2\nHEX = 0x10\nTEXT = 7 mm\nlow = 3\n";
  write(d / "on.ini", "[RS274NGC]\n" + body);
  const gm::Machine on = gm::load_linuxcnc_ini(d / "on.ini").machine;
  // rs274 looks the upper-cased name up; a value that is not a whole number is not defined.
  CHECK(ends_xy(on, "G0 X#<_ini[PROBE]SAFE_Z> Y#<_ini[ probe ] clear >\nM2\n") ==
        std::vector<std::pair<double, double>>{{12.5, 100.0}});
  for (const char* undefined : {"HEX", "TEXT", "low", "NONE"}) {
    const auto diags = diagnostics(on, "G0 X#<_ini[PROBE]" + std::string(undefined) + ">\nM2\n");
    REQUIRE(diags.size() == 1);
    CHECK(diags[0].message.find("is not defined") != std::string::npos);
  }
  // Assigning one is rs274's error; a name the INI lacks is an ordinary global.
  const auto set = diagnostics(on, "#<_ini[PROBE]SAFE_Z> = 2\nM2\n");
  REQUIRE(set.size() == 1);
  CHECK(set[0].message == "Cannot assign to read-only parameter #<_ini[probe]safe_z>");
  CHECK(ends_xy(on, "#<_ini[PROBE]NONE> = 2\nG0 X#<_ini[PROBE]NONE>\nM2\n") ==
        std::vector<std::pair<double, double>>{{2.0, 0.0}});
  // INI_VARS = 0 turns them off; a machine file has none.
  write(d / "off.ini", "[RS274NGC]\nINI_VARS = 0\n" + body);
  const gm::Machine off = gm::load_linuxcnc_ini(d / "off.ini").machine;
  CHECK(off.ini_vars.empty());
  CHECK(diagnostics(off, "G0 X#<_ini[PROBE]SAFE_Z>\nM2\n").size() == 1);
}

TEST_CASE("ini: DISABLE_G92_PERSISTENCE starts without the parameter file's G92 offset") {
  const fs::path d = gmtest::scratch_dir("ini") / "g92-persistence";
  fs::create_directories(d);
  // The X end of `G0 X1` on the INI's machine, the file holding G92 X4 Y0.5 (in effect).
  const auto end_x = [&](const std::string& rs274ngc) {
    write(d / "m.var", "5210\t1.000000\n5211\t4.000000\n5212\t0.500000\n5220\t1.000000\n");
    write(d / "m.ini",
          "[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = mm\n[RS274NGC]\n"
          "PARAMETER_FILE = m.var\n" +
              rs274ngc);
    const gm::Machine m = gm::load_linuxcnc_ini(d / "m.ini").machine;
    std::istringstream in("G0 X1\nM2\n");
    gm::InterpreterOptions opts;
    opts.machine = &m;
    opts.parameter_file = m.parameter_file;
    opts.save_parameters = true;
    double x = -1.0;
    {
      gm::ProgramStream stream(in, "g92.ngc", opts);
      gm::Canon c;
      while (stream.next(c))
        if (const auto* mo = std::get_if<gm::Motion>(&c)) x = mo->end_mm[0];
    }
    return x;
  };
  const auto saved = [&](const std::string& number) {
    std::ifstream in(d / "m.var");
    for (std::string n, v; in >> n >> v;)
      if (n == number) return v;
    return std::string("<none>");
  };
  CHECK(end_x("") == Approx(5.0));  // restored, as LinuxCNC does by default
  CHECK(saved("5211") == "4.000000");
  CHECK(end_x("DISABLE_G92_PERSISTENCE = 0\n") == Approx(5.0));
  CHECK(end_x("DISABLE_G92_PERSISTENCE = 1\n") == Approx(1.0));
  // rs274 reads #5210-#5219 as 0 and writes them back so.
  CHECK(saved("5210") == "0.000000");
  CHECK(saved("5211") == "0.000000");
  CHECK(saved("5220") == "1.000000");  // the rest of the file stays
}

TEST_CASE("ini: ORIENT_OFFSET is added to M19's R, as rs274's ORIENT_SPINDLE prints it") {
  const fs::path d = gmtest::scratch_dir("ini") / "orient-offset";
  fs::create_directories(d);
  write(d / "o.ini",
        "[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = mm\n[RS274NGC]\n"
        "ORIENT_OFFSET = 12.5\n");
  const gm::Machine m = gm::load_linuxcnc_ini(d / "o.ini").machine;
  CHECK(m.orient_offset_deg == 12.5);
  // rs274: ORIENT_SPINDLE(0, 22.5000, 0), (0, 362.5000, 1), (0, 12.5000, 2); bare M19 none.
  std::istringstream in("M19 R10\nM19 R350 P1\nM19 P2\nM19\nM2\n");
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, "orient.ngc", opts);
  std::vector<std::pair<double, int>> orients;
  gm::Canon c;
  while (stream.next(c))
    if (const auto* e = std::get_if<gm::Event>(&c))
      if (e->kind == gm::EventKind::SpindleOrient) orients.emplace_back(e->value, e->index);
  CHECK(orients == std::vector<std::pair<double, int>>{{22.5, 0}, {362.5, 1}, {12.5, 2}});
  CHECK(gm::default_machine().orient_offset_deg == 0.0);
}
