// gmotion._core: the run and check entry points for Python; python/gmotion/__init__.py wraps them.
#include "accdec/analysis.hpp"
#include "accdec/design_procedure.hpp"
#include "accdec/profile_spec.hpp"
#include "common/diagnostic.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "override/override_schedule.hpp"
#include "pipeline/run.hpp"
#include "setup/program_input.hpp"
#include "setup/run_settings.hpp"
#include "trace/block_row.hpp"
#include "trace/trace_row.hpp"
#include "trace/trace_writer.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <numbers>

#include <algorithm>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

/// The keyword options of `what` (run, check, moves): the run settings of `groups`, named as in
/// setup::setting_rows() (the flag without dashes, '-' as '_'), plus `servo` (the opposite of
/// no_servo) and `schedule` (override_file), the names of the first bindings. `machine` (and for
/// moves `axes`) is an argument of its own.
std::vector<std::string> option_names(unsigned groups, const std::string& what) {
  std::vector<std::string> names;
  for (const gm::setup::SettingRow& row : gm::setup::setting_rows())
    if ((row.groups & groups) != 0 && row.flag != "--machine" &&
        (row.flag != "--axes" || what != "moves"))
      names.push_back(row.keyword());
  if ((groups & gm::setup::kMachineGroup) != 0) names.emplace_back("servo");
  if ((groups & gm::setup::kRunGroup) != 0) names.emplace_back("schedule");
  return names;
}

/// The run settings from keyword options (None: the default); a TypeError names an unknown one.
gm::setup::RunSettings settings_from(const py::dict& kw, unsigned groups, const char* what) {
  const std::vector<std::string> names = option_names(groups, what);
  gm::setup::RunSettings s;
  for (const auto& [k, value] : kw) {
    std::string key = k.cast<std::string>();
    if (std::find(names.begin(), names.end(), key) == names.end()) {
      std::string known;
      for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
      throw py::type_error(
          fmt::format("{}() got an unknown option '{}' (the options: {})", what, key, known));
    }
    if (value.is_none()) continue;
    if (key == "servo") {
      s.no_servo = !value.cast<bool>();
      continue;
    }
    if (key == "schedule") key = "override_file";
    for (const gm::setup::SettingRow& row : gm::setup::setting_rows())
      if (row.keyword() == key)
        gm::setup::set_from_text(s, row,
                                 row.is_switch() ? (value.cast<bool>() ? "true" : "false")
                                                 : py::str(value).cast<std::string>());
  }
  return s;
}

py::dict diagnostic_dict(const std::string& file, const gm::Diagnostic& d) {
  py::dict out;
  out["file"] = file;
  out["line"] = d.loc.line;
  out["column"] = d.loc.column;
  out["code"] = d.code;
  out["severity"] = d.severity == gm::Severity::Error     ? "error"
                    : d.severity == gm::Severity::Warning ? "warning"
                                                          : "note";
  out["message"] = d.message;
  out["text"] = gm::format_diagnostic(file, d);
  return out;
}

/// Checks the program; the diagnostics as dicts and the check summary.
py::dict check(const std::string& path, const gm::InterpreterOptions& opts) {
  gm::setup::ProgramInput program(path);
  std::vector<gm::Diagnostic> diags;
  gm::CheckSummary s;
  {
    py::gil_scoped_release unlocked;
    s = gm::check_program_diagnostics(program.rewind(), program.name(), opts, diags);
  }
  py::list list;
  for (const auto& d : diags) list.append(diagnostic_dict(program.name(), d));
  py::dict out;
  out["diagnostics"] = list;
  out["blocks"] = s.blocks;
  out["moves"] = s.moves;
  out["path_length_mm"] = s.path_length_mm;
  out["time_at_feed_s"] = s.time_at_feed_s;
  out["errors"] = s.errors;
  return out;
}

/// The trace's columns as numbers, a vector per column, as a binary trace of the run read back
/// would hold them (TraceReader::next): a run's BlockSink, decimated as its trace would be.
class ColumnCollector final : public gm::BlockSink {
 public:
  explicit ColumnCollector(const gm::TraceMeta& meta)
      : axes_(static_cast<int>(meta.axes.size())),
        decimate_(meta.decimate < 1 ? 1 : meta.decimate),
        period_s_(meta.period_s),
        columns_(gm::trace_column_names(meta.axes)),
        values_(columns_.size()) {
    // The header lines as TraceReader::header() gives them: without the leading "# ".
    std::istringstream text(gm::trace_header(meta));
    for (std::string l; std::getline(text, l);)
      if (l.rfind("# ", 0) == 0) header_.push_back(l.substr(2));
  }

  void consume(const gm::SampleBlock& b, int first) override {
    // The rows on the decimation grid (k % decimate == 0), as TraceWriter::write_block.
    const auto off = static_cast<int>((b.k0 + first) % decimate_);
    first += off == 0 ? 0 : decimate_ - off;
    gm::with_axis_count(axes_, [&](auto n) {
      for (int i = first; i < b.count; i += decimate_) {
        std::size_t c = 0;
        // Each value as the binary field reads back: integers exactly, t = k·T.
        gm::visit_trace_row(gm::BlockRow(b, i, period_s_), n, [&](auto, auto value) {
          values_[c++].push_back(static_cast<double>(value));
        });
      }
    });
  }

  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<std::string>& header() const { return header_; }
  std::vector<std::vector<double>>& values() { return values_; }

 private:
  int axes_;
  int decimate_;
  double period_s_;
  std::vector<std::string> columns_, header_;
  std::vector<std::vector<double>> values_;
};

py::dict run(const std::string& path, const std::string& machine, const py::dict& kw) {
  gm::setup::RunSettings settings = settings_from(kw, gm::setup::kAllSettings, "run");
  settings.machine_file = machine;
  gm::RunOptions o = gm::setup::run_options(settings, gm::setup::resolve_machine(settings));
  gm::InterpreterOptions opts = gm::setup::interpreter_options(settings, o.config.machine);

  py::dict out;
  const py::dict checked = check(path, opts);
  if (checked["errors"].cast<int>() > 0) {
    out["diagnostics"] = checked["diagnostics"];
    return out;
  }
  opts.save_parameters = true;  // as `gmotion run`: written once, after the run

  gm::setup::ProgramInput program(path);
  o.program_name = program.name();

  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;
  std::vector<std::string> header;
  std::string summary_json, tolerance_text, unsettled;
  std::int64_t over_tolerance = 0;  // samples over the tolerance in force (check_tolerance)
  gm::RunStatus st = gm::RunStatus::Working;
  {
    py::gil_scoped_release unlocked;
    std::optional<ColumnCollector> collector;  // outlives the run, whose thread fills it
    gm::Run r(std::move(o), program.rewind(), opts);
    collector.emplace(r.trace_meta());
    r.add_sink(*collector);
    while ((st = r.advance()) == gm::RunStatus::Working) {
    }
    summary_json = r.summary().json();
    tolerance_text = r.tolerance().text();
    if (st == gm::RunStatus::Unsettled) unsettled = r.unsettled_reason();
    if (r.tolerance().exceeded())
      over_tolerance = r.tolerance().cutting().over + r.tolerance().rapids().over;
    columns = collector->columns();
    header = collector->header();
    values = std::move(collector->values());
  }
  if (settings.check_tolerance && over_tolerance > 0)
    throw gm::InputError(
        fmt::format("check_tolerance: {} samples exceed the tolerance in force", over_tolerance));
  py::dict trace;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    py::array_t<double> a(static_cast<py::ssize_t>(values[c].size()));
    std::copy(values[c].begin(), values[c].end(), a.mutable_data());
    std::vector<double>().swap(values[c]);
    trace[py::str(columns[c])] = a;
  }
  out["columns"] = columns;
  out["trace"] = trace;
  out["header"] = header;
  out["summary_json"] = summary_json;
  out["tolerance"] = tolerance_text;
  out["finished"] = st == gm::RunStatus::Finished;
  out["unsettled_reason"] = unsettled;
  return out;
}

template <typename T>
py::array_t<T> to_numpy(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::list xyz(const gm::AxisVec& v) {
  py::list l;
  for (int i = 0; i < 3; ++i) l.append(v[i] + 0.0);
  return l;
}

/// The canonical moves as `gmotion moves` prints them (one dict per JSON Lines record, the same
/// keys; tests/python compares the two).
py::list moves(const std::string& path, const std::string& machine_file, const std::string& axes,
               bool messages, const py::dict& kw) {
  gm::setup::RunSettings settings =
      settings_from(kw, gm::setup::kProgramGroup | gm::setup::kLanguageGroup, "moves");
  settings.machine_file = machine_file;
  settings.axes = axes;
  const gm::Machine machine = gm::setup::resolve_machine(settings);
  gm::setup::validate(settings, machine);
  gm::InterpreterOptions io = gm::setup::interpreter_options(settings, machine);
  gm::setup::ProgramInput program(path);
  std::vector<gm::Canon> all;
  {
    py::gil_scoped_release unlocked;
    std::vector<gm::Diagnostic> diags;
    const gm::CheckSummary s =
        gm::check_program_diagnostics(program.rewind(), program.name(), io, diags);
    if (s.errors > 0) {
      std::string text;
      for (const auto& d : diags)
        if (d.severity == gm::Severity::Error) text += gm::format_diagnostic(program.name(), d);
      throw gm::InputError(text);
    }
    io.save_parameters = true;  // as `gmotion moves`
    gm::ProgramStream stream(program.rewind(), program.name(), io);
    gm::Canon c;
    while (stream.next(c)) all.push_back(c);
  }
  py::list out;
  const gm::AxisLayout& l = machine.layout;
  for (const gm::Canon& c : all) {
    py::dict d;
    if (const auto* m = std::get_if<gm::Motion>(&c)) {
      d["line"] = m->line;
      d["kind"] = gm::motion_kind_name(*m);
      d["end"] = xyz(m->end_mm);
      d["feed"] = m->kind == gm::MotionKind::Rapid ? 0.0 : m->feed_mm_min;
      if (!l.is_xyz()) {
        py::dict more;
        for (int a = 0; a < l.count; ++a)
          if (l.program(a) >= 3)
            more[py::str(std::string(1, l.letter(a)))] = m->end_mm[l.program(a)] + 0.0;
        if (!more.empty()) d["axes"] = more;
      }
      if (m->mm_per_rev > 0.0) d["mm_per_rev"] = m->mm_per_rev;
      if (m->kind == gm::MotionKind::Arc) {
        d["center"] = xyz(m->center_mm);
        d["dir"] = m->ccw ? "ccw" : "cw";
        d["turns"] = m->turns;
        d["plane"] = m->plane == gm::Plane::XY ? "XY" : m->plane == gm::Plane::XZ ? "XZ" : "YZ";
      }
    } else if (const auto* w = std::get_if<gm::Dwell>(&c)) {
      d["line"] = w->line;
      d["kind"] = "dwell";
      d["seconds"] = w->seconds;
    } else if (const auto* e = std::get_if<gm::Event>(&c);
               messages && e && e->kind == gm::EventKind::Message) {
      d["line"] = e->line;
      d["kind"] = "message";
      d["text"] = e->text;
    } else {
      continue;
    }
    out.append(d);
  }
  return out;
}

py::dict taps_dict(const gm::Taps& t) {
  py::dict d;
  d["profile"] = t.profile;
  d["N"] = t.N;
  d["cutoff"] = t.cutoff;
  d["max_nonneg_cutoff"] = t.max_nonneg_cutoff;
  d["taps"] = to_numpy(t.real);
  d["taps_int"] = to_numpy(t.integer);
  d["b_s"] = t.b_s;
  d["integer_exact"] = t.integer_exact;
  return d;
}

/// `gmotion design`: the Fig. 9 procedure; the result's taps and Step 4 figures, every attempt.
py::dict design(const std::string& profile, double tau_s, double period_s,
                const gm::DesignLimits& limits, int max_attempts) {
  std::vector<gm::DesignAttempt> attempts;
  {
    py::gil_scoped_release unlocked;
    attempts = gm::design_procedure(profile, tau_s, period_s, limits, max_attempts);
  }
  const gm::DesignAttempt& a = attempts.back();
  py::dict d = taps_dict(a.taps);
  d["period"] = period_s;
  d["tau_initial"] = tau_s;
  d["tau"] = a.tau_s;
  d["quantisation_error"] = gm::quantisation_error(a.taps);
  d["peak_velocity"] = a.peak_velocity_m_s;
  d["peak_accel"] = a.peak_accel_m_s2;
  d["peak_force"] = a.peak_force_N;
  d["peak_power"] = a.peak_power_W;
  d["profile_force"] = a.profile_force_N;
  d["profile_power"] = a.profile_power_W;
  d["v_ok"] = a.v_ok;
  d["f_ok"] = a.f_ok;
  d["p_ok"] = a.p_ok;
  d["ok"] = a.ok();
  py::list tries;
  for (const auto& x : attempts) {
    py::dict t;
    t["tau"] = x.tau_s;
    t["N"] = x.taps.N;
    t["cutoff"] = x.taps.cutoff;
    t["b_s"] = x.taps.b_s;
    t["peak_accel"] = x.peak_accel_m_s2;
    t["peak_force"] = x.peak_force_N;
    t["peak_power"] = x.peak_power_W;
    t["ok"] = x.ok();
    tries.append(t);
  }
  d["attempts"] = tries;
  return d;
}

/// `gmotion analyze response`: amplitude of the real and the applied (integer) taps on a grid of
/// `points` frequencies from 0 to Nyquist.
py::dict response(const std::string& profile, double tau_s, double period_s, int points) {
  if (points < 2) throw gm::InputError(fmt::format("points {} must be >= 2", points));
  const gm::Taps t = gm::design_taps(profile, tau_s, period_s);
  const auto applied = gm::as_double(t.integer);
  std::vector<double> f(static_cast<std::size_t>(points)), a(f.size()), ai(f.size());
  for (int j = 0; j < points; ++j) {
    const auto k = static_cast<std::size_t>(j);
    f[k] = static_cast<double>(j) / (points - 1);
    a[k] = gm::amplitude_response(t.real, std::numbers::pi * f[k]);
    ai[k] = gm::amplitude_response(applied, std::numbers::pi * f[k]);
  }
  py::dict d = taps_dict(t);
  d["f_norm"] = to_numpy(f);
  std::vector<double> hz(f);
  for (double& x : hz) x *= 0.5 / period_s;
  d["f_hz"] = to_numpy(hz);
  d["amplitude"] = to_numpy(a);
  d["amplitude_int"] = to_numpy(ai);
  return d;
}

/// `gmotion analyze radius-error`: radius loss of a circle per feed, µm (sampled for any
/// profile; Eq. 18 and Eq. 19 for reference).
py::dict radius_error(const std::string& profile, double tau_s, double period_s, double radius_mm,
                      const std::vector<double>& feeds_mm_min) {
  if (!(radius_mm > 0)) throw gm::InputError(fmt::format("radius {} mm must be > 0", radius_mm));
  const gm::Taps t = gm::design_taps(profile, tau_s, period_s);
  std::vector<double> sampled, cont, approx;
  for (double feed : feeds_mm_min) {
    if (!(feed > 0)) throw gm::InputError(fmt::format("feed {} mm/min must be > 0", feed));
    const double v = feed / 60.0;
    sampled.push_back(1000.0 * gm::radius_loss_sampled(t.real, radius_mm, v, period_s));
    cont.push_back(1000.0 * gm::radius_loss_linear_continuous(radius_mm, v, tau_s));
    approx.push_back(1000.0 * gm::radius_loss_linear_approx(radius_mm, v, tau_s));
  }
  py::dict d = taps_dict(t);
  d["radius_mm"] = radius_mm;
  d["feed_mm_min"] = to_numpy(feeds_mm_min);
  d["sampled_um"] = to_numpy(sampled);
  d["continuous_linear_um"] = to_numpy(cont);
  d["approx_linear_um"] = to_numpy(approx);
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "gmotion's C++ core: use the gmotion package, not this module";
  static py::exception<gm::InputError> input_error(m, "InputError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const gm::InputError& e) {
      input_error(e.what());
    }
  });
  m.attr("version") = GMOTION_VERSION;
  m.def("run", &run, py::arg("program"), py::arg("machine"), py::arg("options"));
  m.def(
      "check",
      [](const std::string& path, const std::string& machine_file, const py::dict& kw) {
        gm::setup::RunSettings settings =
            settings_from(kw, gm::setup::kProgramGroup | gm::setup::kLanguageGroup, "check");
        settings.machine_file = machine_file;
        const gm::Machine machine = gm::setup::resolve_machine(settings);
        gm::setup::validate(settings, machine);
        return check(path, gm::setup::interpreter_options(settings, machine));
      },
      py::arg("program"), py::arg("machine"), py::arg("options"));
  m.def(
      "options",
      [](const std::string& what) {
        return option_names(what == "run" ? gm::setup::kAllSettings
                                          : gm::setup::kProgramGroup | gm::setup::kLanguageGroup,
                            what);
      },
      py::arg("what"));
  m.def("moves", &moves, py::arg("program"), py::arg("machine"), py::arg("axes"),
        py::arg("messages"), py::arg("options"));
  m.def(
      "design",
      [](const std::string& profile, double tau, double period, double v_max, double mass,
         double damping, double f_max, double p_max, double v_step, int max_attempts) {
        gm::DesignLimits l;
        l.v_max_m_s = v_max;
        l.mass_kg = mass;
        l.damping_kg_s = damping;
        l.f_max_N = f_max;
        l.p_max_W = p_max;
        l.v_step_m_s = v_step;
        return design(profile, tau, period, l, max_attempts);
      },
      py::arg("profile"), py::arg("tau"), py::arg("period"), py::arg("v_max"), py::arg("mass"),
      py::arg("damping"), py::arg("f_max"), py::arg("p_max"), py::arg("v_step"),
      py::arg("max_attempts"));
  m.def("response", &response, py::arg("profile"), py::arg("tau"), py::arg("period"),
        py::arg("points"));
  m.def("radius_error", &radius_error, py::arg("profile"), py::arg("tau"), py::arg("period"),
        py::arg("radius"), py::arg("feeds"));
}
