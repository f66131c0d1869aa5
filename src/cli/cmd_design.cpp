// gmotion design — the paper's Fig. 9 Acc/Dec design procedure (Steps 1-4) on the command line.
#include "accdec/analysis.hpp"
#include "accdec/design_procedure.hpp"
#include "accdec/profile_spec.hpp"
#include "accdec/profiles.hpp"
#include "accdec/taps.hpp"
#include "cli/commands.hpp"
#include "cli/json_number.hpp"
#include "cli/vibration_figures.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace gm::cli {

namespace {

struct DesignOptions {
  double period_s = 0.004;
  double tau_s = 0.164;
  std::string profile = "blackman";
  DesignLimits limits;
  int max_attempts = 2000;
  bool json = false;
  bool list_profiles = false;
  std::string mode;  ///< "F[@Z]": design against a mode instead of the Fig. 9 procedure
  double feed_mm_min = 6000;
};

// A JSON number (shortest round-trip form), or null when not finite.
template <typename T>
std::string jarray(const std::vector<T>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) s += ",";
    if constexpr (std::is_floating_point_v<T>)
      s += json_number(v[i]);
    else
      s += fmt::format("{}", v[i]);
  }
  return s + "]";
}

std::string jstr(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

const char* pass(bool ok) {
  return ok ? "ok" : "FAIL";
}

void print_json(const DesignOptions& o, const std::vector<DesignAttempt>& attempts) {
  const DesignAttempt& a = attempts.back();
  const Taps& t = a.taps;
  std::string s = "{";
  s += fmt::format("\"profile\":{},\"period\":{},\"tau_initial\":{},\"tau\":{},", jstr(t.profile),
                   json_number(o.period_s), json_number(o.tau_s), json_number(a.tau_s));
  s += fmt::format("\"N\":{},\"cutoff\":{},\"max_nonneg_cutoff\":{},", t.N, json_number(t.cutoff),
                   json_number(t.max_nonneg_cutoff));
  s += fmt::format("\"taps\":{},\"taps_int\":{},\"b_s\":{},\"integer_exact\":{},", jarray(t.real),
                   jarray(t.integer), t.b_s, t.integer_exact ? "true" : "false");
  s += fmt::format("\"quantisation_error\":{},", json_number(quantisation_error(t)));
  s += fmt::format(
      "\"v_step\":{},\"peak_velocity\":{},\"peak_accel\":{},\"peak_force\":{},"
      "\"peak_power\":{},\"profile_force\":{},\"profile_power\":{},",
      json_number(o.limits.v_step_m_s), json_number(a.peak_velocity_m_s),
      json_number(a.peak_accel_m_s2), json_number(a.peak_force_N), json_number(a.peak_power_W),
      json_number(a.profile_force_N), json_number(a.profile_power_W));
  s += fmt::format("\"limits\":{{\"vmax\":{},\"mass\":{},\"damping\":{},\"fmax\":{},\"pmax\":{}}},",
                   json_number(o.limits.v_max_m_s), json_number(o.limits.mass_kg),
                   json_number(o.limits.damping_kg_s), json_number(o.limits.f_max_N),
                   json_number(o.limits.p_max_W));
  s += fmt::format("\"v_ok\":{},\"f_ok\":{},\"p_ok\":{},\"ok\":{},\"attempts\":[",
                   a.v_ok ? "true" : "false", a.f_ok ? "true" : "false", a.p_ok ? "true" : "false",
                   a.ok() ? "true" : "false");
  for (std::size_t i = 0; i < attempts.size(); ++i) {
    const DesignAttempt& x = attempts[i];
    s += fmt::format(
        "{}{{\"tau\":{},\"N\":{},\"cutoff\":{},\"b_s\":{},\"peak_accel\":{},"
        "\"peak_force\":{},\"peak_power\":{},\"ok\":{}}}",
        i ? "," : "", json_number(x.tau_s), x.taps.N, json_number(x.taps.cutoff), x.taps.b_s,
        json_number(x.peak_accel_m_s2), json_number(x.peak_force_N), json_number(x.peak_power_W),
        x.ok() ? "true" : "false");
  }
  s += "]}";
  fmt::print("{}\n", s);
}

void print_human(const DesignOptions& o, const std::vector<DesignAttempt>& attempts) {
  const DesignLimits& L = o.limits;
  fmt::print("Acc/Dec design (Chen & Lee 1998, Fig. 9): profile {}, T = {} s, initial tau = {} s\n",
             attempts.front().taps.profile, o.period_s, o.tau_s);
  fmt::print(
      "velocity step V = {} m/s, m = {} kg, c = {} kg/s; limits V_max {} m/s, "
      "F_max {} N, P_max {} W\n\n",
      L.v_step_m_s, L.mass_kg, L.damping_kg_s, L.v_max_m_s, L.f_max_N, L.p_max_W);
  fmt::print("{:>7}  {:>9}  {:>5}  {:>9}  {:>12}  {:>11}  {:>10}  {:>9}  {}\n", "attempt",
             "tau [s]", "N", "cutoff", "b_s", "a [m/s^2]", "F [N]", "P [W]", "Step 4");
  for (std::size_t i = 0; i < attempts.size(); ++i) {
    const DesignAttempt& a = attempts[i];
    std::string verdict = a.ok() ? "ok" : "fails:";
    if (!a.v_ok) verdict += " V";
    if (!a.f_ok) verdict += " F";
    if (!a.p_ok) verdict += " P";
    if (!a.ok() && i + 1 < attempts.size()) verdict += " -> tau += T";
    const std::string cutoff =
        std::isfinite(a.taps.cutoff) ? fmt::format("{:.6g}", a.taps.cutoff) : "-";
    fmt::print("{:>7}  {:>9.6g}  {:>5}  {:>9}  {:>12}  {:>11.6g}  {:>10.6g}  {:>9.6g}  {}\n", i + 1,
               a.tau_s, a.taps.N, cutoff, a.taps.b_s, a.peak_accel_m_s2, a.peak_force_N,
               a.peak_power_W, verdict);
  }
  const DesignAttempt& a = attempts.back();
  const Taps& t = a.taps;
  fmt::print("\nStep 1 (Eq. 24): N = tau/T - 1 = {:.6g}/{} - 1 = {}\n", a.tau_s, o.period_s, t.N);
  if (std::isfinite(t.cutoff))
    fmt::print(
        "Step 2 (Eq. 25): cutoff = {:.6g} of Nyquist (2/(N+1) = {:.6g}); largest cutoff "
        "keeping all taps >= 0: {:.6g}\n",
        t.cutoff, 2.0 / (t.N + 1), t.max_nonneg_cutoff);
  else
    fmt::print("Step 2: no cutoff (not a window design)\n");
  fmt::print(
      "Step 3 (Eq. 5): b_s = {} = sum of integer taps ({}); frequency-response "
      "quantisation error max |dA| = {:.3g}\n",
      t.b_s,
      t.integer_exact ? "exactly proportional to the design"
                      : "real taps scaled so the largest is 65536, rounded",
      quantisation_error(t));
  fmt::print("\n{:>5}  {:>24}  {:>10}\n", "i", "b_i real (DC gain 1)", "b_i int");
  for (std::size_t i = 0; i < t.real.size(); ++i)
    fmt::print("{:>5}  {:>24.17g}  {:>10}\n", i, t.real[i], t.integer[i]);
  fmt::print("\nStep 4 (Eq. 7, 26, 29) with V = {} m/s:\n", L.v_step_m_s);
  fmt::print("  V'max = {:.6g} m/s  <= V_max {} m/s : {}\n", a.peak_velocity_m_s, L.v_max_m_s,
             pass(a.v_ok));
  fmt::print("  a     = V*max(b_i)/(T*b_s) = {:.6g} m/s^2\n", a.peak_accel_m_s2);
  fmt::print("  F     = m*a + c*V = {:.6g} N  <= F_max {} N : {}\n", a.peak_force_N, L.f_max_N,
             pass(a.f_ok));
  fmt::print("  P     = F*V = {:.6g} W  <= P_max {} W : {}\n", a.peak_power_W, L.p_max_W,
             pass(a.p_ok));
  fmt::print("  (along the actual step response: max F = {:.6g} N, max P = {:.6g} W)\n",
             a.profile_force_N, a.profile_power_W);
  fmt::print("\nresult: {} (tau = {:.6g} s)\n", a.ok() ? "design complete" : "limits NOT met",
             a.tau_s);
}

// --- design against a mode (f, ζ): a notch of the profile on f, or a shaper added ------------

struct ModeRow {
  std::string label;
  std::string spec;
  double tau_s;
};

// The tap count near n0 whose taps put a notch nearest f: the local minimum of V(f) over
// n0 ± one notch spacing (1/f) closest to n0 (the shorter on a tie); n0 itself when its V(f) is
// below 0.1 % already.
int notch_taps(const std::string& profile, int n0, double period_s, double f, double z) {
  const int m = static_cast<int>(std::ceil(1.0 / (f * period_s))) + 1;
  const int lo = std::max(1, n0 - m), hi = std::min(kMaxAccDecTaps, n0 + m);
  std::vector<double> v(static_cast<std::size_t>(hi - lo + 1), 2.0);
  for (int n = lo; n <= hi; ++n) try {
      const Taps t = design_taps(profile, n * period_s, period_s);
      v[static_cast<std::size_t>(n - lo)] =
          residual_vibration(as_double(t.integer), period_s, f, z);
    } catch (const InputError&) {
      // too short for this profile (e.g. an S-curve below 2 taps): not a candidate
    }
  // Below 0.1 % already (a mode in the profile's stop band): nothing to move.
  if (v[static_cast<std::size_t>(n0 - lo)] < 1e-3) return n0;
  int best = n0;
  double best_v = 2.0;
  for (int n = lo; n <= hi; ++n) {
    const auto i = static_cast<std::size_t>(n - lo);
    const bool local = (i == 0 || v[i] <= v[i - 1]) && (i + 1 == v.size() || v[i] <= v[i + 1]);
    if (!local || v[i] >= 1.0) continue;
    if (best_v > 1.0 || std::abs(n - n0) < std::abs(best - n0)) {
      best = n;
      best_v = v[i];
    }
  }
  return best;
}

void run_design_mode(const DesignOptions& o, bool tau_given) {
  const auto at = o.mode.find('@');
  const double f = parse_profile_number("--mode", o.mode.substr(0, at), "mode frequency");
  const double z = at == std::string::npos
                       ? 0.1
                       : parse_profile_number("--mode", o.mode.substr(at + 1), "damping ratio");
  if (!(f > 0 && 2 * f * o.period_s < 1))
    throw InputError(fmt::format("--mode {}: the frequency must be in (0, 1/(2T)) = (0, {:.6g}) Hz",
                                 o.mode, 0.5 / o.period_s));
  if (!(z >= 0 && z < 1))
    throw InputError(fmt::format("--mode {}: the damping ratio must be in [0, 1)", o.mode));
  const ProfileSpec spec = parse_profile_spec(o.profile);
  const int fixed = spec.fixed_length(o.period_s);
  const double tau0 = !tau_given && fixed > 0 ? fixed * o.period_s : o.tau_s;
  const int n0 = tap_count(tau0, o.period_s);
  const std::string mode = fmt::format("{:g}@{:g}", f, z);

  std::vector<ModeRow> rows{{"as designed", o.profile, tau0}};
  if (fixed == 0 && spec.stages.empty()) {
    const int n = notch_taps(o.profile, n0, o.period_s, f, z);
    rows.push_back(
        {n == n0 ? "notch on f (tau kept)" : "notch on f (tau moved)", o.profile, n * o.period_s});
  }
  for (const char* shaper : {"zv", "mzv", "zvd", "ei", "2hei"}) {
    const std::string part = fmt::format("{}:{}", shaper, mode);
    const int len = parse_profile_spec(part).fixed_length(o.period_s);
    rows.push_back(
        {fmt::format("+ {} shaper", shaper), o.profile + "+" + part, (n0 + len - 1) * o.period_s});
  }
  fmt::print(
      "Acc/Dec against a mode f = {:g} Hz, zeta = {:g}: profile {}, T = {} s, tau = {:.6g} s\n"
      "V = residual vibration of the applied taps (docs/vibration.md); band = where V <= 5 % "
      "around f, searched within [f/2, 2f]; sigma, corner = smoothing (90 deg corner at F{:g}, no "
      "pause); "
      "cost = tau added to every stop\n\n",
      f, z, o.profile, o.period_s, tau0, o.feed_mm_min);
  fmt::print("{:<24}  {:<28}  {:>8}  {:>9}  {:>8}  {:>9}  {:>9}  {:>17}  {:>8}  {:>9}\n", "design",
             "profile", "tau s", "cost ms", "V(f) %", "V(.8f) %", "V(1.2f) %", "band Hz",
             "sigma ms", "corner mm");
  for (const ModeRow& r : rows) {
    const VibrationFigures v =
        vibration_figures(r.spec, r.tau_s, o.period_s, f, z, o.feed_mm_min, 0.05);
    const FrequencyBand b = v.robustness.band_at_f(f);
    const std::string band =
        b.hi_hz > b.lo_hz ? fmt::format("{:.2f}-{:.2f}", b.lo_hz, b.hi_hz) : std::string("-");
    fmt::print(
        "{:<24}  {:<28}  {:>8.4f}  {:>+9.1f}  {:>8.3f}  {:>9.3f}  {:>9.3f}  {:>17}  {:>8.3f}  "
        "{:>9.4f}\n",
        r.label, r.spec, r.tau_s, 1e3 * (r.tau_s - tau0), 100 * v.robustness.v_at_f,
        100 * v.robustness.v_minus_20, 100 * v.robustness.v_plus_20, band, 1e3 * v.sigma_s,
        v.corner_error_mm);
  }
}

}  // namespace

void add_design(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<DesignOptions>();
  auto* sub = app.add_subcommand(
      "design",
      "Design an FIR Acc/Dec filter by the paper's Fig. 9 procedure (Steps 1-4); "
      "defaults are the paper's section 6 example");
  sub->add_option("--period", o->period_s, "sampling period T, s")->capture_default_str();
  auto* tau = sub->add_option("--tau", o->tau_s,
                              "initial Acc/Dec time constant tau = (N+1)T, s "
                              "(custom/cascade: defaults to taps x T)")
                  ->capture_default_str();
  sub->add_option("--profile", o->profile, profile_forms(" | ") + "  (C = cutoff or max)")
      ->capture_default_str();
  sub->add_option("--vmax", o->limits.v_max_m_s, "velocity limit V_max, m/s")
      ->capture_default_str();
  sub->add_option("--mass", o->limits.mass_kg, "equivalent mass m, kg")->capture_default_str();
  sub->add_option("--damping", o->limits.damping_kg_s, "equivalent viscous damping c, kg/s")
      ->capture_default_str();
  sub->add_option("--fmax", o->limits.f_max_N, "force limit F_max, N")->capture_default_str();
  sub->add_option("--pmax", o->limits.p_max_W, "power limit P_max, W")->capture_default_str();
  sub->add_option("--v-override", o->limits.v_step_m_s,
                  "largest overridden velocity step V fed to the filter, m/s")
      ->capture_default_str();
  sub->add_option("--max-attempts", o->max_attempts, "give up after this many tau values")
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object instead of the table");
  sub->add_option("--mode", o->mode,
                  "F[@Z]: a mode at F Hz, damping ratio Z (default 0.1); print the profile's "
                  "residual vibration, smoothing and cost with a notch moved onto F and with "
                  "shapers added, instead of the Fig. 9 procedure");
  sub->add_option("--feed", o->feed_mm_min, "feed of --mode's corner error, mm/min")
      ->capture_default_str();
  sub->add_flag("--list-profiles", o->list_profiles,
                "print the profile registry (form, paper's set or not, taps) and exit");
  sub->callback([o, tau, &ctx] {
    if (o->list_profiles) {
      for (const ProfileRow& r : profile_rows())
        fmt::print("{}\t{}\t{}\t{}\n", r.name, r.form, r.paper ? "paper" : "-", r.help);
      ctx.exit_code = 0;
      return;
    }
    if (!o->mode.empty()) {
      run_design_mode(*o, tau->count() > 0);
      ctx.exit_code = 0;
      return;
    }
    if (tau->count() == 0) {
      // Fixed-length profiles define tau themselves.
      if (const int fixed = parse_profile_spec(o->profile).fixed_length(o->period_s); fixed > 0)
        o->tau_s = fixed * o->period_s;
    }
    const auto attempts =
        design_procedure(o->profile, o->tau_s, o->period_s, o->limits, o->max_attempts);
    if (o->json)
      print_json(*o, attempts);
    else
      print_human(*o, attempts);
    if (!attempts.back().ok()) {
      std::fflush(stdout);
      fmt::print(stderr, "gmotion: error: the limits are not met by profile '{}' at tau = {} s{}\n",
                 o->profile, attempts.back().tau_s,
                 parse_profile_spec(o->profile).fixed_length(o->period_s) > 0
                     ? " (its length is fixed, tau cannot grow)"
                 : !attempts.back().v_ok ? " (V'max = V exceeds V_max whatever tau)"
                                         : " (attempts exhausted)");
      ctx.exit_code = 1;
      return;
    }
    ctx.exit_code = 0;
  });
}

}  // namespace gm::cli
