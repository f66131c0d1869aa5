// Machine file: the bundled files load with the paper's numbers; every error names key+file+line.
#include "machine/machine_file.hpp"

#include "common/status.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

using gm::Machine;

namespace {

const std::filesystem::path kMachines =
    std::filesystem::path(GMOTION_TESTS_DIR) / ".." / "programs" / "machines";

void require_equal(const Machine& a, const Machine& b) {
  CHECK(a.name == b.name);
  CHECK(a.period_s == b.period_s);
  CHECK(a.servo_substeps == b.servo_substeps);
  CHECK(a.rapid_mm_min == b.rapid_mm_min);
  CHECK(a.max_override == b.max_override);
  CHECK(a.profile == b.profile);
  CHECK(a.tau_s == b.tau_s);
  CHECK(a.arc_rule == b.arc_rule);
  CHECK(a.tolerance_on == b.tolerance_on);
  CHECK(a.arc_precompensation == b.arc_precompensation);
  CHECK(a.g61_arc_precompensation == b.g61_arc_precompensation);
  CHECK(a.private_arcs == b.private_arcs);
  CHECK(a.servo_matching == b.servo_matching);
  CHECK(a.tool_lengths_mm == b.tool_lengths_mm);
  for (std::size_t g = 0; g < 6; ++g) CHECK(a.work_offsets_mm[g] == b.work_offsets_mm[g]);
  CHECK(a.layout.letters() == b.layout.letters());
  CHECK(a.program_inch == b.program_inch);
  CHECK(a.lathe == b.lathe);
  CHECK(a.spindle_accel_rpm_s == b.spindle_accel_rpm_s);
  REQUIRE(a.axes.size() == b.axes.size());
  for (std::size_t i = 0; i < a.axes.size(); ++i) {
    INFO("axis " << i);
    const gm::AxisConfig &x = a.axes[i], &y = b.axes[i];
    CHECK(x.blu_mm == y.blu_mm);
    CHECK(x.v_max_mm_s == y.v_max_mm_s);
    CHECK(x.f_max_N == y.f_max_N);
    CHECK(x.p_max_W == y.p_max_W);
    CHECK(x.mass_kg == y.mass_kg);
    CHECK(x.damping_kg_s == y.damping_kg_s);
    CHECK(x.plant_num == y.plant_num);
    CHECK(x.plant_den == y.plant_den);
    CHECK(x.kvp == y.kvp);
    CHECK(x.kvi == y.kvi);
    CHECK(x.kp_1_s == y.kp_1_s);
    CHECK(x.backlash_blu == y.backlash_blu);
    CHECK(x.coulomb_N == y.coulomb_N);
    CHECK(x.ff1 == y.ff1);
    CHECK(x.ff2_s == y.ff2_s);
    CHECK(x.mode_hz == y.mode_hz);
    CHECK(x.mode_damping == y.mode_damping);
    CHECK(x.plant_blu_s_per_unit == y.plant_blu_s_per_unit);
    CHECK(x.kv_period_s == y.kv_period_s);
    CHECK(x.kv_form == y.kv_form);
    CHECK(x.drive_N_per_unit == y.drive_N_per_unit);
  }
}

// A minimal valid file; tests patch one line at a time.
const std::string kMinimal = R"(name = "m"
period_s = 0.004
[axes.x]
plant_num = [33.518]
plant_den = [1, 14.45]
kvp = 0.0422
kvi = 0.0094
kp_1_s = 30
[axes.y]
plant_num = [32.07]
plant_den = [1, 13.823]
kvp = 0.0442
kvi = 0.0098
kp_1_s = 30
[axes.z]
plant_num = [33.518]
plant_den = [1, 14.45]
kvp = 0.0422
kvi = 0.0094
kp_1_s = 30
)";

std::string error_of(const std::string& text) {
  try {
    gm::parse_machine_toml(text, "t.toml");
  } catch (const gm::InputError& e) {
    return e.what();
  }
  return "<no error>";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto p = s.find(from);
  REQUIRE(p != std::string::npos);
  return s.replace(p, from.size(), to);
}

}  // namespace

TEST_CASE("paper.toml loads with the paper's numbers", "[machine]") {
  const Machine m = gm::load_machine_file(kMachines / "paper.toml");
  CHECK(m.name == "chen-lee-1998");
  CHECK(m.period_s == 0.004);
  CHECK(m.servo_substeps == 1);
  CHECK(m.profile == "blackman");
  CHECK(m.tau_s == 0.164);
  CHECK(m.source.find("paper.toml") != std::string::npos);
  const auto& x = m.axes[0];
  const auto& y = m.axes[1];
  const auto& z = m.axes[2];
  CHECK(x.blu_mm == 0.001);
  CHECK(x.v_max_mm_s == 1000.0);  // 1 m/s
  CHECK(x.f_max_N == 4000.0);
  CHECK(x.p_max_W == 500.0);
  CHECK(x.mass_kg == 500.0);
  CHECK(x.damping_kg_s == 500.0);
  CHECK(x.plant_num == std::vector<double>{33.518});
  CHECK(x.plant_den == std::vector<double>{1.0, 14.45});
  CHECK(y.plant_num == std::vector<double>{32.07});
  CHECK(y.plant_den == std::vector<double>{1.0, 13.823});
  CHECK(x.kvp == 0.0422);
  CHECK(x.kvi == 0.0094);
  CHECK(y.kvp == 0.0442);
  CHECK(y.kvi == 0.0098);
  CHECK(z.plant_num == x.plant_num);
  CHECK(z.plant_den == x.plant_den);
  for (const auto& a : m.axes) {
    CHECK(a.kp_1_s == 30.0);
    CHECK(a.backlash_blu == 0.0);
    CHECK(a.coulomb_N == 0.0);
  }
}

TEST_CASE("default.toml equals default_machine()", "[machine]") {
  Machine f = gm::load_machine_file(kMachines / "default.toml");
  const Machine d = gm::default_machine();
  CHECK(d.source == "<built-in>");
  require_equal(f, d);
}

TEST_CASE("machine_to_toml round-trips the default and a modified machine", "[machine]") {
  const Machine d = gm::default_machine();
  require_equal(gm::parse_machine_toml(gm::machine_to_toml(d), "rt.toml"), d);
  Machine m = d;
  m.name = "odd";
  m.period_s = 0.001 / 3.0;
  m.servo_substeps = 7;
  m.max_override = 1.5;
  m.arc_rule = gm::ArcRule::G2core;
  m.tool_lengths_mm = {0.0, 12.345678901234567, -3.0};
  m.work_offsets_mm[2].head<3>() << 1.0 / 3.0, -2.5, 1e-9;  // the vector is nine wide (XYZABCUVW)
  m.work_offsets_mm[2][3] = 22.5;                           // A, degrees
  m.axes[1].backlash_blu = 2.5;
  m.axes[1].kv_form = gm::VelocityLoopForm::Pi;
  m.axes[2].plant_num = {2.0};
  m.axes[2].plant_den = {1.0, 3.0, 2.0};
  m.axes[2].drive_N_per_unit = 123.0;
  m.axes[0].ff1 = 0.857;
  m.axes[2].ff2_s = 0.01431;
  m.axes[1].mode_hz = {40.0, 123.5};
  m.axes[1].mode_damping = {0.0, 0.02};
  m.program_inch = true;
  m.lathe = true;
  m.spindle_accel_rpm_s = 250.0;
  m.tolerance_on = gm::ToleranceOn::Encoder;
  m.arc_precompensation = false;
  m.g61_arc_precompensation = true;
  m.private_arcs = false;
  m.servo_matching = false;
  require_equal(gm::parse_machine_toml(gm::machine_to_toml(m), "rt.toml"), m);
  // Names with TOML's special characters (found by fuzz_machine: backslashes did not survive).
  for (const char* name :
       {"de\\\\fault", "say \"hi\"", "tab\there", "bell\x07", "caf\xC3\xA9 \xE2\x86\x92"}) {
    m.name = name;
    INFO(name);
    require_equal(gm::parse_machine_toml(gm::machine_to_toml(m), "rt.toml"), m);
  }
}

TEST_CASE("minimal file: optional keys take the documented defaults", "[machine]") {
  const Machine m = gm::parse_machine_toml(kMinimal, "t.toml");
  CHECK(m.name == "m");
  CHECK(m.servo_substeps == 1);
  CHECK(m.rapid_mm_min == 6000.0);
  CHECK(m.max_override == 2.0);
  CHECK(m.tau_s == 0.164);
  CHECK(m.axes[0].blu_mm == 0.001);
  CHECK(m.axes[0].plant_blu_s_per_unit == 34000.0);
  CHECK(m.axes[0].kv_form == gm::VelocityLoopForm::Ip);
  CHECK(m.axes[0].ff1 == 0.0);  // no feedforward: the paper's loop
  CHECK(m.axes[0].ff2_s == 0.0);
  // A machine without feedforward writes no ff keys (files and goldens read as before).
  CHECK(gm::machine_to_toml(gm::default_machine()).find("ff1") == std::string::npos);
  CHECK(gm::machine_to_toml(gm::default_machine()).find("ff2_s") == std::string::npos);
  const Machine f = gm::parse_machine_toml(
      replace(kMinimal, "[axes.y]\n", "ff1 = 0.857\nff2_s = 0.01431\n[axes.y]\n"), "t.toml");
  CHECK(f.axes[0].ff1 == 0.857);
  CHECK(f.axes[0].ff2_s == 0.01431);
  CHECK(f.axes[1].ff1 == 0.0);
  CHECK(gm::machine_to_toml(f).find("ff1 = 0.857\nff2_s = 0.01431\n") != std::string::npos);
  CHECK(m.servo_matching);                 // "on"
  CHECK(m.arc_precompensation);            // "on"
  CHECK_FALSE(m.g61_arc_precompensation);  // "off"
  CHECK(m.private_arcs);                   // "on"
  CHECK(gm::machine_to_toml(m).find("g61_arc") == std::string::npos);
  CHECK_FALSE(m.program_inch);  // programs start in G21
  CHECK_FALSE(m.lathe);         // kind = "mill"
  CHECK(
      gm::parse_machine_toml(
          replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nkind = \"lathe\"\n"), "t.toml")
          .lathe);
  CHECK(gm::parse_machine_toml(
            replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nprogram_units = \"inch\"\n"),
            "t.toml")
            .program_inch);
  // The machine-level blu_mm is the axes' default; an axis may override it.
  const Machine b = gm::parse_machine_toml(
      replace(replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nblu_mm = 0.0005\n"),
              "[axes.z]\n", "[axes.z]\nblu_mm = 0.01\n"),
      "t.toml");
  CHECK(b.axes[0].blu_mm == 0.0005);
  CHECK(b.axes[2].blu_mm == 0.01);
}

TEST_CASE("out-of-range value: exact message with key, file and line", "[machine]") {
  // [axes.x] is line 3, so plant_num is line 4; blu_mm inserted as line 4.
  CHECK(error_of(replace(kMinimal, "[axes.x]\n", "[axes.x]\nblu_mm = -1\n")) ==
        "t.toml:4: key 'axes.x.blu_mm': must be >= 1e-6 mm (1 nm): positions up to ±1e12 mm "
        "must fit int64 counts (got -1)");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004", "period_s = 0")) ==
        "t.toml:2: key 'period_s': must be in 1e-06..1 s (got 0)");
  CHECK(
      error_of(replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nservo_substeps = 0\n")) ==
      "t.toml:3: key 'servo_substeps': must be in 1..1000 (got 0)");
  CHECK(error_of(
            replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\n[accdec]\ntau_s = 0\n")) ==
        "t.toml:4: key 'accdec.tau_s': must be >= period_s (at least one tap) (got 0)");
  CHECK(error_of(replace(kMinimal, "kp_1_s = 30\n[axes.y]", "kp_1_s = -30\n[axes.y]")) ==
        "t.toml:8: key 'axes.x.kp_1_s': must be >= 0.001 1/s (got -30)");
  CHECK(error_of(replace(kMinimal, "[axes.y]\n", "[axes.y]\ncoulomb_N = -5\n")) ==
        "t.toml:10: key 'axes.y.coulomb_N': must be >= 0 (got -5)");
  CHECK(error_of(replace(kMinimal, "[axes.y]\n", "[axes.y]\nff1 = 11\n")) ==
        "t.toml:10: key 'axes.y.ff1': must be in -10..10 (got 11)");
  CHECK(error_of(replace(kMinimal, "[axes.y]\n", "[axes.y]\nff2_s = -2\n")) ==
        "t.toml:10: key 'axes.y.ff2_s': must be in -1..1 s (got -2)");
  CHECK(error_of(replace(kMinimal, "[axes.y]\n",
                         "[axes.y]\nmode_hz = [40, 0]\nmode_damping = [0, 0]\n")) ==
        "t.toml:10: key 'axes.y.mode_hz': every frequency must be > 0 Hz (got 0)");
  CHECK(error_of(replace(kMinimal, "[axes.y]\n", "[axes.y]\nmode_hz = [40]\n")) ==
        "t.toml:10: key 'axes.y.mode_damping': needs one damping ratio per mode_hz (0 against 1)");
  CHECK(error_of(
            replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\narc_rule = \"fanuc\"\n")) ==
        "t.toml:3: key 'arc_rule': must be \"linuxcnc\", \"grbl\" or \"g2core\" (got \"fanuc\")");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n",
                         "period_s = 0.004\nservo_matching = \"yes\"\n")) ==
        "t.toml:3: key 'servo_matching': must be \"off\" or \"on\" (got \"yes\")");
  CHECK(error_of(replace(kMinimal, "[axes.z]\n", "[axes.z]\nkv_form = \"pid\"\n")) ==
        "t.toml:16: key 'axes.z.kv_form': must be \"ip\" or \"pi\" (got \"pid\")");
  CHECK(error_of(replace(kMinimal, "plant_den = [1, 13.823]", "plant_den = [0, 13.823]")) ==
        "t.toml:11: key 'axes.y.plant_den': the leading denominator coefficient must be finite and "
        "non-zero");
  CHECK(error_of(replace(kMinimal, "plant_num = [32.07]", "plant_num = [1, 32.07]")) ==
        "t.toml:11: key 'axes.y.plant_den': must be strictly proper (numerator degree < "
        "denominator degree)");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n",
                         "period_s = 0.004\nmax_override_percent = 50\n")) ==
        "t.toml:3: key 'max_override_percent': must be in 100..1000 (got 50)");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n",
                         "period_s = 0.004\nprogram_units = \"in\"\n")) ==
        "t.toml:3: key 'program_units': must be \"mm\" or \"inch\" (got \"in\")");
  CHECK(error_of(
            replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nkind = \"mill-turn\"\n")) ==
        "t.toml:3: key 'kind': must be \"mill\" or \"lathe\" (got \"mill-turn\")");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n",
                         "period_s = 0.004\nspindle_accel_rpm_s = -1\n")) ==
        "t.toml:3: key 'spindle_accel_rpm_s': must be 0..1e7 rpm/s (got -1)");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nblu_mm = nan\n")) ==
        "t.toml:3: key 'blu_mm': must be finite (got nan)");
}

TEST_CASE("values a run cannot use are refused by the reader (found by fuzzing)", "[machine]") {
  // tau_s left at its default 0.164 s must still be at least one period.
  CHECK(error_of(replace(kMinimal, "period_s = 0.004", "period_s = 0.202")) ==
        "t.toml:2: key 'period_s': does not suit accdec.tau_s = 0.164 s (the default): tau_s must "
        "be >= "
        "period_s (at least one tap) (got 0.202)");
  // A huge tau/T would design and filter with billions of taps.
  CHECK(error_of(
            replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\n[accdec]\ntau_s = 4e6\n")) ==
        "t.toml:4: key 'accdec.tau_s': must be <= 100000 x period_s = 400 s (tau/T = 1e+09 taps; "
        "at most "
        "100000) (got 4000000)");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004", "period_s = 1e-6"))
            .find("key 'period_s': does not suit accdec.tau_s = 0.164 s (the default): tau_s must "
                  "be <= 100000") != std::string::npos);
  // The servo lag 5/(kp T) is counted in samples: kp and T have floors.
  CHECK(error_of(replace(kMinimal, "kp_1_s = 30\n[axes.y]", "kp_1_s = 1e-300\n[axes.y]")) ==
        "t.toml:8: key 'axes.x.kp_1_s': must be >= 0.001 1/s (got 1e-300)");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004", "period_s = 1e-300")) ==
        "t.toml:2: key 'period_s': must be in 1e-06..1 s (got 1e-300)");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n",
                         "period_s = 0.004\n[accdec]\ntau_s = 400\n")) == "<no error>");
  // A BLU of 1e-20 mm counted the 0.5 mm of a line as 5e19 BLU, beyond int64 (UBSan: signed
  // overflow in the FIR block kernel). 1 nm is the floor, on the machine and on an axis.
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nblu_mm = 1e-20\n")) ==
        "t.toml:3: key 'blu_mm': must be >= 1e-6 mm (1 nm): positions up to ±1e12 mm must fit "
        "int64 counts (got 1e-20)");
  CHECK(error_of(replace(kMinimal, "kp_1_s = 30\n[axes.y]", "kp_1_s = 30\nblu_mm = 9e-7\n[axes.y]"))
            .find("key 'axes.x.blu_mm': must be >= 1e-6 mm") != std::string::npos);
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nblu_mm = 1e-6\n")) ==
        "<no error>");
}

TEST_CASE("missing required key: names the key, the file and the table's line", "[machine]") {
  CHECK(
      error_of(replace(kMinimal, "kvi = 0.0094\nkp_1_s = 30\n[axes.y]", "kp_1_s = 30\n[axes.y]")) ==
      "t.toml:3: key 'axes.x.kvi': required key is missing");
  CHECK(error_of(replace(kMinimal, "period_s = 0.004\n", "")) ==
        "t.toml:1: key 'period_s': required key is missing");
  const std::string no_z = kMinimal.substr(0, kMinimal.find("[axes.z]"));
  CHECK(error_of(no_z) == "t.toml:3: key 'axes.z': required key is missing");
}

TEST_CASE("mistyped value: names the key, the file and the line", "[machine]") {
  CHECK(error_of(replace(kMinimal, "kvp = 0.0442", "kvp = \"0.0442\"")) ==
        "t.toml:12: key 'axes.y.kvp': must be a number (got a string)");
  CHECK(error_of(
            replace(kMinimal, "period_s = 0.004\n", "period_s = 0.004\nservo_substeps = 2.5\n")) ==
        "t.toml:3: key 'servo_substeps': must be an integer (got a float)");
  CHECK(error_of(replace(kMinimal,
                         "plant_num = [33.518]\nplant_den = [1, 14.45]\nkvp = 0.0422\nkvi = "
                         "0.0094\nkp_1_s = 30\n[axes.y]",
                         "plant_num = [33.518, \"a\"]\nplant_den = [1, 14.45]\nkvp = 0.0422\nkvi = "
                         "0.0094\nkp_1_s = 30\n[axes.y]")) ==
        "t.toml:4: key 'axes.x.plant_num[1]': must be a number (got a string)");
  CHECK(error_of(kMinimal + "tools = 5\n") == "t.toml:21: key 'axes.z.tools': unknown key");
  CHECK(error_of("tools = 5\n" + kMinimal) ==
        "t.toml:1: key 'tools': must be an array of numbers (got an integer)");
  CHECK(error_of("work_offsets = { g54 = [1, 2] }\n" + kMinimal) ==
        "t.toml:1: key 'work_offsets.g54': must have 3..9 elements (got 2)");
}

TEST_CASE("unknown key (a typo): names the key, the file and the line", "[machine]") {
  CHECK(error_of(replace(kMinimal, "[axes.y]\n", "[axes.y]\nblu_m = 0.001\n")) ==
        "t.toml:10: key 'axes.y.blu_m': unknown key");
  CHECK(error_of("perod_s = 0.004\n" + kMinimal) == "t.toml:1: key 'perod_s': unknown key");
  CHECK(error_of(kMinimal + "[axes.w]\nkvp = 1\n") == "t.toml:21: key 'axes.w': unknown key");
  CHECK(error_of(kMinimal + "[accdec]\ntau = 0.1\n") == "t.toml:22: key 'accdec.tau': unknown key");
  CHECK(error_of(kMinimal + "[work_offsets]\ng60 = [0, 0, 0]\n") ==
        "t.toml:22: key 'work_offsets.g60': unknown key");
}

TEST_CASE("TOML syntax error and unreadable file", "[machine]") {
  const std::string e = error_of(replace(kMinimal, "kvp = 0.0442", "kvp = = 0.0442"));
  CHECK(e.rfind("t.toml:12: TOML syntax error:", 0) == 0);
  CHECK_THROWS_WITH(gm::load_machine_file("/nonexistent/m.toml"),
                    Catch::Contains("/nonexistent/m.toml"));
}
