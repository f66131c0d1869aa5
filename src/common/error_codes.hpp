// The one G-code error catalogue (grammar and interpreter alike): a stable code per rule.
#pragma once

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

}  // namespace gm
