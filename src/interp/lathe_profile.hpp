// Lathe profile geometry of G70-G72 (LinuxCNC 2.9's cycles): a profile of lines and arcs in the
// ZX plane, offset by a distance, roughed in layers (G71/G72) or finished (G70).
#pragma once

#include <complex>
#include <cstdint>
#include <string>
#include <vector>

namespace gm::lathe {

/// A point of the ZX plane, program units: real = Z, imag = X (radius).
using Pt = std::complex<double>;

/// One element of a profile: a line from a to b, or an arc from a to b about c.
struct Seg {
  enum class Kind : std::uint8_t { Line, Arc };
  enum class Corner : std::uint8_t { None, Fillet, Chamfer };
  Kind kind = Kind::Line;
  bool ccw = false;  ///< arc: G3
  Pt a, b, c;
  Corner corner = Corner::None;  ///< a rounding or chamfer of size `finish` still to be made
  double finish = 0.0;

  static Seg line(Pt a, Pt b) { return Seg{Kind::Line, false, a, b, Pt{}, Corner::None, 0.0}; }
  static Seg arc(bool ccw, Pt a, Pt c, Pt b) {
    return Seg{Kind::Arc, ccw, a, b, c, Corner::None, 0.0};
  }
  /// A corner (profile word A: fillet, C: chamfer) of size d at point p.
  static Seg corner_at(Corner k, double d, Pt p) {
    return Seg{k == Corner::Fillet ? Kind::Arc : Kind::Line, false, p, p, p, k, d};
  }
};

/// Where the cycle's moves go (program units, the ZX plane as given to the cycle).
class PathSink {
 public:
  virtual ~PathSink() = default;
  virtual void feed(Pt end) = 0;
  virtual void rapid(Pt end) = 0;
  virtual void arc(bool ccw, Pt centre, Pt end) = 0;
};

/// The cycle's numbers (program units).
struct RoughParams {
  int sub = 0;          ///< 0: everything, 1: no pockets (G7x.1), 2: after the first pocket (G7x.2)
  bool facing = false;  ///< G72: layers along X
  double x = 0, z = 0;  ///< the cycle's start
  double d = 0;         ///< distance left to the profile
  double i = 1;         ///< depth of a layer
  double r = 0.5;       ///< retract
  double u = 0, w = 0;  ///< displacement of the profile
};
struct FinishParams {
  double x = 0, z = 0;
  double d = 0, e = 0, p = 1;
};

/// Limits that keep a hostile program from running long or filling memory: the moves of one
/// cycle (all held as one block's canon), and the element offsets of one cycle (G70 offsets the
/// profile again for every pass).
inline constexpr std::int64_t kMaxCycleMoves = 200'000;
inline constexpr std::int64_t kMaxOffsetWork = 5'000'000;
inline constexpr std::size_t kMaxProfileSegments = 100'000;

/// G71/G72 over `profile` (its first element runs from the cycle's start to the profile). False
/// with `error` set when the profile cannot be cut (error empty: the sink reported one).
bool rough(std::vector<Seg> profile, const RoughParams& p, PathSink& out, std::string& error);
/// G70.
bool finish(std::vector<Seg> profile, const FinishParams& p, PathSink& out, std::string& error);
/// The profile moved `distance` away from the material (towards the cycle's start for a
/// positive one), with joining arcs where the elements part; `profile` as rough() takes it,
/// already turned so that Z and X decrease. Exposed for the tests.
bool offset_profile(std::vector<Seg>& profile, double distance, std::string& error);

}  // namespace gm::lathe
