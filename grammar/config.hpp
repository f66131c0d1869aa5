// The iterator and context types the one instantiated X3 rule is compiled for.
#pragma once

#include <boost/spirit/home/x3.hpp>

namespace gm::grammar::parser {

namespace x3 = boost::spirit::x3;

/// The parser runs over the compacted line in memory.
using iterator_type = const char*;
/// No skipper (spaces are removed before parsing) and no extra context.
using context_type = x3::unused_type;

}  // namespace gm::grammar::parser
