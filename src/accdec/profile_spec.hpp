// A parsed Acc/Dec profile spec ("blackman", "kaiser:6@max", "custom:0.5,1,2,1,0.5", ...).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace gm {

struct ProfileRow;  // accdec/profiles.hpp: one row of the profile registry

/// How the cutoff of a window design is chosen.
enum class CutoffRule {
  Paper,      ///< Eq. 25: w = 2/(N+1) (the default)
  MaxNonNeg,  ///< "@max": the largest cutoff that keeps every tap >= 0 (closed form, window.cpp)
  Explicit    ///< "@0.05": the given value, normalised to Nyquist, in (0, 1]
};

/// A parsed profile spec: its registry row and the parameters written after the name.
struct ProfileSpec {
  std::string text;                 ///< the spec as given
  const ProfileRow* row = nullptr;  ///< never null after parse_profile_spec
  std::vector<double> args;         ///< the ':' argument: kaiser's beta, custom taps, lengths, a
                                    ///< shaper's frequency (Hz) and damping ratio
  std::vector<ProfileSpec> stages;  ///< a composition "P1+P2+...": its parts, in order
  CutoffRule cutoff_rule = CutoffRule::Paper;
  double cutoff = 0.0;  ///< for CutoffRule::Explicit

  /// Number of taps fixed by the spec itself at period T (custom, cascade, shapers, compositions
  /// of those), else 0 (taps follow tau/T).
  int fixed_length(double period_s) const;
  /// The registry name ("blackman", "custom", ...).
  std::string_view name() const;
};

/// Parses `spec` as NAME[:ARG][@C] against the profile registry (accdec/profiles.cpp), where
/// C = a cutoff in (0,1] or "max" for the profiles that take one (shapers read "@Z" in their
/// argument themselves), or as a composition P1+P2+... (the registry's "+" row).
/// Throws gm::InputError naming the bad part and listing the accepted forms.
ProfileSpec parse_profile_spec(std::string_view spec);

/// Helpers for the registry rows' argument parsers.
[[noreturn]] void profile_spec_error(std::string_view spec, const std::string& why);
/// A whole string as a finite double, or profile_spec_error naming `what`.
double parse_profile_number(std::string_view spec, std::string_view s, std::string_view what);
/// True when `spec` joins profiles with '+' (a '+' that is not a number's exponent sign).
bool is_composition(std::string_view spec);
/// "a+b+c" split at those '+'.
std::vector<std::string_view> split_composition(std::string_view spec);
/// "a,b,c" split at the commas (empty parts kept, so they can be rejected).
std::vector<std::string_view> split_profile_list(std::string_view s);

}  // namespace gm
