// What Haas mills define apart from Fanuc (--dialect haas): G154 P1-P99 work offsets and their
// G10 L20, G187 smoothness, G103 look-ahead, M19 P, M41/M42 gears; M97 is interp/haas_flow.cpp.
#pragma once

#include "common/diagnostic.hpp"
#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"
#include "interp/program_axes.hpp"
#include "motion/canon.hpp"

#include <array>
#include <string>
#include <vector>

namespace gm {

/// Haas's codes on one program's blocks, before the interpreter (LinuxCNC's) runs them.
class HaasCodes {
 public:
  /// Rewrites `block` (its words evaluated) into what the interpreter runs: `G154 Pn` selects
  /// work offset n (run as G59.3 holding its offsets), `G10 L20 Pn` sets it, `G187 [P] [E]` is
  /// `G64 [P E]`, `G103` is passed over, `M19 P` is `M19 R`, M41/M42 are recorded in `out`.
  /// Warnings go to `diags`. False with `err` on an error.
  bool apply(grammar::Block& block, Interpreter& interp, const std::string& text,
             std::vector<Canon>& out, std::vector<Diagnostic>& diags, InterpError& err);
  /// True if `block` holds M97 (a local subprogram call).
  static bool local_call(const grammar::Block& block);
  /// The G154 P number in effect, 0 when none.
  int work_offset() const { return active_; }

 private:
  bool g154(grammar::Block& block, std::size_t at, Interpreter& interp, InterpError& err);
  bool g10_l20(grammar::Block& block, Interpreter& interp, InterpError& err);
  void select(Interpreter& interp, int p);
  void warn_once(bool& warned, SourceLoc loc, const std::string& what, const std::string& text,
                 std::vector<Diagnostic>& diags) const;

  std::array<Pos9, 99> offsets_mm_ = make_offsets();  ///< G154 P1..P99 (machine coordinates)
  int active_ = 0;
  bool smoothness_warned_ = false, lookahead_warned_ = false;
  static std::array<Pos9, 99> make_offsets() {
    std::array<Pos9, 99> a;
    for (auto& p : a) p.setZero();
    return a;
  }
};

}  // namespace gm
