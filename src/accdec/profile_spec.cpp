// Parsing of an Acc/Dec profile spec string into a ProfileSpec (see profile_spec.hpp for the
// grammar).
#include "accdec/profile_spec.hpp"

#include "machine/machine.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace gm {

namespace {

constexpr const char* kForms =
    "accepted profiles: linear, scurve1, scurve2, blackman[@C], hann[@C], hamming[@C], "
    "kaiser:BETA[@C], custom:b0,b1,..., cascade:L1,L2,... (C = cutoff in (0,1] or 'max')";

[[noreturn]] void fail(std::string_view spec, const std::string& why) {
  throw InputError(fmt::format("bad Acc/Dec profile '{}': {}; {}", spec, why, kForms));
}

// Parses a whole string as a finite double, or fails naming `what`.
double parse_number(std::string_view spec, std::string_view s, std::string_view what) {
  std::string buf(s);
  if (buf.empty()) fail(spec, fmt::format("{} is empty", what));
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(buf.c_str(), &end);
  if (end != buf.c_str() + buf.size() || errno == ERANGE || !std::isfinite(v))
    fail(spec, fmt::format("{} '{}' is not a number", what, buf));
  return v;
}

// Splits "a,b,c" into its comma-separated parts (empty parts kept, so they can be rejected).
std::vector<std::string_view> split_commas(std::string_view s) {
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

}  // namespace

int ProfileSpec::fixed_length() const {
  if (kind == ProfileKind::Custom) return static_cast<int>(custom_taps.size());
  if (kind == ProfileKind::Cascade) {
    int n = 1;
    for (int len : cascade_lengths) n += len - 1;
    return n;
  }
  return 0;
}

ProfileSpec parse_profile_spec(std::string_view spec) {
  ProfileSpec p;
  p.text = std::string(spec);
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
  if (const auto at = carrier.find('@'); at != std::string_view::npos) {
    cutoff_text = carrier.substr(at + 1);
    carrier = carrier.substr(0, at);
    has_cutoff = true;
  }

  auto no_arg = [&] {
    if (has_arg) fail(spec, fmt::format("profile '{}' takes no ':' argument", head));
  };
  auto no_cutoff = [&] {
    if (has_cutoff) fail(spec, fmt::format("profile '{}' takes no '@cutoff'", head));
  };

  if (head == "linear") {
    no_arg(), no_cutoff();
    p.kind = ProfileKind::Linear;
  } else if (head == "scurve1") {
    no_arg(), no_cutoff();
    p.kind = ProfileKind::SCurve1;
  } else if (head == "scurve2") {
    no_arg(), no_cutoff();
    p.kind = ProfileKind::SCurve2;
  } else if (head == "blackman" || head == "hann" || head == "hamming" || head == "kaiser") {
    p.kind = ProfileKind::Window;
    if (head == "kaiser") {
      p.window = WindowKind::Kaiser;
      if (!has_arg) fail(spec, "kaiser needs its beta, e.g. kaiser:6");
      p.kaiser_beta = parse_number(spec, arg, "kaiser beta");
      if (p.kaiser_beta < 0) fail(spec, fmt::format("kaiser beta {} is negative", p.kaiser_beta));
    } else {
      no_arg();
      p.window = head == "blackman" ? WindowKind::Blackman
                 : head == "hann"   ? WindowKind::Hann
                                    : WindowKind::Hamming;
    }
    if (has_cutoff) {
      if (cutoff_text == "max") {
        p.cutoff_rule = CutoffRule::MaxNonNeg;
      } else {
        p.cutoff_rule = CutoffRule::Explicit;
        p.cutoff = parse_number(spec, cutoff_text, "cutoff");
        if (!(p.cutoff > 0.0 && p.cutoff <= 1.0))
          fail(spec, fmt::format("cutoff {} is outside (0, 1] (normalised to Nyquist)", p.cutoff));
      }
    }
  } else if (head == "custom") {
    no_cutoff();
    p.kind = ProfileKind::Custom;
    if (!has_arg || arg.empty()) fail(spec, "custom needs its taps, e.g. custom:0.5,1,2,1,0.5");
    int i = 0;
    for (std::string_view part : split_commas(arg)) {
      const double b = parse_number(spec, part, fmt::format("tap b{}", i));
      if (b < 0)
        fail(spec, fmt::format("tap b{} = {} is negative; section 2 requires every b_i >= 0 "
                               "(negative taps make the velocity oscillate, Fig. 4)",
                               i, b));
      p.custom_taps.push_back(b);
      ++i;
    }
    double sum = 0;
    for (double b : p.custom_taps) sum += b;
    if (!(sum > 0)) fail(spec, "all custom taps are zero; b_s = sum of b_i must be > 0");
  } else if (head == "cascade") {
    no_cutoff();
    p.kind = ProfileKind::Cascade;
    if (!has_arg || arg.empty()) fail(spec, "cascade needs its lengths, e.g. cascade:21,21");
    int i = 0;
    for (std::string_view part : split_commas(arg)) {
      if (i == kMaxCascadeStages)
        fail(spec, fmt::format("more than {} cascade stages", kMaxCascadeStages));
      const double len = parse_number(spec, part, fmt::format("length L{}", i + 1));
      if (len < 1 || len != std::floor(len))
        fail(spec, fmt::format("length L{} = {} is not an integer >= 1", i + 1, len));
      if (len > kMaxAccDecTaps)
        fail(spec, fmt::format("length L{} = {} is more than {} taps", i + 1, len, kMaxAccDecTaps));
      p.cascade_lengths.push_back(static_cast<int>(len));
      ++i;
    }
  } else {
    fail(spec, fmt::format("unknown profile name '{}'", head));
  }
  return p;
}

}  // namespace gm
