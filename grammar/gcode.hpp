// Declaration of the block rule (one line of G-code); its definition is in gcode_def.hpp.
#pragma once

#include "grammar/ast.hpp"

#include <boost/spirit/home/x3.hpp>

namespace gm::grammar::parser {

namespace x3 = boost::spirit::x3;

struct block_class;
/// block := ( word | '(' comment ')' | ';' rest-of-line )*
/// Stops (without failing) at the first character that starts none of these; throws
/// x3::expectation_failure for a letter without a number and for an unclosed/nested comment.
using block_type = x3::rule<block_class, ast::Block>;
BOOST_SPIRIT_DECLARE(block_type)

struct oword_args_class;
/// oword_args := ( '[' expression ']' )*
using oword_args_type = x3::rule<oword_args_class>;
BOOST_SPIRIT_DECLARE(oword_args_type)

struct oword_param_class;
/// oword_param := '#' parameter (the O-word number of `o#<name> call`)
using oword_param_type = x3::rule<oword_param_class>;
BOOST_SPIRIT_DECLARE(oword_param_type)

}  // namespace gm::grammar::parser
