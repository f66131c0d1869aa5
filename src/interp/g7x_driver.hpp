// G70-G72 on the program's side: the cycle's profile subroutine is called from the cycle's line,
// its blocks are collected (not run), and the cycle runs when it returns (steps_g7x.cpp cuts).
#pragma once

#include "interp/interpreter.hpp"
#include "interp/oword_flow.hpp"

#include <vector>

namespace gm {

/// Between a G70-G72 line and the return of its profile subroutine (LinuxCNC interp_g7x.cc):
/// the interpreter records the cycle (Interpreter::g7x_pending), this calls the subroutine as
/// `O<q> call` from that line, hands its blocks to the interpreter to collect, and has the
/// cycle cut when the subroutine returns to the cycle's call depth.
class G7xDriver {
 public:
  G7xDriver(Interpreter& interp, OwordFlow& flow) : interp_(interp), flow_(flow) {}

  /// A G70-G72 line just ran: its profile subroutine is to be called (start).
  bool pending() const { return interp_.g7x_pending(); }
  /// Calls the pending cycle's profile subroutine from the line at `at`; false with `err` when
  /// the call fails (the program is over then).
  bool start(const LinePos& at, FlowJump& jump, InterpError& err);
  /// True while the profile's blocks are read: they are collected, not run.
  bool collecting() const { return base_ >= 0 && flow_.call_depth() > base_; }
  /// One block of the profile: its motion is recorded.
  bool collect(const grammar::Block& block, InterpError& err) {
    return interp_.g7x_collect(block, err);
  }
  /// After an O-word line at `line` left call depth `depth_before`: when the profile has just
  /// returned, the cycle's moves are appended to `out` (false with `err` on an error there).
  bool after_return(int depth_before, int line, std::vector<Canon>& out, InterpError& err);

 private:
  Interpreter& interp_;
  OwordFlow& flow_;
  int base_ = -1;  ///< the call depth of the cycle's line while its profile is read, else -1
};

}  // namespace gm
