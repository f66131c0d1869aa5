// Fanuc's modal rules that LinuxCNC's interpreter does not have (--dialect fanuc, haas): axis
// words after G80 move in the group 01 mode, G15/G16 polar coordinates, G68/G69 coordinate
// rotation, G51/G50 scaling and G51.1/G50.1 programmable mirror image.
#pragma once

#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"

#include <array>

namespace gm {

/// Rewrites each block (its words evaluated) into the block LinuxCNC's interpreter runs: the
/// transform codes are taken out and the axis words of its motion are given in the coordinates
/// the interpreter reads (programmed point -> mirror -> scaling -> rotation).
class FanucModal {
 public:
  /// `s`: the interpreter's state before `block`. False with `err` on an error.
  bool apply(grammar::Block& block, const ModalState& s, InterpError& err);

  /// An affine map of X Y Z (program units): q = a p + b.
  struct Affine {
    std::array<std::array<double, 3>, 3> a{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    std::array<double, 3> b{};
    std::array<double, 3> map(const std::array<double, 3>& p) const;
    std::array<double, 3> turn(const std::array<double, 3>& v) const;  ///< a v
    bool invert(Affine& inv) const;
  };
  /// The transform in force (identity when none).
  Affine transform() const;
  bool active() const { return polar_ || rotating_ || scaling_ || mirroring(); }
  bool scaling() const { return scaling_; }
  bool rotating() const { return rotating_; }
  bool polar() const { return polar_; }
  /// On a lathe machine G50 is left to the lathe's rules (G50 S, G50 X Z).
  void set_lathe(bool on) { lathe_ = on; }

 private:
  bool mirroring() const { return mirror_[0] || mirror_[1] || mirror_[2]; }
  bool modes(grammar::Block& block, const ModalState& s, const std::array<double, 3>& q_cur,
             const std::array<double, 3>& p_cur, InterpError& err);
  void group01(grammar::Block& block, const ModalState& s);
  bool rewrite(grammar::Block& block, const ModalState& s, const std::array<double, 3>& q_cur,
               const std::array<double, 3>& p_cur, InterpError& err);

  int group01_ = -1;  ///< the G0-G3 mode programmed (x 10), -1 none yet
  bool swapped_ = false;
  bool lathe_ =
      false;  ///< G50 is the lathe's  ///< the last rewrite ran G2 as G3 or back (a mirror image)
  bool polar_ = false;
  int polar_plane_ = 0;  ///< Plane of the G16 (radius: its first axis, angle: its second)
  bool rotating_ = false;
  int rotation_plane_ = 0;
  double rotation_deg_ = 0.0, rotation_ca_ = 0.0, rotation_cb_ = 0.0;
  bool scaling_ = false;
  std::array<double, 3> scale_{1, 1, 1}, scale_centre_{};
  std::array<bool, 3> mirror_{};
  std::array<double, 3> mirror_centre_{};
};

}  // namespace gm
