// Fanuc's modal macro call (--dialect fanuc, haas): after `G66 P p <arguments>`, each block that
// moves calls the macro as `G65 P p <arguments>` would, until G67.
#pragma once

#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"

namespace gm {

class ModalMacroCall {
 public:
  /// Takes G66 (with its P and arguments: the whole line) or G67 out of `block`, read at call
  /// level `call_depth`. False with `err` on an error.
  bool take(grammar::Block& block, int call_depth, InterpError& err);
  /// The G65 line to run after `block` (which moves, at the G66's call level), else null.
  const grammar::Block* after(const grammar::Block& block, int call_depth) const;

 private:
  bool on_ = false;
  int depth_ = 0;
  grammar::Block call_;  ///< `G65 P p <arguments>`
};

}  // namespace gm
