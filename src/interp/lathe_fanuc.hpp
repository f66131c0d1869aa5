// Fanuc/Haas lathe conventions (--dialect fanuc on a lathe machine): blocks rewritten into the
// words the interpreter runs, and the two-block cycles G70-G72 and G76 expanded into moves.
#pragma once

#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace gm {

/// One move a lathe cycle makes, in program units of the ZX plane (X a radius).
struct LatheMove {
  enum class Kind : std::uint8_t { Rapid, Feed, ArcCw, ArcCcw, Thread };
  Kind kind = Kind::Feed;
  double z = 0.0, x = 0.0;    ///< the end
  double cz = 0.0, cx = 0.0;  ///< arcs: the centre
  double f = -1.0;            ///< feed words: F (< 0: the modal feed); Thread: the lead
};

/// A point of a cycle's profile (program units, X a radius) and how it was reached.
struct LatheProfileElement {
  LatheMove move;  ///< Rapid/Feed (G0/G1) or an arc, to this element's end
  int line = 0;    ///< the profile block's line
};

/// The words, modes and cycles of Fanuc/Haas lathe programs (docs/dialects.md, "Fanuc/Haas
/// lathe"): X is a diameter (G7 from the start), U/W incremental X (diameter)/Z, T0101 a tool
/// and its offset, G50 S a spindle clamp and G50 X Z a coordinate setting, G98/G99 feed per
/// minute/revolution, the two-block G71/G72/G73/G70 over the blocks Nns..Nnf, G74-G76 and the
/// single cycles G90/G92/G94 (modal, group 1 in G-code system A).
class FanucLathe {
 public:
  /// What a block became.
  enum class Outcome : std::uint8_t {
    Run,       ///< the rewritten block is to be run
    Recorded,  ///< a first cycle block or a bare G50 S: its values are kept, nothing runs
    Profile,   ///< G70-G73 with P Q: the profile Nns..Nnf is to be read (profile())
    Moves,     ///< G74-G76, G90/G92/G94: moves() holds the cycle's moves
  };

  /// The block run before the program's first line: G7 (X words are diameters) G18 (ZX plane)
  /// G95 (G99, feed per revolution: a Fanuc or Haas lathe's power-on mode).
  static void start_block(grammar::Block& block);

  /// Rewrites `b` under the state `s` (the program's position and modes); false with `err`.
  bool rewrite(grammar::Block& b, const ModalState& s, Outcome& outcome, InterpError& err);

  // The profile cycle (Outcome::Profile) ------------------------------------------------------
  int cycle_code() const { return cycle_.code; }
  long profile_first() const { return cycle_.ns; }
  long profile_last() const { return cycle_.nf; }
  SourceLoc cycle_loc() const { return cycle_.loc; }
  /// "G71 P10 Q20", for messages.
  std::string cycle_name() const;
  /// One block of the profile (its sequence number `n`, -1 without); false with `err`.
  bool collect(const grammar::Block& b, InterpError& err);
  /// The cycle's moves once Nnf was collected; false with `err` (located at the cycle line when
  /// the profile as a whole is wrong, at a profile line when one element is).
  bool finish_profile(InterpError& err);
  /// The moves of the last cycle, as blocks for the interpreter (line = the cycle's line).
  const std::vector<LatheMove>& moves() const { return moves_; }
  /// The cycle's moves as blocks of G0/G1/G2/G3/G33 words the interpreter runs under `s`.
  void move_blocks(const ModalState& s, std::vector<grammar::Block>& out) const;

  /// Where block N`n` was seen (the driver seeks there for a profile above the cycle line).
  struct Seen {
    std::uint64_t offset = 0, next = 0;
    int line = 0;
  };
  void note_sequence(long n, const Seen& at);
  const Seen* seen(long n) const;

  // Exposed for the tests: the cycles' geometry on a profile already read.
  struct RoughInput {
    bool facing = false;            ///< G72: layers along Z, cuts along X
    double z0 = 0, x0 = 0;          ///< the start point A (X radius)
    double depth = 0, retract = 0;  ///< Δd (radius for G71, Z for G72), e
    double du = 0, dw = 0;          ///< finishing allowances: ΔU (diameter), ΔW
    double feed = -1;               ///< F of the cycle line (< 0: modal)
    std::vector<LatheProfileElement> profile;
  };
  /// G71/G72 (type I): the layers, the allowance pass and the return to A; false with `why` and
  /// `line` (0: the cycle's line) when the profile cannot be roughed.
  static bool rough(const RoughInput& in, std::vector<LatheMove>& out, std::string& why, int& line);
  /// G70: the profile with its own feeds from A, then back to A.
  static void finish(double z0, double x0, const std::vector<LatheProfileElement>& profile,
                     std::vector<LatheMove>& out);
  struct PatternInput {
    double z0 = 0, x0 = 0;  ///< the start point A (X radius)
    double relief_x = 0;    ///< Δi: the first pass's extra offset in X (radius)
    double relief_z = 0;    ///< Δk: the same in Z
    int passes = 1;         ///< d: the number of passes
    double du = 0, dw = 0;  ///< finishing allowances: ΔU (diameter), ΔW
    double feed = -1;       ///< F of the cycle line (< 0: modal)
    std::vector<LatheProfileElement> profile;
  };
  /// G73: the path A, Nns..Nnf offset by the relief and the allowance, d times, the offset
  /// shrinking by Δi/(d-1), Δk/(d-1) down to the allowance, a rapid back to A after the last.
  static void pattern(const PatternInput& in, std::vector<LatheMove>& out);

  /// A single cycle of G-code system A (program units, X a radius).
  struct SingleInput {
    int code = 90;          ///< 90 outer/inner diameter cutting, 92 threading, 94 end face cutting
    double z0 = 0, x0 = 0;  ///< the start point
    double ze = 0, xe = 0;  ///< the end of the cut (X, Z or U, W)
    double taper = 0;       ///< R: cut start minus cut end, in X (radius) for G90/G92, Z for G94
    double f = -1;          ///< G90/G94: F (< 0: modal); G92: the lead
  };
  /// G90: rapid in X to the cut's start, feed to the end, feed out in X to the start's X, rapid
  /// back in Z; G94 the same with X and Z exchanged; G92 as G90 with the cut spindle-synchronised
  /// and the way out a rapid.
  static void single_cycle_moves(const SingleInput& in, std::vector<LatheMove>& out);

 private:
  bool rewrite_tool(grammar::Block& b, std::size_t t, InterpError& err) const;
  bool rewrite_incremental(grammar::Block& b, const ModalState& s, InterpError& err) const;
  bool profile_cycle(grammar::Block& b, int code, const ModalState& s, Outcome& outcome,
                     InterpError& err);
  bool thread_cycle(grammar::Block& b, const ModalState& s, Outcome& outcome, InterpError& err);
  bool peck_cycle(grammar::Block& b, int code, const ModalState& s, Outcome& outcome,
                  InterpError& err);
  /// G90/G92/G94 given, repeated (a block of X/Z/U/W/R in their mode) or cancelled (G00-G03,
  /// G32); `handled` when the block was the cycle's.
  bool single_cycle(grammar::Block& b, const ModalState& s, Outcome& outcome, bool& handled,
                    InterpError& err);

  double clamp_rpm_ = 0.0;  ///< G50 S (0: none)
  // The first blocks of the two-block cycles (modal, as Fanuc keeps them).
  double g71_depth_ = 0.0, g71_retract_ = 0.0;
  double g72_depth_ = 0.0, g72_retract_ = 0.0;
  int g76_finish_passes_ = 1, g76_chamfer_ = 0, g76_angle_deg_ = 60;
  double g76_min_depth_ = 0.0, g76_allowance_ = 0.0;
  double g74_retract_ = 0.0, g75_retract_ = 0.0;
  double g73_relief_x_ = 0.0, g73_relief_z_ = 0.0;
  int g73_passes_ = 1;
  // The single cycle in force (0: none) and its words kept from block to block.
  struct Single {
    int code = 0;
    bool has_x = false, has_z = false;
    double xe = 0, ze = 0;  ///< the cut's end (program units, X a radius)
    double taper = 0, lead = -1;
  } single_;
  struct Cycle {
    int code = 0;  ///< 70, 71, 72, 73
    long ns = -1, nf = -1;
    SourceLoc loc;
    double z0 = 0, x0 = 0;
    double du = 0, dw = 0, feed = -1;   ///< the allowances (U a diameter), F of the line
    double depth = 0, retract = 0;      ///< the first block's depth of cut and retract
    double relief_x = 0, relief_z = 0;  ///< G73: Δi, Δk
    int passes = 1;                     ///< G73: d
    std::vector<LatheProfileElement> profile;
    bool first = true;         ///< the next profile block is Nns
    double z = 0, x = 0;       ///< the profile's point so far (X a radius)
    int motion = 0;            ///< the profile's motion mode (0-3)
    double profile_feed = -1;  ///< the profile's last F (G70 cuts at it)
    double mm_per_unit = 1.0;
    bool diameter = true;  ///< X words are diameters
  } cycle_;
  std::vector<LatheMove> moves_;
  std::unordered_map<long, Seen> seen_;
};

}  // namespace gm
