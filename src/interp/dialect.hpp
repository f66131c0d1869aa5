// The G-code dialects gmotion reads: LinuxCNC's RS274/NGC (the reference), Fanuc/Haas posts, grbl.
#pragma once

#include "grammar/parse.hpp"

#include <string>
#include <string_view>

namespace gm {

/// What a program is written for (docs/dialects.md). LinuxCNC: exactly rs274's rules. Fanuc:
/// LinuxCNC's plus a program without M2/M30 ends with a warning and machine M-codes LinuxCNC
/// does not know are passed over (one warning each). Grbl: grbl 1.1's subset ('$' lines passed
/// over, no program end needed, G0 in effect at the start, what grbl rejects rejected).
enum class Dialect { LinuxCNC, Fanuc, Grbl };

/// "linuxcnc", "fanuc", "grbl" (any case); false for anything else.
bool parse_dialect(std::string_view text, Dialect& out);
const char* dialect_name(Dialect d);

/// A grbl setting or command line (`$H`, `$$`, `$110=500`, `$J=...`): first non-blank is '$'.
bool grbl_dollar_line(std::string_view text);

/// Checks `b` against grbl 1.1's G-code (gnea/grbl README and gcode.c): no parameters,
/// expressions or O-words; G and M codes and word letters from grbl's set; no P on arcs. False
/// with the offending place and why.
bool grbl_accepts(const grammar::Block& b, SourceLoc& loc, std::string& why);

}  // namespace gm
