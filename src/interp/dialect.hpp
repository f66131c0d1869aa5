// The G-code dialects gmotion reads (LinuxCNC's RS274/NGC, the reference; Fanuc/Haas posts;
// grbl) and their rules, in one place: DialectRules.
#pragma once

#include "common/diagnostic.hpp"
#include "grammar/parse.hpp"
#include "machine/tool_table.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// What a program is written for (docs/dialects.md). LinuxCNC: exactly rs274's rules. Fanuc:
/// LinuxCNC's plus a program without M2/M30 ends with a warning and machine M-codes LinuxCNC
/// does not know are passed over (one warning each). Grbl: grbl 1.1's subset ('$' lines passed
/// over, no program end needed, G0 in effect at the start, what grbl rejects rejected). Haas:
/// Fanuc's and what Haas mills define apart (M97, G154, G187, ...; interp/haas_codes.hpp).
/// Mach3: LinuxCNC's language as Mach3 reads it (G31, M47; interp/mach3_codes.cpp).
enum class Dialect { LinuxCNC, Fanuc, Grbl, Haas, Mach3 };

/// "linuxcnc", "fanuc", "grbl", "haas", "mach3" (any case); false for anything else.
bool parse_dialect(std::string_view text, Dialect& out);
const char* dialect_name(Dialect d);
/// Fanuc and Haas: Fanuc Macro B, Fanuc's modal rules (interp/fanuc_modal.hpp), machine M codes.
inline bool fanuc_family(Dialect d) {
  return d == Dialect::Fanuc || d == Dialect::Haas;
}

/// A grbl setting or command line (`$H`, `$$`, `$110=500`, `$J=...`): first non-blank is '$'.
bool grbl_dollar_line(std::string_view text);

/// Checks `b` against grbl 1.1's G-code (gnea/grbl README and gcode.c): no parameters,
/// expressions or O-words; G and M codes (the code table's grbl column) and word letters from
/// grbl's set; no P on arcs. False with the offending place and why.
bool grbl_accepts(const grammar::Block& b, SourceLoc& loc, std::string& why);

/// The line echoed under a diagnostic: very long lines are not (the location is still exact).
std::string echoed_line(const std::string& text);

/// rs274's LINELEN (255) less one: fgets filling this many bytes is LinuxCNC's "Command too long".
inline constexpr std::uint64_t kRs274LineBytes = 254;

/// The per-line rules in which the dialects differ, for one program (it remembers what it has
/// warned about). Each check appends its diagnostics to `diags`; `text` is the line as read.
class DialectRules {
 public:
  explicit DialectRules(Dialect d) : dialect_(d) {}
  Dialect dialect() const { return dialect_; }

  /// rs274 reads a line with fgets into 255 bytes and refuses one that fills 254 of them (line
  /// end included), even on lines it passes over: "Command too long". False (with the error)
  /// for such a line of `bytes` bytes; `truncated`: longer than the grammar reads (reported
  /// apart).
  bool line_fits(std::uint64_t bytes, bool truncated, int line, const std::string& text,
                 std::vector<Diagnostic>& diags) const {
    return dialect_ != Dialect::LinuxCNC || truncated || bytes < kRs274LineBytes ||
           line_too_long(bytes, line, text, diags);
  }
  /// grbl's setting and command lines ($H, $$, $110=500): not G-code, passed over (true), with
  /// a warning at the first.
  bool passed_over(const std::string& text, bool truncated, int line,
                   std::vector<Diagnostic>& diags) {
    return dialect_ == Dialect::Grbl && !truncated && grbl_passed_over(text, line, diags);
  }
  /// '/' skips the line under --block-delete; grbl passes over '/' and runs the line
  /// (protocol.c: block delete not supported).
  bool honours_block_delete() const { return dialect_ != Dialect::Grbl; }
  /// What the dialect refuses in a parsed block (grbl: what grbl 1.1 does not have). False with
  /// the error.
  bool accepts(const grammar::Block& block, const std::string& text,
               std::vector<Diagnostic>& diags) const {
    return dialect_ != Dialect::Grbl || grbl_block_accepted(block, text, diags);
  }
  /// Fanuc: M codes of Fanuc/Haas machines that LinuxCNC does not have (M31 chip conveyor, M88
  /// through-spindle coolant, ...) are taken out of `block` with one warning per code; M97 (Haas
  /// local subprogram call) is refused. False when nothing is left to execute.
  bool machine_codes(grammar::Block& block, const std::string& text,
                     std::vector<Diagnostic>& diags);
  /// Mach3 (interp/mach3_codes.cpp): G31 is G38.2; M47 (repeat from the first line) ends the
  /// program as M2, with a warning.
  void mach3_codes(grammar::Block& block, const std::string& text, std::vector<Diagnostic>& diags);
  /// Every dialect but LinuxCNC (interp/missing_tools.cpp): a T, H or D naming a tool `tools`
  /// lacks is a zero-length tool, added to `add` with a warning.
  void missing_tools(const grammar::Block& block, const ToolTable& tools, const std::string& text,
                     std::vector<Diagnostic>& diags, std::vector<ToolEntry>& add) const;
  /// Fanuc and Haas dwell (interp/fanuc_dwell.cpp): `P` without a decimal point is
  /// milliseconds (`P2000` = 2 s), Haas reads `P2.5` as seconds, Fanuc refuses a point in P; in
  /// G04 (`X`, and `U` on a `lathe`, are seconds) and in a mill's drilling cycles (G73, G74,
  /// G81-G89: the block naming one, or a block of holes under `motion`, the interpreter's motion
  /// mode x 10). Rewritten into LinuxCNC's seconds; false with the error in `diags`.
  bool fanuc_dwell(grammar::Block& block, bool lathe, int motion, const std::string& text,
                   std::vector<Diagnostic>& diags) const;
  /// The input ended after line `last_line` (0: empty) without M2/M30 or a closing '%':
  /// LinuxCNC's error, Fanuc's warning, nothing for grbl (it streams). `opened_percent`: the
  /// program opened with '%'; `last_text` and `file` locate it.
  void missing_end(int last_line, bool opened_percent, const std::string& last_text,
                   const std::string& file, std::vector<Diagnostic>& diags) const;
  /// A block the interpreter runs before the program's first line (grbl starts in G0: a first
  /// `X10` moves, where rs274 refuses it). False when there is none.
  bool start_block(grammar::Block& block) const;

 private:
  bool dwell_words(grammar::Block& block, bool lathe, int motion, const std::string& text,
                   std::vector<Diagnostic>& diags) const;
  bool g04_dwell(grammar::Block& block, grammar::Word* p, bool lathe, const std::string& text,
                 std::vector<Diagnostic>& diags) const;
  bool dwell_p(grammar::Word& p, const std::string& code, bool or_x, const std::string& text,
               std::vector<Diagnostic>& diags) const;

  // The parts of line_fits, passed_over and accepts past their dialect test (most lines of
  // most dialects never reach them).
  bool line_too_long(std::uint64_t bytes, int line, const std::string& text,
                     std::vector<Diagnostic>& diags) const;
  bool grbl_passed_over(const std::string& text, int line, std::vector<Diagnostic>& diags);
  bool grbl_block_accepted(const grammar::Block& block, const std::string& text,
                           std::vector<Diagnostic>& diags) const;

  Dialect dialect_;
  bool dollar_warned_ = false;
  bool m47_warned_ = false;
  std::array<bool, 100> fanuc_warned_{};
};

}  // namespace gm
