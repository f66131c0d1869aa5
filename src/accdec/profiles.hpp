// The Acc/Dec profile registry: one row per profile (name, parameters, tap design, help).
#pragma once

#include "accdec/profile_spec.hpp"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

struct Taps;
struct ShaperImpulses;

/// Most moving averages a cascade profile may chain (each at most kMaxAccDecTaps long), and most
/// profiles a composition "P1+P2+..." may convolve.
inline constexpr int kMaxCascadeStages = 16;

/// Name of the composition row: a spec with a '+' between profiles is parsed by that row.
inline constexpr std::string_view kCompositionName = "+";

/// What a row's tap design is given besides its spec.
struct TapRequest {
  int n = 0;  ///< number of taps, tau/T (Eq. 24)
  double tau_s = 0;
  double period_s = 0;
};

/// One Acc/Dec profile. Every list of profiles (parsing, error messages, CLI help, `design
/// --list-profiles`, `compare`'s default set, the tests, docs/pipeline.md) comes from the table
/// in profiles.cpp; adding a profile is adding a row there.
struct ProfileRow {
  std::string_view name;     ///< what a spec starts with
  std::string_view form;     ///< how a spec is written, e.g. "kaiser:BETA[@C]"
  std::string_view example;  ///< a valid spec (for messages, tests and docs), e.g. "kaiser:6"
  std::string_view help;     ///< one line: the taps it designs
  bool takes_cutoff;         ///< accepts "@C" / "@max" (window designs)
  bool paper;                ///< one of the paper's four (compare's default set)
  bool takes_damping;        ///< its ':' argument carries "@Z", a damping ratio (shapers)
  /// Parses the ':' argument into spec.args (has_arg false: none was written); nullptr: the
  /// profile takes none.
  void (*parse_arg)(ProfileSpec& spec, bool has_arg, std::string_view arg);
  /// Taps fixed by the spec at period T (custom, cascade, shapers), or nullptr when they follow
  /// tau/T; may return 0 (a composition with a stage that follows tau/T).
  int (*fixed_length)(const ProfileSpec& spec, double period_s);
  /// The raw taps (any positive scale; negative taps are refused by design_taps); may set
  /// t.cutoff and t.max_nonneg_cutoff.
  std::vector<double> (*design)(const ProfileSpec& spec, const TapRequest& r, Taps& t);
};

/// Every row, in the order of the help texts.
std::span<const ProfileRow> profile_rows();
/// The row named `name`, or nullptr.
const ProfileRow* find_profile(std::string_view name);
/// "linear, scurve1, ..., cascade:L1,L2,..." (every row's form, comma separated).
std::string profile_forms(std::string_view separator = ", ");
/// The names of the rows with `paper` set, in table order.
std::vector<std::string> paper_profiles();

/// The continuous impulse sequences of a spec's shapers: the spec's own when it is a shaper, its
/// parts' when it is a composition; empty when it has none.
std::vector<ShaperImpulses> spec_shapers(const ProfileSpec& spec);

}  // namespace gm
