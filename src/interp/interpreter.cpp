// Block interpretation in grbl's four steps: import words, check them against a copy of the
// modal state, compute the motion, commit. LinuxCNC (rs274ngc) semantics throughout.
#include "interp/interpreter.hpp"

#include "common/units.hpp"
#include "interp/arc.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace gm {

namespace {

// Modal groups of the G codes this interpreter knows (LinuxCNC numbering where it has one).
enum GGroup : int {
  kGNonModal = 0,  // G4, G92, G92.1
  kGMotion,        // G0 G1 G2 G3
  kGPlane,         // G17 G18 G19
  kGDistance,      // G90 G91
  kGIjkDistance,   // G90.1 G91.1
  kGFeedMode,      // G93 G94
  kGUnits,         // G20 G21
  kGCutterComp,    // G40
  kGToolLength,    // G43 G49
  kGCoord,         // G54..G59
  kGControl,       // G61 G61.1 G64
  kGExactStop,     // G9 (non-modal, kept apart so it combines with G4/G92)
  kGGroups
};
enum MGroup : int { kMStop = 0, kMToolChange, kMSpindle, kMCoolant, kMOverride, kMGroups };

constexpr std::array<const char*, kGGroups> kGGroupNames{
    "non-modal (G4 G92 G92.1)", "motion (G0 G1 G2 G3)",         "plane (G17 G18 G19)",
    "distance (G90 G91)",       "arc distance (G90.1 G91.1)",   "feed mode (G93 G94)",
    "units (G20 G21)",          "cutter compensation (G40)",    "tool length (G43 G49)",
    "work offset (G54-G59)",    "path control (G61 G61.1 G64)", "exact stop (G9)"};
constexpr std::array<const char*, kMGroups> kMGroupNames{"stop (M0 M1 M2 M30)", "tool change (M6)",
                                                         "spindle (M3 M4 M5)", "coolant (M7 M8 M9)",
                                                         "override (M48 M49 M50)"};

int g_group(int code10) {
  switch (code10) {
    case 0:
    case 10:
    case 20:
    case 30:
      return kGMotion;
    case 40:
    case 920:
    case 921:
      return kGNonModal;
    case 90:
      return kGExactStop;
    case 170:
    case 180:
    case 190:
      return kGPlane;
    case 200:
    case 210:
      return kGUnits;
    case 400:
      return kGCutterComp;
    case 430:
    case 490:
      return kGToolLength;
    case 540:
    case 550:
    case 560:
    case 570:
    case 580:
    case 590:
      return kGCoord;
    case 610:
    case 611:
    case 640:
      return kGControl;
    case 900:
    case 910:
      return kGDistance;
    case 901:
    case 911:
      return kGIjkDistance;
    case 930:
    case 940:
      return kGFeedMode;
    default:
      return -1;
  }
}

int m_group(int code) {
  switch (code) {
    case 0:
    case 1:
    case 2:
    case 30:
      return kMStop;
    case 6:
      return kMToolChange;
    case 3:
    case 4:
    case 5:
      return kMSpindle;
    case 7:
    case 8:
    case 9:
      return kMCoolant;
    case 48:
    case 49:
    case 50:
      return kMOverride;
    default:
      return -1;
  }
}

std::string g_name(int code10) {
  return code10 % 10 == 0 ? fmt::format("G{}", code10 / 10)
                          : fmt::format("G{}.{}", code10 / 10, code10 % 10);
}

bool is_value_letter(char c) {
  switch (c) {
    case 'F':
    case 'H':
    case 'I':
    case 'J':
    case 'K':
    case 'N':
    case 'P':
    case 'Q':
    case 'R':
    case 'S':
    case 'T':
    case 'X':
    case 'Y':
    case 'Z':
      return true;
    default:
      return false;
  }
}

// Plane axes in LinuxCNC order: (a, b, normal).
struct PlaneAxes {
  int a, b, n;
};
PlaneAxes plane_axes(Plane p) {
  switch (p) {
    case Plane::XY:
      return {0, 1, 2};
    case Plane::XZ:
      return {2, 0, 1};
    case Plane::YZ:
      return {1, 2, 0};
  }
  return {0, 1, 2};
}

// The words of one block, by letter and group (grbl's parser_block_t).
struct BlockWords {
  std::array<const grammar::Word*, 26> value{};  // value words by letter
  std::array<int, kGGroups> g{};
  std::array<const grammar::Word*, kGGroups> g_word{};
  std::array<int, kMGroups> m{};
  std::array<const grammar::Word*, kMGroups> m_word{};
  const grammar::Word* first_axis = nullptr;

  const grammar::Word* operator[](char c) const { return value[static_cast<std::size_t>(c - 'A')]; }
  bool has(char c) const { return (*this)[c] != nullptr; }
  bool has_g(int group) const { return g_word[static_cast<std::size_t>(group)] != nullptr; }
  int gv(int group) const { return g[static_cast<std::size_t>(group)]; }
  bool has_m(int group) const { return m_word[static_cast<std::size_t>(group)] != nullptr; }
  int mv(int group) const { return m[static_cast<std::size_t>(group)]; }
};

bool fail(InterpError& err, ErrorCode code, SourceLoc loc, std::string msg) {
  err.code = code;
  err.loc = loc;
  err.message = std::move(msg);
  return false;
}

// Largest magnitude of a machine position (mm) or a feed (mm/min) handed downstream, and the
// largest tool number: beyond them a run's integer positions (BLU) and counts would overflow.
constexpr double kMaxPositionMm = 1e12;
constexpr double kMaxFeedMmMin = 1e12;
constexpr double kMaxToolNumber = 1e6;

bool within(double v, double limit) {
  return std::fabs(v) <= limit;
}  // false for NaN

bool near_integer(double v, double& rounded) {
  rounded = std::round(v);
  return std::fabs(v - rounded) < 1e-6;
}

}  // namespace

double arc_sweep_rad(const Motion& m) {
  const PlaneAxes ax = plane_axes(m.plane);
  const double t1 =
      std::atan2(m.start_mm[ax.b] - m.center_mm[ax.b], m.start_mm[ax.a] - m.center_mm[ax.a]);
  double t2 = std::atan2(m.end_mm[ax.b] - m.center_mm[ax.b], m.end_mm[ax.a] - m.center_mm[ax.a]);
  constexpr double two_pi = 2.0 * std::numbers::pi;
  const int extra = m.turns > 0 ? m.turns - 1 : 0;
  // LinuxCNC find_turn (interp_find.cc).
  if (m.ccw) {
    if (t2 <= t1) t2 += two_pi;
    return t2 - t1 + extra * two_pi;
  }
  if (t2 >= t1) t2 -= two_pi;
  return t2 - t1 - extra * two_pi;
}

double motion_length_mm(const Motion& m) {
  if (m.kind != MotionKind::Arc) return (m.end_mm - m.start_mm).norm();
  const PlaneAxes ax = plane_axes(m.plane);
  const double r1 =
      std::hypot(m.start_mm[ax.a] - m.center_mm[ax.a], m.start_mm[ax.b] - m.center_mm[ax.b]);
  const double r2 =
      std::hypot(m.end_mm[ax.a] - m.center_mm[ax.a], m.end_mm[ax.b] - m.center_mm[ax.b]);
  const double h = m.end_mm[ax.n] - m.start_mm[ax.n];
  return std::hypot(0.5 * (r1 + r2) * std::fabs(arc_sweep_rad(m)), h);
}

Interpreter::Interpreter(const Machine& machine) : machine_(machine) {}

AxisVec Interpreter::total_offset_mm() const {
  AxisVec off =
      machine_.work_offsets_mm[static_cast<std::size_t>(state_.coord_system)] + state_.g92_mm;
  off[2] += state_.tool_length_mm;
  return off;
}

bool Interpreter::execute(const grammar::Block& block, std::vector<Canon>& out, InterpError& err) {
  const int line = block.line;
  // STEP 1-2: import the words -----------------------------------------------------------------
  BlockWords w;
  for (std::size_t i = 0; i < block.words.size(); ++i) {
    const grammar::Word& word = block.words[i];
    const char c = word.letter;
    if (c == 'G' || c == 'M') {
      double r = 0;
      const double scaled = c == 'G' ? word.value * 10.0 : word.value;
      if (word.value < 0 || !near_integer(scaled, r) || r > 1e6)
        return fail(err, ErrorCode::BadCodeNumber, word.loc,
                    fmt::format("{}{:g} names no {} code", c, word.value, c));
      const int code = static_cast<int>(r);
      if (c == 'G') {
        const int grp = g_group(code);
        if (grp < 0)
          return fail(err, ErrorCode::UnknownGCode, word.loc,
                      fmt::format("{} is not supported", g_name(code)));
        const auto gi = static_cast<std::size_t>(grp);
        if (w.g_word[gi])
          return fail(err, ErrorCode::ModalGroupViolation, word.loc,
                      fmt::format("{} and {} are both in modal group {}", g_name(w.g[gi]),
                                  g_name(code), kGGroupNames[gi]));
        w.g[gi] = code;
        w.g_word[gi] = &word;
      } else {
        const int grp = m_group(code);
        if (grp < 0)
          return fail(err, ErrorCode::UnknownMCode, word.loc,
                      fmt::format("M{} is not supported", code));
        const auto mi = static_cast<std::size_t>(grp);
        if (w.m_word[mi])
          return fail(err, ErrorCode::ModalGroupViolation, word.loc,
                      fmt::format("M{} and M{} are both in modal group {}", w.m[mi], code,
                                  kMGroupNames[mi]));
        w.m[mi] = code;
        w.m_word[mi] = &word;
      }
      continue;
    }
    if (c == 'A' || c == 'B' || c == 'C' || c == 'U' || c == 'V' || c == 'W')
      return fail(err, ErrorCode::AxisUnavailable, word.loc,
                  fmt::format("axis {} is not available: this machine has X, Y and Z", c));
    if (!is_value_letter(c))
      return fail(err, ErrorCode::UnknownLetter, word.loc,
                  fmt::format("unknown word letter {}", c));
    if (c == 'N' && i != 0)
      return fail(err, ErrorCode::LineNumberNotFirst, word.loc,
                  "line number N must be the first word of the block");
    auto& slot = w.value[static_cast<std::size_t>(c - 'A')];
    if (slot)
      return fail(
          err, ErrorCode::DuplicateWord, word.loc,
          fmt::format("{} appears twice in the block (first at column {})", c, slot->loc.column));
    slot = &word;
    if ((c == 'X' || c == 'Y' || c == 'Z') && !w.first_axis) w.first_axis = &word;
  }

  // STEP 3: check against a copy of the state ---------------------------------------------------
  ModalState s = state_;
  const std::size_t out_mark = out.size();
  auto rollback = [&] {
    out.resize(out_mark);
    return false;
  };
  const bool has_axes = w.first_axis != nullptr;
  const bool g92_uses_axes = w.has_g(kGNonModal) && (w.gv(kGNonModal) == 920);
  int motion_to_be = -1;
  if (w.has_g(kGMotion))
    motion_to_be = w.gv(kGMotion) / 10;
  else if (has_axes && !g92_uses_axes)
    motion_to_be = s.motion;

  if (has_axes && g92_uses_axes && w.has_g(kGMotion))
    return fail(err, ErrorCode::ModalGroupViolation, w.g_word[kGMotion]->loc,
                fmt::format("G92 and {} both use the axis words", g_name(w.gv(kGMotion))));
  if (has_axes && !g92_uses_axes && motion_to_be < 0)
    return fail(err, ErrorCode::AxisWordsWithoutMotion, w.first_axis->loc,
                fmt::format("axis word {} with no motion mode (G0-G3) or G92 to use it",
                            w.first_axis->letter));
  const bool is_arc = motion_to_be == 2 || motion_to_be == 3;
  for (char c : {'I', 'J', 'K', 'R'})
    if (w.has(c) && !is_arc)
      return fail(err, ErrorCode::UnusedWord, w[c]->loc,
                  fmt::format("{} word with no G2 or G3 to use it", c));
  const bool g4 = w.has_g(kGNonModal) && w.gv(kGNonModal) == 40;
  const bool g64 = w.has_g(kGControl) && w.gv(kGControl) == 640;
  const bool m50 = w.has_m(kMOverride) && w.mv(kMOverride) == 50;
  if (w.has('P') && !(g4 || is_arc || g64 || m50))
    return fail(err, ErrorCode::UnusedWord, w['P']->loc,
                "P word with no G4, G2, G3, G64 or M50 to use it");
  if (w.has('Q') && !g64)
    return fail(err, ErrorCode::UnusedWord, w['Q']->loc, "Q word with no G64 to use it");
  const bool g43 = w.has_g(kGToolLength) && w.gv(kGToolLength) == 430;
  if (w.has('H') && !g43)
    return fail(err, ErrorCode::UnusedWord, w['H']->loc, "H word with no G43 to use it");
  for (char c : {'S', 'T', 'H'})
    if (w.has(c) && w[c]->value < 0)
      return fail(err, ErrorCode::NegativeValue, w[c]->loc,
                  fmt::format("{}{:g} is negative", c, w[c]->value));

  // STEP 4: execute on the copy in LinuxCNC's order ----------------------------------------------
  for (std::size_t i = 0; i < block.message_count; ++i)
    out.emplace_back(Event{line, EventKind::Message, block.messages[i].text});

  if (w.has_g(kGFeedMode)) {
    const bool to_inverse = w.gv(kGFeedMode) == 930;
    if (!to_inverse && s.inverse_time) s.feed_mm_min = 0.0;  // LinuxCNC: SET_FEED_RATE(0) on G94
    s.inverse_time = to_inverse;
  }
  double inverse_f = 0.0;
  if (w.has('F')) {
    const double f = w['F']->value;
    if (f < 0)
      return rollback() ||
             fail(err, ErrorCode::NegativeFeed, w['F']->loc, fmt::format("F{:g} is negative", f));
    if (s.inverse_time)
      inverse_f = f;
    else
      s.feed_mm_min = f * (s.inch ? units::kMmPerInch : 1.0);  // units before this block's G20/G21
    if (!within(s.feed_mm_min, kMaxFeedMmMin))
      return rollback() || fail(err, ErrorCode::ValueOutOfRange, w['F']->loc,
                                fmt::format("F{:g} is {:g} mm/min, beyond {:g} mm/min", f,
                                            s.feed_mm_min, kMaxFeedMmMin));
  }
  if (w.has('T')) {
    double t = 0;
    if (!near_integer(w['T']->value, t))
      return rollback() || fail(err, ErrorCode::BadCodeNumber, w['T']->loc,
                                fmt::format("T{:g} is not an integer", w['T']->value));
    if (t > kMaxToolNumber)
      return rollback() ||
             fail(err, ErrorCode::ValueOutOfRange, w['T']->loc,
                  fmt::format("T{:g}: tool numbers go up to {:g}", t, kMaxToolNumber));
    s.tool_selected = static_cast<int>(t);
  }
  if (w.has_m(kMToolChange)) s.tool_in_spindle = s.tool_selected;
  if (w.has_m(kMOverride)) {
    const int m = w.mv(kMOverride);
    EventKind k = m == 49 ? EventKind::OverrideDisable : EventKind::OverrideEnable;
    if (m == 50 && w.has('P')) {
      const double p = w['P']->value;
      if (p == 0.0)
        k = EventKind::OverrideDisable;
      else if (p != 1.0)
        return rollback() || fail(err, ErrorCode::BadPWord, w['P']->loc,
                                  fmt::format("M50 P{:g}: P must be 0 or 1", p));
    }
    out.emplace_back(Event{line, k, {}});
  }
  if (g4) {
    if (!w.has('P'))
      return rollback() || fail(err, ErrorCode::DwellWithoutP, w.g_word[kGNonModal]->loc,
                                "G4 without P (dwell seconds)");
    const double p = w['P']->value;
    if (p < 0)
      return rollback() || fail(err, ErrorCode::NegativeDwell, w['P']->loc,
                                fmt::format("G4 P{:g}: negative dwell", p));
    out.emplace_back(Dwell{line, p});
  }
  if (w.has_g(kGPlane)) {
    const int g = w.gv(kGPlane);
    s.plane = g == 170 ? Plane::XY : g == 180 ? Plane::XZ : Plane::YZ;
  }
  if (w.has_g(kGUnits)) s.inch = w.gv(kGUnits) == 200;
  if (g43) {
    double tool = s.tool_in_spindle;  // H may be any size: compared as a double, never cast first
    if (w.has('H')) {
      if (!near_integer(w['H']->value, tool))
        return rollback() || fail(err, ErrorCode::BadCodeNumber, w['H']->loc,
                                  fmt::format("H{:g} is not an integer", w['H']->value));
    }
    const auto n = machine_.tool_lengths_mm.size();
    if (tool < static_cast<double>(n))
      s.tool_length_mm = machine_.tool_lengths_mm[static_cast<std::size_t>(tool)];
    else if (tool == 0)
      s.tool_length_mm = 0.0;
    else
      return rollback() ||
             fail(err, ErrorCode::ToolNumberOutOfRange,
                  w.has('H') ? w['H']->loc : w.g_word[kGToolLength]->loc,
                  fmt::format("tool {:g} has no length: the machine's tool table has {} entries",
                              tool, n));
  } else if (w.has_g(kGToolLength)) {
    s.tool_length_mm = 0.0;  // G49
  }
  if (w.has_g(kGCoord)) s.coord_system = (w.gv(kGCoord) - 540) / 10;
  if (w.has_g(kGControl)) {
    const int g = w.gv(kGControl);
    // LinuxCNC: G61 = exact path, G61.1 = exact stop, G64 = continuous (P/Q ignored here).
    s.path_mode = g == 610   ? PathMode::ExactPath
                  : g == 611 ? PathMode::ExactStop
                             : PathMode::Continuous;
    if (g == 640) {  // G64 P<path tolerance> Q<naive CAM tolerance>, in program units (issue 21)
      const double u = s.inch ? units::kMmPerInch : 1.0;
      for (char c : {'P', 'Q'})
        if (w.has(c) && !(w[c]->value >= 0.0))
          return rollback() || fail(err, ErrorCode::ValueOutOfRange, w[c]->loc,
                                    fmt::format("G64 {} must not be negative", c));
      s.path_tolerance_mm = w.has('P') ? w['P']->value * u : -1.0;
      s.naive_cam_tolerance_mm = w.has('Q') ? w['Q']->value * u : 0.0;
    }
  }
  if (w.has_g(kGDistance)) s.incremental = w.gv(kGDistance) == 910;
  if (w.has_g(kGIjkDistance)) s.ijk_absolute = w.gv(kGIjkDistance) == 901;

  const double scale = s.inch ? units::kMmPerInch : 1.0;
  auto offset_of = [&](const ModalState& st) {
    AxisVec off = machine_.work_offsets_mm[static_cast<std::size_t>(st.coord_system)] + st.g92_mm;
    off[2] += st.tool_length_mm;
    return off;
  };

  if (w.has_g(kGNonModal) && w.gv(kGNonModal) == 920) {  // G92
    if (!has_axes)
      return rollback() || fail(err, ErrorCode::G92WithoutAxes, w.g_word[kGNonModal]->loc,
                                "G92 without axis words");
    for (int i = 0; i < kAxes; ++i) {
      const auto* aw = w[kAxisLetters[static_cast<std::size_t>(i)]];
      if (!aw) continue;
      // The current point gets coordinate value: machine = program + work + g92 + tool.
      s.g92_mm[i] = 0.0;
      const AxisVec off = offset_of(s);
      s.g92_mm[i] = s.position_mm[i] - off[i] - aw->value * scale;
    }
  } else if (w.has_g(kGNonModal) && w.gv(kGNonModal) == 921) {
    s.g92_mm.setZero();
  }

  if (w.has_g(kGMotion)) s.motion = w.gv(kGMotion) / 10;

  if (motion_to_be >= 0) {
    const SourceLoc mloc = w.has_g(kGMotion) ? w.g_word[kGMotion]->loc
                           : w.first_axis    ? w.first_axis->loc
                                             : SourceLoc{line, 1};
    if (motion_to_be >= 1) {
      if (s.inverse_time) {
        if (!w.has('F'))
          return rollback() ||
                 fail(err, ErrorCode::InverseTimeFeedMissing, mloc,
                      fmt::format("G{} in inverse time mode (G93) without F on the block",
                                  motion_to_be));
        if (inverse_f <= 0.0)
          return rollback() || fail(err, ErrorCode::ZeroFeed, w['F']->loc,
                                    fmt::format("G{} with F0 in inverse time mode", motion_to_be));
      } else if (s.feed_mm_min <= 0.0) {
        return rollback() ||
               fail(err, ErrorCode::ZeroFeed, mloc,
                    fmt::format("G{} with zero feed rate (no F yet, or F0)", motion_to_be));
      }
    }
    const AxisVec off = offset_of(s);
    AxisVec target = s.position_mm;
    for (int i = 0; i < kAxes; ++i) {
      const auto* aw = w[kAxisLetters[static_cast<std::size_t>(i)]];
      if (!aw) continue;
      target[i] = s.incremental ? s.position_mm[i] + aw->value * scale : aw->value * scale + off[i];
    }
    for (int i = 0; i < kAxes; ++i) {
      if (within(target[i], kMaxPositionMm)) continue;
      const auto* aw = w[kAxisLetters[static_cast<std::size_t>(i)]];
      return rollback() ||
             fail(err, ErrorCode::ValueOutOfRange, aw ? aw->loc : mloc,
                  fmt::format("{} would move to {:g} mm (offsets included), outside -{:g}..{:g} mm",
                              kAxisLetters[static_cast<std::size_t>(i)], target[i], kMaxPositionMm,
                              kMaxPositionMm));
    }
    Motion mo;
    mo.line = line;
    mo.start_mm = s.position_mm;
    mo.end_mm = target;
    mo.plane = s.plane;
    mo.path_mode = w.has_g(kGExactStop) ? PathMode::ExactStop : s.path_mode;
    if (mo.path_mode == PathMode::Continuous) {
      mo.path_tolerance_mm =
          s.path_tolerance_mm >= 0.0 ? s.path_tolerance_mm : machine_.path_tolerance_mm;
      mo.naive_cam_tolerance_mm = s.naive_cam_tolerance_mm;
    }
    mo.kind = motion_to_be == 0   ? MotionKind::Rapid
              : motion_to_be == 1 ? MotionKind::Line
                                  : MotionKind::Arc;
    if (mo.kind == MotionKind::Arc) {
      const PlaneAxes ax = plane_axes(s.plane);
      const char la = "IJK"[ax.a], lb = "IJK"[ax.b], ln = "IJK"[ax.n];
      if (w.has(ln))
        return rollback() || fail(err, ErrorCode::ArcOffsetWrongPlane, w[ln]->loc,
                                  fmt::format("{} word given for an arc in the {} plane (G{})", ln,
                                              s.plane == Plane::XY   ? "XY"
                                              : s.plane == Plane::XZ ? "XZ"
                                                                     : "YZ",
                                              s.plane == Plane::XY   ? 17
                                              : s.plane == Plane::XZ ? 18
                                                                     : 19));
      if (w.has('R') && (w.has(la) || w.has(lb)))
        return rollback() || fail(err, ErrorCode::ArcRWithIjk, w['R']->loc,
                                  "R given together with I/J/K for an arc");
      if (!w.has('R') && !w.has(la) && !w.has(lb))
        return rollback() ||
               fail(err, ErrorCode::ArcMissingCenter, mloc,
                    fmt::format("arc without R and without {} or {} (centre unknown)", la, lb));
      int turns = 1;
      if (w.has('P')) {
        double p = 0;
        if (!near_integer(w['P']->value, p) || p < 1 || p > 1e6)
          return rollback() ||
                 fail(err, ErrorCode::BadPWord, w['P']->loc,
                      fmt::format("arc P{:g}: P must be an integer of 1 or more (turns)",
                                  w['P']->value));
        turns = static_cast<int>(p);
      }
      ArcInput in;
      in.start_a = (s.position_mm[ax.a] - off[ax.a]) / scale;
      in.start_b = (s.position_mm[ax.b] - off[ax.b]) / scale;
      in.end_a = (target[ax.a] - off[ax.a]) / scale;
      in.end_b = (target[ax.b] - off[ax.b]) / scale;
      in.use_r = w.has('R');
      in.r = in.use_r ? w['R']->value : 0.0;
      in.off_a = w.has(la) ? w[la]->value : 0.0;
      in.off_b = w.has(lb) ? w[lb]->value : 0.0;
      in.offsets_absolute = s.ijk_absolute;
      in.ccw = motion_to_be == 3;
      in.mm_per_unit = scale;
      in.rule = machine_.arc_rule;
      ArcResult ar = compute_arc(in);
      if (ar.error != ErrorCode::None) {
        const SourceLoc aloc = in.use_r ? w['R']->loc : w.has(la) ? w[la]->loc : w[lb]->loc;
        return rollback() || fail(err, ar.error, aloc, std::move(ar.message));
      }
      mo.center_mm = s.position_mm;
      mo.center_mm[ax.a] = s.position_mm[ax.a] + ar.rel_a * scale;
      mo.center_mm[ax.b] = s.position_mm[ax.b] + ar.rel_b * scale;
      for (const int i : {ax.a, ax.b}) {
        if (within(mo.center_mm[i], kMaxPositionMm)) continue;
        const SourceLoc aloc = in.use_r ? w['R']->loc : w.has(la) ? w[la]->loc : w[lb]->loc;
        return rollback() || fail(err, ErrorCode::ValueOutOfRange, aloc,
                                  fmt::format("arc centre {} = {:g} mm, outside -{:g}..{:g} mm",
                                              kAxisLetters[static_cast<std::size_t>(i)],
                                              mo.center_mm[i], kMaxPositionMm, kMaxPositionMm));
      }
      mo.ccw = in.ccw;
      mo.turns = turns;
    }
    const bool zero_length = mo.kind != MotionKind::Arc && mo.end_mm == mo.start_mm;
    if (!zero_length) {
      if (mo.kind != MotionKind::Rapid) {
        if (s.inverse_time) {
          // LinuxCNC (interp_inverse.cc): rate = MAX(0.1, length × F) in program units/min.
          const double length_mm = motion_length_mm(mo);
          mo.feed_mm_min = std::max(0.1 * scale, length_mm * inverse_f);
          mo.inverse_time_s = units::kSecondsPerMinute * length_mm / mo.feed_mm_min;
          if (!within(mo.feed_mm_min, kMaxFeedMmMin))
            return rollback() ||
                   fail(err, ErrorCode::ValueOutOfRange, w['F']->loc,
                        fmt::format("G93 F{:g} over {:g} mm is {:g} mm/min, beyond {:g} mm/min",
                                    inverse_f, length_mm, mo.feed_mm_min, kMaxFeedMmMin));
        } else {
          mo.feed_mm_min = s.feed_mm_min;
        }
      }
      out.emplace_back(mo);
    }
    s.position_mm = target;
  }

  if (w.has_m(kMStop)) {
    const int m = w.mv(kMStop);
    const EventKind k = m == 0   ? EventKind::Pause
                        : m == 1 ? EventKind::OptionalPause
                                 : EventKind::End;
    out.emplace_back(Event{line, k, {}});
    if (k == EventKind::End) s.ended = true;
  }

  // Commit.
  state_ = s;
  return true;
}

}  // namespace gm
