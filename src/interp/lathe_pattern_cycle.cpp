// The Fanuc/Haas lathe's G73 pattern repeating cycle: the profile Nns..Nnf cut d times, offset
// by the relief and the finishing allowance, the offset shrinking to the allowance.
#include "interp/lathe_fanuc.hpp"

namespace gm {

void FanucLathe::pattern(const PatternInput& in, std::vector<LatheMove>& out) {
  const int d = in.passes < 1 ? 1 : in.passes;
  for (int k = 1; k <= d; ++k) {
    // Pass k of d: the relief times (d - k) / (d - 1) (all of it first, none last), plus the
    // allowance (U a diameter).
    const double share = d == 1 ? 0.0 : static_cast<double>(d - k) / static_cast<double>(d - 1);
    const double sx = in.relief_x * share + in.du / 2, sz = in.relief_z * share + in.dw;
    LatheMove to_start;  // to A shifted (A_k), from A or from the end of the pass before
    to_start.kind = LatheMove::Kind::Rapid;
    to_start.z = in.z0 + sz;
    to_start.x = in.x0 + sx;
    out.push_back(to_start);
    for (const LatheProfileElement& e : in.profile) {
      LatheMove m = e.move;
      m.z += sz;
      m.x += sx;
      m.cz += sz;
      m.cx += sx;
      m.f = m.kind == LatheMove::Kind::Rapid ? -1.0
                                             : in.feed;  // the cycle's F (the profile's: G70's)
      out.push_back(m);
    }
  }
  LatheMove back;
  back.kind = LatheMove::Kind::Rapid;
  back.z = in.z0;
  back.x = in.x0;
  out.push_back(back);
}

}  // namespace gm
