// gmotion compare: one program through several Acc/Dec profiles, measured against the analysis
// (the paper's circle test: Fig. 13, Eq. 34/35), and at the tool tip on a machine with modes.
#include "accdec/analysis.hpp"
#include "accdec/profiles.hpp"
#include "cli/commands.hpp"
#include "cli/settings_flags.hpp"
#include "common/status.hpp"
#include "common/units.hpp"
#include "measure/run_summary.hpp"
#include "pipeline/run.hpp"
#include "setup/program_input.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

namespace gm::cli {
namespace {

using setup::ProgramInput;

struct CompareFlags {
  std::string program;
  setup::RunSettings settings;  ///< the machine choice and the language
  std::vector<std::string> profiles = paper_profiles();
  std::vector<double> taus;  ///< one τ per profile; empty: the machine's for each
  bool json = false;
};

// The first arc of the program: its radius and programmed tangent speed, for the analysis column.
std::optional<Motion> first_arc(ProgramInput& program, const InterpreterOptions& opts) {
  ProgramStream stream(program.rewind(), program.name(), opts);
  Canon c;
  while (stream.next(c))
    if (const auto* m = std::get_if<Motion>(&c); m != nullptr && m->kind == MotionKind::Arc)
      return *m;
  return std::nullopt;
}

// Runs the program once through the pipeline and returns its summary.
RunSummary run_once(const RunConfig& cfg, ProgramInput& program, const InterpreterOptions& opts,
                    std::size_t* taps, std::vector<double>* real_taps) {
  RunOptions o;
  o.config = cfg;
  o.program_name = program.name();
  o.consumer_thread = false;
  Run run(std::move(o), program.rewind(), opts);
  while (run.advance() == RunStatus::Working) {
  }
  if (taps) *taps = run.pipeline().taps().integer.size();
  if (real_taps) *real_taps = run.pipeline().taps().real;
  return run.summary();
}

struct Row {
  std::string profile;
  std::size_t taps = 0;
  double analysis_blu = 0, accdec_blu = 0, total_blu = 0, additive_blu = 0, predicted_total_blu = 0;
  double tau_s = 0, cycle_s = 0, contour_max_blu = 0;
  bool settled = false;
  /// On a machine with modes (servo on): the worst stop's residual vibration and settling at
  /// the tool tip over the axes (RunSummary::vibration()).
  bool modes = false;
  double residual_blu = 0, settle_blu = 0;
};

// The first arc's radius and tangent speed in BLU, and Eq. 35's servo radius loss for them.
struct ArcFigures {
  std::optional<Motion> arc;
  double r_blu = 0, v_blu_s = 0, servo_eq35 = 0, kp = 0;
};

ArcFigures arc_figures(ProgramInput& program, const InterpreterOptions& opts, const Machine& m) {
  ArcFigures a;
  a.arc = first_arc(program, opts);
  const double blu = m.contour_blu_mm();
  if (a.arc) {
    a.r_blu = (a.arc->start_mm - a.arc->center_mm).norm() / blu;  // planar arcs: in-plane radius
    a.v_blu_s = units::mm_min_to_mm_s(a.arc->feed_mm_min) / blu;
  }
  a.kp = m.axes[0].kp_1_s;
  a.servo_eq35 = a.arc ? a.v_blu_s * a.v_blu_s / (2.0 * a.r_blu * a.kp * a.kp) : 0.0;
  return a;
}

// One profile's row: the run without servo (Acc/Dec alone), then with it unless --no-servo.
Row profile_row(const std::string& profile, double tau_s, const Machine& base, bool servo,
                ProgramInput& program, const InterpreterOptions& opts, const ArcFigures& a,
                double servo_alone_blu) {
  Row row;
  row.profile = profile;
  row.tau_s = tau_s;
  RunConfig cfg;
  cfg.machine = base;
  cfg.machine.profile = profile;
  cfg.machine.tau_s = tau_s;
  cfg.servo = false;
  std::vector<double> real_taps;
  const RunSummary ideal = run_once(cfg, program, opts, &row.taps, &real_taps);
  if (a.arc) row.analysis_blu = radius_loss_sampled(real_taps, a.r_blu, a.v_blu_s, base.period_s);
  row.accdec_blu = -ideal.arc_ref_radial_dev_blu;
  const RunSummary* shown = &ideal;
  std::optional<RunSummary> with_servo;
  if (servo) {
    cfg.servo = true;
    with_servo.emplace(run_once(cfg, program, opts, nullptr, nullptr));
    row.total_blu = -with_servo->arc_enc_radial_dev_blu;
    shown = &*with_servo;
  }
  row.cycle_s = shown->cycle_time_s;
  row.contour_max_blu = shown->contour_err_blu.value;
  row.settled = shown->settled;
  if (const VibrationMeter* v = shown->vibration()) {
    row.modes = true;
    for (int x = 0; x < v->axes(); ++x) {
      row.residual_blu = std::max(row.residual_blu, v->axis(x).residual_blu);
      row.settle_blu = std::max(row.settle_blu, v->axis(x).settle_blu);
    }
  }
  row.additive_blu = row.accdec_blu + servo_alone_blu;
  row.predicted_total_blu = row.analysis_blu + a.servo_eq35;
  return row;
}

// A table cell: the value at `precision` right-aligned in `width`, or "-" where there is none
// (a radius column on a program without arcs).
std::string cell(double v, int width, int precision) {
  return std::isfinite(v) ? fmt::format("{:>{}.{}f}", v, width, precision)
                          : fmt::format("{:>{}}", "-", width);
}

// A JSON number as the table's JSON prints it (6 significant digits), null where there is none.
std::string json6(double v) {
  return std::isfinite(v) ? fmt::format("{:.6g}", v) : "null";
}

void print_json(const std::vector<Row>& rows, const ArcFigures& a, double servo_alone_blu) {
  std::string j = "{\"rows\":[";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    j += fmt::format(
        "{}{{\"profile\":\"{}\",\"taps\":{},\"analysis_blu\":{},\"accdec_blu\":{},"
        "\"total_blu\":{},"
        "\"additive_blu\":{},\"predicted_total_blu\":{},\"cycle_time_s\":{:.6g},"
        "\"contour_err_max_blu\":{:.6g},\"settled\":{}{}}}",
        i ? "," : "", r.profile, r.taps, json6(r.analysis_blu), json6(r.accdec_blu),
        json6(r.total_blu), json6(r.additive_blu), json6(r.predicted_total_blu), r.cycle_s,
        r.contour_max_blu, r.settled ? "true" : "false",
        r.modes ? fmt::format(",\"tau_s\":{:.6g},\"residual_vibration_max_blu\":{:.6g},"
                              "\"settle_max_blu\":{:.6g}",
                              r.tau_s, r.residual_blu, r.settle_blu)
                : "");
  }
  j += fmt::format(
      "],\"radius_blu\":{},\"v_tan_blu_s\":{},\"servo_alone_blu\":{},\"servo_eq35_blu\":{}}}\n",
      json6(a.r_blu), json6(a.v_blu_s), json6(servo_alone_blu), json6(a.servo_eq35));
  fmt::print("{}", j);
}

void print_table(const std::vector<Row>& rows, const std::string& name, const Machine& base,
                 bool servo, const ArcFigures& a, double servo_alone_blu) {
  fmt::print("{} on {}: T = {} s, tau = {} s", name, base.name, base.period_s, base.tau_s);
  if (a.arc)
    fmt::print(", circle R = {:.0f} BLU at V_tan = {:.0f} BLU/s (line {})\n", a.r_blu, a.v_blu_s,
               a.arc->line);
  else
    fmt::print(", no arcs (radius columns are empty)\n");
  fmt::print("Steady-state radius loss on arcs, BLU (positive = radius decreased):\n");
  fmt::print("  {:<10} {:>5} {:>12} {:>12}", "profile", "taps", "analysis", "Acc/Dec");
  if (servo) fmt::print(" {:>11} {:>14} {:>14}", "with servo", "Acc/Dec+servo", "analysis+Eq35");
  fmt::print(" {:>10} {:>14}", "cycle s", "max contour");
  // A machine with modes: the tool tip's columns (the contour is the tip's then).
  const bool modes = !rows.empty() && rows.front().modes;
  std::size_t width = 10;
  for (const Row& r : rows) width = std::max(width, r.profile.size());
  if (modes) fmt::print(" {:>8} {:>12} {:>12}", "tau s", "residual vib", "settling");
  fmt::print("\n");
  for (const Row& r : rows) {
    fmt::print("  {:<{}} {:>5} {} {}", r.profile, modes ? width : 10, r.taps,
               cell(r.analysis_blu, 12, 2), cell(r.accdec_blu, 12, 2));
    if (servo)
      fmt::print(" {} {} {}", cell(r.total_blu, 11, 2), cell(r.additive_blu, 14, 2),
                 cell(r.predicted_total_blu, 14, 2));
    fmt::print(" {:>10.3f} {:>14.2f}", r.cycle_s, r.contour_max_blu);
    if (modes) fmt::print(" {:>8.4f} {:>12.2f} {:>12.2f}", r.tau_s, r.residual_blu, r.settle_blu);
    fmt::print("{}\n", r.settled ? "" : "  (not settled)");
  }
  fmt::print(
      "analysis = R(1-|D(e^jwT)|), w = V/R (Eq. 13/14); Acc/Dec = measured on the filter output "
      "(servo off);\n"
      "with servo = measured on the encoder; Acc/Dec+servo = Eq. 34 with the servo's own loss "
      "measured\n"
      "(Acc/Dec off): {} BLU; analysis+Eq35 = Eq. 34 with Eq. 35's V^2/(2 R Kp^2) = {} BLU "
      "(Kp = {} 1/s).\n",
      cell(servo_alone_blu, 1, 2), cell(a.servo_eq35, 1, 2), a.kp);
  if (modes)
    fmt::print(
        "The machine has structural modes: max contour is measured at the tool tip; residual vib "
        "= the worst\nstop's max |tip - motor side| (the modes' deflection) and settling its max "
        "|tip - ref|, over {:.3f} s after\nthe Acc/Dec output rests, worst axis (docs/"
        "vibration.md).\n",
        VibrationMeter::kDefaultWindowS);
}

int compare(const CompareFlags& f) {
  const Machine base = setup::resolve_machine(f.settings);
  ProgramInput program(f.program);
  const InterpreterOptions opts = setup::interpreter_options(f.settings, base);
  if (!setup::validate_program(program, opts)) return static_cast<int>(ExitCode::InputError);
  const ArcFigures a = arc_figures(program, opts, base);
  const bool servo = !f.settings.no_servo;

  // The servo's own radius loss: the same program with the Acc/Dec off (one tap, tau = T).
  double servo_alone_blu = 0.0;
  if (servo && a.arc) {
    RunConfig cfg;
    cfg.machine = base;
    cfg.machine.profile = "custom:1";
    cfg.machine.tau_s = base.period_s;
    servo_alone_blu = -run_once(cfg, program, opts, nullptr, nullptr).arc_enc_radial_dev_blu;
  }
  if (!f.taus.empty() && f.taus.size() != f.profiles.size())
    throw InputError(fmt::format("--taus: one tau per profile ({} profiles, {} taus)",
                                 f.profiles.size(), f.taus.size()));
  std::vector<Row> rows;
  for (std::size_t i = 0; i < f.profiles.size(); ++i)
    rows.push_back(profile_row(f.profiles[i], f.taus.empty() ? base.tau_s : f.taus[i], base, servo,
                               program, opts, a, servo_alone_blu));
  if (f.json)
    print_json(rows, a, servo_alone_blu);
  else
    print_table(rows, program.name(), base, servo, a, servo_alone_blu);
  return 0;
}

}  // namespace

void add_compare(CLI::App& app, Context& ctx) {
  auto flags = std::make_shared<CompareFlags>();
  auto* sub = app.add_subcommand(
      "compare", "Run a program through several Acc/Dec profiles and tabulate radius loss");
  sub->add_option("program", flags->program, "G-code program, or - for stdin")->required();
  add_setting_flags(sub, flags->settings, setup::kMachineGroup | setup::kLanguageGroup);
  sub->add_option("--profiles", flags->profiles,
                  "Comma-separated profiles; default: the paper's (" +
                      fmt::format("{}", fmt::join(paper_profiles(), ",")) + ")")
      ->delimiter(',');
  sub->add_option("--taus", flags->taus,
                  "Comma-separated tau, s, one per profile (default: the machine's for each)")
      ->delimiter(',');
  sub->add_flag("--json", flags->json, "Print the table as JSON");
  sub->callback([flags, &ctx] { ctx.exit_code = compare(*flags); });
}

}  // namespace gm::cli
