// G70-G72's profile subroutine: called from the cycle's line, collected, then cut on its return.
#include "interp/g7x_driver.hpp"

namespace gm {

bool G7xDriver::start(const LinePos& at, FlowJump& jump, InterpError& err) {
  grammar::Block call;
  call.line = at.line;
  call.oword.kind = grammar::OKind::Call;
  call.oword.label = interp_.g7x().label;
  call.oword.loc = interp_.g7x().loc;
  interp_.g7x_started();
  const int depth = flow_.call_depth();
  base_ = depth;
  const bool ok = flow_.handle(call, at, jump, err);
  if (ok && flow_.call_depth() > depth) interp_.enter_call(flow_.call_depth());
  if (!ok) base_ = -1;
  return ok;
}

bool G7xDriver::after_return(int depth_before, int line, std::vector<Canon>& out,
                             InterpError& err) {
  if (base_ < 0 || flow_.call_depth() != base_ || depth_before <= base_) return true;
  base_ = -1;  // the profile subroutine returned: the cycle runs
  return interp_.g7x_finish(line, out, err);
}

}  // namespace gm
