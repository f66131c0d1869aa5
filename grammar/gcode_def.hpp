// Definition of the block rule: words (letter + real number), ( comments ), ; comments.
#pragma once

#include "grammar/ast.hpp"
#include "grammar/ast_adapted.hpp"
#include "grammar/error_handler.hpp"
#include "grammar/gcode.hpp"

#include <boost/spirit/home/x3.hpp>

namespace gm::grammar::parser {

namespace x3 = boost::spirit::x3;

// The line is compacted before parsing: no spaces or tabs outside comments, letters upper case.
// Characters are matched with explicit ranges (never std::isalpha: bytes >= 0x80 are negative).
inline auto const letter = x3::char_('A', 'Z');
inline auto const digit = x3::char_('0', '9');

struct number_class;
struct close_paren_class;
inline x3::rule<number_class> const number{kNumberRule.data()};
inline x3::rule<close_paren_class> const close_paren{kCloseParenRule.data()};

/// A real number: optional sign, digits with an optional point (leading or trailing), and an
/// exponent that is only accepted so it can be reported (G-code has none).
inline auto const number_def = -x3::char_("+-") >>
                               ((+digit >> -(x3::lit('.') >> *digit)) | (x3::lit('.') >> +digit)) >>
                               -(x3::char_("E") >> -x3::char_("+-") >> +digit);
inline auto const close_paren_def = x3::lit(')');

namespace actions {
inline auto const begin_word = [](auto& ctx) {
  ast::Block& b = x3::_val(ctx);
  ast::Word& w = b.next_word();
  w.letter = x3::_attr(ctx);
  // _where is the input after the match: the letter is the one character before it.
  w.id_first = static_cast<int>(x3::_where(ctx).begin() - b.origin) - 1;
  w.num_first = w.num_last = w.id_last = w.id_first + 1;
};
inline auto const end_word = [](auto& ctx) {
  ast::Block& b = x3::_val(ctx);
  ast::Word& w = b.words[b.word_count - 1];
  w.num_first = static_cast<int>(x3::_attr(ctx).begin() - b.origin);
  w.num_last = w.id_last = static_cast<int>(x3::_attr(ctx).end() - b.origin);
};
inline auto const begin_comment = [](auto& ctx) {
  ast::Block& b = x3::_val(ctx);
  ast::Comment& c = b.next_comment();
  c.id_first = static_cast<int>(x3::_where(ctx).begin() - b.origin) - 1;  // the '(' just matched
  c.text_first = c.text_last = c.id_last = c.id_first + 1;
};
inline auto const comment_text = [](auto& ctx) {
  ast::Block& b = x3::_val(ctx);
  ast::Comment& c = b.comments[b.comment_count - 1];
  c.text_first = static_cast<int>(x3::_attr(ctx).begin() - b.origin);
  c.text_last = static_cast<int>(x3::_attr(ctx).end() - b.origin);
  c.id_last = c.text_last + 1;
};
}  // namespace actions

inline auto const word = letter[actions::begin_word] > x3::raw[number][actions::end_word];
inline auto const comment = x3::lit('(')[actions::begin_comment] >
                            x3::raw[*(x3::char_ - x3::char_("()"))][actions::comment_text] >
                            close_paren;
inline auto const line_comment = x3::lit(';') >> x3::omit[*x3::char_];

inline block_type const block = "block";
inline auto const block_def = *(word | comment | line_comment);

BOOST_SPIRIT_DEFINE(number, close_paren, block)

}  // namespace gm::grammar::parser
