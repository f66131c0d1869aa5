// Definition of the block rule: words (letter + number or expression), parameter settings,
// ( comments ), ; comments. Expressions are emitted as reverse-Polish operation lists.
#pragma once

#include "grammar/ast.hpp"
#include "grammar/ast_adapted.hpp"
#include "grammar/error_handler.hpp"
#include "grammar/gcode.hpp"

#include <boost/spirit/home/x3.hpp>

namespace gm::grammar::parser {

namespace x3 = boost::spirit::x3;

/// The block being parsed on this thread (set by parse_items): the actions of the nested
/// expression rules append to it (X3 rules without attributes have no _val of their own).
static thread_local ast::Block* current_block = nullptr;
inline ast::Block& B() {
  return *current_block;
}

// The line is compacted before parsing: no spaces or tabs outside comments, letters upper case.
// Characters are matched with explicit ranges (never std::isalpha: bytes >= 0x80 are negative).
inline auto const letter = x3::char_("A-Z@^");  // @ and ^: polar radius and angle
inline auto const digit = x3::char_('0', '9');

struct number_class;
struct close_paren_class;
struct value_class;
struct expr_class;
struct unary_class;
struct primary_class;
struct param_body_class;
struct name_class;
struct close_name_class;
struct open_bracket_class;
struct close_bracket_class;
struct slash_class;
struct equals_class;
struct assign_value_class;
struct macro_expr_class;
inline x3::rule<number_class> const number{kNumberRule.data()};
inline x3::rule<close_paren_class> const close_paren{kCloseParenRule.data()};
inline x3::rule<value_class> const value{kNumberRule.data()};
inline x3::rule<expr_class> const expr{kExpressionRule.data()};
inline x3::rule<unary_class> const unary{kExpressionRule.data()};
inline x3::rule<primary_class> const primary{kExpressionRule.data()};
inline x3::rule<param_body_class> const param_body{kParameterRule.data()};
inline x3::rule<name_class> const name{kNameRule.data()};
inline x3::rule<close_name_class> const close_name{kCloseNameRule.data()};
inline x3::rule<open_bracket_class> const open_bracket{kOpenBracketRule.data()};
inline x3::rule<close_bracket_class> const close_bracket{kCloseBracketRule.data()};
inline x3::rule<slash_class> const slash{kSlashRule.data()};
inline x3::rule<equals_class> const equals{kEqualsRule.data()};
inline x3::rule<assign_value_class> const assign_value{kExpressionRule.data()};
inline x3::rule<macro_expr_class> const macro_expr{kExpressionRule.data()};

/// Matches nothing, and succeeds only while the block is read as Fanuc Macro B (--dialect
/// fanuc): the Macro B forms stay behind one flag test.
struct macro_b_parser : x3::parser<macro_b_parser> {
  using attribute_type = x3::unused_type;
  static bool const has_attribute = false;
  template <typename It, typename Ctx, typename RCtx, typename Attr>
  bool parse(It&, It const&, Ctx const&, RCtx&, Attr&) const {
    return B().macro_b;
  }
};
inline macro_b_parser const macro_b{};

namespace actions {
/// The word being read was written with a decimal point (Fanuc's `G04 P2.` against `P2000`).
inline auto const word_point = [](auto&) { B().words[B().word_count - 1].decimal_point = true; };
}  // namespace actions
/// A real number: optional sign, digits with an optional point (leading or trailing). No
/// exponent: E is a word letter (M66/M67/M68 E<channel>), so X1E5 is X1 then E5, as in rs274.
inline auto const point = x3::lit('.')[actions::word_point];
inline auto const number_def = -x3::char_("+-") >>
                               ((+digit >> -(point >> *digit)) | (point >> +digit));
/// A number inside an expression: no sign (unary minus is an operator), no exponent.
inline auto const unsigned_number =
    (+digit >> -(x3::lit('.') >> *digit)) | (x3::lit('.') >> +digit);
inline auto const close_name_def = x3::lit('>');
inline auto const open_bracket_def = x3::lit('[');
inline auto const close_bracket_def = x3::lit(']');
inline auto const slash_def = x3::lit('/');

namespace actions {
inline int here(const auto& ctx) {
  return B().offset(x3::_where(ctx).begin());
}
inline auto const begin_word = [](auto& ctx) {
  ast::Block& b = B();
  ast::Word& w = b.next_word();
  w.letter = x3::_attr(ctx);
  // _where is the input after the match: the letter is the one character before it.
  w.id_first = here(ctx) - 1;
  w.num_first = w.num_last = w.id_last = w.id_first + 1;
  w.decimal_point = false;
  w.expr_first = w.expr_last = static_cast<int>(b.ops.size());
  b.open = ast::Open::Word;
  b.open_ops = b.ops.size();
};
inline auto const end_word = [](auto& ctx) {
  ast::Block& b = B();
  ast::Word& w = b.words[b.word_count - 1];
  w.num_first = b.offset(x3::_attr(ctx).begin());
  w.num_last = w.id_last = b.offset(x3::_attr(ctx).end());
  b.open = ast::Open::None;
};
inline auto const end_expr_word = [](auto& ctx) {
  ast::Block& b = B();
  ast::Word& w = b.words[b.word_count - 1];
  w.expr_last = static_cast<int>(b.ops.size());
  w.decimal_point = false;  // (an expression's value has no written point)
  w.num_first = w.id_first + 1;
  w.num_last = w.id_last = b.offset(x3::_attr(ctx).end());
  b.open = ast::Open::None;
};
inline auto const begin_comment = [](auto& ctx) {
  ast::Block& b = B();
  ast::Comment& c = b.next_comment();
  c.id_first = here(ctx) - 1;  // the '(' just matched
  c.text_first = c.text_last = c.id_last = c.id_first + 1;
  b.open = ast::Open::Comment;
};
inline auto const comment_text = [](auto& ctx) {
  ast::Block& b = B();
  ast::Comment& c = b.comments[b.comment_count - 1];
  c.text_first = b.offset(x3::_attr(ctx).begin());
  c.text_last = b.offset(x3::_attr(ctx).end());
  c.id_last = c.text_last + 1;
};
inline auto const end_comment = [](auto&) { B().open = ast::Open::None; };

// Expressions ---------------------------------------------------------------------------------
inline void push(Op op, int first, int last = 0) {
  B().ops.push_back(ast::ExprOp{op, first, last});
}
inline auto const emit_number = [](auto& ctx) {
  push(Op::Number, B().offset(x3::_attr(ctx).begin()), B().offset(x3::_attr(ctx).end()));
};
/// Operators are emitted by actions on x3::raw[...]: the attribute is the range the operator and
/// its operands span, and it begins where the operator is written.
template <Op kOp>
inline auto const emit = [](auto& ctx) { push(kOp, B().offset(x3::_attr(ctx).begin())); };
/// Remembers the operator or function just matched until its operand(s) are parsed.
inline auto const hold = [](auto& ctx) { B().pending.push_back(x3::_attr(ctx)); };
inline auto const emit_held = [](auto& ctx) {
  ast::Block& b = B();
  const Op op = b.pending.back();
  b.pending.pop_back();
  push(op, b.offset(x3::_attr(ctx).begin()));
};
/// The last name read (between '<' and '>'), kept for the action that uses it.
static thread_local int last_name_first = 0;
static thread_local int last_name_last = 0;
inline auto const grab_name = [](auto& ctx) {
  last_name_first = B().offset(x3::_attr(ctx).begin());
  last_name_last = B().offset(x3::_attr(ctx).end());
};
inline auto const emit_named = [](auto&) { push(Op::Named, last_name_first, last_name_last); };
inline auto const emit_exists = [](auto&) { push(Op::Exists, last_name_first, last_name_last); };

// Parameter settings --------------------------------------------------------------------------
inline auto const begin_assign = [](auto& ctx) {
  ast::Block& b = B();
  ast::Assign a;
  a.pos = here(ctx) - 1;  // the '#' just matched
  a.index_first = a.index_last = static_cast<int>(b.ops.size());
  b.assigns.push_back(a);
  b.open = ast::Open::Assign;
  b.open_ops = b.ops.size();
};
inline auto const assign_name = [](auto&) {
  ast::Assign& a = B().assigns.back();
  a.name_first = last_name_first;
  a.name_last = last_name_last;
};
inline auto const assign_index = [](auto&) {
  B().assigns.back().index_last = static_cast<int>(B().ops.size());
};
inline auto const begin_value = [](auto&) {
  B().assigns.back().value_first = static_cast<int>(B().ops.size());
};
inline auto const end_assign = [](auto&) {
  ast::Block& b = B();
  b.assigns.back().value_last = static_cast<int>(b.ops.size());
  b.open = ast::Open::None;
};
}  // namespace actions

// Actions of named rules sit inside their definitions: an action around a rule would hide the
// rule's name from expectation failures (which() names what was expected).
inline auto const close_paren_def = x3::lit(')')[actions::end_comment];
inline auto const equals_def = x3::lit('=')[actions::begin_value];

/// Functions of one bracketed argument (ATAN and EXISTS have their own forms).
struct functions_ : x3::symbols<Op> {
  functions_() {
    add("ABS", Op::Abs)("ACOS", Op::Acos)("ASIN", Op::Asin)("COS", Op::Cos)("EXP", Op::Exp)(
        "FIX", Op::Fix)("FUP", Op::Fup)("ROUND", Op::Round)("LN", Op::Ln)("SIN", Op::Sin)(
        "SQRT", Op::Sqrt)("TAN", Op::Tan);
  }
};
struct mul_ops_ : x3::symbols<Op> {
  mul_ops_() { add("*", Op::Mul)("/", Op::Div)("MOD", Op::Mod); }
};
struct add_ops_ : x3::symbols<Op> {
  add_ops_() { add("+", Op::Add)("-", Op::Sub); }
};
struct rel_ops_ : x3::symbols<Op> {
  rel_ops_() {
    add("EQ", Op::Eq)("NE", Op::Ne)("GT", Op::Gt)("GE", Op::Ge)("LT", Op::Lt)("LE", Op::Le);
  }
};
struct logic_ops_ : x3::symbols<Op> {
  logic_ops_() { add("AND", Op::And)("OR", Op::Or)("XOR", Op::Xor); }
};
/// Fanuc Macro B: AND is a multiplication-level operator, OR and XOR addition-level ones, all
/// bit by bit (FANUC 16i/18i-MB operator's manual B-63534EN, II-15.3, Table 15.3(a)).
struct macro_mul_ops_ : x3::symbols<Op> {
  macro_mul_ops_() { add("*", Op::Mul)("/", Op::Div)("MOD", Op::Mod)("AND", Op::BitAnd); }
};
struct macro_add_ops_ : x3::symbols<Op> {
  macro_add_ops_() { add("+", Op::Add)("-", Op::Sub)("OR", Op::BitOr)("XOR", Op::BitXor); }
};
inline macro_mul_ops_ const macro_mul_ops;
inline macro_add_ops_ const macro_add_ops;
inline functions_ const functions;
inline mul_ops_ const mul_ops;
inline add_ops_ const add_ops;
inline rel_ops_ const rel_ops;
inline logic_ops_ const logic_ops;

using actions::emit;
using actions::emit_held;
using actions::hold;

// #<name>: the name is everything up to '>' (spaces were removed, letters upper-cased).
inline auto const name_def = x3::raw[+(x3::char_ - x3::char_('>'))][actions::grab_name];
inline auto const named = x3::lit('<') > name > close_name;
inline auto const param_body_def =
    x3::omit[named][actions::emit_named] | x3::raw[primary][emit<Op::Param>];
inline auto const bracketed = open_bracket > expr > close_bracket;
inline auto const primary_def =
    x3::raw[unsigned_number][actions::emit_number] | (x3::lit('#') > param_body) |
    (x3::lit('[') > expr > close_bracket) |
    x3::raw[x3::lit("ATAN") > bracketed > slash > bracketed][emit<Op::Atan2>] |
    x3::omit[(x3::lit("EXISTS") >> x3::lit("[#<")) > name > close_name > close_bracket]
            [actions::emit_exists] |
    x3::raw[x3::lit("EXISTS") > open_bracket > x3::lit('#') > primary > close_bracket]
           [emit<Op::ExistsNumber>] |
    x3::raw[functions[hold] > bracketed][emit_held];
inline auto const unary_def =
    x3::raw[x3::lit('-') > unary][emit<Op::Neg>] | (x3::lit('+') > unary) | primary;
// LinuxCNC's precedence, each level left-associative: ** ; * / MOD ; + - ; EQ NE GT GE LT LE ;
// AND OR XOR (one level).
inline auto const power_level = unary >> *(x3::raw[x3::lit("**") > unary][emit<Op::Pow>]);
inline auto const mul_level = power_level >> *(x3::raw[mul_ops[hold] > power_level][emit_held]);
inline auto const add_level = mul_level >> *(x3::raw[add_ops[hold] > mul_level][emit_held]);
inline auto const rel_level = add_level >> *(x3::raw[rel_ops[hold] > add_level][emit_held]);
inline auto const linuxcnc_expr = rel_level >> *(x3::raw[logic_ops[hold] > rel_level][emit_held]);
// Fanuc Macro B's precedence (B-63534EN II-15.3): functions; * / MOD AND; + - OR XOR; EQ NE GT
// GE LT LE. LinuxCNC's ** stays (a Fanuc program never writes it).
inline auto const macro_mul_level = power_level >>
                                    *(x3::raw[macro_mul_ops[hold] > power_level][emit_held]);
inline auto const macro_add_level = macro_mul_level >>
                                    *(x3::raw[macro_add_ops[hold] > macro_mul_level][emit_held]);
inline auto const macro_expr_def = macro_add_level >>
                                   *(x3::raw[rel_ops[hold] > macro_add_level][emit_held]);
inline auto const expr_def = (macro_b > macro_expr) | linuxcnc_expr;

/// A word's value: a plain number (the fast path of every ordinary line) or an expression.
inline auto const value_def =
    x3::raw[number][actions::end_word] | x3::raw[unary][actions::end_expr_word];

inline auto const word = letter[actions::begin_word] > value;
/// A setting's value: LinuxCNC's one operand (`#1=[#2+#3]`), Fanuc's whole expression (`#1=#2+#3`).
inline auto const assign_value_def = (macro_b > macro_expr) | unary;
inline auto const assignment = x3::lit('#')[actions::begin_assign] >
                               (x3::omit[named][actions::assign_name] |
                                primary[actions::assign_index]) > equals
                               > assign_value[actions::end_assign];
inline auto const comment = x3::lit('(')[actions::begin_comment] >
                            x3::raw[*(x3::char_ - x3::char_("()"))][actions::comment_text] >
                            close_paren;
inline auto const line_comment = x3::lit(';') >> x3::omit[*x3::char_];

// O-word arguments: bracketed expressions, one after the other.
namespace actions {
inline auto const begin_arg = [](auto&) { B().arg_first = static_cast<int>(B().ops.size()); };
inline auto const end_arg = [](auto&) {
  B().args.push_back(ast::Block::Arg{B().arg_first, static_cast<int>(B().ops.size())});
};
}  // namespace actions
inline oword_args_type const oword_args = "oword arguments";
inline auto const oword_args_def =
    *x3::omit[x3::eps[actions::begin_arg] >> (x3::lit('[') > expr > close_bracket)]
             [actions::end_arg];

// `o#<name>`: the O-word number read from a parameter, kept as one argument.
inline oword_param_type const oword_param = "oword parameter";
inline auto const oword_param_def =
    x3::omit[x3::eps[actions::begin_arg] >> (x3::lit('#') > param_body)][actions::end_arg];

inline block_type const block = "block";
inline auto const block_def = *x3::omit[word | comment | line_comment | assignment];

BOOST_SPIRIT_DEFINE(number, close_paren, value, expr, unary, primary, param_body, name, close_name,
                    open_bracket, close_bracket, slash, equals, assign_value, macro_expr, block,
                    oword_args, oword_param)

}  // namespace gm::grammar::parser
