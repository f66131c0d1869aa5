// Friendly names for the X3 rules an expectation can fail on, and the error they mean.
#pragma once

#include "common/error_codes.hpp"

#include <string_view>

namespace gm::grammar::parser {

/// Rule names used in the grammar; an x3::expectation_failure's which() is one of these.
inline constexpr std::string_view kNumberRule = "number";
inline constexpr std::string_view kCloseParenRule = "')'";

/// The catalogue code for an expectation failure on rule `which` where the input holds `at`
/// ('\0' at the end of the line).
inline ErrorCode classify_expectation(std::string_view which, char at) {
  if (which == kCloseParenRule)
    return at == '(' ? ErrorCode::NestedComment : ErrorCode::UnclosedComment;
  return ErrorCode::ExpectedNumber;
}

}  // namespace gm::grammar::parser
