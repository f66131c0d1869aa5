// Fanuc's modal rules on each block before LinuxCNC's interpreter runs it (--dialect fanuc,
// haas): the group 01 mode after G80, polar coordinates (G15/G16), coordinate rotation
// (G68/G69), scaling (G51/G50), programmable mirror image (G51.1/G50.1) and G41/G42 H.
#include "interp/fanuc_modal.hpp"

#include "common/error_codes.hpp"
#include "interp/block_edit.hpp"
#include "interp/codes.hpp"
#include "interp/frame.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace gm {

namespace {

namespace be = block_edit;
using V3 = std::array<double, 3>;
constexpr std::array<char, 3> kXyz{'X', 'Y', 'Z'};
constexpr double kDegToRad = std::numbers::pi / 180.0;

// The code x 10 of G word `w` (G51.1 = 511), -1 when it is not a tenth.
int code10(const grammar::Word& w) {
  const double t = w.value * 10.0;
  if (!(t >= 0.0 && t < 1e5)) return -1;
  const int n = static_cast<int>(t + 0.5);
  return std::fabs(t - n) < 1e-6 ? n : -1;
}

// On a lathe G50 is the lathe's (coordinate setting, spindle clamp), not the end of scaling.
bool ours(int n10, bool lathe) {
  switch (n10) {
    case 500:
      return !lathe;
    case 150:
    case 160:
    case 501:
    case 510:
    case 511:
    case 680:
    case 690:
      return true;
    default:
      return false;
  }
}

bool axis_letter(char c) {
  return c == 'X' || c == 'Y' || c == 'Z' || c == 'A' || c == 'B' || c == 'C' || c == 'U' ||
         c == 'V' || c == 'W';
}

Plane block_plane(const grammar::Block& b, const ModalState& s) {
  if (be::find_code(b, 'G', 170) != be::kNone) return Plane::XY;
  if (be::find_code(b, 'G', 180) != be::kNone) return Plane::XZ;
  if (be::find_code(b, 'G', 190) != be::kNone) return Plane::YZ;
  return s.plane;
}

bool block_incremental(const grammar::Block& b, const ModalState& s) {
  if (be::find_code(b, 'G', 910) != be::kNone) return true;
  if (be::find_code(b, 'G', 900) != be::kNone) return false;
  return s.incremental;
}

// The programmed point (program units, the active work system) the interpreter is at: under
// cutter compensation the uncompensated point.
V3 interpreter_point(const ModalState& s) {
  Pos9 m = s.position_mm;
  if (s.comp.on() && !s.comp.first_move) {
    const PlaneAxes pa = plane_axes(s.plane);
    m[pa.a] = s.comp.prog_a;
    m[pa.b] = s.comp.prog_b;
  }
  const Pos9 p = Frame(s).to_program(m);
  const double u = s.mm_per_unit();
  return {p[0] / u, p[1] / u, p[2] / u};
}

// Left-composes `t` with the diagonal map q_i = f_i (p_i - c_i) + c_i.
void then_diagonal(FanucModal::Affine& t, const V3& f, const V3& c) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) t.a[i][j] *= f[i];
    t.b[i] = f[i] * (t.b[i] - c[i]) + c[i];
  }
}

// Left-composes `t` with the turn by `deg` counter-clockwise about (ca, cb) in plane (i, j).
void then_rotation(FanucModal::Affine& t, int i, int j, double deg, double ca, double cb) {
  const double c = std::cos(deg * kDegToRad), s = std::sin(deg * kDegToRad);
  for (int k = 0; k < 3; ++k) {
    const double x = t.a[i][k], y = t.a[j][k];
    t.a[i][k] = c * x - s * y;
    t.a[j][k] = s * x + c * y;
  }
  const double x = t.b[i] - ca, y = t.b[j] - cb;
  t.b[i] = c * x - s * y + ca;
  t.b[j] = s * x + c * y + cb;
}

// `G42 H19` (FANUC 0M programs): the cutter radius offset numbered by H, as a Fanuc control
// reads it with parameter OFH (No. 5001 #2) set to 1; run as `G42 D19` (the radius of the tool
// table's entry 19). Left alone when the block has a D, or a code that takes H itself (G43 H).
void radius_offset_by_h(grammar::Block& b) {
  grammar::Word* h = nullptr;
  for (grammar::Word& w : b.words) {
    if (w.letter == 'D') return;
    if (w.letter == 'H') h = &w;
    if (w.letter != 'G') continue;
    const int n = code10(w);
    if (n == 410 || n == 420) continue;
    const Code* c = find_code('G', n);
    if (c != nullptr && (c->word_mask & letter_mask("H")) != 0) return;
  }
  if (h != nullptr) h->letter = 'D';
}

}  // namespace

V3 FanucModal::Affine::map(const V3& p) const {
  V3 q = turn(p);
  for (int i = 0; i < 3; ++i) q[i] += b[i];
  return q;
}

V3 FanucModal::Affine::turn(const V3& v) const {
  V3 q{};
  for (int i = 0; i < 3; ++i) q[i] = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
  return q;
}

bool FanucModal::Affine::invert(Affine& inv) const {
  const auto& m = a;
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  if (!(std::fabs(det) > 1e-12)) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      inv.a[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / det;
    }
  const V3 t = inv.turn(b);
  for (int i = 0; i < 3; ++i) inv.b[i] = -t[i];
  return true;
}

FanucModal::Affine FanucModal::transform() const {
  Affine t;
  if (mirroring()) {
    V3 f{1, 1, 1};
    for (int i = 0; i < 3; ++i) f[i] = mirror_[i] ? -1.0 : 1.0;
    then_diagonal(t, f, mirror_centre_);
  }
  if (scaling_) then_diagonal(t, scale_, scale_centre_);
  if (rotating_) {
    const PlaneAxes pa = plane_axes(static_cast<Plane>(rotation_plane_));
    then_rotation(t, pa.a, pa.b, rotation_deg_, rotation_ca_, rotation_cb_);
  }
  return t;
}

bool FanucModal::apply(grammar::Block& block, const ModalState& s, InterpError& err) {
  bool has_ours = false, g80 = false, comp = false;
  for (const grammar::Word& w : block.words) {
    if (w.letter != 'G') continue;
    const int n = code10(w);
    if (n == 0 || n == 10 || n == 20 || n == 30) {
      group01_ = n;
    } else {
      g80 = g80 || n == 800;
      comp = comp || n == 410 || n == 420;
      has_ours = has_ours || ours(n, lathe_);
    }
  }
  if (comp && !lathe_) radius_offset_by_h(block);
  // The G80 rule looks at the block only after G80, with it, or after a mirrored arc.
  const bool modal = g80 || s.motion == 800 || swapped_;
  if (!has_ours && !active()) {
    if (modal) group01(block, s);
    return true;
  }
  const V3 q_cur = interpreter_point(s);
  V3 p_cur = q_cur;  // the programmed point under the transform before this block
  if (Affine inv; transform().invert(inv)) p_cur = inv.map(q_cur);
  if (has_ours && !modes(block, s, q_cur, p_cur, err)) return false;
  if (modal) group01(block, s);  // on the axis words the transform codes left
  if (!active()) return true;
  Affine inv;
  if (!transform().invert(inv))
    return fail(err, ErrorCode::ValueOutOfRange, SourceLoc{block.line, 1},
                "the scaling makes the coordinates degenerate");
  return rewrite(block, s, q_cur, inv.map(q_cur), err);
}

// Axis words after G80 (or with it) and no motion code move in the group 01 mode in force:
// Fanuc keeps G00-G03 (group 01) apart from the canned cycles (group 09), which G80 cancels.
void FanucModal::group01(grammar::Block& block, const ModalState& s) {
  int motion = -1;
  std::size_t at = be::kNone, g80 = be::kNone, g0123 = be::kNone;
  bool axes = false, axis_user = false;
  for (std::size_t i = 0; i < block.words.size(); ++i) {
    const grammar::Word& w = block.words[i];
    if (axis_letter(w.letter)) axes = true;
    if (w.letter != 'G') continue;
    const int n = code10(w);
    if (n == 0 || n == 10 || n == 20 || n == 30 || n == 800) {  // (the common ones first)
      motion = n;
      at = i;
      (n == 800 ? g80 : g0123) = i;
      continue;
    }
    const Code* c = n < 0 ? nullptr : find_code('G', n);
    if (c == nullptr) continue;
    if (c->group == Group::Motion) {
      motion = n;
      at = i;
    }
    if (c->uses_axes || n == 530) axis_user = true;
  }
  // `G00 G80 Z100.`: two groups on Fanuc, one (motion) in LinuxCNC, where the G00 alone
  // already ends the cycle: the G80 goes.
  if (g80 != be::kNone && g0123 != be::kNone) {
    block.words.erase(block.words.begin() + static_cast<std::ptrdiff_t>(g80));
    return;
  }
  if (!axes || axis_user || group01_ < 0) return;
  const bool restore = swapped_ && s.motion != group01_ && s.motion >= 0 && s.motion <= 30;
  swapped_ = false;
  if (motion == 800) {
    block.words[at].value = group01_ / 10.0;
  } else if (motion < 0 && (s.motion == 800 || restore)) {
    block.words.push_back(grammar::Word{'G', group01_ / 10.0, block.words.front().loc});
  }
}

// The transform codes of the block, taken out with their words.
bool FanucModal::modes(grammar::Block& block, const ModalState& s, const V3& q_cur, const V3& p_cur,
                       InterpError& err) {
  const Plane plane = block_plane(block, s);
  const PlaneAxes pa = plane_axes(plane);
  int with_words = 0;  // codes whose words are theirs: one per block
  for (std::size_t i = 0; i < block.words.size();) {
    const grammar::Word w = block.words[i];
    const int n = w.letter == 'G' ? code10(w) : -1;
    if (!ours(n, lathe_)) {
      ++i;
      continue;
    }
    be::erase(block, i);
    const bool takes_words = n == 680 || n == 510 || n == 511 || n == 501;
    if (takes_words && ++with_words > 1)
      return fail(err, ErrorCode::ModalGroupViolation, w.loc,
                  "one of G68, G51, G51.1 and G50.1 per block (each takes the axis words)");
    // The value of word `c` (taken out of the block), or `fallback`.
    auto take = [&block](char c, double fallback, bool& given) {
      const std::size_t k = be::find(block, c);
      given = k != be::kNone;
      if (!given) return fallback;
      const double v = block.words[k].value;
      be::erase(block, k);
      return v;
    };
    bool given = false;
    switch (n) {
      case 160:  // G16: X (first axis) the radius, Y (second) the angle
        polar_ = true;
        polar_plane_ = static_cast<int>(plane);
        break;
      case 150:
        polar_ = false;
        break;
      case 690:
        rotating_ = false;
        break;
      case 680: {  // G68 a b R: about (a, b), the tool's point when not given
        rotation_plane_ = static_cast<int>(plane);
        rotation_ca_ = take(kXyz[static_cast<std::size_t>(pa.a)],
                            q_cur[static_cast<std::size_t>(pa.a)], given);
        rotation_cb_ = take(kXyz[static_cast<std::size_t>(pa.b)],
                            q_cur[static_cast<std::size_t>(pa.b)], given);
        rotation_deg_ = take('R', 0.0, given);
        if (!given)
          return fail(err, ErrorCode::MissingWord, w.loc,
                      "G68 needs R, the angle (the control's default angle parameter is not "
                      "modelled)");
        rotating_ = true;
        break;
      }
      case 500:
        scaling_ = false;
        scale_ = {1, 1, 1};
        break;
      case 510: {  // G51 X Y Z (centre, else the programmed point) P (all axes) or I J K
        V3 c{}, f{1, 1, 1};
        for (int a = 0; a < 3; ++a) c[a] = take(kXyz[a], p_cur[a], given);
        bool any = false;
        const double p = take('P', 1.0, given);
        if (given) f = {p, p, p};
        any = given;
        for (int a = 0; a < 3; ++a) {
          f[a] = take(static_cast<char>('I' + a), f[a], given);
          any = any || given;
        }
        if (!any)
          return fail(err, ErrorCode::MissingWord, w.loc,
                      "G51 needs P (the factor) or I J K (per axis; the control's default "
                      "factor setting is not modelled)");
        for (int a = 0; a < 3; ++a)
          if (!(std::fabs(f[a]) >= 1e-6 && std::fabs(f[a]) <= 1e6))
            return fail(err, ErrorCode::ValueOutOfRange, w.loc,
                        fmt::format("G51: scaling factor {:g} (0.000001 to 1000000, negative "
                                    "mirrors)",
                                    f[a]));
        scaling_ = true;
        scale_ = f;
        scale_centre_ = c;
        break;
      }
      case 511:    // G51.1 X Y Z: mirror image about the given positions
      case 501: {  // G50.1 X Y Z: cancel it on those axes (all when none is given)
        bool any = false;
        for (int a = 0; a < 3; ++a) {
          const double v = take(kXyz[a], 0.0, given);
          if (!given) continue;
          any = true;
          mirror_[a] = n == 511;
          mirror_centre_[a] = v;
        }
        if (!any && n == 501) mirror_ = {false, false, false};
        if (!any && n == 511)
          return fail(err, ErrorCode::MissingWord, w.loc,
                      "G51.1 needs the axes to mirror (X, Y, Z: the mirror's position)");
        break;
      }
      default:
        break;
    }
  }
  return true;
}

// The axis words (and I J K R of arcs, Z R of cycles) of the block's motion in the coordinates
// the interpreter reads.
bool FanucModal::rewrite(grammar::Block& block, const ModalState& s, const V3& q_cur,
                         const V3& p_cur, InterpError& err) {
  const Affine t = transform();
  const Plane plane = block_plane(block, s);
  const PlaneAxes pa = plane_axes(plane);
  const auto at = [](const V3& v, int i) { return v[static_cast<std::size_t>(i)]; };
  // The arc plane's determinant: negative under a mirror image (G2 runs as G3, G41 as G42).
  const double det = t.a[pa.a][pa.a] * t.a[pa.b][pa.b] - t.a[pa.a][pa.b] * t.a[pa.b][pa.a];
  if (det < 0.0)
    for (grammar::Word& w : block.words)
      if (w.letter == 'G' && (code10(w) == 410 || code10(w) == 420))
        w.value = code10(w) == 410 ? 42.0 : 41.0;
  int motion = -1;
  std::size_t motion_at = be::kNone;
  bool axes = false;
  for (std::size_t i = 0; i < block.words.size(); ++i) {
    const grammar::Word& w = block.words[i];
    if (w.letter >= 'X' && w.letter <= 'Z') axes = true;
    if (w.letter != 'G') continue;
    const int n = code10(w);
    const Code* c = n < 0 ? nullptr : find_code('G', n);
    if (c == nullptr) continue;
    if (c->uses_axes || n == 530) return true;  // G10 G28 G30 G52 G53 G92: as written
    if (c->group == Group::Motion) {
      motion = n;
      motion_at = i;
    }
  }
  if (motion < 0) motion = s.motion;
  const bool arc = motion == 20 || motion == 30;
  const bool cycle = motion == 730 || motion == 740 || (motion >= 810 && motion <= 890);
  const bool straight = motion == 0 || motion == 10 || (motion >= 382 && motion <= 385);
  bool arc_words = false;
  for (const char c : {'I', 'J', 'K', 'R'})
    arc_words = arc_words || be::find(block, c) != be::kNone;
  if (!axes && !(arc && arc_words)) return true;
  const SourceLoc loc = block.words.front().loc;
  if (!arc && !cycle && !straight)
    return fail(err, ErrorCode::NotInDialect, loc,
                fmt::format("{} under G16/G68/G51/G51.1 is not read (G0-G3, G38.x and the "
                            "drilling cycles are)",
                            motion < 0 ? std::string("no motion mode") : code_name('G', motion)));
  if (cycle &&
      (plane != Plane::XY || (rotating_ && rotation_plane_ != 0) || (polar_ && polar_plane_ != 0)))
    return fail(err, ErrorCode::NotInDialect, loc,
                "drilling cycles under G16/G68 are read in the XY plane (G17) only");
  const bool incremental = block_incremental(block, s);
  std::array<bool, 3> given{};
  V3 p = p_cur;
  for (int a = 0; a < 3; ++a) {
    if (cycle && a == 2) continue;  // the cycle's Z is a depth: below
    const grammar::Word* w = be::word(block, kXyz[static_cast<std::size_t>(a)]);
    if (w == nullptr) continue;
    given[a] = true;
    p[a] = incremental ? p_cur[a] + w->value : w->value;
  }
  if (polar_) {  // G16: the first axis word is the radius, the second the angle (degrees)
    const PlaneAxes pp = plane_axes(static_cast<Plane>(polar_plane_));
    const grammar::Word* rw = be::word(block, kXyz[static_cast<std::size_t>(pp.a)]);
    const grammar::Word* aw = be::word(block, kXyz[static_cast<std::size_t>(pp.b)]);
    if ((rw != nullptr || aw != nullptr) && !(cycle && (pp.a == 2 || pp.b == 2))) {
      const double r_cur = std::hypot(at(p_cur, pp.a), at(p_cur, pp.b));
      const double th_cur = std::atan2(at(p_cur, pp.b), at(p_cur, pp.a)) / kDegToRad;
      double ox = 0.0, oy = 0.0, r = r_cur, th = th_cur;
      if (!incremental) {  // about the work zero: radius and angle absolute
        if (rw != nullptr) r = rw->value;
        if (aw != nullptr) th = aw->value;
      } else if (rw != nullptr) {  // G91 radius: from the current point, at the angle so far
        ox = at(p_cur, pp.a);
        oy = at(p_cur, pp.b);
        r = rw->value;
        if (aw != nullptr) th += aw->value;
      } else {  // G91 angle alone: about the work zero, the radius kept
        th += aw->value;
      }
      p[pp.a] = ox + r * std::cos(th * kDegToRad);
      p[pp.b] = oy + r * std::sin(th * kDegToRad);
      given[pp.a] = given[pp.b] = true;
    }
  }
  if (rotating_) {
    const PlaneAxes rp = plane_axes(static_cast<Plane>(rotation_plane_));
    if (given[rp.a] || given[rp.b]) given[rp.a] = given[rp.b] = true;
  }
  const V3 q = t.map(p);
  for (int a = 0; a < 3; ++a)
    if (given[a]) be::set(block, kXyz[a], incremental ? q[a] - q_cur[a] : q[a], loc);
  if (cycle) {  // Z (bottom) and R (retract plane): along Z, scaled and mirrored only
    for (const char c : {'Z', 'R'}) {
      const std::size_t k = be::find(block, c);
      if (k == be::kNone) continue;
      const double v = block.words[k].value;
      block.words[k].value = incremental ? t.a[2][2] * v : t.a[2][2] * v + t.b[2];
    }
  }
  if (!arc) return true;
  if (s.ijk_absolute || be::find_code(block, 'G', 901) != be::kNone)
    return fail(err, ErrorCode::NotInDialect, loc,
                "G90.1 (absolute arc centres) under G68/G51/G51.1 is not read");
  const char ci = static_cast<char>('I' + pa.a), cj = static_cast<char>('I' + pa.b);
  if (be::find(block, ci) != be::kNone || be::find(block, cj) != be::kNone) {
    V3 v{};
    for (int a = 0; a < 3; ++a)
      if (const grammar::Word* w = be::word(block, static_cast<char>('I' + a))) v[a] = w->value;
    const V3 u = t.turn(v);
    be::set(block, ci, at(u, pa.a), loc);
    be::set(block, cj, at(u, pa.b), loc);
  }
  if (const std::size_t k = be::find(block, 'R'); k != be::kNone) {
    // R scales with the plane when the plane keeps its shape (equal factors).
    const double c1 = std::hypot(t.a[pa.a][pa.a], t.a[pa.b][pa.a]);
    const double c2 = std::hypot(t.a[pa.a][pa.b], t.a[pa.b][pa.b]);
    if (std::fabs(c1 - c2) > 1e-9 * std::max(c1, c2))
      return fail(err, ErrorCode::NotInDialect, block.words[k].loc,
                  "an R arc under unequal scaling factors would be an ellipse: not read");
    block.words[k].value *= c1;
  }
  if (det < 0.0) {  // a mirror image turns the arc the other way
    const double swapped = motion == 20 ? 3.0 : 2.0;
    if (motion_at != be::kNone)
      block.words[motion_at].value = swapped;
    else
      block.words.push_back(grammar::Word{'G', swapped, loc});
    swapped_ = true;
  }
  return true;
}

}  // namespace gm
