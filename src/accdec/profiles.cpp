// The Acc/Dec profile registry: the table of profiles and each one's argument and tap design.
#include "accdec/profiles.hpp"

#include "accdec/taps.hpp"
#include "accdec/window.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace gm {

namespace {

// --- tap designs ---------------------------------------------------------------------------

std::vector<double> linear_taps(const ProfileSpec&, const TapRequest& r, Taps&) {
  return std::vector<double>(static_cast<std::size_t>(r.n), 1.0);
}

// Eq. 22a/23: b_{k-1} ∝ a'[k] = 6(k/n) - 6(k/n)^2 = 6k(n-k)/n^2, k = 1..n -> raw k(n-k).
// Eq. 22b/23: b_{k-1} ∝ a'[k] = 30(k/n)^2 - 60(k/n)^3 + 30(k/n)^4 = 30k^2(n-k)^2/n^4 -> k^2(n-k)^2.
// The raw taps are exact integers (as doubles), so Step 3 keeps the shape exactly for small n.
// Note Eq. 23 samples a'(t) at t = k/n, k = 1..n: the last tap a'(1) is 0, the first is not.
template <int Degree>
std::vector<double> scurve_taps(const ProfileSpec& spec, const TapRequest& r, Taps&) {
  const int n = r.n;
  if (n < 2)
    throw InputError(
        fmt::format("profile '{}' needs tau >= 2T (its last tap a'(1) is 0); "
                    "got tau = {} s, T = {} s",
                    spec.text, r.tau_s, r.period_s));
  std::vector<double> b(static_cast<std::size_t>(n));
  for (int k = 1; k <= n; ++k) {
    const double p = static_cast<double>(k) * static_cast<double>(n - k);
    b[static_cast<std::size_t>(k - 1)] = Degree == 1 ? p : p * p;
  }
  return b;
}

// Matlab fir1(N, cutoff, window(N+1)) with the cutoff of the spec's rule (Eq. 25 by default).
template <WindowKind Kind>
std::vector<double> window_taps(const ProfileSpec& spec, const TapRequest& r, Taps& t) {
  const double beta = Kind == WindowKind::Kaiser ? spec.args.at(0) : 0.0;
  const auto w = make_window(Kind, r.n, beta);
  t.max_nonneg_cutoff = max_nonnegative_cutoff(Kind, t.N);
  t.cutoff = spec.cutoff_rule == CutoffRule::Paper       ? std::min(1.0, 2.0 / r.n)
             : spec.cutoff_rule == CutoffRule::MaxNonNeg ? t.max_nonneg_cutoff
                                                         : spec.cutoff;
  std::vector<double> raw = fir1_lowpass(t.N, t.cutoff, w);
  double sum = 0;
  for (double v : raw) sum += v;
  if (!(sum > 0))
    throw InputError(
        fmt::format("profile '{}' with N = {} has all-zero taps (the window "
                    "vanishes); use a larger tau (got tau = {} s, T = {} s)",
                    spec.text, t.N, r.tau_s, r.period_s));
  return raw;
}

std::vector<double> custom_taps(const ProfileSpec& spec, const TapRequest&, Taps&) {
  return spec.args;
}

// Convolution of moving averages of the given lengths.
std::vector<double> cascade_taps(const ProfileSpec& spec, const TapRequest&, Taps&) {
  std::vector<double> b{1.0};
  for (double len_d : spec.args) {
    const auto len = static_cast<std::size_t>(len_d);
    std::vector<double> c(b.size() + len - 1, 0.0);
    for (std::size_t i = 0; i < b.size(); ++i)
      for (std::size_t j = 0; j < len; ++j) c[i + j] += b[i];
    b = std::move(c);
  }
  return b;
}

// --- arguments -----------------------------------------------------------------------------

void kaiser_arg(ProfileSpec& p, bool has_arg, std::string_view arg) {
  if (!has_arg)
    profile_spec_error(
        p.text, fmt::format("kaiser needs its beta, e.g. {}", find_profile("kaiser")->example));
  const double beta = parse_profile_number(p.text, arg, "kaiser beta");
  if (beta < 0) profile_spec_error(p.text, fmt::format("kaiser beta {} is negative", beta));
  p.args = {beta};
}

void custom_arg(ProfileSpec& p, bool has_arg, std::string_view arg) {
  if (!has_arg || arg.empty())
    profile_spec_error(
        p.text, fmt::format("custom needs its taps, e.g. {}", find_profile("custom")->example));
  int i = 0;
  for (std::string_view part : split_profile_list(arg)) {
    const double b = parse_profile_number(p.text, part, fmt::format("tap b{}", i));
    if (b < 0)
      profile_spec_error(p.text,
                         fmt::format("tap b{} = {} is negative; section 2 requires every b_i >= 0 "
                                     "(negative taps make the velocity oscillate, Fig. 4)",
                                     i, b));
    p.args.push_back(b);
    ++i;
  }
  double sum = 0;
  for (double b : p.args) sum += b;
  if (!(sum > 0))
    profile_spec_error(p.text, "all custom taps are zero; b_s = sum of b_i must be > 0");
}

void cascade_arg(ProfileSpec& p, bool has_arg, std::string_view arg) {
  if (!has_arg || arg.empty())
    profile_spec_error(p.text, fmt::format("cascade needs its lengths, e.g. {}",
                                           find_profile("cascade")->example));
  int i = 0;
  for (std::string_view part : split_profile_list(arg)) {
    if (i == kMaxCascadeStages)
      profile_spec_error(p.text, fmt::format("more than {} cascade stages", kMaxCascadeStages));
    const double len = parse_profile_number(p.text, part, fmt::format("length L{}", i + 1));
    if (len < 1 || len != std::floor(len))
      profile_spec_error(p.text, fmt::format("length L{} = {} is not an integer >= 1", i + 1, len));
    if (len > kMaxAccDecTaps)
      profile_spec_error(
          p.text, fmt::format("length L{} = {} is more than {} taps", i + 1, len, kMaxAccDecTaps));
    p.args.push_back(len);
    ++i;
  }
}

int custom_length(const ProfileSpec& p) {
  return static_cast<int>(p.args.size());
}

int cascade_length(const ProfileSpec& p) {
  int n = 1;
  for (double len : p.args) n += static_cast<int>(len) - 1;
  return n;
}

// --- the table -----------------------------------------------------------------------------

constexpr std::array kRows{
    ProfileRow{.name = "linear",
               .form = "linear",
               .example = "linear",
               .help = "b_i = 1 (moving average, Eq. 15)",
               .takes_cutoff = false,
               .paper = true,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = linear_taps},
    ProfileRow{.name = "scurve1",
               .form = "scurve1",
               .example = "scurve1",
               .help = "3t^2 - 2t^3 mapped by Eq. 22a/23",
               .takes_cutoff = false,
               .paper = true,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = scurve_taps<1>},
    ProfileRow{.name = "scurve2",
               .form = "scurve2",
               .example = "scurve2",
               .help = "10t^3 - 15t^4 + 6t^5 mapped by Eq. 22b/23",
               .takes_cutoff = false,
               .paper = true,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = scurve_taps<2>},
    ProfileRow{.name = "blackman",
               .form = "blackman[@C]",
               .example = "blackman",
               .help = "fir1(N, C, blackman(N+1)); C = 2/(N+1) by default (Eq. 25)",
               .takes_cutoff = true,
               .paper = true,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Blackman>},
    ProfileRow{.name = "hann",
               .form = "hann[@C]",
               .example = "hann",
               .help = "fir1(N, C, hann(N+1))",
               .takes_cutoff = true,
               .paper = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Hann>},
    ProfileRow{.name = "hamming",
               .form = "hamming[@C]",
               .example = "hamming",
               .help = "fir1(N, C, hamming(N+1))",
               .takes_cutoff = true,
               .paper = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Hamming>},
    ProfileRow{.name = "kaiser",
               .form = "kaiser:BETA[@C]",
               .example = "kaiser:6",
               .help = "fir1(N, C, kaiser(N+1, BETA))",
               .takes_cutoff = true,
               .paper = false,
               .parse_arg = kaiser_arg,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Kaiser>},
    ProfileRow{.name = "custom",
               .form = "custom:b0,b1,...",
               .example = "custom:0.5,1,2,1,0.5",
               .help = "the given taps; tau = their count x T",
               .takes_cutoff = false,
               .paper = false,
               .parse_arg = custom_arg,
               .fixed_length = custom_length,
               .design = custom_taps},
    ProfileRow{.name = "cascade",
               .form = "cascade:L1,L2,...",
               .example = "cascade:21,21",
               .help = "convolution of moving averages of those lengths; tau fixed by them",
               .takes_cutoff = false,
               .paper = false,
               .parse_arg = cascade_arg,
               .fixed_length = cascade_length,
               .design = cascade_taps},
};

}  // namespace

std::span<const ProfileRow> profile_rows() {
  return kRows;
}

const ProfileRow* find_profile(std::string_view name) {
  for (const ProfileRow& r : kRows)
    if (r.name == name) return &r;
  return nullptr;
}

std::string profile_forms(std::string_view separator) {
  std::string out;
  for (const ProfileRow& r : kRows) {
    if (!out.empty()) out += separator;
    out += r.form;
  }
  return out;
}

std::vector<std::string> paper_profiles() {
  std::vector<std::string> out;
  for (const ProfileRow& r : kRows)
    if (r.paper) out.emplace_back(r.name);
  return out;
}

}  // namespace gm
