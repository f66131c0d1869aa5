// Evaluates the expressions of a parsed line (reverse Polish) against the parameter store.
#pragma once

#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"
#include "interp/parameters.hpp"

#include <string>
#include <vector>

namespace gm {

class MacroVariables;

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
  /// Evaluates with Fanuc Macro B's rules from now on (--dialect fanuc; null: LinuxCNC's).
  void set_macro(const MacroVariables* m) { macro_ = m; }

 private:
  /// Fanuc Macro B's rules (interp/macro_expression.cpp): vacant values, Fanuc's variable
  /// numbers, FIX/FUP/ATAN/ASIN as Fanuc, AND/OR/XOR bit by bit.
  bool evaluate_macro(const grammar::Block& block, grammar::OpRange r, const ParameterStore& params,
                      double& out, InterpError& err);
  std::vector<double> stack_;
  const MacroVariables* macro_ = nullptr;
};

namespace detail {
/// A function or unary operator applied to `b` with LinuxCNC's rules (Param reads #b).
bool apply_unary(const grammar::ExprOp& o, double b, const ParameterStore& params, double& result,
                 InterpError& err);
/// A binary operator (or ATAN) applied to `a` and `b` with LinuxCNC's rules.
bool apply_binary(const grammar::ExprOp& o, double a, double b, double& result, InterpError& err);
/// True if a setting `#<name>=` comes before op `i` on the line.
bool declared_before(const grammar::Block& block, std::string_view name, std::uint32_t i);
/// What push_leaf did with op `i`: pushed its value, failed (`err` set), or left it (an operator).
enum class Leaf { Pushed, Failed, NotLeaf };
/// Pushes the value of a leaf op (a number, a named parameter, EXISTS[...]) as every dialect
/// reads it; an undefined named parameter fails unless `#<name>=` comes before it on the line.
Leaf push_leaf(const grammar::Block& block, std::uint32_t i, const ParameterStore& params,
               std::vector<double>& stack, InterpError& err);
/// Puts op o's `result` on top of the stack; a result that is not finite fails, located at o.
bool store_result(const grammar::ExprOp& o, double result, std::vector<double>& stack,
                  InterpError& err);
/// The expression's value: the one value left on the stack (else "malformed expression").
bool single_result(const std::vector<double>& stack, double& out, InterpError& err);
}  // namespace detail

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
  /// Fanuc Macro B's rules from now on (null: LinuxCNC's): a vacant value omits its word,
  /// settings go through `m` (#3000's alarm, read-only system variables).
  void set_macro(MacroVariables* m) {
    macro_ = m;
    eval_.set_macro(m);
  }

 private:
  bool run_macro(grammar::Block& block, ParameterStore& params, InterpError& err);
  void substitute_comments(grammar::Block& block, const ParameterStore& params);
  MacroVariables* macro_ = nullptr;
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
