// Lathe profile geometry of G70-G72: offsetting, corner rounding and the layer-by-layer roughing
// walk, in the order and with the tolerances of LinuxCNC 2.9's cycles (so the moves agree).
#include "interp/lathe_profile.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <deque>

namespace gm::lathe {

namespace {

constexpr double kTol = 1e-6;
constexpr Pt kI{0.0, 1.0};

/// A geometric failure: unwinds to rough()/finish(), which report it.
struct Failure {
  std::string message;
};

/// Up to two Z values where an element crosses a given X.
struct Hits {
  double v[2]{};
  int n = 0;
  void add(double z) {
    if (n < 2) v[n++] = z;
  }
  bool empty() const { return n == 0; }
  double front() const { return v[0]; }
  double back() const { return v[n - 1]; }
};

bool is_arc(const Seg& s) {
  return s.kind == Seg::Kind::Arc;
}

bool on_arc(const Seg& s, Pt p) {
  const double from_a = std::imag(std::conj(s.a - s.c) * (p - s.c));
  const double from_b = std::imag(std::conj(s.b - s.c) * (p - s.c));
  return s.ccw ? from_a >= -kTol && from_b <= kTol : from_a <= kTol && from_b >= -kTol;
}

void hits_at(const Seg& s, double x, Hits& h) {
  if (!is_arc(s)) {
    if (std::min(s.a.imag(), s.b.imag()) > x + kTol || std::max(s.a.imag(), s.b.imag()) < x - kTol)
      return;
    if (std::abs(std::imag(s.a - s.b)) < kTol) {
      h.add(s.a.real());
      h.add(s.b.real());
    } else {
      h.add((x - s.a.imag()) / (s.b.imag() - s.a.imag()) * (s.b.real() - s.a.real()) + s.a.real());
    }
    return;
  }
  const double r = std::abs(s.a - s.c);
  double q = -(x - r - s.c.imag()) * (x + r - s.c.imag());
  if (q < -kTol) return;
  q = std::sqrt(std::max(q, 0.0));
  const Pt p1(s.c.real() + q, x), p2(s.c.real() - q, x);
  if (on_arc(s, p1)) h.add(p1.real());
  if (on_arc(s, p2)) h.add(p2.real());
}

double size_of(const Seg& s) {
  return is_arc(s) ? std::min(std::abs(s.a - s.b), std::abs(s.a - s.c)) : std::abs(s.a - s.b);
}

bool monotonic(const Seg& s) {
  if (!is_arc(s)) return std::real(s.b - s.a) <= 1e-3;
  if (s.finish != 0.0) return true;
  const double entry = std::imag(s.a - s.c), exit = std::imag(s.b - s.c);
  const double dz = std::real(s.b - s.a);
  return s.ccw ? entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
               : entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3;
}

void shift(Seg& s, double d) {  // away to the side: LinuxCNC's offset
  if (!is_arc(s)) {
    const Pt n = kI * d * (s.a - s.b) / std::abs(s.a - s.b);
    s.a += n;
    s.b += n;
    return;
  }
  const double r = std::abs(s.a - s.c);
  const double k = (r + (s.ccw ? 1 : -1) * d) / r;
  s.a = k * (s.a - s.c) + s.c;
  s.b = k * (s.b - s.c) + s.c;
}

void draw(const Seg& s, PathSink& out) {
  if (is_arc(s))
    out.arc(s.ccw, s.c, s.b);
  else
    out.feed(s.b);
}

// The circle of arc `arc` meets the line through `line`'s ends: the crossing nearest `near`.
Pt circle_meets_line(const Seg& arc_seg, Pt arc_point, const Seg& line, Pt near) {
  const Pt rot = std::conj(line.a - line.b) / std::abs(line.a - line.b);
  const Pt pe = (arc_point - line.b) * rot;
  const Pt pc = (arc_seg.c - line.b) * rot;
  double q = std::norm(pc - pe) - std::imag(pc) * std::imag(pc);
  q = q < 0 ? 0.0 : std::sqrt(q);
  const Pt s1 = (std::real(pc) + q) / rot + line.b;
  const Pt s2 = (std::real(pc) - q) / rot + line.b;
  return std::abs(near - s1) < std::abs(near - s2) ? s1 : s2;
}

// Moves the end of `p` and the start of `n` to where their (extended) shapes meet.
void join(Seg& p, Seg& n) {
  if (!is_arc(p) && !is_arc(n)) {
    const Pt rot = std::conj(n.a - n.b) / std::abs(n.a - n.b);
    const Pt ps = (p.a - n.b) * rot, pe = (p.b - n.b) * rot;
    if (std::imag(ps - pe) == 0) throw Failure{"Cannot intersect parallel lines"};
    const double f = std::imag(ps) / std::imag(ps - pe);
    n.a = p.b = (ps + f * (pe - ps)) / rot + n.b;
  } else if (is_arc(p) && !is_arc(n)) {
    if (std::abs(n.a - p.b) < kTol) return;
    n.a = p.b = circle_meets_line(p, p.b, n, n.a);
  } else if (!is_arc(p) && is_arc(n)) {
    if (std::abs(n.a - p.b) < kTol) return;
    // the line p; the circle of n through its end b
    const Pt rot = std::conj(p.a - p.b) / std::abs(p.a - p.b);
    const Pt pe = (n.b - p.b) * rot, pc = (n.c - p.b) * rot;
    double q = std::norm(pc - pe) - std::imag(pc) * std::imag(pc);
    q = q < 0 ? 0.0 : std::sqrt(q);
    const Pt s1 = (std::real(pc) + q) / rot + p.b;
    const Pt s2 = (std::real(pc) - q) / rot + p.b;
    n.a = p.b = std::abs(n.a - s1) < std::abs(n.a - s2) ? s1 : s2;
  } else {  // two circles: law of cosines in the triangle of the centres
    const double ra = std::abs(n.a - n.c), rb = std::abs(p.a - p.c), cc = std::abs(n.c - p.c);
    const double cos_b = (cc * cc + ra * ra - rb * rb) / 2.0 / ra / cc;
    const double cos2 = std::min(cos_b * cos_b, 1.0);
    const Pt rot(cos_b, std::sqrt(1 - cos2));
    n.a = p.b = rot * (p.c - n.c) / cc * ra + n.c;
  }
}

// A fillet or chamfer between prev and next: the neighbours are shortened to its ends.
void make_corner(Seg& s, Seg& prev, Seg& next) {
  Seg p = prev, n = next;
  shift(p, s.finish);
  shift(n, s.finish);
  if (std::real(p.b - n.a) > 1e-2) {
    s.finish = -s.finish;
    p = prev;
    n = next;
    shift(p, s.finish);
    shift(n, s.finish);
  }
  if (std::real(p.b - n.a) > 1e-2)
    throw Failure{fmt::format("Corner finish failed at ({:g},{:g})", prev.b.real(), prev.b.imag())};
  join(p, n);
  const Pt centre = (p.b + n.a) / 2.0;
  shift(p, -s.finish);
  shift(n, -s.finish);
  s.a = prev.b = p.b;
  s.b = next.a = n.a;
  if (s.corner == Seg::Corner::Fillet) {
    s.c = centre;
    s.ccw = std::imag(s.a - s.c) > 0 || std::imag(s.b - s.c) > 0;
    s.finish = 0;
  }
  s.corner = Seg::Corner::None;
}

/// The sink seen through the profile's turn: the profile is worked on turned so that Z and X
/// decrease (and rotated a quarter for G72); moves are turned back on the way out.
class TurnedSink : public PathSink {
 public:
  TurnedSink(PathSink& out, int state) : out_(out), state_(state) {}
  void feed(Pt e) override {
    count();
    out_.feed(back(e));
  }
  void rapid(Pt e) override {
    count();
    out_.rapid(back(e));
  }
  void arc(bool ccw, Pt c, Pt e) override {
    count();
    const bool mirrored = ((state_ & 1) != 0) != ((state_ & 2) != 0);
    out_.arc(mirrored ? !ccw : ccw, back(c), back(e));
  }

 private:
  Pt back(Pt q) const {
    if (state_ & 1) q = -std::conj(q);
    if (state_ & 2) q = std::conj(q);
    if (state_ & 4) q = kI * q;
    return q;
  }
  void count() {
    if (++moves_ > kMaxCycleMoves)
      throw Failure{
          fmt::format("more than {} moves in one cycle (a depth of cut I too small, too "
                      "many passes P, or a profile whose pocket walk never ends in LinuxCNC)",
                      kMaxCycleMoves)};
  }
  PathSink& out_;
  int state_;
  std::int64_t moves_ = 0;
};

class Profile {
 public:
  std::vector<Seg> s;
  int state = 0;                 // 1: Z mirrored, 2: X mirrored, 4: rotated a quarter turn
  std::int64_t* work = nullptr;  // element offsets so far in this cycle (kMaxOffsetWork)

  void rotate() {
    for (Seg& g : s) {
      g.a = -g.a * kI;
      g.b = -g.b * kI;
      if (is_arc(g)) g.c = -g.c * kI;
    }
    state ^= 4;
  }
  void mirror_x() {
    for (Seg& g : s) {
      g.a = std::conj(g.a);
      g.b = std::conj(g.b);
      if (is_arc(g)) {
        g.ccw = !g.ccw;
        g.c = std::conj(g.c);
      }
    }
    state ^= 2;
  }
  void mirror_z() {
    for (Seg& g : s) {
      g.a = -std::conj(g.a);
      g.b = -std::conj(g.b);
      if (is_arc(g)) {
        g.ccw = !g.ccw;
        g.c = -std::conj(g.c);
      }
    }
    state ^= 1;
  }
  // Turns the profile so that Z and X decrease along it.
  void normalise() {
    const Pt d = s.front().b - s.back().b;
    if (d.imag() > 0) mirror_x();
    if (d.real() < 0) mirror_z();
  }
  void check_monotonic() {
    if (std::real(s.front().b - s.front().a) > 0) s.front().a.real(s.front().b.real());
    for (const Seg& g : s)
      if (!monotonic(g)) throw Failure{"Not monotonic"};
  }
  void make_corners() {
    for (std::size_t h = 1; h + 1 < s.size(); ++h)
      if (s[h].corner != Seg::Corner::None) make_corner(s[h], s[h - 1], s[h + 1]);
    std::erase_if(s, [](const Seg& g) { return size_of(g) < 1e-3; });
  }
  void offset(double distance);
  void rough(int cycle, PathSink& out, double delta, Pt escape);

 private:
  void require_two() const {
    if (s.size() < 2) throw Failure{"the profile vanished when offset"};
  }
};

void Profile::offset(double distance) {
  require_two();
  const Pt v1 = s.front().b - s.front().a, v2 = s.back().a - s.front().a;
  if (std::imag(v1 / v2) < 0) distance = -distance;
  const Seg lead = s.front();
  s.erase(s.begin());
  double done = 0;
  while (done != distance) {
    if (s.empty()) throw Failure{"the profile vanished when offset"};
    *work += static_cast<std::int64_t>(s.size());
    if (*work > kMaxOffsetWork)
      throw Failure{fmt::format("offsetting the profile by D{:g} takes too many steps", distance)};
    double step = 1e9;
    for (const Seg& g : s) step = std::min(step, size_of(g) / 2);
    step = std::min(step, std::abs(distance - done));
    if (distance < 0) step = -step;
    for (std::size_t k = 0; k < s.size(); ++k) {
      shift(s[k], step);
      if (size_of(s[k]) < 1e-3) s.erase(s.begin() + static_cast<std::ptrdiff_t>(k--));
    }
    // Elements that parted are joined by an arc about the point they shared.
    for (std::size_t k = 0; k + 1 < s.size(); ++k) {
      if (std::real(s[k].b - s[k + 1].a) > 1e-2) {
        Seg p = s[k], n = s[k + 1];
        shift(p, -step);
        shift(n, -step);
        const Pt centre = (p.b + n.a) / 2.0;
        s.insert(s.begin() + static_cast<std::ptrdiff_t>(k + 1),
                 Seg::arc(distance > 0, s[k].b, centre, s[k + 1].a));
        ++k;
      }
    }
    // Elements turned backwards are dropped (the shorter of two), the rest meet again.
    for (std::size_t k = 0; k + 1 < s.size(); ++k) {
      if (!monotonic(s[k])) {
        if (k == 0 || size_of(s[k]) < size_of(s[k - 1]))
          s.erase(s.begin() + static_cast<std::ptrdiff_t>(k));
        else
          s.erase(s.begin() + static_cast<std::ptrdiff_t>(k - 1));
        k = 0;
        if (s.size() < 2) break;
      }
      if (size_of(s[k]) < 1e-3) {
        s.erase(s.begin() + static_cast<std::ptrdiff_t>(k));
        k = 0;  // LinuxCNC goes on with the second element
      } else {
        join(s[k], s[k + 1]);
      }
    }
    done += step;
  }
  if (s.empty()) throw Failure{"the profile vanished when offset"};
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    const Pt mid = (s[k].b + s[k + 1].a) / 2.0;
    s[k].b = s[k + 1].a = mid;
  }
  Seg l = lead;
  l.b = s.front().a;
  s.insert(s.begin(), l);
}

// --- the roughing walk ---------------------------------------------------------------------

// Follows an element that climbs (X increasing along it, the profile turned): false when it
// does, the tool then at its end; true when it does not (a pocket starts).
bool climb(const Seg& g, Pt& loc, PathSink& out) {
  if (!is_arc(g)) {
    if (g.b.imag() + kTol < g.a.imag()) return true;
    if (std::abs(loc - g.a) > kTol) throw Failure{"How did we get here?"};
    out.feed(g.b);
    loc = g.b;
    return false;
  }
  if (!g.ccw) {
    if (loc.real() > g.c.real()) return true;
    if (std::abs(loc - g.b) > 1e-3) out.arc(false, g.c, g.b);
    loc = g.b;
    return false;
  }
  if (loc.real() < g.c.real()) return true;
  Pt ep = g.b;
  if (g.b.real() < g.c.real()) ep = Pt(g.c.real(), g.c.imag() + std::abs(g.a - g.c));
  if (std::abs(loc - ep) > 1e-3) out.arc(true, g.c, ep);
  loc = ep;
  return true;
}

void climb_only(const Seg& g, Pt& loc, PathSink& out) {
  if (!is_arc(g) && g.b.imag() < g.a.imag()) return;
  Hits h;
  hits_at(g, loc.imag(), h);
  if (h.empty()) return;
  if (!is_arc(g)) {
    loc.real(h.front());
    out.feed(loc);
    out.feed(g.b);
    loc = g.b;
    return;
  }
  if (!g.ccw) {
    if (h.back() > g.c.real()) return;
    loc.real(h.back());
    out.feed(loc);
    if (std::abs(loc - g.b) > 1e-3) out.arc(false, g.c, g.b);
    loc = g.b;
    return;
  }
  if (h.front() < g.c.real()) return;
  loc.real(h.front());
  out.feed(loc);
  Pt ep = g.b;
  if (g.b.real() < g.c.real()) ep = Pt(g.c.real(), g.c.imag() + std::abs(g.a - g.c));
  if (std::abs(loc - ep) > 1e-3) out.arc(true, g.c, ep);
  loc = ep;
}

// Follows an element that dives down to layer x: false when it did (loc moved), true when the
// element does not dive.
bool dive(const Seg& g, Pt& loc, double x, PathSink& out, bool fast) {
  if (!is_arc(g)) {
    if (g.a.imag() <= g.b.imag() + kTol) return true;
    Pt ep = g.b;
    if (x >= g.b.imag()) {
      Hits h;
      hits_at(g, x, h);
      if (h.empty()) throw Failure{"x too large in straight dive"};
      ep = Pt(h.front(), x);
    }
    if (fast)
      out.rapid(ep);
    else
      out.feed(ep);
    loc = ep;
    return false;
  }
  if (std::abs(loc - g.b) < kTol || std::real(loc - g.b) <= kTol) {
    loc = g.b;
    return false;
  }
  Hits h;
  hits_at(g, x, h);
  if (h.empty()) hits_at(g, x - kTol, h);
  if (g.ccw) {
    if (loc.real() - kTol > g.c.real()) return true;
    if (h.empty() || h.back() > g.c.real()) {
      out.arc(true, g.c, g.b);
      loc = g.b;
    } else {
      const Pt ep(h.back(), x);
      out.arc(true, g.c, ep);
      loc = ep;
    }
    return false;
  }
  if (loc.real() <= g.c.real()) return true;
  if (h.empty()) {
    out.arc(false, g.c, g.b);
    loc = g.b;
  } else if (h.front() >= g.c.real()) {
    const Pt ep(h.front(), x);
    out.arc(false, g.c, ep);
    loc = ep;
  }  // else: only the far side is hit; the layer goes down
  return false;
}

void Profile::rough(int cycle, PathSink& out, double delta, Pt escape) {
  std::deque<Pt> pocket_starts{s.front().a};
  Pt loc = s.front().a;
  std::size_t p = 0;
  std::int64_t guard = 0;
  auto tick = [&] {
    if (++guard > 4 * kMaxCycleMoves)
      throw Failure{
          "the profile cannot be roughed (no progress; the depth of cut I may be too "
          "small)"};
  };
  for (;;) {  // one pocket a round (LinuxCNC recurses)
    double x = pocket_starts.back().imag();
    if (cycle == 2) {  // skip the first roughing: follow the profile to the first pocket
      for (; p < s.size(); ++p)
        if (dive(s[p], loc, -1e9, out, p == 0)) break;
      cycle = 3;
    }
    bool next_pocket = false;
    while (p < s.size()) {
      while (x - kTol > loc.imag()) {
        x -= delta;
        tick();
      }
      if (dive(s[p], loc, x, out, p == 0)) {
        if (cycle == 1) {
          for (; p < s.size(); ++p) climb_only(s[p], loc, out);
          return;
        }
        for (; p < s.size(); ++p) {
          if (climb(s[p], loc, out)) {
            if (cycle == 3) {
              if (loc.imag() > pocket_starts.back().imag() && pocket_starts.size() > 1)
                pocket_starts.pop_back();
              if (pocket_starts.size() == 1) pocket_starts.push_back(loc);
            }
            next_pocket = true;
            break;
          }
        }
        if (!next_pocket) return;
        break;
      }
      tick();
      if (std::abs(loc.imag() - x) > kTol) {
        ++p;  // the layer is below this element: on to the next
        continue;
      }
      for (std::size_t ip = p; ip < s.size(); ++ip) {
        Hits h;
        hits_at(s[ip], loc.imag(), h);
        if (h.empty()) continue;
        const double dest_z = ip != p ? h.front() : h.back();
        const double dist = std::abs(dest_z - loc.real());
        if (dest_z - kTol > loc.real()) continue;  // the diving element at its start only
        if (dist < kTol) {
          if (p == ip) continue;
          if (std::abs(loc - s[ip].a) < kTol) {
            p = ip;  // another element starts here: follow it
            break;
          }
          x -= delta;  // a zero-length cut: this layer is done
          break;
        }
        // The cut along the layer, the retract at 45 degrees, the return and the step down.
        Pt dest = loc;
        dest.real(dest_z);
        out.feed(dest);
        const double k = std::min(1.0, dist / 2 / escape.real());
        dest += k * escape;
        out.rapid(dest);
        out.rapid(loc - std::conj(k * escape));
        if (p == 0)
          out.rapid(loc);
        else
          out.feed(loc);
        x -= delta;
        break;
      }
    }
    if (!next_pocket) return;
  }
}

Profile turned(std::vector<Seg>&& profile, std::int64_t& work) {
  if (profile.size() > kMaxProfileSegments)
    throw Failure{fmt::format("the profile has more than {} elements", kMaxProfileSegments)};
  Profile pr;
  pr.s = std::move(profile);
  pr.work = &work;
  return pr;
}

}  // namespace

bool offset_profile(std::vector<Seg>& profile, double distance, std::string& error) {
  try {
    std::int64_t work = 0;
    Profile pr = turned(std::move(profile), work);
    pr.offset(distance);
    profile = std::move(pr.s);
    return true;
  } catch (const Failure& f) {
    error = f.message;
    return false;
  }
}

bool rough(std::vector<Seg> profile, const RoughParams& p, PathSink& out, std::string& error) {
  try {
    if (profile.size() < 2) return true;
    std::int64_t work = 0;
    Profile pr = turned(std::move(profile), work);
    pr.s.front().a = Pt(p.z, p.x);
    if (p.facing) pr.rotate();
    pr.normalise();
    pr.make_corners();
    pr.check_monotonic();
    pr.offset(p.d);
    for (Seg& g : pr.s) {
      g.a += Pt(p.w, p.u);
      g.b += Pt(p.w, p.u);
      if (is_arc(g)) g.c += Pt(p.w, p.u);
    }
    TurnedSink tout(out, pr.state);
    const double delta = std::max(p.i, 2 * kTol);
    const Pt escape = p.r * Pt(1, 1);
    tout.rapid(pr.s.front().a);
    if (pr.s.back().b.imag() < pr.s.front().a.imag()) {  // out to the start's level at the end
      Pt ep = pr.s.back().b;
      ep.imag(pr.s.front().a.imag());
      pr.s.push_back(Seg::line(pr.s.back().b, ep));
    }
    pr.rough(p.sub, tout, delta, escape);
    return true;
  } catch (const Failure& f) {
    error = f.message;
    return false;
  }
}

bool finish(std::vector<Seg> profile, const FinishParams& p, PathSink& out, std::string& error) {
  try {
    if (profile.size() < 2) return true;
    std::int64_t work = 0;
    Profile pr = turned(std::move(profile), work);
    pr.s.front().a = Pt(p.z, p.x);
    {  // which way the profile is monotonic: as given, or turned a quarter (a facing profile)
      Profile probe = pr;
      probe.s.erase(probe.s.begin());
      probe.normalise();
      for (const Seg& g : probe.s)
        if (!monotonic(g)) {
          probe.rotate();
          probe.normalise();
          break;
        }
      probe.check_monotonic();
      if (probe.state & 4) pr.rotate();
    }
    pr.normalise();
    pr.make_corners();
    pr.check_monotonic();
    TurnedSink tout(out, pr.state);
    const auto passes = static_cast<std::int64_t>(p.p);
    for (std::int64_t pass = passes; pass > 0; --pass) {
      Profile path = pr;
      path.offset(static_cast<double>(pass - 1) * (p.d - p.e) / p.p + p.e);
      tout.rapid(path.s.front().a);
      tout.rapid(path.s.front().b);
      for (std::size_t k = 1; k < path.s.size(); ++k) draw(path.s[k], tout);
    }
    return true;
  } catch (const Failure& f) {
    error = f.message;
    return false;
  }
}

}  // namespace gm::lathe
