// Expression evaluation (LinuxCNC's operators and functions) and parameter substitution.
#include "interp/expression.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace gm {

namespace {

using grammar::Op;

// LinuxCNC converts angles in long double: sin((x * pi) / 180) is evaluated as long double (its
// result rounded to double), and acos(x) * 180 / pi likewise; matching that keeps every printed
// digit equal to rs274's (TAN[90] is -3.99e19 there, not 1.6e16).
constexpr long double kPiL = std::numbers::pi_v<long double>;
double deg_sin(double x) {
  return static_cast<double>(std::sin((static_cast<long double>(x) * kPiL) / 180.0L));
}
double deg_cos(double x) {
  return static_cast<double>(std::cos((static_cast<long double>(x) * kPiL) / 180.0L));
}
double deg_tan(double x) {
  return static_cast<double>(std::tan((static_cast<long double>(x) * kPiL) / 180.0L));
}
double to_degrees(double rad) {
  return static_cast<double>((static_cast<long double>(rad) * 180.0L) / kPiL);
}
// LinuxCNC rounds by truncating x +- 0.5 to an int (so 0.49999999999999994 rounds to 1); beyond
// the int range the conversion gives INT_MIN on x86-64, which is mirrored.
double linuxcnc_round(double x) {
  const double y = x + (x < 0.0 ? -0.5 : 0.5);
  if (!(y > -2147483649.0 && y < 2147483648.0)) return -2147483648.0;
  return std::trunc(y);
}

std::string show(double v) {
  return fmt::format("{}", v);
}

// True if a setting `#<name>=` comes before op `i` on the line (ops are in the order written).
bool declared_before(const grammar::Block& block, std::string_view name, std::uint32_t i) {
  for (const grammar::Assignment& a : block.assignments)
    if (a.named && a.value.first <= i && block.name_of(a.name, a.name_size) == name) return true;
  return false;
}

}  // namespace

bool detail::declared_before(const grammar::Block& block, std::string_view name, std::uint32_t i) {
  return gm::declared_before(block, name, i);
}

bool detail::store_result(const grammar::ExprOp& o, double result, std::vector<double>& stack,
                          InterpError& err) {
  if (!std::isfinite(result))
    return fail(err, ErrorCode::NotANumber, o.loc,
                fmt::format("{} resulted in {}", grammar::op_name(o.op),
                            std::isnan(result) ? "not a number" : "infinity"));
  stack.back() = result;
  return true;
}

bool detail::single_result(const std::vector<double>& stack, double& out, InterpError& err) {
  if (stack.size() != 1)
    return fail(err, ErrorCode::BadExpression, err.loc, "malformed expression");
  out = stack.back();
  return true;
}

detail::Leaf detail::push_leaf(const grammar::Block& block, std::uint32_t i,
                               const ParameterStore& params, std::vector<double>& stack,
                               InterpError& err) {
  const grammar::ExprOp& o = block.ops[i];
  switch (o.op) {
    case Op::Number:
      stack.push_back(o.value);
      return Leaf::Pushed;
    case Op::Named: {
      const std::string_view name = block.name_of(o.name, o.name_size);
      // LinuxCNC creates a named parameter (value 0) when it reads `#<name>=` on the line:
      // reads written after that see 0 until the line's settings apply.
      double v = 0.0;
      if (!params.get_named(name, v) && !gm::declared_before(block, name, i)) {
        fail(err, ErrorCode::UndefinedParameter, o.loc,
             fmt::format("named parameter #<{}> is not defined", name));
        return Leaf::Failed;
      }
      stack.push_back(v);
      return Leaf::Pushed;
    }
    case Op::Exists: {
      double v = 0.0;
      stack.push_back(params.get_named(block.name_of(o.name, o.name_size), v) ? 1.0 : 0.0);
      return Leaf::Pushed;
    }
    default:
      return Leaf::NotLeaf;
  }
}

bool parameter_number(double v, SourceLoc loc, int& n, InterpError& err) {
  const double r = std::round(v);
  if (!(std::fabs(v - r) < 1e-4))
    return fail(err, ErrorCode::ParameterOutOfRange, loc,
                fmt::format("parameter number {} is not an integer", show(v)));
  if (r < ParameterStore::kFirst || r > ParameterStore::kLast)
    return fail(
        err, ErrorCode::ParameterOutOfRange, loc,
        fmt::format("parameter number #{} out of range (1-{})", show(r), ParameterStore::kLast));
  n = static_cast<int>(r);
  return true;
}

namespace {

// A function or unary operator `o` applied to `b` (Param reads parameter #b).
[[gnu::always_inline]] inline bool apply_unary(const grammar::ExprOp& o, double b,
                                               const ParameterStore& params, double& result,
                                               InterpError& err) {
  switch (o.op) {
    case Op::Param: {
      int n = 0;
      if (!parameter_number(b, o.loc, n, err)) return false;
      result = params.get(n);
      return true;
    }
    case Op::ExistsNumber: {  // rs274 2.9: every parameter number exists, others do not
      const double r = std::round(b);
      if (!(std::fabs(b - r) < 1e-4))
        return fail(err, ErrorCode::ParameterOutOfRange, o.loc,
                    fmt::format("EXISTS[#{}]: a parameter number is an integer", show(b)));
      result = r >= ParameterStore::kFirst && r <= ParameterStore::kLast ? 1.0 : 0.0;
      return true;
    }
    case Op::Neg:
      result = -b;
      return true;
    case Op::Abs:
      result = std::fabs(b);
      return true;
    case Op::Acos:
    case Op::Asin:
      if (b < -1.0 || b > 1.0)
        return fail(err, ErrorCode::DomainError, o.loc,
                    fmt::format("{}[{}]: argument outside -1..1", grammar::op_name(o.op), show(b)));
      result = to_degrees(o.op == Op::Acos ? std::acos(b) : std::asin(b));
      return true;
    case Op::Cos:
      result = deg_cos(b);
      return true;
    case Op::Sin:
      result = deg_sin(b);
      return true;
    case Op::Tan:
      result = deg_tan(b);
      return true;
    case Op::Exp:
      result = std::exp(b);
      return true;
    case Op::Fix:
      result = std::floor(b);
      return true;
    case Op::Fup:
      result = std::ceil(b);
      return true;
    case Op::Round:
      result = linuxcnc_round(b);
      return true;
    case Op::Ln:
      if (b <= 0.0)
        return fail(err, ErrorCode::DomainError, o.loc,
                    fmt::format("LN[{}]: argument must be positive", show(b)));
      result = std::log(b);
      return true;
    case Op::Sqrt:
      if (b < 0.0)
        return fail(err, ErrorCode::DomainError, o.loc,
                    fmt::format("SQRT[{}]: negative argument", show(b)));
      result = std::sqrt(b);
      return true;
    default:
      return fail(err, ErrorCode::BadExpression, o.loc, "malformed expression");
  }
}

// A binary operator `o` (or ATAN) applied to `a` and `b`.
[[gnu::always_inline]] inline bool apply_binary(const grammar::ExprOp& o, double a, double b,
                                                double& result, InterpError& err) {
  switch (o.op) {
    case Op::Atan2:
      result = to_degrees(std::atan2(a, b));
      return true;
    case Op::Pow:
      if (a < 0.0 && std::floor(b) != b)
        return fail(
            err, ErrorCode::DomainError, o.loc,
            fmt::format("{} ** {}: a negative number to a non-integer power", show(a), show(b)));
      result = std::pow(a, b);
      return true;
    case Op::Mul:
      result = a * b;
      return true;
    case Op::Div:
      if (b == 0.0)
        return fail(err, ErrorCode::DivisionByZero, o.loc,
                    fmt::format("division by zero: {} / 0", show(a)));
      result = a / b;
      return true;
    case Op::Mod:
      result = std::fmod(a, b);
      if (result < 0.0) result += std::fabs(b);
      return true;
    case Op::Add:
      result = a + b;
      return true;
    case Op::Sub:
      result = a - b;
      return true;
    case Op::Eq:
      result = std::fabs(a - b) < kEqualTolerance ? 1.0 : 0.0;
      return true;
    case Op::Ne:
      result = std::fabs(a - b) < kEqualTolerance ? 0.0 : 1.0;
      return true;
    case Op::Gt:
      result = a > b ? 1.0 : 0.0;
      return true;
    case Op::Ge:
      result = a >= b ? 1.0 : 0.0;
      return true;
    case Op::Lt:
      result = a < b ? 1.0 : 0.0;
      return true;
    case Op::Le:
      result = a <= b ? 1.0 : 0.0;
      return true;
    case Op::And:
      result = (a != 0.0 && b != 0.0) ? 1.0 : 0.0;
      return true;
    case Op::Or:
      result = (a != 0.0 || b != 0.0) ? 1.0 : 0.0;
      return true;
    case Op::Xor:
      result = ((a != 0.0) != (b != 0.0)) ? 1.0 : 0.0;
      return true;
    default:
      return fail(err, ErrorCode::BadExpression, o.loc, "malformed expression");
  }
}

}  // namespace

bool detail::apply_unary(const grammar::ExprOp& o, double b, const ParameterStore& params,
                         double& result, InterpError& err) {
  return gm::apply_unary(o, b, params, result, err);
}

bool detail::apply_binary(const grammar::ExprOp& o, double a, double b, double& result,
                          InterpError& err) {
  return gm::apply_binary(o, a, b, result, err);
}

bool Evaluator::evaluate(const grammar::Block& block, grammar::OpRange r,
                         const ParameterStore& params, double& out, InterpError& err) {
  if (macro_ != nullptr) return evaluate_macro(block, r, params, out, err);
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
    if (stack_.size() < (binary ? 2u : 1u))  // cannot happen for parsed input
      return fail(err, ErrorCode::BadExpression, o.loc, "malformed expression");
    const double b = stack_.back();
    if (binary) {
      stack_.pop_back();
      if (!apply_binary(o, stack_.back(), b, result, err)) return false;
    } else if (!apply_unary(o, b, params, result, err)) {
      return false;
    }
    if (!detail::store_result(o, result, stack_, err)) return false;
  }
  return detail::single_result(stack_, out, err);
}

namespace {

// One value as rs274 prints it in a comment: `format` is printf's "%lf", "%.0f" (%d) or "%.Nf";
// a value within 1e-4 of 0 prints as 0 (rs274 2.9), and a text past 29 characters as "######".
void append_comment_value(double v, int decimals, std::string& out) {
  if (std::fabs(v) < 1e-4) v = 0.0;
  const std::string text = fmt::format("{:.{}f}", v, decimals);
  out += text.size() < 30 ? text : std::string("######");
}

}  // namespace

void substitute_parameters(std::string_view text, const ParameterStore& params, std::string& out) {
  int decimals = 6;  // `%d`, `%f` and `%.Nf` set it for the rest of the comment (rs274)
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '%') {
      const char f = i + 1 < text.size() ? text[i + 1] : '\0';
      if (f == 'd' || f == 'f') {
        decimals = f == 'd' ? 0 : 4;
        i += 2;
      } else if (f == '.') {
        const char digit = i + 2 < text.size() ? text[i + 2] : '\0';
        if (digit >= '0' && digit <= '9' && i + 3 < text.size() && text[i + 3] == 'f') {
          decimals = digit - '0';
          i += 4;
        } else {  // rs274 drops the '%' of a '%.' that is no format
          out.push_back('.');
          i += 2;
        }
      } else {
        out.push_back(c);
        ++i;
      }
      continue;
    }
    if (c != '#' || i + 1 >= text.size()) {
      out.push_back(c);
      ++i;
      continue;
    }
    const char next = text[i + 1];
    if (next >= '0' && next <= '9') {
      std::size_t j = i + 1;
      long n = 0;
      while (j < text.size() && text[j] >= '0' && text[j] <= '9') {
        if (n < 1000000) n = n * 10 + (text[j] - '0');
        ++j;
      }
      if (n <= ParameterStore::kLast)
        append_comment_value(n >= ParameterStore::kFirst ? params.get(static_cast<int>(n)) : 0.0,
                             decimals, out);
      else
        out += "######";
      i = j;
    } else if (next == '<') {
      const std::size_t close = text.find('>', i + 2);
      if (close == std::string_view::npos) {
        out.append(text.substr(i));
        return;
      }
      std::string name;
      for (std::size_t k = i + 2; k < close; ++k) {
        char ch = text[k];
        if (ch == ' ' || ch == '\t') continue;
        if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
        name.push_back(ch);
      }
      double v = 0.0;
      if (params.get_named(name, v))
        append_comment_value(v, decimals, out);
      else
        out += "######";
      i = close + 1;
    } else {
      out.push_back(c);
      ++i;
    }
  }
}

bool LineEvaluator::run(grammar::Block& block, ParameterStore& params, InterpError& err) {
  if (macro_ != nullptr) return run_macro(block, params, err);
  // 1. Every value on the line, with the parameters as they were before the line.
  for (const grammar::WordExpr& we : block.word_exprs) {
    double v = 0.0;
    if (!eval_.evaluate(block, we.ops, params, v, err)) return false;
    block.words[we.word].value = v;
  }
  pending_.clear();
  for (const grammar::Assignment& a : block.assignments) {
    Pending p{a.named, 0, a.name, a.name_size, 0.0};
    if (!a.named) {
      double index = 0.0;
      if (!eval_.evaluate(block, a.index, params, index, err)) return false;
      if (!parameter_number(index, a.loc, p.number, err)) return false;
      if (ParameterStore::read_only(p.number))
        return fail(err, ErrorCode::ParameterReadOnly, a.loc,
                    fmt::format("parameter #{} is read-only", p.number));
    } else if (const std::string_view name = block.name_of(a.name, a.name_size);
               params.predefined(name)) {
      return fail(err, ErrorCode::ParameterReadOnly, a.loc,
                  name.starts_with("_ini[")
                      ? fmt::format("Cannot assign to read-only parameter #<{}>", name)
                      : fmt::format("#<{}> is a predefined read-only parameter", name));
    }
    if (!eval_.evaluate(block, a.value, params, p.value, err)) return false;
    pending_.push_back(p);
  }
  // 2. The settings, in the order written (the last of two settings of one parameter wins).
  for (const Pending& p : pending_) {
    if (p.named)
      params.set_named(block.name_of(p.name, p.name_size), p.value);
    else
      params.set(p.number, p.value);
  }
  // 3. The comment sees the new values.
  substitute_comments(block, params);
  return true;
}

void LineEvaluator::substitute_comments(grammar::Block& block, const ParameterStore& params) {
  auto substitute = [&](grammar::Message& m) {
    if (m.kind == grammar::CommentKind::Msg || m.text.find_first_of("#%") == std::string::npos)
      return;
    text_.clear();
    substitute_parameters(m.text, params, text_);
    m.text.swap(text_);
  };
  for (std::size_t i = 0; i < block.message_count; ++i) substitute(block.messages[i]);
  for (std::size_t i = 0; i < block.directive_count; ++i)
    if (block.directives[i].kind == grammar::CommentKind::Abort) substitute(block.directives[i]);
}

}  // namespace gm
