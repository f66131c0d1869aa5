// Friendly names for the X3 rules an expectation can fail on, and the error they mean.
#pragma once

#include "common/error_codes.hpp"

#include <string_view>

namespace gm::grammar::parser {

/// Rule names used in the grammar; an x3::expectation_failure's which() is one of these.
inline constexpr std::string_view kNumberRule = "number";
inline constexpr std::string_view kCloseParenRule = "')'";
inline constexpr std::string_view kExpressionRule = "expression";
inline constexpr std::string_view kParameterRule = "parameter";
inline constexpr std::string_view kNameRule = "name";
inline constexpr std::string_view kCloseNameRule = "'>'";
inline constexpr std::string_view kOpenBracketRule = "'['";
inline constexpr std::string_view kCloseBracketRule = "']'";
inline constexpr std::string_view kSlashRule = "'/'";
inline constexpr std::string_view kEqualsRule = "'='";

/// The catalogue code for an expectation failure on rule `which` where the input holds `at`
/// ('\0' at the end of the line).
inline ErrorCode classify_expectation(std::string_view which, char at) {
  if (which == kCloseParenRule)
    return at == '(' ? ErrorCode::NestedComment : ErrorCode::UnclosedComment;
  if (which == kNumberRule) return ErrorCode::ExpectedNumber;
  const bool word_char = (at >= 'A' && at <= 'Z');
  if (which == kCloseBracketRule)
    return word_char ? ErrorCode::UnknownOperator : ErrorCode::UnclosedBracket;
  if (which == kExpressionRule && word_char) return ErrorCode::UnknownOperator;
  if (which == kCloseNameRule || which == kNameRule) return ErrorCode::BadParameterName;
  if (which == kEqualsRule) return ErrorCode::ExpectedEquals;
  return ErrorCode::BadExpression;
}

}  // namespace gm::grammar::parser
