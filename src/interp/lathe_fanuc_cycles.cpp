// The Fanuc/Haas lathe cycles in their two-block forms: G71/G72 roughing and G70 finishing over
// the blocks Nns..Nnf, G76 threading, as moves the interpreter then runs as G0-G3/G33 blocks.
#include "interp/frame.hpp"
#include "interp/lathe_fanuc.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace gm {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTol = 1e-9;
constexpr long kMaxLayers = 100000;
constexpr double kMaxProfileWork = 5e7;  ///< layers x profile elements one G71/G72 may walk
constexpr int kMaxThreadPasses = 10000;

using Kind = LatheMove::Kind;

bool is_arc(Kind k) {
  return k == Kind::ArcCw || k == Kind::ArcCcw;
}

// The words of a cycle block, by letter (null when absent).
struct Words {
  std::array<const grammar::Word*, 26> w{};
  explicit Words(const grammar::Block& b) {
    for (const grammar::Word& x : b.words)
      if (x.letter >= 'A' && x.letter <= 'Z' && x.letter != 'G')
        w[static_cast<std::size_t>(x.letter - 'A')] = &x;
  }
  const grammar::Word* operator[](char c) const { return w[static_cast<std::size_t>(c - 'A')]; }
  bool has(char c) const { return (*this)[c] != nullptr; }
  double get(char c, double fallback = 0.0) const { return has(c) ? (*this)[c]->value : fallback; }
};

// The words a cycle line may carry; false with the error at the first other one.
bool only_words(const grammar::Block& b, int code, std::string_view allowed, InterpError& err) {
  for (const grammar::Word& x : b.words) {
    if (x.letter == 'N' || allowed.find(x.letter) != std::string_view::npos) continue;
    if (x.letter == 'G' && std::fabs(x.value - code) < 1e-9) continue;
    return fail(err, ErrorCode::UnusedWord, x.loc,
                fmt::format("{}{:g} on a G{} line: a Fanuc lathe G{} takes {}", x.letter, x.value,
                            code, code, allowed));
  }
  return true;
}

// A sequence number word (P ns, Q nf): an integer 1..99999.
bool sequence_word(const grammar::Word* w, int code, long& n, InterpError& err) {
  if (std::fabs(w->value - std::round(w->value)) > 1e-9 || w->value < 1 || w->value > 99999)
    return fail(err, ErrorCode::ValueOutOfRange, w->loc,
                fmt::format("G{} {}{:g}: a sequence number 1-99999 (the profile's {} block N)",
                            code, w->letter, w->value, w->letter == 'P' ? "first" : "last"));
  n = std::lround(w->value);
  return true;
}

// Where the tool is, program units of the ZX plane (X a radius).
void program_point(const ModalState& s, double& z, double& x) {
  const Pos9 p = Frame(s).to_program(s.position_mm);
  z = p[2] / s.mm_per_unit();
  x = p[0] / s.mm_per_unit();
}

// The end point of a block's X/U and Z/W words from (z, x) (X a radius; xs: 0.5 when X words
// are diameters). False with `err` when U and X, or W and Z, share the block.
bool word_end(const Words& w, double xs, double& z, double& x, InterpError& err) {
  if (w.has('X') && w.has('U'))
    return fail(err, ErrorCode::DuplicateWord, w['U']->loc,
                "U and X in one block: on a Fanuc lathe U is X's incremental word");
  if (w.has('Z') && w.has('W'))
    return fail(err, ErrorCode::DuplicateWord, w['W']->loc,
                "W and Z in one block: on a Fanuc lathe W is Z's incremental word");
  if (w.has('X')) x = w.get('X') * xs;
  if (w.has('U')) x += w.get('U') * xs;
  if (w.has('Z')) z = w.get('Z');
  if (w.has('W')) z += w.get('W');
  return true;
}

// The points of a profile element: its start `a`, and the element.
struct Planar {
  double a = 0, b = 0;
};

// Angle of p about c, radians.
double angle_of(double pz, double px, double cz, double cx) {
  return std::atan2(px - cx, pz - cz);
}

// Sweep from angle `from` to `to` in the arc's direction (ccw in the ZX plane's z-right, x-up
// view), in [0, 2pi).
double sweep(double from, double to, bool ccw) {
  double d = ccw ? to - from : from - to;
  while (d < 0) d += 2 * kPi;
  while (d >= 2 * kPi) d -= 2 * kPi;
  return d;
}

}  // namespace

std::string FanucLathe::cycle_name() const {
  return fmt::format("G{} P{} Q{}", cycle_.code, cycle_.ns, cycle_.nf);
}

bool FanucLathe::profile_cycle(grammar::Block& b, int code, const ModalState& s, Outcome& outcome,
                               InterpError& err) {
  const Words w(b);
  const SourceLoc at =
      b.words[0].letter == 'N' && b.words.size() > 1 ? b.words[1].loc : b.words[0].loc;
  if (!w.has('P') && !w.has('Q')) {  // the first block: depth of cut and retract
    if (code == 70)
      return fail(err, ErrorCode::MissingWord, at,
                  "G70 without P and Q (the profile's first and last sequence numbers)");
    if (code == 73) {  // G73 U(Δi) W(Δk) R(d): the relief (signed) and the number of passes
      if (!only_words(b, code, "UWR", err)) return false;
      const double d = w.get('R', 1.0);
      if (std::fabs(d - std::round(d)) > 1e-9 || d < 1 || d > 99999)
        return fail(err, ErrorCode::ValueOutOfRange, w.has('R') ? w['R']->loc : at,
                    fmt::format("G73 R{:g}: the number of passes, a whole number 1-99999", d));
      g73_relief_x_ = w.get('U');
      g73_relief_z_ = w.get('W');
      g73_passes_ = static_cast<int>(std::lround(d));
      outcome = Outcome::Recorded;
      return true;
    }
    const char depth_letter = code == 71 ? 'U' : 'W';
    if (!only_words(b, code, code == 71 ? "UR" : "WR", err)) return false;
    if (!w.has(depth_letter) || !(w.get(depth_letter) > 0.0))
      return fail(err, ErrorCode::MissingWord, at,
                  fmt::format("G{} {}(depth of cut) R(retract): the depth {} must be more than 0",
                              code, depth_letter, depth_letter));
    if (w.has('R') && !(w.get('R') >= 0.0))
      return fail(err, ErrorCode::ValueOutOfRange, w['R']->loc,
                  fmt::format("G{} R{:g}: the retract is negative", code, w.get('R')));
    (code == 71 ? g71_depth_ : g72_depth_) = w.get(depth_letter);
    (code == 71 ? g71_retract_ : g72_retract_) = w.get('R');
    outcome = Outcome::Recorded;
    return true;
  }
  if (!only_words(b, code, code == 70 ? "PQ" : code == 73 ? "PQUWF" : "PQUWFD", err)) return false;
  if (!w.has('P') || !w.has('Q'))
    return fail(err, ErrorCode::MissingWord, at,
                fmt::format("G{} needs both P (the profile's first sequence number) and Q (its "
                            "last): {} is missing",
                            code, w.has('P') ? "Q" : "P"));
  Cycle c;
  c.code = code;
  c.loc = at;
  if (!sequence_word(w['P'], code, c.ns, err) || !sequence_word(w['Q'], code, c.nf, err))
    return false;
  if (s.plane != Plane::XZ)
    return fail(err, ErrorCode::CycleMisused, at,
                fmt::format("G{} needs the ZX plane (G18), the lathe's", code));
  if (code != 70 && s.comp.active())
    return fail(err, ErrorCode::CutterCompMisused, at,
                fmt::format("G{} with tool nose radius compensation on (G41/G42): cancel it "
                            "with G40 first",
                            code));
  c.du = w.get('U');
  c.dw = w.get('W');
  c.feed = w.has('F') ? w.get('F') : -1.0;
  if (w.has('F') && !(c.feed >= 0.0))
    return fail(err, ErrorCode::NegativeFeed, w['F']->loc,
                fmt::format("F{:g} is negative", c.feed));
  double depth = code == 71 ? g71_depth_ : g72_depth_;
  if (w.has('D')) depth = w.get('D');  // Haas's one-block form: D the depth of cut
  if (code != 70 && code != 73 && !(depth > 0.0))
    return fail(err, ErrorCode::MissingWord, at,
                fmt::format("G{} P Q without a depth of cut: G{} {}(depth) R(retract) comes first "
                            "(or D on this line)",
                            code, code, code == 71 ? 'U' : 'W'));
  program_point(s, c.z0, c.x0);
  c.z = c.z0;
  c.x = c.x0;
  c.mm_per_unit = s.mm_per_unit();
  c.diameter = s.lathe_diameter;
  c.depth = depth;
  c.retract = code == 71 ? g71_retract_ : g72_retract_;
  c.relief_x = g73_relief_x_;
  c.relief_z = g73_relief_z_;
  c.passes = g73_passes_;
  cycle_ = std::move(c);
  outcome = Outcome::Profile;
  return true;
}

bool FanucLathe::collect(const grammar::Block& b, InterpError& err) {
  Cycle& c = cycle_;
  const Words w(b);
  const SourceLoc at{b.line, 1};
  int motion = -1;
  for (const grammar::Word& x : b.words)
    if (x.letter == 'G')
      for (const int m : {0, 1, 2, 3})
        if (x.value == m) motion = m;
  if (c.first && motion != 0 && motion != 1)
    return fail(
        err, ErrorCode::CycleMisused, at,
        fmt::format("{}: the profile's first block N{} must be G00 or G01", cycle_name(), c.ns));
  c.first = false;
  if (motion >= 0) c.motion = motion;
  double z = c.z, x = c.x;
  if (!word_end(w, c.diameter ? 0.5 : 1.0, z, x, err)) return false;
  if (w.has('F')) c.profile_feed = w.get('F');
  for (const char l : {'X', 'U', 'Z', 'W', 'I', 'K', 'R', 'F'})
    if (w.has(l) && !std::isfinite(w.get(l)))
      return fail(err, ErrorCode::NotANumber, w[l]->loc, "not a number");
  if (std::fabs(z - c.z) < kTol && std::fabs(x - c.x) < kTol) return true;
  if (c.profile.size() >= lathe::kMaxProfileSegments)
    return fail(err, ErrorCode::ValueOutOfRange, at,
                fmt::format("{}: the profile has more than {} elements", cycle_name(),
                            lathe::kMaxProfileSegments));
  LatheProfileElement e;
  e.line = b.line;
  e.move.z = z;
  e.move.x = x;
  e.move.f = c.profile_feed;
  if (c.motion == 0 || c.motion == 1) {
    e.move.kind = c.motion == 0 ? Kind::Rapid : Kind::Feed;
  } else {
    e.move.kind = c.motion == 3 ? Kind::ArcCcw : Kind::ArcCw;
    if (w.has('R')) {
      if (w.has('I') || w.has('K'))
        return fail(err, ErrorCode::ArcRWithIjk, w['R']->loc, "R and I/K in one arc block");
      const double r = std::fabs(w.get('R'));
      const double dz = z - c.z, dx = x - c.x, chord = std::hypot(dz, dx);
      if (!(r * 2 >= chord - 1e-7))
        return fail(err, ErrorCode::ArcRadiusTooSmall, w['R']->loc,
                    fmt::format("R{:g} cannot reach the arc's end ({:g} away)", r, chord));
      const double h = std::sqrt(std::max(0.0, r * r - chord * chord / 4)) / chord;
      // G3 (counter-clockwise) has its centre to the left of the chord, G2 to the right; a
      // negative R takes the arc over 180 degrees.
      double side = c.motion == 3 ? 1.0 : -1.0;
      if (w.get('R') < 0) side = -side;
      e.move.cz = (c.z + z) / 2 - side * h * dx;
      e.move.cx = (c.x + x) / 2 + side * h * dz;
    } else {
      if (!w.has('I') && !w.has('K'))
        return fail(err, ErrorCode::ArcMissingCenter, at,
                    fmt::format("{}: an arc of the profile needs R or I/K", cycle_name()));
      e.move.cz = c.z + w.get('K');
      e.move.cx = c.x + w.get('I');
      const double r0 = std::hypot(c.z - e.move.cz, c.x - e.move.cx);
      const double r1 = std::hypot(z - e.move.cz, x - e.move.cx);
      if (std::fabs(r0 - r1) > 0.002 + 1e-3 * r0)
        return fail(err, ErrorCode::ArcRadiusMismatch, at,
                    fmt::format("radius to end of arc differs from radius to start: start "
                                "radius {:g}, end radius {:g}",
                                r0, r1));
    }
  }
  c.profile.push_back(e);
  c.z = z;
  c.x = x;
  return true;
}

bool FanucLathe::finish_profile(InterpError& err) {
  Cycle& c = cycle_;
  moves_.clear();
  if (c.profile.empty())
    return fail(err, ErrorCode::CycleMisused, c.loc,
                fmt::format("{}: the profile N{}..N{} makes no move", cycle_name(), c.ns, c.nf));
  if (c.code == 70) {
    finish(c.z0, c.x0, c.profile, moves_);
    return true;
  }
  if (c.code == 73) {
    if (static_cast<double>(c.passes) * static_cast<double>(c.profile.size() + 1) >
        static_cast<double>(lathe::kMaxCycleMoves))
      return fail(err, ErrorCode::CycleMisused, c.loc,
                  fmt::format("{}: {} passes over {} profile elements: more than one cycle may "
                              "make ({} moves)",
                              cycle_name(), c.passes, c.profile.size(), lathe::kMaxCycleMoves));
    PatternInput in;
    in.z0 = c.z0;
    in.x0 = c.x0;
    in.relief_x = c.relief_x;
    in.relief_z = c.relief_z;
    in.passes = c.passes;
    in.du = c.du * (c.diameter ? 1.0 : 2.0);
    in.dw = c.dw;
    in.feed = c.feed;
    in.profile = c.profile;
    pattern(in, moves_);
    return true;
  }
  RoughInput in;
  in.facing = c.code == 72;
  in.z0 = c.z0;
  in.x0 = c.x0;
  in.depth = c.depth;
  in.retract = c.retract;
  in.du = c.du * (c.diameter ? 1.0 : 2.0);
  in.dw = c.dw;
  in.feed = c.feed;
  in.profile = c.profile;
  std::string why;
  int line = 0;
  if (!rough(in, moves_, why, line))
    return fail(err, ErrorCode::CycleMisused, line > 0 ? SourceLoc{line, 1} : c.loc,
                fmt::format("{}: {}", cycle_name(), why));
  return true;
}

void FanucLathe::finish(double z0, double x0, const std::vector<LatheProfileElement>& profile,
                        std::vector<LatheMove>& out) {
  for (const LatheProfileElement& e : profile) out.push_back(e.move);
  LatheMove back;
  back.kind = Kind::Rapid;
  back.z = z0;
  back.x = x0;
  out.push_back(back);
}

bool FanucLathe::rough(const RoughInput& in, std::vector<LatheMove>& out, std::string& why,
                       int& line) {
  line = 0;
  // (a, b): a along the cut, b across the layers; G71 cuts along Z (a = z, b = x), G72 along X.
  auto to_ab = [&](double z, double x) { return in.facing ? Planar{x, z} : Planar{z, x}; };
  const double sz = in.dw, sx = in.du / 2;  // the allowance: the profile shifted by it
  std::vector<LatheProfileElement> p = in.profile;
  for (LatheProfileElement& e : p) {
    e.move.z += sz;
    e.move.x += sx;
    e.move.cz += sz;
    e.move.cx += sx;
  }
  const Planar a0 = to_ab(in.z0, in.x0);
  const Planar first = to_ab(p.front().move.z, p.front().move.x);
  const Planar last = to_ab(p.back().move.z, p.back().move.x);
  const double sb = first.b < a0.b ? 1.0 : -1.0;  // layers go towards -b (turning outside)
  if (std::fabs(first.b - a0.b) < kTol) {
    why = fmt::format(
        "the start point is level with the profile's first point in {}: the "
        "layers have nowhere to go",
        in.facing ? "Z" : "X");
    return false;
  }
  const double sa = last.a < first.a ? -1.0 : 1.0;
  if (std::fabs(last.a - first.a) < kTol) {
    why = fmt::format("the profile does not advance in {}", in.facing ? "X" : "Z");
    return false;
  }
  // Depth q (0 at the start, growing into the material) and progress t along the cut.
  auto q_of = [&](const Planar& v) { return sb * (a0.b - v.b); };
  auto t_of = [&](const Planar& v) { return sa * (v.a - a0.a); };
  // Fanuc's type I: along the profile the depth only decreases and the cut only advances.
  {
    Planar prev = first;
    for (std::size_t i = 1; i < p.size(); ++i) {
      const LatheMove& m = p[i].move;
      std::vector<Planar> pts;
      if (is_arc(m.kind)) {
        const double r = std::hypot(prev.a - to_ab(m.cz, m.cx).a, prev.b - to_ab(m.cz, m.cx).b);
        const double from =
            angle_of(in.facing ? prev.b : prev.a, in.facing ? prev.a : prev.b, m.cz, m.cx);
        const double to = angle_of(m.z, m.x, m.cz, m.cx);
        const bool ccw = m.kind == Kind::ArcCcw;
        const double sw = sweep(from, to, ccw);
        for (int k = 1; k <= 32; ++k) {
          const double ang = from + (ccw ? 1 : -1) * sw * k / 32;
          pts.push_back(to_ab(m.cz + r * std::cos(ang), m.cx + r * std::sin(ang)));
        }
      } else {
        pts.push_back(to_ab(m.z, m.x));
      }
      for (const Planar& v : pts) {
        if (q_of(v) > q_of(prev) + 1e-7 || t_of(v) < t_of(prev) - 1e-7) {
          line = p[i].line;
          why = fmt::format(
              "the profile is not monotone here (type I roughing: along the "
              "profile {} may only move back towards the start point and {} "
              "only onwards). A pocket is type II roughing (Fanuc: the first block Nns "
              "gives both X and Z), which is not modelled: rough it with G73 or write the "
              "moves",
              in.facing ? "Z" : "X", in.facing ? "X" : "Z");
          return false;
        }
        prev = v;
      }
    }
  }
  auto from_ab = [&](double t, double q, LatheMove m) {
    const double a = a0.a + sa * t, b = a0.b - sb * q;
    m.z = in.facing ? b : a;
    m.x = in.facing ? a : b;
    return m;
  };
  const double qmax = q_of(first);
  // Bounded work and moves: each layer walks the profile once and makes four moves.
  const double layers = qmax / in.depth;
  if (!(layers <= static_cast<double>(kMaxLayers)) ||
      layers * static_cast<double>(p.size()) > kMaxProfileWork ||
      4 * layers + static_cast<double>(p.size()) > static_cast<double>(lathe::kMaxCycleMoves)) {
    why = fmt::format(
        "{:g} layers of depth {:g} over {} profile elements: more than one cycle may "
        "make ({} moves)",
        std::ceil(layers), in.depth, p.size(), lathe::kMaxCycleMoves);
    return false;
  }
  const Kind plunge = p.front().move.kind == Kind::Rapid ? Kind::Rapid : Kind::Feed;
  LatheMove feed;
  feed.kind = Kind::Feed;
  feed.f = in.feed;
  LatheMove rapid;
  rapid.kind = Kind::Rapid;
  LatheMove in_move;
  in_move.kind = plunge;
  if (plunge == Kind::Feed) in_move.f = in.feed;
  // The t where the profile first rises to depth q (its end when it never does).
  auto cut_end = [&](double q) {
    Planar prev = first;
    for (std::size_t i = 1; i < p.size(); ++i) {
      const LatheMove& m = p[i].move;
      const Planar e = to_ab(m.z, m.x);
      if (q_of(e) <= q + kTol) {
        if (!is_arc(m.kind)) {
          const double qa = q_of(prev), qb = q_of(e);
          const double f = qa - qb > kTol ? (qa - q) / (qa - qb) : 0.0;
          return t_of(prev) + std::clamp(f, 0.0, 1.0) * (t_of(e) - t_of(prev));
        }
        // The circle at b = the layer's: the crossing first reached along the arc.
        const Planar c = to_ab(m.cz, m.cx);
        const double r = std::hypot(e.a - c.a, e.b - c.b);
        const double b = a0.b - sb * q;
        const double h2 = r * r - (b - c.b) * (b - c.b);
        if (h2 < 0) return t_of(e);
        const bool ccw = m.kind == Kind::ArcCcw;
        const double from =
            angle_of(in.facing ? prev.b : prev.a, in.facing ? prev.a : prev.b, m.cz, m.cx);
        double best = 1e300, best_t = t_of(e);
        for (const double a : {c.a + std::sqrt(h2), c.a - std::sqrt(h2)}) {
          const double z = in.facing ? b : a, x = in.facing ? a : b;
          const double s = sweep(from, angle_of(z, x, m.cz, m.cx), ccw);
          if (s <= sweep(from, angle_of(m.z, m.x, m.cz, m.cx), ccw) + 1e-9 && s < best) {
            best = s;
            best_t = t_of(Planar{a, b});
          }
        }
        return best_t;
      }
      prev = e;
    }
    return t_of(last);
  };
  for (long k = 1;; ++k) {
    const double q = static_cast<double>(k) * in.depth;
    if (q >= qmax - 1e-9) break;
    out.push_back(from_ab(0.0, q, in_move));  // in to the layer
    const double t = cut_end(q);
    out.push_back(from_ab(t, q, feed));                             // along it to the profile
    out.push_back(from_ab(t - in.retract, q - in.retract, rapid));  // off at 45 degrees
    out.push_back(from_ab(0.0, q - in.retract, rapid));             // back to the start
  }
  // The allowance pass along the shifted profile, then back to the start point.
  LatheMove to_first = p.front().move;
  to_first.kind = plunge;
  to_first.f = plunge == Kind::Feed ? in.feed : -1.0;
  out.push_back(to_first);
  for (std::size_t i = 1; i < p.size(); ++i) {
    LatheMove m = p[i].move;
    if (m.kind == Kind::Rapid) m.kind = Kind::Feed;
    m.f = in.feed;
    out.push_back(m);
  }
  LatheMove back = rapid;
  back.z = in.z0;
  back.x = in.x0;
  out.push_back(back);
  return true;
}

bool FanucLathe::thread_cycle(grammar::Block& b, const ModalState& s, Outcome& outcome,
                              InterpError& err) {
  const Words w(b);
  const SourceLoc at =
      b.words[0].letter == 'N' && b.words.size() > 1 ? b.words[1].loc : b.words[0].loc;
  // Q and P are in the least input increment (0.001 mm, 0.0001 in), as Fanuc writes them
  // without a decimal point.
  const double least = s.mm_per_unit() == 1.0 ? 0.001 : 0.0001;
  const bool second = w.has('X') || w.has('Z') || w.has('U') || w.has('W');
  if (!second) {  // G76 P(m)(r)(a) Q(min depth) R(finishing allowance)
    if (!only_words(b, 76, "PQR", err)) return false;
    if (w.has('P')) {
      const double p = w.get('P');
      if (std::fabs(p - std::round(p)) > 1e-9 || p < 0 || p > 999999)
        return fail(err, ErrorCode::ValueOutOfRange, w['P']->loc,
                    fmt::format("G76 P{:g}: six digits mmrraa (finishing passes, chamfer in "
                                "0.1 leads, tool angle)",
                                p));
      const long v = std::lround(p);
      g76_finish_passes_ = static_cast<int>(v / 10000);
      g76_chamfer_ = static_cast<int>(v / 100 % 100);
      g76_angle_deg_ = static_cast<int>(v % 100);
      if (g76_finish_passes_ < 1)
        return fail(err, ErrorCode::ValueOutOfRange, w['P']->loc,
                    fmt::format("G76 P{:06d}: the finishing passes mm must be 1-99", v));
    }
    if (w.has('Q')) g76_min_depth_ = std::fabs(w.get('Q')) * least;
    if (w.has('R')) g76_allowance_ = std::fabs(w.get('R'));
    outcome = Outcome::Recorded;
    return true;
  }
  // G76 X(U) Z(W) R(taper) P(thread height) Q(first depth) F(lead)
  if (!only_words(b, 76, "XZUWRPQF", err)) return false;
  for (const char l : {'P', 'Q', 'F'})
    if (!w.has(l))
      return fail(err, ErrorCode::MissingWord, at,
                  fmt::format("G76 X Z without {} ({})", l,
                              l == 'P'   ? "the thread height"
                              : l == 'Q' ? "the first depth of cut"
                                         : "the lead"));
  if (s.comp.active())
    return fail(err, ErrorCode::CutterCompMisused, at,
                "G76 with tool nose radius compensation on (G41/G42)");
  Cycle c;
  c.code = 76;
  c.loc = at;
  program_point(s, c.z0, c.x0);
  double xe = c.x0, ze = c.z0;
  if (!word_end(w, s.lathe_diameter ? 0.5 : 1.0, ze, xe, err)) return false;
  const double k = std::fabs(w.get('P')) * least, d1 = std::fabs(w.get('Q')) * least;
  const double lead = w.get('F'), taper = w.get('R');
  if (!(k > 0) || !(d1 > 0) || !(lead > 0))
    return fail(err, ErrorCode::ValueOutOfRange, at,
                "G76: the thread height P, the first depth Q and the lead F must be more than 0");
  if (std::fabs(ze - c.z0) < kTol)
    return fail(err, ErrorCode::CycleMisused, at, "G76: the thread has no length in Z");
  const double side = xe < c.x0 ? -1.0 : 1.0;  // -1: outside (towards the axis), +1: inside
  const double sz = ze < c.z0 ? -1.0 : 1.0;
  const double crest = xe - side * k;  // at the end; the root is X
  const double tan_half = std::tan(g76_angle_deg_ * kPi / 360.0);
  const double chamfer = g76_chamfer_ * lead / 10.0;
  const double rough_to = std::max(k - g76_allowance_, 0.0);
  std::vector<double> depths;
  double d = d1;
  for (int n = 1; d < rough_to - kTol; ++n) {
    if (n > kMaxThreadPasses)
      return fail(err, ErrorCode::CycleMisused, at,
                  fmt::format("G76 would cut more than {} passes", kMaxThreadPasses));
    depths.push_back(d);
    const double next = d1 * std::sqrt(static_cast<double>(n + 1));
    d = std::max(next, d + g76_min_depth_);
  }
  if (rough_to > kTol) depths.push_back(rough_to);
  for (int m = 0; m < g76_finish_passes_; ++m) depths.push_back(k);
  moves_.clear();
  LatheMove rapid;
  rapid.kind = Kind::Rapid;
  LatheMove thread;
  thread.kind = Kind::Thread;
  thread.f = lead;
  auto add = [&](LatheMove m, double z, double x) {
    m.z = z;
    m.x = x;
    moves_.push_back(m);
  };
  for (const double depth : depths) {
    const double zs = c.z0 + sz * depth * tan_half;  // in along the flank
    const double x_end = crest + side * depth, x_start = x_end + taper;
    add(rapid, zs, c.x0);
    add(rapid, zs, x_start);
    if (chamfer > 0.0) {  // the pull-out at 45 degrees over r x 0.1 leads
      add(thread, ze - sz * chamfer, x_end);
      add(thread, ze, x_end - side * chamfer);
    } else {
      add(thread, ze, x_end);
    }
    add(rapid, ze, c.x0);
  }
  add(rapid, c.z0, c.x0);
  cycle_ = std::move(c);
  outcome = Outcome::Moves;
  return true;
}

// G74 (end face peck drilling: pecks along Z, steps along X) and G75 (outer/inner diameter
// grooving: pecks along X, steps along Z), two blocks: G74 R(e) / G74 X(U) Z(W) P(Δi) Q(Δk) F.
bool FanucLathe::peck_cycle(grammar::Block& b, int code, const ModalState& s, Outcome& outcome,
                            InterpError& err) {
  const Words w(b);
  const SourceLoc at =
      b.words[0].letter == 'N' && b.words.size() > 1 ? b.words[1].loc : b.words[0].loc;
  const double least = s.mm_per_unit() == 1.0 ? 0.001 : 0.0001;
  const bool second =
      w.has('X') || w.has('Z') || w.has('U') || w.has('W') || w.has('P') || w.has('Q');
  double& retract = code == 74 ? g74_retract_ : g75_retract_;
  if (!second) {  // G74 R(e): the retract after each peck
    if (!only_words(b, code, "R", err)) return false;
    if (!(w.get('R') >= 0.0))
      return fail(err, ErrorCode::ValueOutOfRange, w['R']->loc,
                  fmt::format("G{} R{:g}: the retract is negative", code, w.get('R')));
    retract = w.get('R');
    outcome = Outcome::Recorded;
    return true;
  }
  if (!only_words(b, code, "XZUWPQRF", err)) return false;
  if (w.has('R') && w.get('R') != 0.0)
    return fail(err, ErrorCode::NotInDialect, w['R']->loc,
                fmt::format("G{} R{:g}: the relief at the bottom is not modelled (R0 or none)",
                            code, w.get('R')));
  if (s.comp.active())
    return fail(err, ErrorCode::CutterCompMisused, at,
                fmt::format("G{} with tool nose radius compensation on (G41/G42)", code));
  Cycle c;
  c.code = code;
  c.loc = at;
  program_point(s, c.z0, c.x0);
  double xe = c.x0, ze = c.z0;
  if (!word_end(w, s.lathe_diameter ? 0.5 : 1.0, ze, xe, err)) return false;
  // (a, b): a the peck axis (Z for G74, X for G75), b the step axis.
  const bool face = code == 74;
  const double a0 = face ? c.z0 : c.x0, b0 = face ? c.x0 : c.z0;
  const double ae = face ? ze : xe, be = face ? xe : ze;
  const double peck = std::fabs(w.get(face ? 'Q' : 'P')) * least;
  const double step = std::fabs(w.get(face ? 'P' : 'Q')) * least;
  if (std::fabs(ae - a0) < kTol)
    return fail(err, ErrorCode::CycleMisused, at,
                fmt::format("G{}: no depth: the end {} is the start's", code, face ? "Z" : "X"));
  if (!(peck > 0.0))
    return fail(err, ErrorCode::MissingWord, at,
                fmt::format("G{} needs {} (the depth of each peck, in the least increment)", code,
                            face ? "Q" : "P"));
  if (std::fabs(be - b0) > kTol && !(step > 0.0))
    return fail(err, ErrorCode::MissingWord, at,
                fmt::format("G{} needs {} (the step between grooves, in the least increment)", code,
                            face ? "P" : "Q"));
  const double da = ae > a0 ? 1.0 : -1.0, db = be > b0 ? 1.0 : -1.0;
  const double pecks = std::fabs(ae - a0) / peck;
  const double steps = step > 0.0 ? std::fabs(be - b0) / step : 0.0;
  if (!(pecks * (steps + 1) <= static_cast<double>(lathe::kMaxCycleMoves) / 2))
    return fail(err, ErrorCode::CycleMisused, at,
                fmt::format("G{} would make more than {} pecks", code, lathe::kMaxCycleMoves / 2));
  moves_.clear();
  auto add = [&](Kind k, double a, double bb, double f) {
    LatheMove m;
    m.kind = k;
    m.z = face ? a : bb;
    m.x = face ? bb : a;
    m.f = f;
    moves_.push_back(m);
  };
  const double feed = w.has('F') ? w.get('F') : -1.0;
  for (double bpos = b0;; bpos += db * step) {
    if (db * (bpos - be) > -kTol) bpos = be;
    add(Kind::Rapid, a0, bpos, -1.0);
    for (long n = 1;; ++n) {  // peck in, back off by e, on from there
      double depth = a0 + da * peck * static_cast<double>(n);
      const bool bottom = da * (depth - ae) >= -kTol;
      if (bottom) depth = ae;
      add(Kind::Feed, depth, bpos, feed);
      if (bottom) break;
      add(Kind::Rapid, depth - da * retract, bpos, -1.0);
    }
    add(Kind::Rapid, a0, bpos, -1.0);
    if (std::fabs(bpos - be) < kTol) break;
  }
  add(Kind::Rapid, a0, b0, -1.0);
  cycle_ = std::move(c);
  outcome = Outcome::Moves;
  return true;
}

void FanucLathe::move_blocks(const ModalState& s, std::vector<grammar::Block>& out) const {
  const SourceLoc loc = cycle_.loc;
  const double xs = s.lathe_diameter ? 2.0 : 1.0;
  double z = cycle_.z0, x = cycle_.x0;
  for (const LatheMove& m : moves_) {
    grammar::Block b;
    b.line = loc.line;
    auto word = [&](char l, double v) { b.words.push_back(grammar::Word{l, v, loc}); };
    const double g = m.kind == Kind::Rapid    ? 0.0
                     : m.kind == Kind::Feed   ? 1.0
                     : m.kind == Kind::ArcCw  ? 2.0
                     : m.kind == Kind::ArcCcw ? 3.0
                                              : 33.0;
    word('G', g);
    if (s.incremental) word('G', 90.0);
    word('X', m.x * xs);
    word('Z', m.z);
    if (is_arc(m.kind)) {
      word('I', s.ijk_absolute ? m.cx : m.cx - x);
      word('K', s.ijk_absolute ? m.cz : m.cz - z);
    }
    if (m.kind == Kind::Thread)
      word('K', m.f);
    else if (m.kind != Kind::Rapid && m.f >= 0.0)
      word('F', m.f);
    out.push_back(std::move(b));
    z = m.z;
    x = m.x;
  }
  if (s.incremental && !out.empty()) {
    grammar::Block b;
    b.line = loc.line;
    b.words.push_back(grammar::Word{'G', 91.0, loc});
    out.push_back(std::move(b));
  }
}

}  // namespace gm
