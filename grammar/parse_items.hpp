// The X3-free entry point into the instantiated grammar (defined in gcode.cpp).
#pragma once

#include "common/error_codes.hpp"
#include "grammar/ast.hpp"

namespace gm::grammar {

/// Why parse_items stopped early.
struct ItemFailure {
  ErrorCode code = ErrorCode::None;  ///< ExpectedNumber, UnclosedComment or NestedComment
  const char* where = nullptr;       ///< the character the expectation failed on
};

/// Parses words and comments from `first` up to `last` into `out` (appending). Advances `first`
/// past what it matched. Returns false on an expectation failure (`fail` says which and where);
/// returns true when it stopped, possibly before `last`, at a character that starts no item.
bool parse_items(const char*& first, const char* last, ast::Block& out, ItemFailure& fail);

/// Parses the bracketed arguments of an O-word (`[expr] [expr] ...`) from `first` into
/// out.args/out.ops; stops at the first character that starts no argument. False on a malformed
/// expression (`fail` says which and where).
bool parse_oword_args(const char*& first, const char* last, ast::Block& out, ItemFailure& fail);

/// Parses `#parameter` at `first` (the O-word number of `o#<name> call`) as one argument into
/// out.args/out.ops. False on a malformed parameter (`fail` says which and where).
bool parse_oword_param(const char*& first, const char* last, ast::Block& out, ItemFailure& fail);

}  // namespace gm::grammar
