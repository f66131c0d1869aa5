// Evaluates the expressions of a parsed line (reverse Polish) against the parameter store.
#pragma once

#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"
#include "interp/parameters.hpp"

#include <string>
#include <vector>

namespace gm {

/// LinuxCNC's tolerance for EQ and NE.
inline constexpr double kEqualTolerance = 1e-4;

/// Evaluates expressions with LinuxCNC's rules: angles in degrees, EQ/NE within 1e-4, MOD with
/// the sign of a positive divisor, every result finite. Reuses its stack (no allocation once
/// grown).
class Evaluator {
 public:
  /// Evaluates ops `r` of `block`. False with `err` set (located at the operator at fault).
  bool evaluate(const grammar::Block& block, grammar::OpRange r, const ParameterStore& params,
                double& out, InterpError& err);

 private:
  std::vector<double> stack_;
};

/// Resolves a parameter number computed as a double: it must be within 1e-4 of an integer in
/// 1..5601. False with `err` set at `loc`.
bool parameter_number(double v, SourceLoc loc, int& n, InterpError& err);

/// Replaces #n and #<name> in a DEBUG/PRINT/ABORT text by their values, as LinuxCNC does
/// (%f; "######" for an unset name or a number out of range). Appends to `out`.
void substitute_parameters(std::string_view text, const ParameterStore& params, std::string& out);

/// Evaluates every expression word and parameter setting of `block` and applies the settings
/// (LinuxCNC: every value on the line is read before any setting takes effect), then
/// substitutes the parameters of its DEBUG/PRINT/ABORT comment. On error nothing is set.
class LineEvaluator {
 public:
  bool run(grammar::Block& block, ParameterStore& params, InterpError& err);

 private:
  Evaluator eval_;
  struct Pending {
    bool named;
    int number;
    std::uint32_t name, name_size;
    double value;
  };
  std::vector<Pending> pending_;
  std::string text_;
};

}  // namespace gm
