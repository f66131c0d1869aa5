// Parsing of an Acc/Dec profile spec string against the profile registry (NAME[:ARG][@C]).
#include "accdec/profile_spec.hpp"

#include "accdec/profiles.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace gm {

void profile_spec_error(std::string_view spec, const std::string& why) {
  throw InputError(
      fmt::format("bad Acc/Dec profile '{}': {}; accepted profiles: {} (C = cutoff "
                  "in (0,1] or 'max')",
                  spec, why, profile_forms()));
}

double parse_profile_number(std::string_view spec, std::string_view s, std::string_view what) {
  std::string buf(s);
  if (buf.empty()) profile_spec_error(spec, fmt::format("{} is empty", what));
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(buf.c_str(), &end);
  if (end != buf.c_str() + buf.size() || errno == ERANGE || !std::isfinite(v))
    profile_spec_error(spec, fmt::format("{} '{}' is not a number", what, buf));
  return v;
}

std::vector<std::string_view> split_profile_list(std::string_view s) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = s.find(',', start);
    parts.push_back(s.substr(start, comma == std::string_view::npos ? s.npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return parts;
}

namespace {

// A '+' joining profiles, not the sign of an exponent ("1e+3": 'e' after a digit or '.').
bool joins_profiles(std::string_view s, std::size_t i) {
  if (s[i] != '+') return false;
  if (i >= 2 && (s[i - 1] == 'e' || s[i - 1] == 'E') &&
      (std::isdigit(static_cast<unsigned char>(s[i - 2])) != 0 || s[i - 2] == '.'))
    return false;
  return true;
}

}  // namespace

bool is_composition(std::string_view spec) {
  for (std::size_t i = 0; i < spec.size(); ++i)
    if (joins_profiles(spec, i)) return true;
  return false;
}

std::vector<std::string_view> split_composition(std::string_view spec) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i < spec.size(); ++i)
    if (joins_profiles(spec, i)) {
      parts.push_back(spec.substr(start, i - start));
      start = i + 1;
    }
  parts.push_back(spec.substr(start));
  return parts;
}

int ProfileSpec::fixed_length(double period_s) const {
  return row != nullptr && row->fixed_length != nullptr ? row->fixed_length(*this, period_s) : 0;
}

std::string_view ProfileSpec::name() const {
  return row != nullptr ? row->name : "";
}

ProfileSpec parse_profile_spec(std::string_view spec) {
  ProfileSpec p;
  p.text = std::string(spec);
  if (is_composition(spec)) {
    p.row = find_profile(kCompositionName);
    p.row->parse_arg(p, true, spec);
    return p;
  }
  std::string_view head = spec;
  std::string_view arg;
  bool has_arg = false;
  if (const auto colon = spec.find(':'); colon != std::string_view::npos) {
    head = spec.substr(0, colon);
    arg = spec.substr(colon + 1);
    has_arg = true;
  }
  // Window designs take an optional "@cutoff" suffix (on the name or on the kaiser argument).
  std::string_view cutoff_text;
  bool has_cutoff = false;
  std::string_view& carrier = has_arg ? arg : head;
  const ProfileRow* damping_row = find_profile(head);
  if (damping_row != nullptr && damping_row->takes_damping && has_arg) {
    // A shaper: "@Z" is its damping ratio, parsed with its argument.
  } else if (const auto at = carrier.find('@'); at != std::string_view::npos) {
    cutoff_text = carrier.substr(at + 1);
    carrier = carrier.substr(0, at);
    has_cutoff = true;
  }

  p.row = find_profile(head);
  if (p.row == nullptr) profile_spec_error(spec, fmt::format("unknown profile name '{}'", head));
  if (p.row->parse_arg == nullptr && has_arg)
    profile_spec_error(spec, fmt::format("profile '{}' takes no ':' argument", head));
  if (!p.row->takes_cutoff && has_cutoff)
    profile_spec_error(spec, fmt::format("profile '{}' takes no '@cutoff'", head));
  if (p.row->parse_arg != nullptr) p.row->parse_arg(p, has_arg, arg);
  if (has_cutoff) {
    if (cutoff_text == "max") {
      p.cutoff_rule = CutoffRule::MaxNonNeg;
    } else {
      p.cutoff_rule = CutoffRule::Explicit;
      p.cutoff = parse_profile_number(spec, cutoff_text, "cutoff");
      if (!(p.cutoff > 0.0 && p.cutoff <= 1.0))
        profile_spec_error(
            spec, fmt::format("cutoff {} is outside (0, 1] (normalised to Nyquist)", p.cutoff));
    }
  }
  return p;
}

}  // namespace gm
