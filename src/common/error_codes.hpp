// The one G-code error catalogue (grammar and interpreter alike): a code per rule, with short and
// long text (like grbl report.h).
#pragma once

#include <array>
#include <string_view>

namespace gm {

/// Every diagnostic the G-code front end can produce. Values are stable: tests and the bad-input
/// corpus assert them. Syntax errors are 1xx, block (word) errors 2xx, geometry errors 3xx,
/// program-level errors 4xx.
enum class ErrorCode : int {
  None = 0,
  // Syntax (grammar/) -------------------------------------------------------------------------
  ExpectedNumber = 101,         ///< a letter not followed by a number
  NumberOutOfRange = 102,       ///< the number does not fit a double (e.g. 1 followed by 400 zeros)
  UnexpectedCharacter = 103,    ///< a character that starts no word, comment or delimiter
  UnclosedComment = 104,        ///< `(` without `)` on the same line
  NestedComment = 105,          ///< `(` inside a comment
  ParametersUnsupported = 106,  ///< `#` parameters
  ExpressionsUnsupported = 107,  ///< `[...]` expressions
  OWordsUnsupported = 108,       ///< O-words (subroutines, loops)
  ExponentUnsupported = 109,     ///< `1e3`: E is a word letter in G-code, not an exponent
  LineTooLong = 110,             ///< a line longer than the reader accepts
  NumberWithoutLetter = 111,     ///< a number with no letter in front
  BadExpression = 112,           ///< an operand missing in an expression (`[1+]`, `X[]`)
  UnclosedBracket = 113,         ///< `[` without its `]`
  UnknownOperator = 114,         ///< a name in an expression that is no function or operator
  BadParameterName = 115,        ///< `#<` without `>`, or an empty name
  ExpectedEquals = 116,          ///< `#1` at the start of an item without `=value`
  CommentAbort = 117,            ///< (ABORT, ...) ends the program with an error
  BadOWord = 118,                ///< an O-word without label or keyword, or with words after it
  // Block (interp/) ----------------------------------------------------------------------------
  ModalGroupViolation = 201,     ///< two codes of one modal group in a block
  DuplicateWord = 202,           ///< the same value word twice in a block
  UnknownLetter = 203,           ///< a letter this interpreter does not know (A, B, C, D, E, ...)
  UnknownGCode = 204,            ///< an unsupported or unknown G code
  UnknownMCode = 205,            ///< an unsupported or unknown M code
  AxisWordsWithoutMotion = 206,  ///< X/Y/Z with no motion mode in effect
  ZeroFeed = 207,                ///< G1/G2/G3 with no or zero feed (G94)
  NegativeFeed = 208,            ///< F < 0
  DwellWithoutP = 209,           ///< G4 without P
  NegativeDwell = 210,           ///< G4 P < 0
  InverseTimeFeedMissing = 211,  ///< G93 motion block without F
  BadCodeNumber = 212,           ///< G/M number with a fraction that names no code (G1.5)
  ToolNumberOutOfRange = 213,    ///< H (or T) names no entry of the tool table
  G92WithoutAxes = 214,          ///< G92 with no axis word
  BadPWord = 215,                ///< P on an arc that is not a positive integer, P on M50 not 0/1
  UnusedWord = 216,              ///< a value word nothing in the block uses (I with G1, R with G0)
  NegativeValue = 217,           ///< S, T or H negative
  LineNumberNotFirst = 218,      ///< N after other words (LinuxCNC)
  AxisUnavailable = 219,         ///< an axis word for an axis the machine lacks
  ValueOutOfRange = 220,  ///< a position beyond ±1e12 mm, a feed beyond 1e12 mm/min, a tool beyond
                          ///< 1e6, a block expanding to more than 100,000 moves
  // Expressions and parameters (interp/expression, interp/parameters) --------------------------
  DivisionByZero = 230,       ///< `/` by zero
  DomainError = 231,          ///< SQRT/LN/ACOS/ASIN/** outside their domain
  NotANumber = 232,           ///< a result that is infinite or not a number
  ParameterOutOfRange = 233,  ///< #n with n outside 1..5601, or not an integer
  ParameterReadOnly = 234,    ///< setting #5400-#5413, #5420-#5428 or a predefined #<_name>
  UndefinedParameter = 235,   ///< reading a named parameter that was never set
  // O-word control flow (interp/oword_flow) ----------------------------------------------------
  ControlMismatch = 240,      ///< endsub/endif/endwhile/... without its opening O-word
  UndefinedSubroutine = 241,  ///< a call of a subroutine defined nowhere
  CallTooDeep = 242,          ///< more nested calls than LinuxCNC allows
  TooManyIterations = 243,    ///< loops ran past --max-iterations
  NotSeekable = 244,          ///< control flow needs to re-read an input that cannot seek
  UnterminatedControl = 245,  ///< the program ends inside a sub, if or loop
  SubroutineRedefined = 246,  ///< a second `sub` with a label already defined elsewhere
  SubroutineFile = 247,       ///< a subroutine file that cannot be read (any more)
  PolarMisused = 248,         ///< @/^ with X/Y, with G53, or indeterminate at the origin
  ParameterFile = 249,        ///< the machine's .var file cannot be read or written, or is corrupt
  SubprogramMisused = 250,    ///< M98 without P or with other words; M98/M99 mixed with o-sub
  NotInDialect = 251,         ///< a construct the selected dialect (--dialect) does not have
  // Machine-side codes (offsets, tools, cycles) ------------------------------------------------
  G53Misused = 260,         ///< G53 with a motion other than G0/G1, or in G91 (LinuxCNC)
  BadLWord = 261,           ///< G10 without L or with an L it does not know; cycle L not >= 1
  MissingWord = 262,        ///< a code without a word it needs (G10 P, M61 Q, G43.2 H, cycle R/Z)
  BadCoordSystem = 263,     ///< G10 L2/L20 P outside 0..9
  CycleMisused = 264,       ///< a canned cycle with cutter compensation, or no plane axis word
  CutterCompMisused = 265,  ///< G41/G42 when on, out of XY/XZ, no D; a code compensation forbids
  // Arcs ---------------------------------------------------------------------------------------
  ArcRadiusTooSmall = 301,    ///< R form: |R| cannot reach the end point
  ArcRadiusMismatch = 302,    ///< IJK form: start and end radii differ beyond the rule's tolerance
  ArcZeroRadius = 303,        ///< IJK form: centre on the start or end point
  ArcOffsetWrongPlane = 304,  ///< an I/J/K word that is not in the active plane (K in G17)
  ArcRWithIjk = 305,          ///< R and I/J/K in one arc block
  ArcMissingCenter = 306,     ///< G2/G3 with neither R nor an in-plane offset
  ArcRSameEndPoint = 307,     ///< R form with end == start (a full circle needs I/J/K)
  CompToolTooLarge = 308,     ///< compensation: entry move or arc radius not beyond the tool radius
  CompGouge = 309,            ///< compensation: a concave corner the tool cannot reach
  // Program --------------------------------------------------------------------------------------
  MissingProgramEnd = 401,  ///< no M2/M30 and no closing %
};

struct ErrorInfo {
  ErrorCode code;
  std::string_view name;         ///< short text
  std::string_view description;  ///< long text
};

inline constexpr std::array kErrorTable{
    ErrorInfo{ErrorCode::ExpectedNumber, "expected number",
              "A word letter must be followed by a real number"},
    ErrorInfo{ErrorCode::NumberOutOfRange, "number out of range",
              "The number is too large for a double"},
    ErrorInfo{ErrorCode::UnexpectedCharacter, "unexpected character",
              "This character starts no word, comment or delimiter"},
    ErrorInfo{ErrorCode::UnclosedComment, "unclosed comment",
              "A ( comment must be closed by ) on the same line"},
    ErrorInfo{ErrorCode::NestedComment, "nested comment", "Comments may not contain ("},
    ErrorInfo{ErrorCode::ParametersUnsupported, "parameters not supported",
              "# parameters are not supported"},
    ErrorInfo{ErrorCode::ExpressionsUnsupported, "expressions not supported",
              "[...] expressions are not supported"},
    ErrorInfo{ErrorCode::OWordsUnsupported, "O-words not supported",
              "O-word subroutines and loops are not supported"},
    ErrorInfo{ErrorCode::ExponentUnsupported, "exponent not supported",
              "G-code numbers have no exponent; E is a word letter"},
    ErrorInfo{ErrorCode::LineTooLong, "line too long", "The line exceeds the maximum line length"},
    ErrorInfo{ErrorCode::NumberWithoutLetter, "number without letter",
              "A number must follow a word letter"},
    ErrorInfo{ErrorCode::BadExpression, "bad expression",
              "An operator or bracket is missing its operand"},
    ErrorInfo{ErrorCode::UnclosedBracket, "unclosed bracket", "A [ must be closed by ]"},
    ErrorInfo{ErrorCode::UnknownOperator, "unknown operator",
              "A name in an expression that is no function or operator"},
    ErrorInfo{ErrorCode::BadParameterName, "bad parameter name",
              "A named parameter is #<name> with a non-empty name"},
    ErrorInfo{ErrorCode::ExpectedEquals, "expected '='", "A parameter setting is #n=value"},
    ErrorInfo{ErrorCode::CommentAbort, "abort", "(ABORT, ...) ends the program with an error"},
    ErrorInfo{ErrorCode::BadOWord, "bad O-word",
              "An O-word is O<number or <name>> keyword [arguments]"},
    ErrorInfo{ErrorCode::ModalGroupViolation, "modal group violation",
              "Two codes of the same modal group in one block"},
    ErrorInfo{ErrorCode::DuplicateWord, "duplicate word",
              "The same word appears twice in one block"},
    ErrorInfo{ErrorCode::UnknownLetter, "unknown letter", "This word letter is not supported"},
    ErrorInfo{ErrorCode::UnknownGCode, "unknown G code", "This G code is not supported"},
    ErrorInfo{ErrorCode::UnknownMCode, "unknown M code", "This M code is not supported"},
    ErrorInfo{ErrorCode::AxisWordsWithoutMotion, "axis words without motion",
              "Axis words need a motion mode (G0-G3) or G92"},
    ErrorInfo{ErrorCode::ZeroFeed, "zero feed", "G1/G2/G3 need a positive feed rate F"},
    ErrorInfo{ErrorCode::NegativeFeed, "negative feed", "F must not be negative"},
    ErrorInfo{ErrorCode::DwellWithoutP, "dwell without P", "G4 needs P (seconds)"},
    ErrorInfo{ErrorCode::NegativeDwell, "negative dwell", "G4 P must not be negative"},
    ErrorInfo{ErrorCode::InverseTimeFeedMissing, "G93 feed missing",
              "In G93 every G1/G2/G3 block needs F"},
    ErrorInfo{ErrorCode::BadCodeNumber, "bad code number", "A G or M number names no code"},
    ErrorInfo{ErrorCode::ToolNumberOutOfRange, "tool out of range",
              "The tool number has no entry in the tool table"},
    ErrorInfo{ErrorCode::G92WithoutAxes, "G92 without axes", "G92 needs at least one axis word"},
    ErrorInfo{ErrorCode::BadPWord, "bad P word", "P has a value this code does not accept"},
    ErrorInfo{ErrorCode::UnusedWord, "unused word", "No code in the block uses this word"},
    ErrorInfo{ErrorCode::NegativeValue, "negative value", "This word must not be negative"},
    ErrorInfo{ErrorCode::LineNumberNotFirst, "line number not first",
              "N must be the first word of a block"},
    ErrorInfo{ErrorCode::AxisUnavailable, "axis not available",
              "The machine lacks this axis (its axes: machine key axes.letters, flag --axes; "
              "default XYZ)"},
    ErrorInfo{ErrorCode::ValueOutOfRange, "value out of range",
              "A position, feed or tool number beyond what the machine can represent"},
    ErrorInfo{ErrorCode::DivisionByZero, "division by zero", "An expression divides by zero"},
    ErrorInfo{ErrorCode::DomainError, "domain error",
              "A function or ** argument outside its domain"},
    ErrorInfo{ErrorCode::NotANumber, "not a number",
              "An expression resulted in infinity or not a number"},
    ErrorInfo{ErrorCode::ParameterOutOfRange, "parameter out of range",
              "Parameter numbers are integers 1 to 5601"},
    ErrorInfo{ErrorCode::ParameterReadOnly, "parameter read-only", "This parameter cannot be set"},
    ErrorInfo{ErrorCode::UndefinedParameter, "undefined parameter",
              "A named parameter was read before it was set"},
    ErrorInfo{ErrorCode::ControlMismatch, "control mismatch",
              "An O-word that closes or continues a block that is not open"},
    ErrorInfo{ErrorCode::UndefinedSubroutine, "undefined subroutine",
              "The called subroutine is defined neither in the program nor on the path"},
    ErrorInfo{ErrorCode::CallTooDeep, "calls too deep", "Subroutine calls nest too deep"},
    ErrorInfo{ErrorCode::TooManyIterations, "too many iterations",
              "Loops ran past the iteration limit"},
    ErrorInfo{ErrorCode::NotSeekable, "input not seekable",
              "Loops and calls re-read the program: it must be a file"},
    ErrorInfo{ErrorCode::UnterminatedControl, "unterminated block",
              "The program ends inside a subroutine, if or loop"},
    ErrorInfo{ErrorCode::SubroutineRedefined, "subroutine redefined",
              "A subroutine label is defined twice (in the program or a subroutine file)"},
    ErrorInfo{ErrorCode::SubroutineFile, "subroutine file unreadable",
              "A subroutine file found on the path cannot be read"},
    ErrorInfo{ErrorCode::PolarMisused, "polar coordinates misused",
              "@ and ^ replace X and Y; at the origin a direction is needed"},
    ErrorInfo{ErrorCode::ParameterFile, "parameter file",
              "The machine's parameter file (.var) cannot be read or written, or is corrupt"},
    ErrorInfo{ErrorCode::SubprogramMisused, "subprogram misused",
              "M98 calls a bare O1234 ... M99 with P (and L repeats); o-sub is called with o-call"},
    ErrorInfo{ErrorCode::NotInDialect, "not in the dialect",
              "The program uses what the selected dialect (--dialect) does not have"},
    ErrorInfo{ErrorCode::G53Misused, "G53 misused",
              "G53 needs G0 or G1 and absolute distance mode (G90)"},
    ErrorInfo{ErrorCode::BadLWord, "bad L word", "L has a value this code does not accept"},
    ErrorInfo{ErrorCode::MissingWord, "missing word", "A code lacks a word it needs"},
    ErrorInfo{ErrorCode::BadCoordSystem, "bad coordinate system",
              "G10 L2/L20 P names coordinate systems 0 (current) to 9"},
    ErrorInfo{ErrorCode::CycleMisused, "canned cycle misused",
              "A canned cycle lacks what it needs or meets what it cannot use"},
    ErrorInfo{ErrorCode::CutterCompMisused, "cutter compensation misused",
              "Cutter radius compensation cannot be turned on here, or forbids this code"},
    ErrorInfo{ErrorCode::ArcRadiusTooSmall, "arc radius too small", "R cannot reach the end point"},
    ErrorInfo{ErrorCode::ArcRadiusMismatch, "arc radius mismatch",
              "Start and end radii differ beyond tolerance"},
    ErrorInfo{ErrorCode::ArcZeroRadius, "zero radius arc",
              "The arc centre is on its start or end point"},
    ErrorInfo{ErrorCode::ArcOffsetWrongPlane, "offset not in plane",
              "An I/J/K word that is not in the active plane"},
    ErrorInfo{ErrorCode::ArcRWithIjk, "R with IJK", "R and I/J/K may not be mixed"},
    ErrorInfo{ErrorCode::ArcMissingCenter, "arc without centre",
              "G2/G3 need R or an I/J/K offset in the plane"},
    ErrorInfo{ErrorCode::ArcRSameEndPoint, "R arc to start point",
              "An R-form arc cannot end where it starts"},
    ErrorInfo{ErrorCode::CompToolTooLarge, "tool too large for compensation",
              "An entry move or an arc is not longer or larger than the tool radius"},
    ErrorInfo{ErrorCode::CompGouge, "compensation gouge",
              "The compensated tool cannot reach this concave corner without gouging"},
    ErrorInfo{ErrorCode::MissingProgramEnd, "missing program end",
              "The program must end with M2, M30 or a closing %"},
};

/// The catalogue entry of `code` (a static "unknown" entry for codes not in the table).
constexpr const ErrorInfo& error_info(ErrorCode code) {
  for (const auto& e : kErrorTable)
    if (e.code == code) return e;
  return kErrorTable[0];
}

}  // namespace gm
