// Number formatting for the CSV trace: the exact text fmt's "{}" and "{:.Nf}" give, faster.
#pragma once

#include <cstdint>

namespace gm {

/// Writes `v` in decimal at `p` (at most 20 characters); returns the end. Same text as "{}".
char* put_int(char* p, std::int64_t v);

/// Writes `x` with `decimals` (1..9) digits after the point at `p`; returns the end. The text
/// is exactly fmt's "{:.Nf}" (the correctly rounded decimal of the binary value, "-" kept for
/// negative values that round to zero, "nan"/"inf"): a fast integer path when |x|·10^N < 1e15
/// and the value is not within rounding distance of a half (then fmt itself writes it).
/// At most 350 characters (|x| up to DBL_MAX goes to fmt).
char* put_fixed(char* p, double x, int decimals);

}  // namespace gm
