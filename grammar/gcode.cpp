// The only translation unit that instantiates Spirit X3: the block rule over const char*.
#include "grammar/config.hpp"
#include "grammar/gcode_def.hpp"
#include "grammar/parse_items.hpp"

namespace gm::grammar {

namespace x3 = boost::spirit::x3;

namespace parser {
BOOST_SPIRIT_INSTANTIATE(block_type, iterator_type, context_type)
BOOST_SPIRIT_INSTANTIATE(oword_args_type, iterator_type, context_type)
BOOST_SPIRIT_INSTANTIATE(oword_param_type, iterator_type, context_type)
}  // namespace parser

bool parse_items(const char*& first, const char* last, ast::Block& out, ItemFailure& fail) {
  parser::current_block = &out;
  try {
    x3::parse(first, last, parser::block, out);
    return true;
  } catch (const x3::expectation_failure<parser::iterator_type>& e) {
    fail.where = e.where();
    fail.code = parser::classify_expectation(e.which(), e.where() == last ? '\0' : *e.where());
    return false;
  }
}

bool parse_oword_args(const char*& first, const char* last, ast::Block& out, ItemFailure& fail) {
  parser::current_block = &out;
  try {
    x3::parse(first, last, parser::oword_args);
    return true;
  } catch (const x3::expectation_failure<parser::iterator_type>& e) {
    fail.where = e.where();
    fail.code = parser::classify_expectation(e.which(), e.where() == last ? '\0' : *e.where());
    return false;
  }
}

bool parse_oword_param(const char*& first, const char* last, ast::Block& out, ItemFailure& fail) {
  parser::current_block = &out;
  try {
    x3::parse(first, last, parser::oword_param);
    return true;
  } catch (const x3::expectation_failure<parser::iterator_type>& e) {
    fail.where = e.where();
    fail.code = parser::classify_expectation(e.which(), e.where() == last ? '\0' : *e.where());
    return false;
  }
}

}  // namespace gm::grammar
