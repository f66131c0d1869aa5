// The tolerance planner: a look-ahead CanonSource that caps speeds and pauses at corners so the
// Acc/Dec output stays within each block's G64 P tolerance on every sample.
#pragma once

#include "common/axis.hpp"
#include "common/ring_deque.hpp"
#include "motion/canon.hpp"
#include "motion/geometry.hpp"
#include "planner/arc_precomp.hpp"
#include "planner/arc_residual_table.hpp"
#include "planner/corner_moment_grid.hpp"
#include "planner/filter_moments.hpp"
#include "planner/mismatch_reserve.hpp"
#include "planner/naive_cam.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace gm {

struct PlannerConfig {
  double max_override = 2.0;   ///< largest feed and rapid override (speeds are planned at it)
  double rapid_mm_min = 6000;  ///< G0 path speed at 100 %
  /// Kept out of every tolerance for the BLU rounding of the interpolator and of the filter
  /// output (each at most half a BLU per axis): ‖BLU‖₂, mm.
  double rounding_mm = 0.0;
  /// Table error per unit of path speed that no corner or arc causes, s: the mismatch of X, Y
  /// and Z servos that differ from the planned chain's (servo_mismatch_s). Every block with a
  /// tolerance is capped at reserve(tol)/this, reserve(tol) = min(share/2, V_rapid·this), and so
  /// is every block the chain still holds when it starts; each corner, arc or run keeps this
  /// times the fastest speed its samples can see, at most reserve(tol) (MismatchReserve). 0: none.
  double speed_error_s = 0.0;
  /// The same servos' largest step-response difference (servo_mismatch_peak): what the table
  /// moves per mm of the command's total variation, charged for a compensated arc's end rows,
  /// whose command can jump (ArcPrecompCheck::offset_mismatch_mm). 0: none.
  double step_error = 0.0;
  /// Σ_k |h_k − h_{k−1}| of the Acc/Dec filter's weights (zeros beyond them) when the plan is
  /// for the table: the filter smooths the end rows' jumps of the command before the servos see
  /// them (ArcPrecompCheck::offset_mismatch_mm). 0: not given.
  double fir_variation = 0.0;
  /// Planned for the table: the path speed below which no drive saturates
  /// (drive_speed_limit_mm_s), where the chain is linear. Every block with a tolerance is capped
  /// at it, and so is every block the chain still holds when it starts. Infinity: none.
  double drive_speed_mm_s = std::numeric_limits<double>::infinity();
  std::size_t capacity = 4096;  ///< most motion blocks held for look-ahead (memory bound)
  /// Pre-compensated arcs (docs/tolerance.md): an arc whose cap the curvature bound lowers is
  /// commanded on R + c (Motion::comp_speed_mm_s) and capped by the residual of its transitions
  /// instead, when that is faster. For any weights whose step response stays within [0, 1]: the
  /// FIR's, or a FIR and servo chain that does not overshoot (the interpolator must command by
  /// the same weights: RunConfig::planned_weights).
  bool precompensate_arcs = false;  // the machine's arc_precompensation (on by default)
  /// G61 arcs (exact path, no tolerance) pre-compensated at their fastest speed, not slowed and
  /// not checked (TolerancePlanner::exact_path_comp_speed): g61_arc_precompensation (off).
  bool precompensate_g61_arcs = false;
  /// Pre-compensated arcs with nothing else within their filter's reach (arc_privacy) take the
  /// rows fitted for the distance and are planned by it: private_arcs (on).
  bool private_arcs = false;
};

/// Reads canon from `upstream` (through NaiveCamMerger: G64 Q) and hands on the same program with,
/// for every block whose path_tolerance_mm is > 0, a speed cap (Motion::speed_cap_mm_s, honoured by
/// the interpolator whatever the override) on the pieces near corners and arcs, and a short pause
/// (Dwell) at corners where pausing costs less time than slowing. Blocks with tolerance 0 and
/// everything else pass unchanged, so a program without a tolerance is the same canon, byte for
/// byte.
///
/// The guarantee (docs/tolerance.md): the filter output is Σ h_i x(s_i); with s̄ = Σ h_i s_i
/// on the path, its distance from the path is at most
///   Σ_corners |Δu_c|·(moment of the samples past the corner, away from s̄)  +  κ_max·V²·σ²/2,
/// the corner moment at most V_c·D(P_c) when the speed is at most V_c for (τ − P_c) of time
/// either side of a corner where the interpolator pauses P_c, the curvature term at most
/// κ·V_a²·σ²/2 when the speed is at most V_a within τ of an arc. Elements (corners and arcs)
/// that can share one filter window are less than τ apart in the fastest execution (every
/// override at its maximum, no pause); each gets budget (tol − rounding) / n, n the number of
/// elements within τ of it, so whatever shares a window adds up to at most the tolerance.
/// Overrides and holds only slow the path, and every bound above only shrinks.
///
/// A run of small turns between short G1 lines (a CAM polyline) is planned as one curve instead
/// of corner by corner: the turning between two path points in the run is at most
/// κ_eff·(distance) + δ (κ_eff the largest turn over the segment before it, δ the largest turn),
/// so the run adds at most κ_eff·V²·σ²/2 + δ·V·M₁ (M₁ = abs_moment_s()). It is held in chunks of
/// at most τ of travel; the chunks of one run count once in each other's sharing and each takes
/// κ_eff and δ of every chunk of its run within reach.
///
/// One pass over the program; at most `capacity` blocks and the elements within 2τ of travel
/// are held. If `capacity` blocks fit in 2τ of travel, a full stop is planned at the window end.
class TolerancePlanner : public CanonSource {
 public:
  TolerancePlanner(const FilterMoments& filter, const PlannerConfig& cfg, CanonSource& upstream);
  bool next(Canon& out) override;
  /// A block handed on whole (one piece) comes with the geometry the planner built for it.
  const MotionGeometry* geometry() const override { return out_geometry_; }
  /// The G64 Q stage in front of the window (moves read and handed on).
  const NaiveCamMerger& naive_cam() const { return merger_; }

 private:
  // The planner's rules (docs/tolerance.md, "The planner").
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr double kMinTurn = 1e-9;  ///< |Δu| below which a join is tangent; least weight
  /// A vertex between two G1 lines joins a run of small turns when it turns by at most this
  /// (|Δu|, about 5.7°), by so little that the run's δ term alone keeps within the tolerance at
  /// 100 % feed (δ·V·M₁ <= tol; larger turns do better corner by corner, where they can pause),
  /// and the line before it is shorter than τ of travel. A run of fewer than kMinRunVertices
  /// vertices is planned corner by corner.
  static constexpr double kRunTurn = 0.1;
  /// A dense polyline (a fillet posted as chords): where the line before the vertex is shorter
  /// than kDenseRunSegment of τ's travel at 100 % feed, turns up to kDenseRunTurn (about 14°)
  /// with δ·V₁₀₀·M₁ <= kDenseRunDeltaShare·tol join a run too. So many corners lie in each
  /// other's zones there that each would count the others' weights, while the run counts its
  /// worst turn once (δ) and the rest as curvature (κ_eff). Only for chains without negative
  /// weights, whose M₁ = 2·D(0): a run's absolute moments are then as tight as a corner's.
  static constexpr double kDenseRunTurn = 0.25;
  static constexpr double kDenseRunSegment = 0.05;
  static constexpr double kDenseRunDeltaShare = 8.0;
  /// A corner turning by at most this (|Δu|, about 0.57°: CAM output rounded to 3 decimals turns
  /// 0 to 0.13° at joins meant to be tangent) may claim its error at its fastest speed, above
  /// 100 % feed too (assign_claims).
  static constexpr double kClaimFreeTurn = 0.01;
  /// A corner turning by at most this (|Δu|, about 5.7°: arcs rounded to 4 decimals of an inch
  /// meet at kinks of 0.1 to 2°) may claim its error at 100 % feed, its zone capped there.
  static constexpr double kClaimTurn = 0.1;
  /// A near circle: its radii differ by at most this fraction of the smaller;
  /// ArcPrecompCheck::spiral_mm's bound assumes Δr/r small.
  static constexpr double kNearCircle = 0.01;
  /// A block after a pre-compensated arc whose fastest speed is below this fraction of the arc's
  /// v_p makes the arc's end a stop for its end rows (emit_front): measured, 2 of 450 random
  /// feed-changing chains were over P (to 107 %) with the moving rows there, 0 with these.
  static constexpr double kCrawlRatio = 0.1;
  /// A pre-compensated arc is cut at zone boundaries no nearer its ends than this many samples of
  /// travel at v_p: its end rows (ArcEndRows::kSpan advances), the radial blend (two samples)
  /// and the speed hold before its end lie within them.
  static constexpr double kCompEndSamples = ArcEndRows::kSpan + 2;
  /// A chain's ends are planned slower than its middle (slower_ends) only where its middle gains
  /// more than this fraction of its speed.
  static constexpr double kSlowerEndsGain = 0.02;
  /// Two arcs of one curve for G61 (one_curve): the larger radius at most this times the
  /// smaller. Measured 2026-12-01 on the CAM table: 1.5 and 2 the same but for cambam-engrave.nc
  /// (95.532 and 94.040 s in G61), 4 took fusion-bore-tests.nc's R 0.27 lead arcs into its
  /// R 0.6 helices (0.1216 → 0.1252 mm).
  static constexpr double kG61CurveRatio = 2.0;
  static constexpr int kMinRunVertices = 3;
  static constexpr double kRunDeltaShare = 4.0;

  struct Block {
    Motion m;
    BlockGeometry g;
    std::uint64_t seq = 0;
    double s0 = 0, s1 = 0;     ///< cumulative path length, mm
    double t0 = 0, t1 = 0;     ///< cumulative fastest travel time, s (pauses included)
    double vmax = 0;           ///< at the largest override, mm/s
    double v100 = 0;           ///< at 100 %, mm/s
    double cap_all = 0;        ///< cap over the whole block (speed_error_s), mm/s; inf = none
    std::vector<Canon> after;  ///< what follows until the next block (events, dwells, ...)
    double dwell_after_s = 0;  ///< dwells in `after`
    bool stop_after = false;   ///< the filter drains after it (exact stop, forced stop)
    bool forced_stop = false;  ///< the planner adds the stop (window full)
    /// G61 (exact path): the join to the next block is tangent (exact_path_passes), so the
    /// block is handed on as continuous and the join planned as a corner within the rounding.
    bool tangent_exit = false;
  };
  /// What an element of the path is; the fields marked with kinds apply to those only.
  enum class ElementKind {
    Corner,  ///< a vertex between two blocks, planned by a pause and a cap
    Arc,     ///< an arc block, planned by a cap over it and its zone
    Run,     ///< a chunk of a run of small turns: a curve of κ_eff and δ
    Stop,    ///< a stop of a chain that overshoots (mark_stop): a corner to rest
  };
  struct Element {
    ElementKind kind = ElementKind::Corner;
    std::uint64_t run_id = 0;  ///< Run: the run it is a chunk of
    double delta = 0;          ///< Run: the largest turn |Δu|
    std::uint64_t seq = 0;     ///< Corner, Stop, Run: the block before it; Arc: the arc
    /// Arc: its last block. A chain of arcs on one circle (or helix) is one arc element
    /// (same_circle): seq..seq_last; one block: seq_last == seq.
    std::uint64_t seq_last = 0;
    /// Arc: the next block on its circle joins it (same_circle): a circle, not a near one.
    bool chainable = false;
    double t0 = 0, t1 = 0;  ///< extent in fastest travel time
    double s0 = 0, s1 = 0;  ///< extent in path length
    double tol_mm = 0;
    double turn = 0;    ///< Corner, Stop: |u_after − u_before| = 2 sin(φ/2) (1 for a Stop)
    double kappa = 0;   ///< Arc: curvature bound; Run: κ_eff, 1/mm
    double pause0 = 0;  ///< Corner, Stop: pause already there (dwells; the drain for a Stop)
    double vmax = 0;    ///< fastest adjacent speed
    double v100 = 0;    ///< adjacent speed at 100 %
    bool decided = false;
    double cap = 0;         ///< mm/s; infinity = none
    double pause = 0;       ///< Corner, Stop: total pause at the vertex
    double z0 = 0, z1 = 0;  ///< zone in path length where the cap applies
    double weight = 0;      ///< share weight: Corner, Stop |Δu|, Arc 1, Run its error per D(0)
    double cum = 0;         ///< weights of all elements before it (prefix sum)
    /// Decided: the bound its decision leaves on its error (at its cap, its pause), mm; what the
    /// elements decided after it whose zone it reaches take off their share instead of
    /// counting its weight.
    double err = 0;
    double reach0 = 0, reach1 = 0;  ///< decided: its zone at its speed, [s0 − v·t, s1 + v·t]
    double share = 0;  ///< decided or being decided: the share of its tolerance (share_of), mm
    /// Decided Corner, Stop: the time its decision costs, s (the pause added and the slowing,
    /// corner_cost_s); decide_untoleranced_group weighs a group by it.
    double cost_s = 0;
    /// Decided Corner: what a full stop there would cost instead (the drain pause), s; infinity
    /// when it is not an option.
    double stop_cost_s = std::numeric_limits<double>::infinity();
    /// Decided Corner: a full stop (its pause drains the filter, D = 0). No window holds both
    /// sides of it: it parts the elements before it from those after (tolerance_near).
    bool stopped = false;
    // Arc: for pre-compensation (arc_precomp.hpp).
    double radius = 0;          ///< Arc: radius, mm (0: not a circle, never compensated)
    double spiral = 0;          ///< Arc: how far its radius runs below `radius` (a near circle), mm
    double sweep = 0;           ///< Arc: |θ|, rad
    double comp_speed = 0;      ///< Arc: > 0 when compensated, the speed it was planned for, mm/s
    bool comp_private = false;  ///< Arc: compensated as a private arc (arc_is_private)
    /// A near-tangent corner (|Δu| <= kClaimTurn) may take its error as a claim instead of a
    /// share (assign_claims): claim = v·D(pause0)·|Δu|, no pause; v its fastest speed or its
    /// speed at 100 % feed (claim_cap: its zone capped there either way).
    enum class Claim : std::uint8_t { Unassigned, Claimant, Share } claim_state = Claim::Unassigned;
    double claim = 0;                                            ///< Claimant: its error bound, mm
    double claim_cap = std::numeric_limits<double>::infinity();  ///< Claimant: its cap
    /// Claimant: the half-width of its tent (claim_at), tent_s_ times its speed, mm; 0: none.
    double claim_half = 0;
    bool split = false;  ///< Arc: cut at zone boundaries like a line (splits)
    /// Decided arc (a chain, or one block) whose ends are slower than its middle (docs/
    /// tolerance.md, "A chain's ends slower than its middle"): the cap of its start and of its
    /// end (infinity: `cap`), each over its stretch [lo, hi] (the path beside the end within τ
    /// of travel, the arc's own up to 2τ + kCompEndSamples samples of travel), and the error
    /// bound each end leaves (ends[0].err seen by the elements before the arc, ends[1].err by
    /// those after it; err the largest).
    struct EndCap {
      double cap = std::numeric_limits<double>::infinity();
      double lo = 0, hi = 0, err = 0;
    };
    std::array<EndCap, 2> ends{};
    bool slower_ends() const {
      return ends[0].cap < std::numeric_limits<double>::infinity() ||
             ends[1].cap < std::numeric_limits<double>::infinity();
    }
    /// Planned for the tolerance of a later block (plan_untoleranced): that block's seq, else 0;
    /// and the t1 of the group's last element (the one nearest that block).
    std::uint64_t untol_for = 0;
    double group_t1 = 0;
  };
  /// An arc is cut at zone boundaries into arcs of the same centre when it turns at most once
  /// (K/P full turns: it takes the smallest cap of the zones touching it whole).
  static bool splits(const Motion& m) { return m.kind != MotionKind::Arc || m.turns == 1; }
  /// v_p for a G61 arc pre-compensated at its fastest speed (precompensate_g61_arcs), else 0.
  double exact_path_comp_speed(const Block& b) const;

  void pull();  ///< one item from upstream into the window
  /// pull() of an item that is not a block of the path: held after the window's last block.
  void hold_after_last();
  /// pull() of a block: built in a new slot at the window's end (speeds, extents, cap_all).
  Block& push_block(const Motion& m);
  double speed_at_100_mm_s(const Motion& m, double length_mm) const;
  /// The vertex between prev and b: a corner element, a vertex of a run, or the end of a run.
  void add_corner(const Block& prev, const Block& b);
  static Element corner_element(const Block& prev, const Block& b, double turn, double tol);
  static Element arc_element(const Block& b);
  /// b goes on from prev along first's circle (first: the chain's first block, or prev): the
  /// same centre and radius (within 0.1 µm), plane, direction and lead per radian, the same
  /// feed, tolerance and mode, nothing between prev and b.
  bool same_circle(const Block& first, const Block& prev, const Block& b) const;
  /// Arcs g and h on one circle: the same plane, sense, centre and radius (within 0.1 µm, not
  /// near circles) and the same lead per radian (a helix goes on as the same helix).
  static bool one_circle(const BlockGeometry& g, const BlockGeometry& h);
  /// Arcs g and h turning the same way in one plane, their radii within kG61CurveRatio of each
  /// other (one_circle among them): G61 passes a tangent join between them whatever their
  /// lengths (exact_path_passes).
  static bool one_curve(const BlockGeometry& g, const BlockGeometry& h);
  /// The arc element ending with prev when it is the last element and undecided, or none.
  Element* growing_arc(const Block& prev);
  /// The arc element b is in (its own, or its chain's), or none.
  const Element* arc_of(const Block& b) const;
  /// The arc element of a chain of two or more blocks that b is in, or none.
  const Element* chain_of(const Block& b) const;
  /// |u_after − u_before| at the join of prev and b.
  static double join_turn(const Block& prev, const Block& b);
  void mark_stop(Block& b);  ///< the filter drains after b (and the overshoot is planned for)
  /// G61: the window's last block, when it is exact path and its end is not yet decided, either
  /// passes a tangent join to `next` (a block of the path) or stops (next == nullptr: anything
  /// else follows, or nothing).
  void end_exact_path(const Motion* next, const BlockGeometry* next_g);
  /// LinuxCNC's tangency (tpSetupTangent): the kink's acceleration within a tenth of the machine's.
  bool exact_path_passes(const Block& prev, const Motion& next, const BlockGeometry& next_g) const;
  /// Tolerance `tol` less the rounding, and the part of it kept for speed_error_s.
  double share_of(double tol) const;
  /// What a tangent G61 join is planned within: the rounding margin (share_of gives it whole).
  double exact_path_tolerance() const { return std::max(cfg_.rounding_mm, 1e-6); }
  double reserve_of(double tol) const;
  /// What e keeps of a share for tolerance `tol` for speed_error_s (MismatchReserve).
  MismatchReserve mismatch_reserve(const Element& e, double tol) const;
  bool lookahead_enough() const;
  /// The cap, zone and (corners) pause of e within its share of the tolerance.
  void decide(Element& e);
  /// The smallest tolerance e's samples can meet; nothing past a full stop (Element::stopped)
  /// counts.
  double tolerance_near(const Element& e) const;
  void decide_arc(Element& e, double share, const MismatchReserve& res) const;
  /// The cap of arc e pre-compensated within `share`, mm/s: `floor` (the curvature bound's
  /// cap) or less when compensating is no faster.
  /// An arc's ends may be slower than its middle: `ends` (when not null) then gets their caps
  /// and errs (caps infinite: one speed).
  /// `private_arc` (when not null): whether the speed returned is a private arc's
  /// (arc_is_private at it), commanded with the distance rows.
  double precomp_arc_speed(const Element& e, double share, double floor, double& err,
                           std::array<Element::EndCap, 2>* ends = nullptr,
                           bool* private_arc = nullptr) const;
  /// An arc (a chain, or one block) planned at one speed v_one whose middle alone could run
  /// faster (up to vlim; `fits` the check of an end, `fits_middle(v, allotment, exact)` of the
  /// middle, by the table or simulated): the middle's speed, its ends' caps in `ends` and the
  /// middle's allotment in mid_err; 0 (ends untouched) when the arc is too short for it or the
  /// middle gains too little.
  template <class Fits, class FitsMiddle>
  double slower_ends(const Element& e, double v_one, double vlim, double share, Fits& fits,
                     FitsMiddle& fits_middle, std::array<Element::EndCap, 2>& ends,
                     double& mid_err) const;
  /// decide_arc with the claims beside the arc taken off its share.
  void decide_arc_beside_claims(Element& e, double share, const MismatchReserve& res) const;
  void decide_run(Element& e, double share, const MismatchReserve& res) const;
  void decide_corner(Element& e, double share, const MismatchReserve& res);
  /// A decided corner: its pause, cap, err, reach and zone for pause P, cap V and D(P) = d.
  void settle_corner(Element& e, double pause, double v_cap, double d, double cost) const;
  /// The first pause of the corner grid whose moment D is 0 (the drain: a full stop), s; −1
  /// when there is none.
  double drain_pause_s();
  int drain_j_ = -2;  ///< that pause's grid index, −1 when none, −2 until asked
  /// An arc's or a run's decision, weighed against full stops at the corners at its ends (the
  /// corner before it re-decided, the one after it decided too).
  void decide_weighing_stops(Element& a, double share, const MismatchReserve& res);
  /// An arc's (decide_arc_beside_claims) or a run's decision (decide_run, part_zone), the
  /// corners beside it as they are.
  void decide_between_corners(Element& e, double share, const MismatchReserve& res) const;
  /// A corner's decision, weighed against a full stop at the corner after it where a smaller
  /// tolerance beyond that corner lowers its own (`tol`, from tolerance_near): the stop parts
  /// it from there.
  void decide_corner_weighing(Element& e, double tol, double share, const MismatchReserve& res);
  /// The corner c (undecided) decided on a copy beside `beside` as it is (the decided prefix
  /// extended for it): its cost_s; c, `beside` and the prefix left as they were.
  double cost_decided_aside(Element& c, Element& beside);
  /// The corners at arc a's ends whose full stop decide_weighing_stops weighs (null: none).
  struct WeighedCorners {
    Element* start = nullptr;
    Element* end = nullptr;
  };
  WeighedCorners weighed_corners(const Element& a, double p_stop);
  /// A copy of `corner` settled as a full stop (pause p_stop, D 0, no weight); `after`: the
  /// corner after the arc, decided here.
  Element stopped_corner(const Element& corner, double p_stop, bool after) const;
  /// A decided arc's (or run's) slowing: its zone at its cap instead of each block's speed at
  /// 100 % (an arc's slower ends at theirs), s.
  double slowing_s(const Element& arc) const;
  /// [z0, z1] of the window's blocks at v instead of their speeds at 100 %, s.
  double stretch_slowing_s(double z0, double z1, double v) const;
  /// Sets f's share weight (the prefix sums after it follow).
  void set_weight(Element& f, double w);
  /// e's index in elems_, searched from the decided prefix on (elems_.size(): not there).
  std::size_t index_past_prefix(const Element& e) const;
  /// An element's saved state put back (a tentative decision undone): its weight with the prefix
  /// sums after it, and its own prefix sum as it is now (the weights before it may have changed
  /// since it was saved).
  void restore(Element& f, const Element& saved);
  /// Tentative decisions under way (decide_weighing_stops): they assign no claims and weigh
  /// nothing further.
  int weigh_depth_ = 0;
  /// Time a corner costs with a pause of pause_s (D(pause) = d): the pause added plus the
  /// slowing; `v` is the cap that keeps it within the share with `res` kept beside it.
  double corner_cost_s(const Element& e, double pause_s, double d, double share,
                       const MismatchReserve& res, double v_ref, double& v) const;
  double zone_back(double s_from, double time_s, double cap) const;
  double zone_fwd(double s_from, double time_s, double cap) const;
  /// The elements reaching into [z0, z1] (in path order): elems_[first, last).
  struct ZoneRange {
    std::size_t first = 0, last = 0;
    bool operator==(const ZoneRange&) const = default;
  };
  ZoneRange zone_range(double z0, double z1) const;
  /// zone_range(z0, z1) walked from `hint`, a range near it: cheaper when the two are close.
  ZoneRange zone_range_from(ZoneRange hint, double z0, double z1) const;
  /// f is e (or e a copy of it: the same kind and block).
  static bool same_element(const Element& f, const Element& e);
  /// The nearest full stops (Element::stopped) before and after e, or none.
  struct StopsBeside {
    const Element* before = nullptr;
    const Element* after = nullptr;
  };
  StopsBeside stops_beside(const Element& e) const;
  /// e's zone and reach ended at the full stops beside it (Element::stopped).
  void part_zone(Element& e) const;
  /// r without what a full stop in it parts from e (Element::stopped).
  ZoneRange parted(ZoneRange r, const Element& e) const;
  /// The weights of the range's undecided elements (those past the decided prefix; one
  /// decided out of order counts both ways, weight and err).
  double range_weight(ZoneRange r) const;
  double range_weight_all(ZoneRange r) const;  ///< every element's, decided or not
  /// The largest weights one window holds (window_weights): of the undecided elements, of all.
  /// The same for every span in [span_lo, span_hi].
  struct WindowWeights {
    double undecided = 0;
    double all = 0;
    double span_lo = -kInf, span_hi = kInf;
  };
  /// What the range's decided elements leave to e (docs/tolerance.md, "Sharing a window"): the
  /// errs of those whose own zone reaches e (only those can be active at one instant with it),
  /// and of those among them whose zone also reaches an undecided element of the range besides
  /// e (only those can be active with both).
  struct Decided {
    double all = 0, shared = 0;
  };
  /// (run_of: only the chunks of that element's run.)
  Decided range_decided(ZoneRange r, const Element& e, const Element* run_of = nullptr) const;
  /// Whether range_decided(…, e) counts f: decided, not e, its zone reaching e.
  static bool counts_decided(const Element& f, const Element& e);
  /// The bound decided f leaves on its error in windows e shares with it: an arc with slower
  /// ends leaves each end's to the elements beyond that end.
  static double err_seen(const Element& f, const Element& e);
  double range_claims(ZoneRange r) const;  ///< zone_claims of the range
  /// range_weight, range_decided and (with claims) zone_claims of the last range asked for.
  struct ZoneMemo {
    ZoneRange range;
    bool valid = false;
    /// The windows' span the weights are for (window_weights); negative: the whole zone's.
    double span = -1.0;
    ZoneRange parted;                 ///< range, parted for the element (parted)
    double zone_weight = 0;           ///< the parted range's undecided elements' (range_weight)
    double zone_weight_all = 0;       ///< every one's, decided or not
    double weight = 0;                ///< the undecided elements' one window holds, or zone_weight
    double weight_all = 0;            ///< every element's, decided or not
    double span_lo = 0, span_hi = 0;  ///< the spans the weights hold for (WindowWeights)
    double claims = 0;
    Decided decided;
  };
  /// The largest weights of the elements of z's parted range one window can overlap, a window
  /// spanning at most `span` of travel and overlapping e: every element active at an instant
  /// with e is overlapped by the window then (docs/tolerance.md, "Sharing a window"). Of the
  /// undecided ones (as range_weight counts them) and of all.
  WindowWeights window_weights(const ZoneMemo& z, const Element& e, double span) const;
  /// Arc e at speed v, private or not (arc_privacy), and the turns its drift meets.
  struct Privacy {
    bool on = false;
    double turns = 0.0;  ///< Σ|Δu| of the near-tangent corners within reach, and a near circle's
  };
  /// Whether arc e (planar, a circle or near circle) at speed v is private:
  /// within v·τ of travel of its ends (its zone at that speed, `z`) no other arc and no run, and
  /// every block that near a line with a tolerance, still to be emitted, whose joins turn by at
  /// most kPrivateTurn each and kPrivateTurns in all (a full stop at its own start or end ends
  /// that reach: nothing beyond it shares a window with the arc). Its cap
  /// holds the lines at v within v·τ, so its windows hold its samples, its lines' and the
  /// corners' only: the output is the arc's error plus the corners' (their own terms, shared),
  /// and the path near it the simulated one turned by at most those corners, which turns the
  /// arc's drift along its lines by at most kDriftTurnFactor·turns·(its |y − x(s̄)|) into
  /// distance (ArcPrecompCheck::Judging::Private, docs/tolerance-arc-ends.md, "Private arcs").
  Privacy arc_privacy(const Element& e, double v, const ZoneMemo& z) const;
  static constexpr double kPrivateTurn = 0.02;   ///< |Δu|, 1.15°
  static constexpr double kPrivateTurns = 0.05;  ///< Σ|Δu|
  /// |s̄ − s_q| <= (π/2)·2·|e| (arc length to chord on the path near the output): 4 > π; and
  /// 1.25 on the check's |e| (PrivateDrift), which feed holds on the arc exceed by up to 3 %
  /// (test "a private arc: ...") and its residual table falls below by up to 5 %.
  static constexpr double kDriftTurnFactor = 4.0 * 1.25;
  /// The load of an element with error `own` and share weight w beside a zone's values, to be
  /// within the share (less the reserve): own within the larger of its share by weight,
  /// (share − claims)·w/W_all, and what the decided elements leave, the smaller of
  /// (share − claims − shared)·w/W and share − claims − all (docs/tolerance.md, "Sharing a
  /// window").
  static double zone_load(double own, double w, const ZoneMemo& z) {
    return std::min(own * z.weight_all / w,
                    std::max(own * z.weight / w + z.decided.shared, own + z.decided.all)) +
           z.claims;
  }
  /// The largest error zone_load lets an element of weight w have (share less the reserve).
  static double zone_allotment(double share, double w, const ZoneMemo& z) {
    const double left = share - z.claims;
    return std::max(left * w / z.weight_all,
                    std::min((left - z.decided.shared) * w / z.weight, left - z.decided.all));
  }
  /// memo's values for range r beside e, recomputed only when r differs from memo's range;
  /// with span >= 0 the weights are the largest one window of that span holds (window_weights).
  const ZoneMemo& zone_values(ZoneMemo& memo, ZoneRange r, const Element& e, bool with_claims,
                              double span = -1.0) const;
  /// The largest v <= vmax with load(v, range of [s0 − v·t, s1 + v·t]) <= share (the load grows
  /// with v): vmax, else by 40 halvings; guess(range) estimates where the load of that range
  /// reaches the share, which ends them early with the same result.
  /// largest_speed_in_zones' 40 halvings read off at once: the bracket narrowed by a few loads
  /// near the root of the zone's load and where the next element enters the zone, the halvings'
  /// end point confirmed by two loads; nothing when the bracket stays wider than a halving's step
  /// (hi_r: the zone at vmax, whose load is over the share).
  template <class Load, class Guess>
  std::optional<double> narrowed_speed_in_zones(double vmax, double share, double s0, double s1,
                                                double t, ZoneRange hi_r, Load& load,
                                                Guess& guess) const;
  template <class Load, class Guess>
  double largest_speed_in_zones(double vmax, double share, double s0, double s1, double t,
                                Load&& load, Guess&& guess) const;
  /// After a decision: the decided prefix grows over every decided element at its front.
  void extend_decided_prefix();
  /// Near-tangent corners: claimants are assigned in path order through time `t_until`; at
  /// every instant a claimant is active, it and the claimants before it stay within half its
  /// share.
  void assign_claims(double t_until);
  /// What claimant c adds to the error of the window whose weighted mean is at path length x:
  /// with weights >= 0 its tent, claim·max(0, 1 − |x − s|/claim_half) (docs/tolerance.md,
  /// "Claims by their tents"); else its whole claim.
  double claim_at(const Element& c, double x) const;
  /// The largest sum of the claims active at one instant among the claimants in [z0, z1]: what
  /// can be active beside an element with that zone, taken off its share.
  double zone_claims(double z0, double z1) const;
  void push_element(Element e);
  CornerMomentGrid& grid_d();  ///< grid_d_, built on first use
  /// The grid index of the pause the last corner decided on took (-1: none yet), tried first
  /// at the next corner.
  int last_corner_pause_j_ = -1;
  /// filter_.corner_moment_s(pause_s), the last pause asked for kept.
  double corner_moment(double pause_s) const;
  /// Hands on the window's front block: as pieces with their caps, then its pauses and what
  /// follows it.
  void emit_front();
  /// Decides every element a block ending at t1_s (fastest travel time) can reach.
  void decide_reachable(double t1_s);
  /// Where the decisions that hand on b must see to: b's end, or its chain's (chain_of).
  double emit_horizon_t(const Block& b) const;
  /// Decides the elements plan_untoleranced pushed for one block, the group elems_[i] belongs
  /// to, from the one nearest that block back; those wholly before the zone of a capped one
  /// decided nearer are let go.
  void decide_untoleranced_group(std::size_t i);
  /// pieces_ between the zone boundaries in [s0, s1] (a block, or a chain of arcs: chain_of);
  /// comp_v: its v_p when it is a pre-compensated arc; cap_all: the blocks' smallest cap_all;
  /// whole: not cut at all (an arc of several turns).
  /// own: the arc (or chain) being cut, whose pieces within its slower ends' stretches are
  /// planned at those ends' caps (Piece::plan).
  void cut_pieces(double s0, double s1, double cap_all, bool whole, double comp_v,
                  const Element* own = nullptr);
  /// Path length over which a pre-compensated arc's ramp brakes from `from` to `to`, mm.
  double braking_length_mm(double from, double to, double comp_v) const;
  /// The fastest speed from which that ramp brakes to `to` within len mm (to when none is).
  double fastest_braking_mm_s(double to, double len, double comp_v) const;
  /// The command stops on b's end point before the next motion (the interpolator waits there).
  bool stops_after(const Block& b) const;
  /// A pre-compensated arc ending with b takes the end rows for a stop (Motion::
  /// comp_stops_at_end): its command stops there, or the block after it crawls.
  bool comp_stops_after(const Block& b, double comp_v) const;
  void merge_short_pieces(const Block& b);
  /// A pre-compensated arc's pieces: each brakes to the next one's cap by the arc's ramp
  /// (Motion::comp_exit_speed_mm_s), or where it is too short to, runs at the fastest speed it
  /// can brake from (fastest_braking_mm_s).
  void brake_comp_pieces(double comp_v);
  /// b handed on as pieces_; a chain's block (chain: its element) as its part of the chain's
  /// pieces, each commanded as a piece of the chain's arc.
  /// Motion::override_ramp_mm_s of line b: the ramp's step of the first private arc whose reach
  /// (v_p·τ before its start) b ends in, else 0. Every such line is still to be emitted when
  /// the arc is decided private (arc_privacy), so each gets it.
  double override_ramp_before(const Block& b) const;
  /// `comp_private`: the arc is a private one (Motion::comp_private on every piece).
  void emit_pieces(const Block& b, double comp_v, const Element* chain, bool comp_private);
  /// Runs of small turns (CAM polylines): a vertex joins the run being gathered; a chunk is
  /// closed (pushed as one element, or as its corners while the run is short) when it spans τ,
  /// when a decision could reach it, and when the run ends.
  void add_run_vertex(const Element& corner, double seg_before_mm);
  void close_run_chunk();
  void end_run();
  /// The chunks of e's run in range r: their weight as range_weight counts it, their errs as
  /// range_decided(r, e) does.
  struct SameRun {
    double weight = 0, weight_all = 0;
    Decided decided;
  };
  SameRun same_run(const Element& e, ZoneRange r) const;
  /// Corners and arcs without a tolerance whose rounding the filter still holds when a block
  /// with one starts (within τ of fastest travel after them) are planned for that block's
  /// tolerance: each sample is judged against its own line's. They wait in untoleranced_ until
  /// a block decides: a toleranced one starting within τ plans them (plan_untoleranced), any
  /// block reaching τ past them lets them go (drop_untoleranced).
  void plan_untoleranced(const Block& b);
  void drop_untoleranced(double t_s);

  struct PendingRun {
    bool open = false;  ///< a chunk is being gathered
    Element chunk;
    std::vector<Element>
        corners;  ///< the run's first vertices, pushed as corners if it stays short
    std::uint64_t id = 0;
    int vertices = 0;  ///< in the run so far
  };

  FilterMoments filter_;
  PlannerConfig cfg_;
  NaiveCamMerger merger_;                   ///< reads the upstream source: G64 Q runs arrive merged
  std::optional<CornerMomentGrid> grid_d_;  ///< D(j·T), j = 0..N, each on first use
  mutable double moment_pause_s_ = std::numeric_limits<double>::quiet_NaN(), moment_s_ = 0.0;
  // Rings of reused slots, not std::deque: a deque allocates a node per Block and per Canon.
  RingDeque<Block> window_;
  BlockGeometry pulled_g_;  ///< pull()'s geometry of the item read
  RingDeque<Element> elems_;
  /// What is ready to hand on, with the block's geometry when the item is a whole block.
  struct Ready {
    Canon canon;
    bool has_geometry = false;
    BlockGeometry g;
  };
  RingDeque<Ready> ready_;
  const BlockGeometry* out_geometry_ = nullptr;  ///< geometry(): in ready_'s popped front slot
  void make_ready(Canon&& c, const BlockGeometry* g = nullptr);
  /// emit_front's scratch (kept, so a block allocates nothing): the cuts of the front block
  /// and its pieces between them.
  struct Piece {
    double a, c, cap;
    /// A chain's block's part of a chain piece: where that piece ends and the speed the next
    /// one needs (0: none lower).
    double exit_at = 0.0, exit_speed = 0.0;
    /// A pre-compensated piece's v_p when it is not the arc's (an arc's slower end), else 0.
    double plan = 0.0;
    double plan_or(double comp_v) const { return plan > 0.0 ? plan : comp_v; }
  };
  std::vector<double> cuts_;
  std::vector<Piece> pieces_;
  /// A chain of arcs pre-compensated as one: its pieces, cut once over the whole chain when its
  /// first block is handed on (every zone reaching it decided then), and the blocks take theirs.
  std::vector<Piece> chain_pieces_;
  std::vector<Piece> block_pieces_;  ///< emit_pieces' scratch: one block's part of them
  bool chain_stops_ = false;         ///< the chain's command stops on its end point
  /// decide_untoleranced_group's copy of a group, restored when a stop is cheaper (kept).
  std::vector<Element> saved_group_;
  Canon scratch_;
  bool ended_ = false;
  std::uint64_t seq_ = 0;
  double s_end_ = 0, t_end_ = 0;  ///< where the last block in the window ends
  /// Where the last block handed on ends (fastest travel time): blocks before the window.
  double emitted_t1_ = -std::numeric_limits<double>::infinity();
  /// The end of the last block handed on that has a tolerance (exact_path_comp_speed).
  double toleranced_t1_ = -std::numeric_limits<double>::infinity();
  double weight_total_ = 0.0;       ///< weights of all elements pushed so far
  std::size_t decided_prefix_ = 0;  ///< elems_[0, decided_prefix_) are decided
  std::size_t decided_count_ = 0;   ///< decided elements in elems_
  PendingRun run_;
  std::uint64_t runs_ = 0;
  std::optional<ArcPrecompCheck> precomp_;            ///< set when arcs may be pre-compensated
  std::optional<ArcResidualTable> residual_;          ///< precomp_'s term tabulated (with precomp_)
  std::optional<ArcResidualTable> residual_private_;  ///< the same of private arcs
  std::optional<ArcResidualTable> residual_drift_;    ///< their |y − x(s̄)| (fits_private)
  /// T·max(m, N − m) (m the weights' centre) when every weight is >= 0: a corner's rounding in a
  /// window is then at most its bound times a tent of half-width V·tent_s_ about the corner in
  /// the window's weighted mean (claim_at); 0 with negative weights (no tents).
  double tent_s_ = 0.0;
  bool dense_runs_ = false;  ///< every weight >= 0: dense polylines may join runs (kDenseRunTurn)
  std::size_t claim_cursor_ = 0;        ///< elems_[0, claim_cursor_) have their claim assigned
  std::uint64_t claimants_ = 0;         ///< claimants so far (none: zone_claims is 0 at once)
  std::uint64_t claim_candidates_ = 0;  ///< near-tangent corners pushed, not yet assigned
  /// A vertex (after block `seq`) or an arc (block `seq`) without a tolerance, in path order:
  /// where it starts and where what it leaves in the filter ends (fastest travel time): τ after
  /// the vertex is reached (the window no longer holds samples before it), τ after the arc.
  struct Untoleranced {
    std::uint64_t seq;
    bool arc;
    double t0, end;
  };
  RingDeque<Untoleranced> untoleranced_;
};

}  // namespace gm
