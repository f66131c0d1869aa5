// gmotion analyze — radius error (Table 1, Fig. 13) and amplitude response (Fig. 8c, 12c) of taps.
#include "accdec/analysis.hpp"
#include "accdec/profile_spec.hpp"
#include "accdec/taps.hpp"
#include "cli/commands.hpp"
#include "cli/json_number.hpp"
#include "common/status.hpp"
#include "common/units.hpp"
#include "planner/filter_moments.hpp"

#include <fmt/format.h>

#include <cmath>
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

}  // namespace

void add_analyze(CLI::App& app, Context& ctx) {
  auto* sub =
      app.add_subcommand("analyze", "Analyse Acc/Dec taps: radius error, amplitude response");
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
}

}  // namespace gm::cli
