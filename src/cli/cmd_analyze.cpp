// gmotion analyze — radius error (Table 1, Fig. 13), amplitude response (Fig. 8c, 12c), corner
// error and residual vibration of taps.
#include "accdec/analysis.hpp"
#include "accdec/profile_spec.hpp"
#include "accdec/profiles.hpp"
#include "accdec/taps.hpp"
#include "accdec/vibration.hpp"
#include "cli/commands.hpp"
#include "cli/json_number.hpp"
#include "cli/vibration_figures.hpp"
#include "common/status.hpp"
#include "common/units.hpp"
#include "planner/filter_moments.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace gm::cli {

namespace {

std::string jtaps(const Taps& t) {
  std::string s = fmt::format("\"profile\":\"{}\",\"N\":{},\"cutoff\":{},\"taps\":[", t.profile,
                              t.N, json_number(t.cutoff));
  for (std::size_t i = 0; i < t.real.size(); ++i) s += (i ? "," : "") + json_number(t.real[i]);
  s += "],\"taps_int\":[";
  for (std::size_t i = 0; i < t.integer.size(); ++i)
    s += fmt::format("{}{}", i ? "," : "", t.integer[i]);
  return s + fmt::format("],\"b_s\":{}", t.b_s);
}

struct RadiusOptions {
  std::string profile = "linear";
  double tau_s = 0.041;
  double period_s = 0.001;
  double radius_mm = 150.0;
  std::vector<double> feeds_mm_min{30000, 25000, 20000, 15000, 10000, 8000, 6000,
                                   4000,  2000,  1000,  600,   400,   200};
  bool json = false;
};

struct ResponseOptions {
  std::string profile = "blackman";
  double tau_s = 0.164;
  double period_s = 0.004;
  int points = 201;
  bool json = false;
};

void run_radius(const RadiusOptions& o) {
  if (!(o.radius_mm > 0)) throw InputError(fmt::format("--radius {} mm must be > 0", o.radius_mm));
  const Taps t = design_taps(o.profile, o.tau_s, o.period_s);
  const bool linear = parse_profile_spec(o.profile).name() == "linear";
  struct Row {
    double feed, sampled, cont, approx;
  };
  std::vector<Row> rows;
  for (double f : o.feeds_mm_min) {
    if (!(f > 0)) throw InputError(fmt::format("--feeds: feed {} mm/min must be > 0", f));
    const double v_mm_s = units::mm_min_to_mm_s(f);
    rows.push_back({f, 1000.0 * radius_loss_sampled(t.real, o.radius_mm, v_mm_s, o.period_s),
                    1000.0 * radius_loss_linear_continuous(o.radius_mm, v_mm_s, o.tau_s),
                    1000.0 * radius_loss_linear_approx(o.radius_mm, v_mm_s, o.tau_s)});
  }
  if (o.json) {
    std::string s =
        "{" + jtaps(t) +
        fmt::format(",\"tau\":{},\"period\":{},\"radius_mm\":{},\"rows\":[", json_number(o.tau_s),
                    json_number(o.period_s), json_number(o.radius_mm));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      s += fmt::format("{}{{\"feed_mm_min\":{},\"sampled_um\":{}", i ? "," : "",
                       json_number(rows[i].feed), json_number(rows[i].sampled));
      if (linear)
        s += fmt::format(",\"continuous_um\":{},\"approx_um\":{}", json_number(rows[i].cont),
                         json_number(rows[i].approx));
      s += "}";
    }
    fmt::print("{}]}}\n", s);
    return;
  }
  fmt::print(
      "Radius error of a circle through the Acc/Dec filter: profile {}, N = {}, tau = {} s, "
      "T = {} s, R = {} mm\n",
      t.profile, t.N, o.tau_s, o.period_s, o.radius_mm);
  fmt::print("sampled = R(1-|D(e^jwT)|), w = V/R (Eq. 9-16)");
  if (linear)
    fmt::print("; continuous = Eq. 18 R-2R/(tau w) sin(tau w/2); approx = Eq. 19 (tau V)^2/(24R)");
  fmt::print("\n\n{:>12}  {:>10}  {:>22}", "feed mm/min", "w rad/s", "sampled um");
  if (linear) fmt::print("  {:>22}  {:>22}", "continuous um (Eq.18)", "approx um (Eq.19)");
  fmt::print("\n");
  for (const Row& r : rows) {
    fmt::print("{:>12.6g}  {:>10.6g}  {:>22.15g}", r.feed,
               units::mm_min_to_mm_s(r.feed) / o.radius_mm, r.sampled);
    if (linear) fmt::print("  {:>22.15g}  {:>22.15g}", r.cont, r.approx);
    fmt::print("\n");
  }
}

void run_response(const ResponseOptions& o) {
  if (o.points < 2) throw InputError(fmt::format("--points {} must be >= 2", o.points));
  const Taps t = design_taps(o.profile, o.tau_s, o.period_s);
  const auto applied = as_double(t.integer);
  const double nyquist_hz = 0.5 / o.period_s;
  auto sample = [&](int j, double& f_norm, double& a, double& a_int) {
    f_norm = static_cast<double>(j) / (o.points - 1);
    a = amplitude_response(t.real, std::numbers::pi * f_norm);
    a_int = amplitude_response(applied, std::numbers::pi * f_norm);
  };
  if (o.json) {
    std::string s = "{" + jtaps(t) +
                    fmt::format(",\"tau\":{},\"period\":{},\"response\":[", json_number(o.tau_s),
                                json_number(o.period_s));
    for (int j = 0; j < o.points; ++j) {
      double f, a, ai;
      sample(j, f, a, ai);
      s += fmt::format("{}{{\"f_norm\":{},\"f_hz\":{},\"amplitude\":{},\"amplitude_int\":{}}}",
                       j ? "," : "", json_number(f), json_number(f * nyquist_hz), json_number(a),
                       json_number(ai));
    }
    fmt::print("{}]}}\n", s);
    return;
  }
  fmt::print("# profile={} N={} tau={} period={} cutoff={} b_s={}\n", t.profile, t.N, o.tau_s,
             o.period_s, t.cutoff, t.b_s);
  std::string taps = "# taps=";
  for (std::size_t i = 0; i < t.real.size(); ++i) {
    if (i) taps += ' ';  // appended in two steps: g++ 12 -O3 warns falsely on `a + b`
    taps += fmt::format("{:.10g}", t.real[i]);
  }
  fmt::print("{}\n# taps_int=", taps);
  for (std::size_t i = 0; i < t.integer.size(); ++i) fmt::print("{}{}", i ? " " : "", t.integer[i]);
  fmt::print("\nf_norm,f_hz,omega_T,amplitude,amplitude_int\n");
  for (int j = 0; j < o.points; ++j) {
    double f, a, ai;
    sample(j, f, a, ai);
    fmt::print("{:.8g},{:.8g},{:.8g},{:.12g},{:.12g}\n", f, f * nyquist_hz, std::numbers::pi * f, a,
               ai);
  }
}

struct CornerOptions {
  std::string profile = "blackman";
  double tau_s = 0.164;
  double period_s = 0.004;
  std::vector<double> angles_deg{10, 30, 45, 60, 90, 120, 150, 170};
  std::vector<double> feeds_mm_min{500, 1000, 2000, 4000, 6000, 10000};
  double tolerance_mm = 0.01;
};

// G64 P tolerance: the corner error of the Acc/Dec output (FilterMoments) against angle and feed,
// and the largest feed for a tolerance, slowed (no pause) and paused.
void run_corner(const CornerOptions& o) {
  if (!(o.tolerance_mm > 0))
    throw InputError(fmt::format("--tolerance {} mm must be > 0", o.tolerance_mm));
  for (double a : o.angles_deg)
    if (!(a > 0 && a <= 180)) throw InputError(fmt::format("--angles: {} must be in (0, 180]", a));
  for (double f : o.feeds_mm_min)
    if (!(f > 0)) throw InputError(fmt::format("--feeds: feed {} mm/min must be > 0", f));
  const Taps t = design_taps(o.profile, o.tau_s, o.period_s);
  const FilterMoments fm(t, o.period_s);
  const double d0 = fm.corner_moment_s(0.0);
  fmt::print("# corner error of the Acc/Dec output: profile={} tau={} s T={} s taps={}\n",
             t.profile, o.tau_s, o.period_s, t.integer.size());
  fmt::print(
      "# centre m = {:.6g} samples, D = T*sum h_i*max(m-i,0) = {:.6g} ms, sigma = {:.6g} ms\n",
      fm.centre(), 1e3 * d0, 1e3 * std::sqrt(fm.variance_s2()));
  fmt::print(
      "# a corner turning by phi at feed F: F*D*sin(phi) from the path, "
      "2*F*D*sin(phi/2) from the vertex; a pause P at the vertex replaces D by D(P)\n");
  fmt::print("\n# error from the path, mm, no pause\nangle_deg");
  for (double f : o.feeds_mm_min) fmt::print(",F{:g}", f);
  fmt::print("\n");
  for (double a : o.angles_deg) {
    const double phi = a * std::numbers::pi / 180.0;
    fmt::print("{:g}", a);
    for (double f : o.feeds_mm_min)
      fmt::print(",{:.6f}", fm.corner_error_mm(units::mm_min_to_mm_s(f), phi, 0.0));
    fmt::print("\n");
  }
  fmt::print(
      "\n# tolerance {} mm: largest feed without a pause (slowed), mm/min; and the "
      "shortest pause at each feed (paused), ms\nangle_deg,slowed_feed_mm_min",
      o.tolerance_mm);
  for (double f : o.feeds_mm_min) fmt::print(",pause_ms_F{:g}", f);
  fmt::print("\n");
  for (double a : o.angles_deg) {
    const double phi = a * std::numbers::pi / 180.0;
    const double v = fm.largest_corner_speed_mm_s(o.tolerance_mm, phi, 0.0);
    fmt::print("{:g},{}", a,
               std::isfinite(v) ? fmt::format("{:.1f}", units::mm_s_to_mm_min(v)) : "inf");
    for (double f : o.feeds_mm_min)
      fmt::print(",{:.3f}",
                 1e3 * fm.shortest_pause_s(o.tolerance_mm, phi, units::mm_min_to_mm_s(f)));
    fmt::print("\n");
  }
  fmt::print(
      "\n# pause P, ms -> D(P), ms (0 from P = N*T = {:g} ms: the filter drains)\n"
      "pause_ms,D_ms\n",
      1e3 * fm.order() * o.period_s);
  for (int k = 0; k <= fm.order(); k += std::max(1, fm.order() / 10))
    fmt::print("{:g},{:.6g}\n", 1e3 * k * o.period_s, 1e3 * fm.corner_moment_s(k * o.period_s));
}

struct VibrationOptions {
  std::string profile = "mzv:45";
  double tau_s = 0;  // 0: the profile's fixed length x T
  double period_s = 0.001;
  std::string freq_range = "5:200";
  int points = 196;
  double damping = 0.1;
  double freq_hz = 0;  // 0: the first shaper's frequency, else where V is least in the range
  double feed_mm_min = 6000;
  double limit_pct = 5;
};

// The residual vibration V(f) of the applied taps over a frequency range (CSV), the robustness
// around the mode and the smoothing.
void run_vibration(VibrationOptions o) {
  const auto colon = o.freq_range.find(':');
  if (colon == std::string::npos)
    throw InputError(fmt::format("--freq-range '{}' is not LO:HI (Hz)", o.freq_range));
  auto number = [&](const std::string& text) {
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(x))
      throw InputError(fmt::format("--freq-range '{}' is not LO:HI (Hz)", o.freq_range));
    return x;
  };
  const double lo = number(o.freq_range.substr(0, colon));
  const double hi = number(o.freq_range.substr(colon + 1));
  if (!(lo > 0 && hi > lo))
    throw InputError(fmt::format("--freq-range {}:{} needs 0 < LO < HI", lo, hi));
  if (o.points < 2) throw InputError(fmt::format("--points {} must be >= 2", o.points));
  if (!(o.damping >= 0 && o.damping < 1))
    throw InputError(fmt::format("--damping {} must be in [0, 1)", o.damping));
  if (!(o.limit_pct > 0)) throw InputError(fmt::format("--limit {} % must be > 0", o.limit_pct));
  const ProfileSpec spec = parse_profile_spec(o.profile);
  if (o.tau_s == 0) {
    const int fixed = spec.fixed_length(o.period_s);
    o.tau_s = fixed > 0 ? fixed * o.period_s : 0.164;
  }
  const Taps t = design_taps(o.profile, o.tau_s, o.period_s);
  const auto applied = as_double(t.integer);
  auto grid = [&](int j) { return lo + (hi - lo) * j / (o.points - 1); };
  if (o.freq_hz == 0) {
    const auto shapers = spec_shapers(spec);
    if (!spec.stages.empty())
      for (const ProfileSpec& s : spec.stages)
        if (!spec_shapers(s).empty()) {
          o.freq_hz = s.args.at(0);
          break;
        }
    if (o.freq_hz == 0 && spec.stages.empty() && !shapers.empty()) o.freq_hz = spec.args.at(0);
    if (o.freq_hz == 0) {
      double best = 2.0;
      for (int j = 0; j < o.points; ++j)
        if (const double v = residual_vibration(applied, o.period_s, grid(j), o.damping);
            v < best) {
          best = v;
          o.freq_hz = grid(j);
        }
    }
  }
  if (!(o.freq_hz > 0)) throw InputError(fmt::format("--freq {} Hz must be > 0", o.freq_hz));
  const VibrationFigures v = vibration_figures(o.profile, o.tau_s, o.period_s, o.freq_hz, o.damping,
                                               o.feed_mm_min, o.limit_pct / 100);
  const VibrationRobustness& r = v.robustness;
  fmt::print("# residual vibration: profile={} tau={:.6g} s T={} s taps={} b_s={}\n", t.profile,
             o.tau_s, o.period_s, t.integer.size(), t.b_s);
  fmt::print(
      "# V(f) = e^(-zeta w t_n) |sum h_i e^(zeta w t_i) e^(j w_d t_i)| / sum h_i, t_i = i T, "
      "w = 2 pi f, w_d = w sqrt(1 - zeta^2), zeta = {}\n",
      o.damping);
  fmt::print("# mode f = {:g} Hz: V(f) = {:.4f} %   V(0.8 f) = {:.4f} %   V(1.2 f) = {:.4f} %\n",
             o.freq_hz, 100 * r.v_at_f, 100 * r.v_minus_20, 100 * r.v_plus_20);
  if (std::isfinite(v.v_continuous))
    fmt::print("# the shapers as continuous impulses (no sampling): V(f) = {:.4f} %\n",
               100 * v.v_continuous);
  if (r.bands.empty()) fmt::print("# V <= {:g} % nowhere in [f/2, 2f]\n", o.limit_pct);
  for (const FrequencyBand& b : r.bands)
    fmt::print("# V <= {:g} % from {:.3f} to {:.3f} Hz ({:+.1f} % .. {:+.1f} % of f){}\n",
               o.limit_pct, b.lo_hz, b.hi_hz, 100 * (b.lo_hz / o.freq_hz - 1),
               100 * (b.hi_hz / o.freq_hz - 1),
               b.lo_hz <= o.freq_hz && o.freq_hz <= b.hi_hz ? "" : " (not holding f)");
  fmt::print(
      "# smoothing: sigma = {:.4f} ms, D(0) = {:.4f} ms, 90 deg corner error at F{:g} = "
      "{:.4f} mm\n",
      1e3 * v.sigma_s, 1e3 * v.corner_moment_s, o.feed_mm_min, v.corner_error_mm);
  fmt::print("f_hz,vibration_pct{}\n",
             std::isfinite(v.v_continuous) ? ",shapers_continuous_pct" : "");
  const auto shapers = spec_shapers(spec);
  for (int j = 0; j < o.points; ++j) {
    const double f = grid(j);
    fmt::print("{:.6g},{:.6f}", f, 100 * residual_vibration(applied, o.period_s, f, o.damping));
    if (std::isfinite(v.v_continuous)) {
      double c = 1.0;
      for (const ShaperImpulses& s : shapers) c *= residual_vibration(s, f, o.damping);
      fmt::print(",{:.6f}", 100 * c);
    }
    fmt::print("\n");
  }
}

}  // namespace

void add_analyze(CLI::App& app, Context& ctx) {
  auto* sub =
      app.add_subcommand("analyze",
                         "Analyse Acc/Dec taps: radius error, amplitude response, corner error, "
                         "residual vibration");
  sub->require_subcommand(1);

  auto r = std::make_shared<RadiusOptions>();
  auto* rs = sub->add_subcommand(
      "radius-error",
      "Radius loss of circular motion through the filter (paper Table 1, Fig. 13); "
      "defaults reproduce Table 1 with T = 1 ms (41 taps)");
  rs->add_option("--profile", r->profile, "profile spec (see gmotion design --help)")
      ->capture_default_str();
  rs->add_option("--tau", r->tau_s, "Acc/Dec time constant, s")->capture_default_str();
  rs->add_option("--period", r->period_s, "sampling period T, s (tau/T must be an integer)")
      ->capture_default_str();
  rs->add_option("--radius", r->radius_mm, "circle radius R, mm")->capture_default_str();
  rs->add_option("--feeds", r->feeds_mm_min, "tangential feeds, mm/min, comma separated")
      ->delimiter(',')
      ->capture_default_str();
  rs->add_flag("--json", r->json, "print {\"rows\":[...]} JSON");
  rs->callback([r, &ctx] {
    run_radius(*r);
    ctx.exit_code = 0;
  });

  auto q = std::make_shared<ResponseOptions>();
  auto* rp = sub->add_subcommand("response",
                                 "Taps and amplitude response |D(e^jwT)| on a grid "
                                 "from 0 to Nyquist (CSV, or JSON), for plotting");
  rp->add_option("--profile", q->profile, "profile spec (see gmotion design --help)")
      ->capture_default_str();
  rp->add_option("--tau", q->tau_s, "Acc/Dec time constant, s")->capture_default_str();
  rp->add_option("--period", q->period_s, "sampling period T, s")->capture_default_str();
  rp->add_option("--points", q->points, "number of grid frequencies")->capture_default_str();
  rp->add_flag("--json", q->json, "print one JSON object instead of CSV");
  rp->callback([q, &ctx] {
    run_response(*q);
    ctx.exit_code = 0;
  });

  auto c = std::make_shared<CornerOptions>();
  auto* rc = sub->add_subcommand(
      "corner",
      "Corner error of the filter output against angle and feed; largest feed for a tolerance, "
      "slowed and paused (G64 P tolerance)");
  rc->add_option("--profile", c->profile, "profile spec (see gmotion design --help)")
      ->capture_default_str();
  rc->add_option("--tau", c->tau_s, "Acc/Dec time constant, s")->capture_default_str();
  rc->add_option("--period", c->period_s, "sampling period T, s")->capture_default_str();
  rc->add_option("--angles", c->angles_deg, "turn angles, degrees, comma separated")
      ->delimiter(',')
      ->capture_default_str();
  rc->add_option("--feeds", c->feeds_mm_min, "feeds, mm/min, comma separated")
      ->delimiter(',')
      ->capture_default_str();
  rc->add_option("--tolerance", c->tolerance_mm, "contour tolerance, mm")->capture_default_str();
  rc->callback([c, &ctx] {
    run_corner(*c);
    ctx.exit_code = 0;
  });
  auto vo = std::make_shared<VibrationOptions>();
  auto* rv = sub->add_subcommand(
      "vibration",
      "Residual vibration V(f) of the taps for a mode of damping zeta over a frequency range "
      "(CSV, the input-shaper graph), with V at f and f +- 20 %, the band where V <= 5 % and "
      "the smoothing (docs/vibration.md)");
  rv->add_option("--profile", vo->profile, "profile spec (see gmotion design --help)")
      ->capture_default_str();
  rv->add_option("--tau", vo->tau_s,
                 "Acc/Dec time constant, s (default: taps x T for fixed-length profiles, else "
                 "0.164)");
  rv->add_option("--period", vo->period_s, "sampling period T, s")->capture_default_str();
  rv->add_option("--freq-range", vo->freq_range, "LO:HI, Hz")->capture_default_str();
  rv->add_option("--points", vo->points, "number of grid frequencies")->capture_default_str();
  rv->add_option("--damping", vo->damping, "damping ratio zeta of the mode")->capture_default_str();
  rv->add_option("--freq", vo->freq_hz,
                 "mode frequency f, Hz (default: the first shaper's, else where V is least)");
  rv->add_option("--feed", vo->feed_mm_min, "feed for the corner error, mm/min")
      ->capture_default_str();
  rv->add_option("--limit", vo->limit_pct, "vibration limit of the band, %")->capture_default_str();
  rv->callback([vo, &ctx] {
    run_vibration(*vo);
    ctx.exit_code = 0;
  });
}

}  // namespace gm::cli
