// The code table: one row per G or M code (group, step, function, words); adding a code is a row.
#include "interp/codes.hpp"

#include "interp/steps.hpp"

#include <fmt/format.h>

#include <array>

namespace gm {

namespace {

using G = Group;
using S = Step;
// Dialect columns: grbl 1.1 has the code (gnea/grbl README "G-code support", gcode.c), or not.
constexpr DialectSet Any = kAllDialects;
constexpr DialectSet NoGrbl = kAllDialects & ~kGrblBit;

// clang-format off
constexpr std::array kCodes{
    // Non-modal (group 0)
    Code{'G',   40, G::NonModal,    S::Dwell,       Any,    run_dwell,        "P"},
    Code{'G',  100, G::NonModal,    S::NonModal,    Any,    run_g10,          "LPR", true},
    Code{'G',  280, G::NonModal,    S::NonModal,    Any,    run_home,         "",  true},
    Code{'G',  281, G::NonModal,    S::NonModal,    Any,    run_home_set},
    Code{'G',  300, G::NonModal,    S::NonModal,    Any,    run_home,         "",  true},
    Code{'G',  301, G::NonModal,    S::NonModal,    Any,    run_home_set},
    Code{'G',  520, G::NonModal,    S::NonModal,    NoGrbl, run_g52,          "",  true},
    Code{'G',  530, G::NonModal,    S::Motion,      Any,    run_nothing},  // modifies G0/G1 (motion step)
    Code{'G',  920, G::NonModal,    S::NonModal,    Any,    run_g92,          "",  true},
    Code{'G',  921, G::NonModal,    S::NonModal,    Any,    run_g92_x},
    Code{'G',  922, G::NonModal,    S::NonModal,    NoGrbl, run_g92_x},
    Code{'G',  923, G::NonModal,    S::NonModal,    NoGrbl, run_g92_x},
    // Motion (group 1)
    Code{'G',    0, G::Motion,      S::Motion,      Any,    run_straight},
    Code{'G',   10, G::Motion,      S::Motion,      Any,    run_straight},
    Code{'G',   20, G::Motion,      S::Motion,      Any,    run_arc,          "IJKRP"},
    Code{'G',   30, G::Motion,      S::Motion,      Any,    run_arc,          "IJKRP"},
    Code{'G',   50, G::Motion,      S::Motion,      NoGrbl, run_spline,       "IJPQ"},
    Code{'G',   51, G::Motion,      S::Motion,      NoGrbl, run_spline,       "IJ"},
    Code{'G',   52, G::Motion,      S::Motion,      NoGrbl, run_nurbs_point,  "PL"},
    Code{'G',   53, G::Motion,      S::Motion,      NoGrbl, run_nurbs_end},
    Code{'G',  330, G::Motion,      S::Motion,      NoGrbl, run_spindle_sync, "K"},
    Code{'G',  331, G::Motion,      S::Motion,      NoGrbl, run_rigid_tap,    "KI"},
    Code{'G',  382, G::Motion,      S::Motion,      Any,    run_probe},
    Code{'G',  383, G::Motion,      S::Motion,      Any,    run_probe},
    Code{'G',  384, G::Motion,      S::Motion,      Any,    run_probe},
    Code{'G',  385, G::Motion,      S::Motion,      Any,    run_probe},
    Code{'G',  700, G::Motion,      S::Motion,      NoGrbl, run_g7x,          "QDEP"},
    Code{'G',  710, G::Motion,      S::Motion,      NoGrbl, run_g7x,          "QDIR"},
    Code{'G',  711, G::Motion,      S::Motion,      NoGrbl, run_g7x,          "QDIR"},
    Code{'G',  712, G::Motion,      S::Motion,      NoGrbl, run_g7x,          "QDIR"},
    Code{'G',  720, G::Motion,      S::Motion,      NoGrbl, run_g7x,          "QDIR"},
    Code{'G',  721, G::Motion,      S::Motion,      NoGrbl, run_g7x,          "QDIR"},
    Code{'G',  722, G::Motion,      S::Motion,      NoGrbl, run_g7x,          "QDIR"},
    Code{'G',  730, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLQ"},
    Code{'G',  760, G::Motion,      S::Motion,      NoGrbl, run_threading,    "PIJKRQHEL"},
    Code{'G',  740, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLP"},
    Code{'G',  800, G::Motion,      S::Motion,      Any,    run_nothing},
    Code{'G',  810, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RL"},
    Code{'G',  820, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLP"},
    Code{'G',  830, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLQ"},
    Code{'G',  840, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLP"},
    Code{'G',  850, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RL"},
    Code{'G',  860, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLP"},
    Code{'G',  870, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLIJK"},
    Code{'G',  880, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLP"},
    Code{'G',  890, G::Motion,      S::Motion,      NoGrbl, run_cycle,        "RLP"},
    // Plane (group 2)
    Code{'G',  170, G::Plane,       S::Plane,       Any,    run_plane},
    Code{'G',  180, G::Plane,       S::Plane,       Any,    run_plane},
    Code{'G',  190, G::Plane,       S::Plane,       Any,    run_plane},
    // Distance (groups 3, 4)
    Code{'G',  900, G::Distance,    S::Distance,    Any,    run_distance},
    Code{'G',  910, G::Distance,    S::Distance,    Any,    run_distance},
    Code{'G',  901, G::ArcDistance, S::Distance,    NoGrbl, run_arc_distance},
    Code{'G',  911, G::ArcDistance, S::Distance,    Any,    run_arc_distance},
    // Feed mode (group 5)
    Code{'G',  930, G::FeedMode,    S::FeedMode,    Any,    run_feed_mode},
    Code{'G',  940, G::FeedMode,    S::FeedMode,    Any,    run_feed_mode},
    Code{'G',  950, G::FeedMode,    S::FeedMode,    NoGrbl, run_feed_mode},
    // Spindle mode (group 14): constant surface speed, constant rpm
    Code{'G',  960, G::SpindleMode, S::SpindleMode, NoGrbl, run_spindle_mode, "D"},
    Code{'G',  970, G::SpindleMode, S::SpindleMode, NoGrbl, run_spindle_mode},
    // Units (group 6)
    Code{'G',  200, G::Units,       S::Units,       Any,    run_units},
    Code{'G',  210, G::Units,       S::Units,       Any,    run_units},
    // Cutter compensation (group 7)
    Code{'G',  400, G::CutterComp,  S::CutterComp,  Any,    run_cutter_comp},
    Code{'G',  410, G::CutterComp,  S::CutterComp,  NoGrbl, run_cutter_comp,  "D"},
    Code{'G',  411, G::CutterComp,  S::CutterComp,  NoGrbl, run_cutter_comp,  "DL"},
    Code{'G',  420, G::CutterComp,  S::CutterComp,  NoGrbl, run_cutter_comp,  "D"},
    Code{'G',  421, G::CutterComp,  S::CutterComp,  NoGrbl, run_cutter_comp,  "DL"},
    // Tool length (group 8)
    Code{'G',  430, G::ToolLength,  S::ToolLength,  NoGrbl, run_tool_length,  "H"},
    Code{'G',  431, G::ToolLength,  S::ToolLength,  Any,    run_tool_length,  "",  true},
    Code{'G',  432, G::ToolLength,  S::ToolLength,  NoGrbl, run_tool_length,  "H"},
    Code{'G',  490, G::ToolLength,  S::ToolLength,  Any,    run_tool_length},
    // Canned cycle return (group 10)
    Code{'G',  980, G::ReturnMode,  S::ReturnMode,  NoGrbl, run_retract_mode},
    Code{'G',  990, G::ReturnMode,  S::ReturnMode,  NoGrbl, run_retract_mode},
    // Coordinate system (group 12)
    Code{'G',  540, G::CoordSystem, S::CoordSystem, Any,    run_coord_system},
    Code{'G',  550, G::CoordSystem, S::CoordSystem, Any,    run_coord_system},
    Code{'G',  560, G::CoordSystem, S::CoordSystem, Any,    run_coord_system},
    Code{'G',  570, G::CoordSystem, S::CoordSystem, Any,    run_coord_system},
    Code{'G',  580, G::CoordSystem, S::CoordSystem, Any,    run_coord_system},
    Code{'G',  590, G::CoordSystem, S::CoordSystem, Any,    run_coord_system},
    Code{'G',  591, G::CoordSystem, S::CoordSystem, NoGrbl, run_coord_system},
    Code{'G',  592, G::CoordSystem, S::CoordSystem, NoGrbl, run_coord_system},
    Code{'G',  593, G::CoordSystem, S::CoordSystem, NoGrbl, run_coord_system},
    // Path control (group 13)
    Code{'G',  610, G::PathControl, S::PathControl, Any,    run_path_control},
    Code{'G',  611, G::PathControl, S::PathControl, NoGrbl, run_path_control},
    Code{'G',  640, G::PathControl, S::PathControl, NoGrbl, run_path_control, "PQ"},
    // Lathe diameter/radius mode (group 15): X words are diameters under G7
    Code{'G',   70, G::LatheMode,   S::Distance,    NoGrbl, run_lathe_mode},
    Code{'G',   80, G::LatheMode,   S::Distance,    NoGrbl, run_lathe_mode},
    // Exact stop for one block
    Code{'G',   90, G::ExactStop,   S::Motion,      NoGrbl, run_nothing},
    // M codes
    Code{'M',    0, G::MStop,       S::Stop,        Any,    run_stop},
    Code{'M',   10, G::MStop,       S::Stop,        Any,    run_stop},
    Code{'M',   20, G::MStop,       S::Stop,        Any,    run_stop},
    Code{'M',  300, G::MStop,       S::Stop,        Any,    run_stop},
    Code{'M',  600, G::MStop,       S::Stop,        NoGrbl, run_stop},
    Code{'M',   60, G::MToolChange, S::ToolChange,  NoGrbl, run_tool_change},
    Code{'M',  610, G::MToolChange, S::ToolChange,  NoGrbl, run_m61,          "Q"},
    Code{'M',   30, G::MSpindle,    S::Spindle,     Any,    run_spindle},
    Code{'M',   40, G::MSpindle,    S::Spindle,     Any,    run_spindle},
    Code{'M',   50, G::MSpindle,    S::Spindle,     Any,    run_spindle},
    Code{'M',  190, G::MSpindle,    S::Spindle,     NoGrbl, run_orient,       "RPQ"},
    Code{'M',  700, G::MSpindle,    S::Spindle,     NoGrbl, run_modes_save},
    Code{'M',  710, G::MSpindle,    S::Spindle,     NoGrbl, run_modes_save},
    Code{'M',  720, G::MSpindle,    S::Spindle,     NoGrbl, run_modes_save},
    Code{'M',  730, G::MSpindle,    S::Spindle,     NoGrbl, run_modes_save},
    Code{'M',   70, G::MCoolant,    S::Coolant,     Any,    run_coolant},
    Code{'M',   80, G::MCoolant,    S::Coolant,     Any,    run_coolant},
    Code{'M',   90, G::MCoolant,    S::Coolant,     Any,    run_coolant},
    Code{'M',  480, G::MOverride,   S::Override,    NoGrbl, run_override},
    Code{'M',  490, G::MOverride,   S::Override,    NoGrbl, run_override},
    Code{'M',  500, G::MOverride,   S::Override,    NoGrbl, run_override,     "P"},
    Code{'M',  620, G::MIo,         S::Io,          NoGrbl, run_digital_out,  "P"},
    Code{'M',  630, G::MIo,         S::Io,          NoGrbl, run_digital_out,  "P"},
    Code{'M',  640, G::MIo,         S::Io,          NoGrbl, run_digital_out,  "P"},
    Code{'M',  650, G::MIo,         S::Io,          NoGrbl, run_digital_out,  "P"},
    Code{'M',  660, G::MIo,         S::Io,          NoGrbl, run_wait_input,   "PELQ"},
    Code{'M',  670, G::MIo,         S::Io,          NoGrbl, run_analog_out,   "EQ"},
    Code{'M',  680, G::MIo,         S::Io,          NoGrbl, run_analog_out,   "EQ"},
};

// M100..M199 (user codes, group 10): one row each, made here rather than written out.
constexpr int kUserMFirst = 100, kUserMCount = 100;
constexpr std::array<Code, kUserMCount> make_user_codes() {
  std::array<Code, kUserMCount> a{};
  for (int i = 0; i < kUserMCount; ++i)
    a[static_cast<std::size_t>(i)] = Code{'M', 10 * (kUserMFirst + i), G::MUser, S::UserMcode, NoGrbl, run_user_mcode, "PQ"};
  return a;
}
constexpr auto kUserCodes = make_user_codes();
// clang-format on

constexpr std::array<const char*, kGroupCount> kGroupTitles{"non-modal",
                                                            "motion",
                                                            "plane",
                                                            "distance",
                                                            "arc distance",
                                                            "feed mode",
                                                            "units",
                                                            "cutter compensation",
                                                            "tool length",
                                                            "canned cycle return",
                                                            "work offset",
                                                            "path control",
                                                            "lathe diameter mode",
                                                            "spindle mode",
                                                            "exact stop",
                                                            "stop",
                                                            "tool change",
                                                            "spindle",
                                                            "coolant",
                                                            "override",
                                                            "I/O",
                                                            "user M code"};

// Lookup by number (G and M numbers x 10 below 2000) and by value word, built at compile time.
constexpr int kMaxNumber10 = 2000;
struct CodeIndex {
  std::array<std::int16_t, kMaxNumber10> g{};
  std::array<std::int16_t, kMaxNumber10> m{};
  std::array<bool, 26> word{};
  std::uint32_t word_mask = 0;  ///< `word` as letter bits
};
constexpr CodeIndex make_index() {
  CodeIndex ix;
  for (auto& v : ix.g) v = -1;
  for (auto& v : ix.m) v = -1;
  for (std::size_t i = 0; i < kCodes.size(); ++i) {
    const Code& c = kCodes[i];
    auto& slot = c.letter == 'G' ? ix.g : ix.m;
    slot[static_cast<std::size_t>(c.number10)] = static_cast<std::int16_t>(i);
    for (const char w : c.words) ix.word[static_cast<std::size_t>(w - 'A')] = true;
  }
  for (const char w : kUserCodes[0].words) ix.word[static_cast<std::size_t>(w - 'A')] = true;
  for (std::size_t i = 0; i < ix.word.size(); ++i)
    if (ix.word[i]) ix.word_mask |= std::uint32_t{1} << i;
  return ix;
}
constexpr CodeIndex kIndex = make_index();

}  // namespace

std::span<const Code> code_table() {
  return kCodes;
}

const Code* find_code(char letter, int number10) {
  if (number10 < 0 || number10 >= kMaxNumber10) return nullptr;
  if (letter == 'M' && number10 >= 10 * kUserMFirst && number10 < 10 * (kUserMFirst + kUserMCount))
    return number10 % 10 == 0 ? &kUserCodes[static_cast<std::size_t>(number10 / 10 - kUserMFirst)]
                              : nullptr;
  const auto i = (letter == 'G' ? kIndex.g : kIndex.m)[static_cast<std::size_t>(number10)];
  return i < 0 ? nullptr : &kCodes[static_cast<std::size_t>(i)];
}

std::string code_name(char letter, int number10) {
  return number10 % 10 == 0 ? fmt::format("{}{}", letter, number10 / 10)
                            : fmt::format("{}{}.{}", letter, number10 / 10, number10 % 10);
}

std::string group_name(Group g) {
  std::string s = fmt::format("{} (", kGroupTitles[static_cast<std::size_t>(g)]);
  bool first = true;
  for (const Code& c : kCodes) {
    if (c.group != g) continue;
    if (!first)
      s += ' ';  // appended in two steps: g++ 12 -O3 warns falsely (-Wrestrict) on `a + b`
    s += code_name(c);
    first = false;
  }
  return s + ")";
}

bool code_word(char letter) {
  return letter >= 'A' && letter <= 'Z' && kIndex.word[static_cast<std::size_t>(letter - 'A')];
}

std::uint32_t code_word_mask() {
  return kIndex.word_mask;
}

std::string codes_using(char letter) {
  std::vector<std::string> names;
  for (const Code& c : kCodes)
    if (c.words.find(letter) != std::string_view::npos) names.push_back(code_name(c));
  if (kUserCodes[0].words.find(letter) != std::string_view::npos) names.emplace_back("M100..M199");
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i)
    s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return s;
}

}  // namespace gm
