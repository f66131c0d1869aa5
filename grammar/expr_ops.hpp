// The operations of a parsed expression (reverse Polish), shared by the grammar and the evaluator.
#pragma once

#include <cstdint>

namespace gm::grammar {

/// One step of an expression in reverse Polish order. Operands are pushed (Number, Named,
/// Exists), Param pops a parameter number and pushes its value, the rest pop their operands.
enum class Op : std::uint8_t {
  Number,        ///< a literal
  Param,         ///< #n: pops n, pushes the value of parameter n
  Named,         ///< #<name>
  Exists,        ///< EXISTS[#<name>]
  ExistsNumber,  ///< EXISTS[#n]: pops n, pushes 1 when #n is a parameter number (1..5601)
  Neg,           ///< unary minus
  // functions of one argument (degrees)
  Abs,
  Acos,
  Asin,
  Cos,
  Exp,
  Fix,
  Fup,
  Round,
  Ln,
  Sin,
  Sqrt,
  Tan,
  Atan2,  ///< ATAN[y]/[x]: pops x, then y
  // binary operators, highest precedence first
  Pow,
  Mul,
  Div,
  Mod,
  Add,
  Sub,
  Eq,
  Ne,
  Gt,
  Ge,
  Lt,
  Le,
  And,
  Or,
  Xor,
  // Fanuc Macro B's logical operators: bit by bit on the integer values (--dialect fanuc)
  BitAnd,
  BitOr,
  BitXor,
};

/// The names of the operators and functions as written, by Op. At namespace scope: a table local
/// to op_name was copied onto the stack at every call (264 bytes per operator evaluated).
inline constexpr const char* kOpNames[] = {
    "number", "#",   "#<>", "EXISTS", "EXISTS", "-",   "ABS",  "ACOS", "ASIN", "COS",
    "EXP",    "FIX", "FUP", "ROUND",  "LN",     "SIN", "SQRT", "TAN",  "ATAN", "**",
    "*",      "/",   "MOD", "+",      "-",      "EQ",  "NE",   "GT",   "GE",   "LT",
    "LE",     "AND", "OR",  "XOR",    "AND",    "OR",  "XOR"};

/// The name of an operator or function as written (for messages).
constexpr const char* op_name(Op op) {
  return kOpNames[static_cast<int>(op)];
}

}  // namespace gm::grammar
