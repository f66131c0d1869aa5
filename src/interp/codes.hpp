// The code table: every G and M code the interpreter knows, its modal group and its step.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace gm {

/// Modal groups (LinuxCNC's groups; G9 kept apart so that it combines with group 0 codes).
enum class Group : std::uint8_t {
  NonModal,     // G group 0: G4 G10 G28 G30 G52 G53 G92 ...
  Motion,       // G group 1: G0 G1 G2 G3 G80 G81..G89 ...
  Plane,        // G group 2
  Distance,     // G group 3
  ArcDistance,  // G group 4: G90.1 G91.1
  FeedMode,     // G group 5
  Units,        // G group 6
  CutterComp,   // G group 7
  ToolLength,   // G group 8
  ReturnMode,   // G group 10: G98 G99
  CoordSystem,  // G group 12
  PathControl,  // G group 13
  LatheMode,    // G group 15: G7 G8
  SpindleMode,  // G group 14: G96 G97
  ExactStop,    // G9
  MStop,        // M group 4
  MToolChange,  // M group 6
  MSpindle,     // M group 7
  MCoolant,     // M group 8
  MOverride,    // M group 9
  MIo,          // M group 5: M62..M68
  MUser,        // M group 10: M100..M199
  Count
};
inline constexpr std::size_t kGroupCount = static_cast<std::size_t>(Group::Count);

/// The steps of a block in LinuxCNC 2.9's documented order of execution ("G-code overview",
/// order of execution). Steps with no code of the block are skipped.
enum class Step : std::uint8_t {
  Comment,      // messages
  SpindleMode,  // G96 G97
  FeedMode,     // G93 G94
  Feed,         // F
  Speed,        // S
  Tool,         // T
  Io,           // M62..M68
  ToolChange,   // M6 M61
  Spindle,      // M3 M4 M5
  Coolant,      // M7 M8 M9
  Override,     // M48 M49 M50
  UserMcode,    // M100..M199
  Dwell,        // G4
  Plane,        // G17 G18 G19
  Units,        // G20 G21
  CutterComp,   // G40
  ToolLength,   // G43 G49
  CoordSystem,  // G54 .. G59.3
  PathControl,  // G61 G61.1 G64
  Distance,     // G90 G91 G90.1 G91.1
  ReturnMode,   // G98 G99
  NonModal,     // G10 G28 G30 G52 G92 ...
  Motion,       // G0..G3, cycles (as modified by G53)
  Stop,         // M0 M1 M2 M30
  Count
};

/// The dialects a code belongs to (docs/dialects.md), one bit each (bit 1 << Dialect).
using DialectSet = std::uint8_t;
inline constexpr DialectSet kLinuxCncBit = 1, kFanucBit = 2, kGrblBit = 4, kHaasBit = 8,
                            kMach3Bit = 16;
inline constexpr DialectSet kAllDialects =
    kLinuxCncBit | kFanucBit | kGrblBit | kHaasBit | kMach3Bit;

struct BlockCtx;
struct Code;
/// Executes one code of a block on the block's copy of the state; false (with the error set) to
/// reject the whole block.
using StepFn = bool (*)(BlockCtx&, const Code&);

/// The letters of `letters` (A..Z) as bits: bit i is letter 'A' + i.
constexpr std::uint32_t letter_mask(std::string_view letters) {
  std::uint32_t m = 0;
  for (const char c : letters) m |= std::uint32_t{1} << (c - 'A');
  return m;
}

struct Code {
  char letter;                  ///< 'G' or 'M'
  int number10;                 ///< code number x 10 (G92.1 = 921, M30 = 300)
  Group group;                  ///< modal group
  Step step;                    ///< when it executes within the block
  DialectSet dialects;          ///< the dialects that have it (grbl has a subset)
  StepFn run;                   ///< what it does
  std::string_view words = {};  ///< the value words it uses (besides the ones every block may have)
  bool uses_axes = false;       ///< a group 0 code that takes the axis words (G92)
  std::uint32_t word_mask = letter_mask(words);  ///< `words` as letter bits (letter_mask)
};

/// Every code, ordered by group then number (the order used when listing codes in messages).
std::span<const Code> code_table();
/// The code `letter` number10, or null if there is none.
const Code* find_code(char letter, int number10);
/// "G92.1", "M30".
std::string code_name(char letter, int number10);
inline std::string code_name(const Code& c) {
  return code_name(c.letter, c.number10);
}
/// "motion (G0 G1 G2 G3)": the group's title and its codes from the table.
std::string group_name(Group g);
/// True if some code uses value word `letter`.
bool code_word(char letter);
/// The letters some code uses as value words, as letter bits (letter_mask).
std::uint32_t code_word_mask();
/// "G4, G2, G3, G64 or M50": the codes that use value word `letter`, for messages.
std::string codes_using(char letter);

}  // namespace gm
