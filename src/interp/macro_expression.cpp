// Fanuc Macro B's expression rules (--dialect fanuc): vacant values, Fanuc's variable numbers and
// functions, bitwise AND/OR/XOR, and a line's settings with vacant words omitted.
#include "interp/expression.hpp"
#include "interp/macro_variables.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gm {

namespace {

using grammar::Op;

double vacant_as_zero(double v) {
  return vacant(v) ? 0.0 : v;
}

// Functions where Fanuc differs from LinuxCNC (B-63534EN II-15.3, Table 15.3(a) and its notes):
// FIX drops the fraction and FUP raises it, both away from or toward zero (FIX[-1.2] = -1,
// FUP[-1.2] = -2); ROUND rounds half away from zero; ASIN gives 270..90 and ATAN 0..360
// degrees (parameter NAT = 0, the default).
bool macro_unary(const grammar::ExprOp& o, double b, const ParameterStore& params, double& result,
                 InterpError& err) {
  switch (o.op) {
    case Op::Fix:
      result = std::trunc(b);
      return true;
    case Op::Fup:
      result = b < 0.0 ? std::floor(b) : std::ceil(b);
      return true;
    case Op::Round:
      result = std::round(b);
      return true;
    case Op::Asin:
      if (!detail::apply_unary(o, b, params, result, err)) return false;
      if (result < 0.0) result += 360.0;
      return true;
    default:
      return detail::apply_unary(o, b, params, result, err);
  }
}

bool macro_binary(const grammar::ExprOp& o, double a, double b, double& result, InterpError& err) {
  switch (o.op) {
    case Op::Atan2:
      if (!detail::apply_binary(o, a, b, result, err)) return false;
      if (result < 0.0) result += 360.0;
      return true;
    case Op::BitAnd:
    case Op::BitOr:
    case Op::BitXor: {  // bit by bit on the binary (integer) values
      if (std::fabs(a) > 2147483647.0 || std::fabs(b) > 2147483647.0)
        return fail(
            err, ErrorCode::DomainError, o.loc,
            fmt::format("{} {} {}: a logical operation takes integers below 2^31",
                        fmt::format("{}", a), grammar::op_name(o.op), fmt::format("{}", b)));
      const auto x = static_cast<std::int64_t>(std::llround(a));
      const auto y = static_cast<std::int64_t>(std::llround(b));
      result = static_cast<double>(o.op == Op::BitAnd  ? (x & y)
                                   : o.op == Op::BitOr ? (x | y)
                                                       : (x ^ y));
      return true;
    }
    default:
      return detail::apply_binary(o, a, b, result, err);
  }
}

}  // namespace

bool Evaluator::evaluate_macro(const grammar::Block& block, grammar::OpRange r,
                               const ParameterStore& params, double& out, InterpError& err) {
  stack_.clear();
  for (std::uint32_t i = r.first; i < r.last; ++i) {
    const grammar::ExprOp& o = block.ops[i];
    double result = 0.0;
    if (const detail::Leaf leaf = detail::push_leaf(block, i, params, stack_, err);
        leaf != detail::Leaf::NotLeaf) {
      if (leaf == detail::Leaf::Failed) return false;
      continue;
    }
    const bool binary = o.op >= Op::Atan2;
    if (stack_.size() < (binary ? 2u : 1u))
      return fail(err, ErrorCode::BadExpression, o.loc, "malformed expression");
    const double b = stack_.back();
    if (o.op == Op::Param) {  // may be vacant: `#2 = #1` copies the vacancy
      int n = 0;
      if (!MacroVariables::number(b, o.loc, n, err) || !macro_->read(n, o.loc, result, err))
        return false;
      stack_.back() = result;
      continue;
    }
    if (binary) {
      stack_.pop_back();
      const double a = stack_.back();
      if (o.op == Op::Eq || o.op == Op::Ne) {
        // Vacant and 0 differ for EQ and NE only (B-63534EN II-15.1, "Undefined variable").
        const bool equal =
            vacant(a) || vacant(b) ? vacant(a) && vacant(b) : std::fabs(a - b) < kEqualTolerance;
        result = equal == (o.op == Op::Eq) ? 1.0 : 0.0;
      } else if (!macro_binary(o, vacant_as_zero(a), vacant_as_zero(b), result, err)) {
        return false;
      }
    } else if (!macro_unary(o, vacant_as_zero(b), params, result, err)) {
      return false;
    }
    if (!detail::store_result(o, result, stack_, err)) return false;
  }
  return detail::single_result(stack_, out, err);
}

bool LineEvaluator::run_macro(grammar::Block& block, ParameterStore& params, InterpError& err) {
  // 1. Every value on the line, with the variables as they were before the line.
  bool any_vacant = false;
  for (const grammar::WordExpr& we : block.word_exprs) {
    double v = 0.0;
    if (!eval_.evaluate(block, we.ops, params, v, err)) return false;
    block.words[we.word].value = v;
    any_vacant = any_vacant || vacant(v);
  }
  pending_.clear();
  for (const grammar::Assignment& a : block.assignments) {
    Pending p{a.named, 0, a.name, a.name_size, 0.0};
    if (!a.named) {
      double index = 0.0;
      if (!eval_.evaluate(block, a.index, params, index, err)) return false;
      if (!MacroVariables::number(index, a.loc, p.number, err) ||
          !macro_->writable(p.number, a.loc, err))
        return false;
    } else if (const std::string_view name = block.name_of(a.name, a.name_size);
               params.predefined(name)) {
      return fail(err, ErrorCode::ParameterReadOnly, a.loc,
                  fmt::format("#<{}> is a predefined read-only parameter", name));
    }
    if (!eval_.evaluate(block, a.value, params, p.value, err)) return false;
    pending_.push_back(p);
  }
  // 2. The settings, in the order written.
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const Pending& p = pending_[i];
    if (p.named)
      params.set_named(block.name_of(p.name, p.name_size), p.value);
    else if (!macro_->write(p.number, p.value, block.remark, block.assignments[i].loc, err))
      return false;
  }
  // 3. A word whose value is vacant is omitted (B-63534EN II-15.1: G90 X#1 with #1 vacant is
  // G90).
  if (any_vacant)
    block.words.erase(std::remove_if(block.words.begin(), block.words.end(),
                                     [](const grammar::Word& w) { return vacant(w.value); }),
                      block.words.end());
  substitute_comments(block, params);
  return true;
}

}  // namespace gm
