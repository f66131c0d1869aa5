// gmotion._core: the run and check entry points for Python; python/gmotion/__init__.py wraps them.
#include "cli/run_setup.hpp"
#include "common/diagnostic.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "override/override_schedule.hpp"
#include "pipeline/run.hpp"
#include "trace/trace_reader.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

/// The keyword arguments of gmotion.run(), named as the `run` flags are (dashes as underscores).
const std::set<std::string> kRunOptions = {
    "profile",  "tau",           "period",         "blu",      "servo",    "block_delete",
    "override", "tool_table",    "rapid_override", "schedule", "decimate", "tolerance",
    "max_time", "max_iterations"};

template <typename T>
std::optional<T> option(const py::dict& d, const char* key) {
  if (!d.contains(key) || d[key].is_none()) return std::nullopt;
  return d[key].cast<T>();
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
  gm::cli::ProgramInput program(path);
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

/// A binary trace in TMPDIR, removed when this goes out of scope.
struct ScratchTrace {
  std::string path;
  ScratchTrace() {
    const char* dir = std::getenv("TMPDIR");
    path = (dir != nullptr && *dir != '\0' ? std::string(dir) : "/tmp") + "/gmotion-py-XXXXXX";
    const int fd = mkstemp(path.data());
    if (fd < 0)
      throw gm::InputError(fmt::format("cannot make a scratch trace: {}", std::strerror(errno)));
    ::close(fd);
  }
  ~ScratchTrace() { std::remove(path.c_str()); }
  ScratchTrace(const ScratchTrace&) = delete;
  ScratchTrace& operator=(const ScratchTrace&) = delete;
};

py::dict run(const std::string& path, const std::string& machine, const py::dict& kw) {
  for (const auto& item : kw) {
    const auto key = item.first.cast<std::string>();
    if (kRunOptions.count(key) == 0) {
      std::string known;
      for (const auto& k : kRunOptions) known += (known.empty() ? "" : ", ") + k;
      throw py::type_error(
          fmt::format("run() got an unknown option '{}' (the options: {})", key, known));
    }
  }
  gm::cli::MachineFlags flags;
  flags.machine_file = machine;
  flags.profile = option<std::string>(kw, "profile");
  flags.tau_s = option<double>(kw, "tau");
  flags.period_s = option<double>(kw, "period");
  flags.blu_mm = option<double>(kw, "blu");
  flags.no_servo = !option<bool>(kw, "servo").value_or(true);
  flags.block_delete = option<bool>(kw, "block_delete").value_or(false);
  flags.tool_table = option<std::string>(kw, "tool_table").value_or("");

  gm::RunOptions o;
  o.config.machine = gm::cli::resolve_machine(flags);
  o.config.servo = !flags.no_servo;
  if (auto tol = option<double>(kw, "tolerance")) {
    if (!(*tol >= 0.0) || *tol > 1000.0)
      throw gm::InputError(fmt::format("tolerance {} is outside 0..1000 mm", *tol));
    o.config.machine.path_tolerance_mm = *tol;
  }
  const double max_pct = o.config.machine.max_override * 100.0;
  o.feed_override_pct = option<double>(kw, "override").value_or(100.0);
  o.rapid_override_pct = option<double>(kw, "rapid_override").value_or(100.0);
  for (auto [name, v] : {std::pair{"override", o.feed_override_pct},
                         std::pair{"rapid_override", o.rapid_override_pct}})
    if (!(v >= 0.0) || v > max_pct + 1e-9)
      throw gm::InputError(fmt::format("{} {} is outside 0..{} % (the machine's maximum override)",
                                       name, v, max_pct));
  if (auto file = option<std::string>(kw, "schedule"))
    o.schedule = gm::OverrideSchedule::load(*file, max_pct);
  o.decimate = option<int>(kw, "decimate").value_or(1);
  if (o.decimate < 1) throw gm::InputError(fmt::format("decimate {} is below 1", o.decimate));
  o.max_time_s = option<double>(kw, "max_time").value_or(0.0);

  gm::InterpreterOptions opts;
  opts.machine = &o.config.machine;
  opts.block_delete = flags.block_delete;
  if (auto n = option<std::int64_t>(kw, "max_iterations")) opts.max_iterations = *n;

  py::dict out;
  const py::dict checked = check(path, opts);
  if (checked["errors"].cast<int>() > 0) {
    out["diagnostics"] = checked["diagnostics"];
    return out;
  }

  gm::cli::ProgramInput program(path);
  ScratchTrace scratch;
  o.program_name = program.name();
  o.trace_path = scratch.path;
  o.trace_format = gm::TraceFormat::Binary;

  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;
  std::vector<std::string> header;
  std::string summary_json, tolerance_text, unsettled;
  gm::RunStatus st = gm::RunStatus::Working;
  {
    py::gil_scoped_release unlocked;
    gm::Run r(std::move(o), program.rewind(), opts);
    while ((st = r.step()) == gm::RunStatus::Working) {
    }
    summary_json = r.summary().json();
    tolerance_text = r.tolerance().text();
    if (st == gm::RunStatus::Unsettled) unsettled = r.unsettled_reason();
    // The run has finished and closed its trace: read it back into one vector per column.
    gm::TraceReader reader(scratch.path);
    columns = reader.columns();
    header = reader.header();
    values.resize(columns.size());
    std::vector<double> row;
    while (reader.next(row))
      for (std::size_t c = 0; c < row.size(); ++c) values[c].push_back(row[c]);
  }
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
      [](const std::string& path, bool block_delete, std::int64_t max_iterations) {
        gm::InterpreterOptions opts;
        opts.block_delete = block_delete;
        opts.max_iterations = max_iterations;
        return check(path, opts);
      },
      py::arg("program"), py::arg("block_delete") = false,
      py::arg("max_iterations") = gm::InterpreterOptions{}.max_iterations);
}
