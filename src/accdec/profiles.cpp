// The Acc/Dec profile registry: the table of profiles and each one's argument and tap design.
#include "accdec/profiles.hpp"

#include "accdec/shapers.hpp"
#include "accdec/taps.hpp"
#include "accdec/window.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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

int custom_length(const ProfileSpec& p, double) {
  return static_cast<int>(p.args.size());
}

int cascade_length(const ProfileSpec& p, double) {
  int n = 1;
  for (double len : p.args) n += static_cast<int>(len) - 1;
  return n;
}

// --- input shapers (accdec/shapers.hpp): args = {frequency Hz, damping ratio} ---------------

template <ShaperKind Kind>
ShaperImpulses spec_impulses(const ProfileSpec& spec) {
  return shaper_impulses(Kind, spec.args.at(0), spec.args.at(1));
}

template <ShaperKind Kind>
int shaper_length(const ProfileSpec& spec, double period_s) {
  if (!(period_s > 0) || !std::isfinite(period_s)) return 1;
  return shaper_tap_count(spec_impulses<Kind>(spec), period_s, kMaxAccDecTaps + 1);
}

template <ShaperKind Kind>
std::vector<double> shaper_design(const ProfileSpec& spec, const TapRequest& r, Taps&) {
  const double f = spec.args.at(0);
  if (!(2.0 * f * r.period_s < 1.0))
    throw InputError(fmt::format(
        "shaper '{}' at {} Hz is at or above the Nyquist frequency 1/(2T) = {:.6g} Hz of "
        "T = {} s; its impulses cannot be placed on the samples",
        spec.text, f, 0.5 / r.period_s, r.period_s));
  const ShaperImpulses imp = spec_impulses<Kind>(spec);
  if (shaper_tap_count(imp, r.period_s, kMaxAccDecTaps + 1) > kMaxAccDecTaps)
    throw InputError(fmt::format("shaper '{}' lasts {:.6g} s, more than {} taps of T = {} s",
                                 spec.text, imp.duration_s(), kMaxAccDecTaps, r.period_s));
  return shaper_taps(imp, r.period_s);
}

template <ShaperKind Kind>
void shaper_arg(ProfileSpec& p, bool has_arg, std::string_view arg) {
  const std::string name = p.text.substr(0, p.text.find(':'));
  if (!has_arg || arg.empty())
    profile_spec_error(p.text, fmt::format("{} needs its frequency in Hz, e.g. {}", name,
                                           find_profile(name)->example));
  std::string_view freq = arg;
  std::string_view zeta;
  bool has_zeta = false;
  if (const auto at = arg.find('@'); at != std::string_view::npos) {
    freq = arg.substr(0, at);
    zeta = arg.substr(at + 1);
    has_zeta = true;
  }
  const double f = parse_profile_number(p.text, freq, "shaper frequency");
  if (!(f > 0)) profile_spec_error(p.text, fmt::format("shaper frequency {} Hz is not > 0", f));
  const double z =
      has_zeta ? parse_profile_number(p.text, zeta, "damping ratio") : kDefaultShaperDamping;
  const double z_max = shaper_max_damping(Kind);
  if (!(z >= 0 && z <= z_max))
    profile_spec_error(p.text,
                       fmt::format("damping ratio {} is outside [0, {}] for {}", z, z_max, name));
  p.args = {f, z};
}

// --- compositions "P1+P2+...": the convolution of the parts' taps --------------------------

std::vector<double> convolve_taps(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> c(a.size() + b.size() - 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
  return c;
}

void composition_arg(ProfileSpec& p, bool, std::string_view arg) {
  const auto parts = split_composition(arg);
  if (static_cast<int>(parts.size()) > kMaxCascadeStages)
    profile_spec_error(p.text,
                       fmt::format("more than {} profiles joined by '+'", kMaxCascadeStages));
  int free = 0;
  for (std::string_view part : parts) {
    if (part.empty()) profile_spec_error(p.text, "an empty profile between '+'");
    p.stages.push_back(parse_profile_spec(part));
    if (p.stages.back().row->fixed_length == nullptr && ++free > 1)
      profile_spec_error(p.text,
                         "more than one profile follows tau; at most one may, the others "
                         "(shapers, custom, cascade) fix their own taps");
  }
}

// Taps of the parts; 0 when one of them follows tau.
int composition_length(const ProfileSpec& p, double period_s) {
  long long n = 1;
  for (const ProfileSpec& s : p.stages) {
    const int len = s.fixed_length(period_s);
    if (len == 0) return 0;
    n += len - 1;
  }
  return static_cast<int>(std::min<long long>(n, kMaxAccDecTaps + 1));
}

std::vector<double> composition_taps(const ProfileSpec& spec, const TapRequest& r, Taps& t) {
  long long fixed_extra = 0;  // taps the fixed parts add
  for (const ProfileSpec& s : spec.stages)
    if (const int len = s.fixed_length(r.period_s); len > 0) fixed_extra += len - 1;
  const long long n_free = r.n - fixed_extra;
  if (n_free < 1)
    throw InputError(fmt::format(
        "profile '{}': its fixed parts take {} taps beyond the first, so tau must be more "
        "than {} x T = {:.6g} s; got tau = {} s",
        spec.text, fixed_extra, fixed_extra + 1, static_cast<double>(fixed_extra + 1) * r.period_s,
        r.tau_s));
  std::vector<double> b{1.0};
  for (const ProfileSpec& s : spec.stages) {
    int n = s.fixed_length(r.period_s);
    if (n == 0) n = static_cast<int>(n_free);
    Taps part;
    part.N = n - 1;
    part.cutoff = part.max_nonneg_cutoff = std::numeric_limits<double>::quiet_NaN();
    b = convolve_taps(b, s.row->design(s, TapRequest{n, n * r.period_s, r.period_s}, part));
    if (s.row->fixed_length == nullptr) {
      t.cutoff = part.cutoff;
      t.max_nonneg_cutoff = part.max_nonneg_cutoff;
    }
  }
  return b;
}

// --- the table -----------------------------------------------------------------------------

constexpr std::array kRows{
    ProfileRow{.name = "linear",
               .form = "linear",
               .example = "linear",
               .help = "b_i = 1 (moving average, Eq. 15)",
               .takes_cutoff = false,
               .paper = true,
               .takes_damping = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = linear_taps},
    ProfileRow{.name = "scurve1",
               .form = "scurve1",
               .example = "scurve1",
               .help = "3t^2 - 2t^3 mapped by Eq. 22a/23",
               .takes_cutoff = false,
               .paper = true,
               .takes_damping = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = scurve_taps<1>},
    ProfileRow{.name = "scurve2",
               .form = "scurve2",
               .example = "scurve2",
               .help = "10t^3 - 15t^4 + 6t^5 mapped by Eq. 22b/23",
               .takes_cutoff = false,
               .paper = true,
               .takes_damping = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = scurve_taps<2>},
    ProfileRow{.name = "blackman",
               .form = "blackman[@C]",
               .example = "blackman",
               .help = "fir1(N, C, blackman(N+1)); C = 2/(N+1) by default (Eq. 25)",
               .takes_cutoff = true,
               .paper = true,
               .takes_damping = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Blackman>},
    ProfileRow{.name = "hann",
               .form = "hann[@C]",
               .example = "hann",
               .help = "fir1(N, C, hann(N+1))",
               .takes_cutoff = true,
               .paper = false,
               .takes_damping = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Hann>},
    ProfileRow{.name = "hamming",
               .form = "hamming[@C]",
               .example = "hamming",
               .help = "fir1(N, C, hamming(N+1))",
               .takes_cutoff = true,
               .paper = false,
               .takes_damping = false,
               .parse_arg = nullptr,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Hamming>},
    ProfileRow{.name = "kaiser",
               .form = "kaiser:BETA[@C]",
               .example = "kaiser:6",
               .help = "fir1(N, C, kaiser(N+1, BETA))",
               .takes_cutoff = true,
               .paper = false,
               .takes_damping = false,
               .parse_arg = kaiser_arg,
               .fixed_length = nullptr,
               .design = window_taps<WindowKind::Kaiser>},
    ProfileRow{.name = "custom",
               .form = "custom:b0,b1,...",
               .example = "custom:0.5,1,2,1,0.5",
               .help = "the given taps; tau = their count x T",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = false,
               .parse_arg = custom_arg,
               .fixed_length = custom_length,
               .design = custom_taps},
    ProfileRow{.name = "cascade",
               .form = "cascade:L1,L2,...",
               .example = "cascade:21,21",
               .help = "convolution of moving averages of those lengths; tau fixed by them",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = false,
               .parse_arg = cascade_arg,
               .fixed_length = cascade_length,
               .design = cascade_taps},
    ProfileRow{
        .name = "zv",
        .form = "zv:F[@Z]",
        .example = "zv:45",
        .help =
            "ZV input shaper for a mode at F Hz, damping Z (default 0.1): 2 impulses over t_d/2",
        .takes_cutoff = false,
        .paper = false,
        .takes_damping = true,
        .parse_arg = shaper_arg<ShaperKind::ZV>,
        .fixed_length = shaper_length<ShaperKind::ZV>,
        .design = shaper_design<ShaperKind::ZV>},
    ProfileRow{.name = "zvd",
               .form = "zvd:F[@Z]",
               .example = "zvd:40",
               .help = "ZVD input shaper: 3 impulses over t_d",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = true,
               .parse_arg = shaper_arg<ShaperKind::ZVD>,
               .fixed_length = shaper_length<ShaperKind::ZVD>,
               .design = shaper_design<ShaperKind::ZVD>},
    ProfileRow{.name = "zvdd",
               .form = "zvdd:F[@Z]",
               .example = "zvdd:40",
               .help = "ZVDD input shaper (ZV cubed): 4 impulses over 1.5 t_d",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = true,
               .parse_arg = shaper_arg<ShaperKind::ZVDD>,
               .fixed_length = shaper_length<ShaperKind::ZVDD>,
               .design = shaper_design<ShaperKind::ZVDD>},
    ProfileRow{.name = "mzv",
               .form = "mzv:F[@Z]",
               .example = "mzv:45",
               .help = "MZV input shaper: 3 impulses over 0.75 t_d",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = true,
               .parse_arg = shaper_arg<ShaperKind::MZV>,
               .fixed_length = shaper_length<ShaperKind::MZV>,
               .design = shaper_design<ShaperKind::MZV>},
    ProfileRow{.name = "ei",
               .form = "ei:F[@Z]",
               .example = "ei:45",
               .help = "EI input shaper (5 % tolerance): 3 impulses over t_d",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = true,
               .parse_arg = shaper_arg<ShaperKind::EI>,
               .fixed_length = shaper_length<ShaperKind::EI>,
               .design = shaper_design<ShaperKind::EI>},
    ProfileRow{.name = "2hei",
               .form = "2hei:F[@Z]",
               .example = "2hei:60",
               .help = "2-hump EI input shaper (Klipper 2hump_ei): 4 impulses over 1.5/F",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = true,
               .parse_arg = shaper_arg<ShaperKind::TwoHumpEI>,
               .fixed_length = shaper_length<ShaperKind::TwoHumpEI>,
               .design = shaper_design<ShaperKind::TwoHumpEI>},
    ProfileRow{.name = "3hei",
               .form = "3hei:F[@Z]",
               .example = "3hei:80",
               .help = "3-hump EI input shaper (Klipper 3hump_ei): 5 impulses over 2/F",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = true,
               .parse_arg = shaper_arg<ShaperKind::ThreeHumpEI>,
               .fixed_length = shaper_length<ShaperKind::ThreeHumpEI>,
               .design = shaper_design<ShaperKind::ThreeHumpEI>},
    ProfileRow{.name = kCompositionName,
               .form = "P1+P2+...",
               .example = "blackman+mzv:45",
               .help = "convolution of the profiles' taps; at most one follows tau (it gets "
                       "tau minus what the others add)",
               .takes_cutoff = false,
               .paper = false,
               .takes_damping = false,
               .parse_arg = composition_arg,
               .fixed_length = composition_length,
               .design = composition_taps},
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

std::vector<ShaperImpulses> spec_shapers(const ProfileSpec& spec) {
  constexpr std::array kKinds{ShaperKind::ZV,         ShaperKind::ZVD, ShaperKind::ZVDD,
                              ShaperKind::MZV,        ShaperKind::EI,  ShaperKind::TwoHumpEI,
                              ShaperKind::ThreeHumpEI};
  constexpr std::array kDesigns{
      shaper_design<ShaperKind::ZV>,         shaper_design<ShaperKind::ZVD>,
      shaper_design<ShaperKind::ZVDD>,       shaper_design<ShaperKind::MZV>,
      shaper_design<ShaperKind::EI>,         shaper_design<ShaperKind::TwoHumpEI>,
      shaper_design<ShaperKind::ThreeHumpEI>};
  std::vector<ShaperImpulses> out;
  auto add = [&](const ProfileSpec& s) {
    for (std::size_t k = 0; k < kKinds.size(); ++k)
      if (s.row != nullptr && s.row->design == kDesigns[k])
        out.push_back(shaper_impulses(kKinds[k], s.args.at(0), s.args.at(1)));
  };
  add(spec);
  for (const ProfileSpec& s : spec.stages) add(s);
  return out;
}

}  // namespace gm
