// Fanuc Macro B's variables (--dialect fanuc): #0 vacant, locals #1-#33, commons #100-#999 and the
// system variables posts read (#3000 alarm, #3901/#3902, #4001-#4120 modal data, #5001-#5046
// positions, #5221+ work offsets), over the one parameter store; a vacant variable is a NaN.
#pragma once

#include "interp/interpreter.hpp"
#include "interp/parameters.hpp"

#include <cmath>
#include <limits>
#include <string_view>

namespace gm {

/// The value of a vacant ("null") variable: a quiet NaN, which no LinuxCNC value ever is.
inline constexpr double kVacant = std::numeric_limits<double>::quiet_NaN();
inline bool vacant(double v) {
  return std::isnan(v);
}

/// Fanuc Macro B's numbering (FANUC 16i/18i-MB operator's manual B-63534EN, II-15.1 "Variables"
/// and II-15.2 "System variables") over the parameter store: which numbers exist, which are
/// read-only, what the system variables read.
class MacroVariables {
 public:
  explicit MacroVariables(ParameterStore& params) : params_(params) {}

  /// At the program's start: the locals #1-#33 and the volatile commons #100-#499 are vacant,
  /// the kept commons #500-#999 too unless the parameter file gave them a value; #3901/#3902
  /// start at 0.
  void start();
  /// The sequence number (N) and program number (O) of the block before (#4114, #4115).
  void set_sequence(long n) { sequence_ = n; }
  void set_program(double o) { program_ = o; }
  /// Fanuc's transforms in force (interp/fanuc_modal.hpp): #4011 51, #4016 68, #4017 16.
  void set_transforms(bool scaling, bool rotation, bool polar) {
    scaling_ = scaling;
    rotation_ = rotation;
    polar_ = polar;
  }

  /// Haas (--dialect haas): the tool feed timers #5401-#5500 (seconds of feed of tools 1-100)
  /// read 0, as on a fresh machine (gmotion keeps no tool life).
  void set_haas(bool on) { haas_ = on; }

  /// The variable number `v` as computed (`#[#1+2]`): an integer >= 0 (a vacant index is #0).
  static bool number(double v, SourceLoc loc, int& n, InterpError& err);
  /// Reads #n. False with a located error naming the variable when there is no such one.
  bool read(int n, SourceLoc loc, double& v, InterpError& err) const;
  /// Whether a program may set #n (#0, modal data and positions are read-only).
  bool writable(int n, SourceLoc loc, InterpError& err) const;
  /// Sets #n to `v` (vacant allowed). #3000 = n raises alarm 3000 + n with the line's comment
  /// `remark` as its message: false with err.code CommentAbort (the program stops).
  bool write(int n, double v, std::string_view remark, SourceLoc loc, InterpError& err);

 private:
  bool modal(int n, double& v) const;
  bool position(int n, double& v) const;
  double named(std::string_view name) const;

  ParameterStore& params_;
  long sequence_ = -1;
  bool scaling_ = false, rotation_ = false, polar_ = false;
  bool haas_ = false;
  double program_ = kVacant;
};

}  // namespace gm
