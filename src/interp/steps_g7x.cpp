// The lathe cycles G70 (finishing), G71/G71.1/G71.2 (roughing along Z) and G72/G72.1/G72.2
// (facing along X) of LinuxCNC 2.9: the profile subroutine Q is read, not run, then cut.
#include "interp/arc.hpp"
#include "interp/cutter_comp.hpp"
#include "interp/lathe_profile.hpp"
#include "interp/steps.hpp"

#include <cmath>

namespace gm {

namespace {

using lathe::Pt;
using lathe::Seg;

// The cycle's moves as canon: program units of the ZX plane to machine coordinates.
class CanonSink : public lathe::PathSink {
 public:
  CanonSink(BlockCtx& ctx, SourceLoc loc) : ctx_(ctx), loc_(loc) {}
  void feed(Pt e) override { straight(MotionKind::Line, e); }
  void rapid(Pt e) override { straight(MotionKind::Rapid, e); }
  void arc(bool ccw, Pt c, Pt e) override {
    const Pos9 end = at(e);
    const Pos9 prog_now = ctx_.frame().to_program(comp_program_point(ctx_));
    const double u = ctx_.scale();
    // LinuxCNC draws no arc to where the tool is (its equal(): within 1e-7 units).
    if (std::fabs(prog_now[0] / u - e.imag()) < 1e-7 &&
        std::fabs(prog_now[2] / u - e.real()) < 1e-7)
      return;
    // LinuxCNC's convert_arc checks the arc as for a G2/G3 with absolute I K: the radius to
    // the end must agree with the radius to the start.
    ArcInput in;
    in.start_a = prog_now[2] / u;
    in.start_b = prog_now[0] / u;
    in.end_a = e.real();
    in.end_b = e.imag();
    in.off_a = c.real();
    in.off_b = c.imag();
    in.offsets_absolute = true;
    in.ccw = ccw;
    in.mm_per_unit = u;
    in.rule = ctx_.machine.arc_rule;
    const ArcResult r = compute_arc(in);
    if (r.error != ErrorCode::None) {
      ctx_.err.code = r.error;
      ctx_.err.message = r.message;
      throw lathe_error();
    }
    const Pos9 centre = at(c);
    if (ctx_.s.comp.active()) {  // G70 under G41/G42: the arc is compensated as a G2/G3 is
      if (!comp_arc(ctx_, *find_code('G', ccw ? 30 : 20), end, 1, &centre)) throw lathe_error();
    } else if (!emit_arc(ctx_, end, centre, ccw)) {
      throw lathe_error();
    }
  }
  struct lathe_error {};

 private:
  Pos9 at(Pt p) const {
    const double u = ctx_.scale();
    if (!within(p.real() * u, kMaxPositionMm) || !within(p.imag() * u, kMaxPositionMm))
      throw range_error{};
    Pos9 prog = Pos9::Zero();
    prog[0] = p.imag() * u;
    prog[2] = p.real() * u;
    return ctx_.frame().to_machine(comp_program_point(ctx_), prog, 5u);
  }
  void straight(MotionKind k, Pt e) {
    if (ctx_.s.comp.active() ? !comp_straight(ctx_, k, at(e))
                             : !emit_straight(ctx_, k, at(e), loc_))
      throw lathe_error();
  }

 public:
  struct range_error {};

 private:
  BlockCtx& ctx_;
  SourceLoc loc_;
};

}  // namespace

bool run_g7x(BlockCtx& ctx, const Code& c) {
  const BlockWords& w = ctx.w;
  const SourceLoc loc = ctx.loc_of(Group::Motion);
  const int cycle = c.number10 / 10, sub = c.number10 % 10;
  if (!w.has('Q')) return ctx.fail(ErrorCode::MissingWord, loc, "G7x.x requires a Q word");
  if (ctx.s.comp.active() && cycle != 70)
    return ctx.fail(
        ErrorCode::CutterCompMisused, loc,
        fmt::format("G{}.{} cannot be used with cutter compensation enabled", cycle, sub));
  if (ctx.s.plane != Plane::XZ)
    return ctx.fail(ErrorCode::UnknownGCode, loc,
                    fmt::format("G{}.{} can only be used in XZ plane (G18)", cycle, sub));
  for (const char a : {'A', 'B', 'C', 'U', 'V', 'W', 'Y'})
    if (w.has(a))
      return ctx.fail(
          ErrorCode::UnusedWord, w[a]->loc,
          fmt::format("{}: the word {} is not supported on a lathe cycle's line", code_name(c), a));
  double q = 0.0;
  if (!near_integer(w['Q']->value, q) || q <= 0 || q > 99999999)
    return ctx.fail(ErrorCode::ValueOutOfRange, w['Q']->loc,
                    fmt::format("{} Q{:g}: Q must be the number of an O-word subroutine",
                                code_name(c), w['Q']->value));
  // The start: X and Z (absolute, whatever G90/G91 says: LinuxCNC switches to G90 for the
  // cycle's first rapid), else where the tool is.
  const double u = ctx.scale();
  const Pos9 here = ctx.frame().to_program(comp_program_point(ctx));  // G70 under comp
  G7xCycle& g = *ctx.g7x;
  g = G7xCycle{};
  g.code10 = c.number10;
  g.loc = loc;
  g.label = fmt::format("{}", static_cast<long long>(q));
  g.x = here[0] / u;
  g.z = here[2] / u;
  if (ctx.s.incremental) {
    g.x += w.get('X');
    g.z += w.get('Z');
  } else {
    g.x = w.has('X') ? w['X']->value : g.x;
    g.z = w.has('Z') ? w['Z']->value : g.z;
  }
  g.d = w.get('D');
  g.e = w.get('E');
  g.i = w.get('I', 1.0);
  g.p = w.get('P', 1.0);
  g.r = w.get('R', 0.5);
  g.incremental = ctx.s.incremental;
  g.ijk_absolute = ctx.s.ijk_absolute;
  g.diameter = ctx.s.lathe_diameter;
  // LinuxCNC reads the profile in G0 mode: the cycle's rapid to its start (convert_straight G0,
  // made whether or not the line has X or Z) leaves G0 in force, so a profile block without
  // G0-G3 is a straight segment.
  g.motion = 0;
  g.at = Pt(g.z, g.x);
  g.start = g.at;
  if (w.first_axis != nullptr) {
    const bool inc = ctx.s.incremental;
    ctx.s.incremental = false;
    Pos9 target;
    const bool ok = axis_target(ctx, comp_program_point(ctx), target);
    ctx.s.incremental = inc;
    if (!ok) return false;
    if (ctx.s.comp.active() ? !comp_straight(ctx, MotionKind::Rapid, target)
                            : !emit_straight(ctx, MotionKind::Rapid, target, loc))
      return false;
  }
  g.position_mm = ctx.s.position_mm;
  g.pending = true;
  return true;
}

bool Interpreter::g7x_collect(const grammar::Block& block, InterpError& err) {
  G7xCycle& g = g7x_;
  // Only the motion words matter; every other word of a profile block is passed over.
  std::array<const grammar::Word*, 26> wd{};
  int motion = -1;
  for (const grammar::Word& x : block.words) {
    if (x.letter == 'G') {
      for (const int m : {0, 1, 2, 3})
        if (x.value == m) motion = 10 * m;
    } else if (x.letter >= 'A' && x.letter <= 'Z') {
      wd[static_cast<std::size_t>(x.letter - 'A')] = &x;
    }
  }
  struct {
    const std::array<const grammar::Word*, 26>& a;
    bool has(char c) const { return a[static_cast<std::size_t>(c - 'A')] != nullptr; }
    const grammar::Word* operator[](char c) const { return a[static_cast<std::size_t>(c - 'A')]; }
  } w{wd};
  auto val = [&](char c) { return w[c]->value; };
  Pt end = g.incremental ? Pt(0, 0) : g.at;
  if (w.has('U')) {
    if (g.incremental)
      return fail(err, ErrorCode::CycleMisused, w['U']->loc,
                  "G7x error: Cannot use U in incremental mode (G91)");
    if (w.has('X'))
      return fail(err, ErrorCode::CycleMisused, w['U']->loc,
                  "G7x error: Cannot use U and X in the same block");
    end.imag(end.imag() + (g.diameter ? val('U') / 2 : val('U')));
  } else if (w.has('X')) {
    end.imag(g.diameter ? val('X') / 2 : val('X'));
  }
  if (w.has('W')) {
    if (g.incremental)
      return fail(err, ErrorCode::CycleMisused, w['W']->loc,
                  "G7x error: Cannot use W in incremental mode (G91)");
    if (w.has('Z'))
      return fail(err, ErrorCode::CycleMisused, w['W']->loc,
                  "G7x error: Cannot use W and Z in the same block");
    end.real(end.real() + val('W'));
  } else if (w.has('Z')) {
    end.real(val('Z'));
  }
  Pt centre(w.has('K') ? val('K') : 0.0, w.has('I') ? val('I') : 0.0);
  if (g.incremental) end += g.at;
  if (motion >= 0) g.motion = motion;
  const SourceLoc at{block.line, 1};
  for (const char c : {'X', 'Z', 'U', 'W', 'I', 'K', 'R', 'A', 'C'})
    if (w.has(c) && !std::isfinite(val(c)))
      return fail(err, ErrorCode::NotANumber, w[c]->loc, "not a number");
  if (g.at == end) return true;
  if (g.profile.size() + 2 > lathe::kMaxProfileSegments)
    return fail(
        err, ErrorCode::ValueOutOfRange, at,
        fmt::format("G7x: the profile has more than {} elements", lathe::kMaxProfileSegments));
  const int mo = g.motion;
  if (mo == 0 || mo == 10) {
    g.profile.push_back(Seg::line(g.at, end));
  } else if (mo == 20 || mo == 30) {
    if (w.has('R')) {
      if (w.has('I') || w.has('K'))
        return fail(err, ErrorCode::ArcRWithIjk, w['R']->loc,
                    "G7X error: both R and I or K flag used for arc");
      const double r = val('R');
      centre = (g.at + end) / 2.0;
      const Pt d = Pt(0, 1) *
                   std::sqrt((r * r - std::norm(end - g.at) / 4) / std::norm(end - g.at)) *
                   (end - g.at);
      centre = mo == 30 ? centre + d : centre - d;
    } else {
      if (!w.has('I') && !w.has('K'))
        return fail(err, ErrorCode::ArcMissingCenter, at,
                    "G7X error: either I or K must be present for arc");
      if (!g.ijk_absolute) centre += g.at;
    }
    g.profile.push_back(Seg::arc(mo == 30, g.at, centre, end));
  }
  if (mo == 0 || mo == 10 || mo == 20 || mo == 30) {
    if (w.has('A') && w.has('C'))
      return fail(err, ErrorCode::CycleMisused, w['C']->loc,
                  "G7X error: Both A and C parameters on a corner");
    if (w.has('A')) g.profile.push_back(Seg::corner_at(Seg::Corner::Fillet, val('A'), end));
    if (w.has('C')) g.profile.push_back(Seg::corner_at(Seg::Corner::Chamfer, val('C'), end));
  }
  g.at = end;
  // The profile's point is where the tool is, for the subroutine's #<_x> and #<_z> (LinuxCNC
  // moves its current position along the profile while reading it).
  ModalState& st = state_mut();
  Pos9 prog = Pos9::Zero();
  prog[0] = end.imag() * st.mm_per_unit();
  prog[2] = end.real() * st.mm_per_unit();
  if (within(prog[0], kMaxPositionMm) && within(prog[2], kMaxPositionMm))
    st.position_mm = Frame(st).to_machine(st.position_mm, prog, 5u);
  return true;
}

bool Interpreter::g7x_finish(int line, std::vector<Canon>& out, InterpError& err) {
  G7xCycle g = std::move(g7x_);
  g7x_ = G7xCycle{};
  grammar::Block block;
  block.line = g.loc.line;  // the moves are the cycle line's; its errors are the return line's
  BlockWords w;
  ModalState& s = begin_block();
  BlockCtx ctx{machine_, block, w, s, out, err, tables_, nullptr};
  ctx.call_level = call_level_;
  const SourceLoc loc{line, 1};
  // The rs274 checked against (2.9.0~pre1) leaves its current point at the profile's end after
  // reading it; only under compensation (G70) does a move start from there (the first move is a
  // rapid, which prints only its end).
  if (!s.comp.active()) s.position_mm = g.position_mm;
  s.motion = g.motion;  // LinuxCNC leaves the profile's last motion mode in force
  const std::size_t mark = out.size();
  auto failed = [&](ErrorCode code, std::string msg) {
    out.resize(mark);
    return fail(err, code, loc, std::move(msg));
  };
  if (g.profile.size() <= 1) {
    commit_block();
    return true;
  }
  if (g.i <= 0)
    return failed(ErrorCode::ValueOutOfRange, "G7X error: I must be greater than zero.");
  if (!s.per_rev && !s.inverse_time && s.feed_mm_min <= 0.0)
    return failed(ErrorCode::ZeroFeed, "G7x: cannot feed with zero feed rate");
  if (s.inverse_time)
    return failed(ErrorCode::CycleMisused, "G7x in inverse time (G93) is not supported");
  const int cycle = g.code10 / 10;
  std::string why;
  bool ok = false;
  CanonSink sink(ctx, loc);
  try {
    if (cycle == 70) {
      ok = lathe::finish(std::move(g.profile), lathe::FinishParams{g.x, g.z, g.d, g.e, g.p}, sink,
                         why);
    } else {
      lathe::RoughParams rp;
      rp.sub = g.code10 % 10;
      rp.facing = cycle == 72;
      rp.x = g.x;
      rp.z = g.z;
      rp.d = g.d;
      rp.i = g.i;
      rp.r = g.r;
      ok = lathe::rough(std::move(g.profile), rp, sink, why);
    }
  } catch (const CanonSink::lathe_error&) {
    out.resize(mark);
    err.loc = loc;
    return false;
  } catch (const CanonSink::range_error&) {
    return failed(ErrorCode::ValueOutOfRange,
                  fmt::format("G7x: a move goes beyond {:g} mm", kMaxPositionMm));
  }
  if (!ok) return failed(ErrorCode::CycleMisused, "G7X error: " + why);
  commit_block();
  return true;
}

}  // namespace gm
