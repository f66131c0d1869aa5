// Fusion adaptation of the AST (must be at global scope), for attribute-based use and printing.
#pragma once

#include "grammar/ast.hpp"

#include <boost/fusion/include/adapt_struct.hpp>

BOOST_FUSION_ADAPT_STRUCT(gm::grammar::ast::Word, letter, num_first, num_last)
BOOST_FUSION_ADAPT_STRUCT(gm::grammar::ast::Comment, text_first, text_last)
