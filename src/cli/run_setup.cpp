// Shared set-up of the pipeline commands: machine resolution and program input.
#include "cli/run_setup.hpp"

#include "accdec/accel_limit.hpp"
#include "accdec/profiles.hpp"
#include "common/position_limits.hpp"
#include "common/status.hpp"
#include "machine/linuxcnc_ini.hpp"
#include "machine/machine_file.hpp"

#include <fmt/format.h>

#include <unistd.h>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace gm::cli {

void add_machine_flags(CLI::App* sub, MachineFlags& f) {
  sub->add_option(
      "--machine", f.machine_file,
      "Machine file (TOML, or a LinuxCNC .ini: docs/linuxcnc-ini.md); default: the built-in "
      "3-axis machine");
  sub->add_option("--axes", f.axes, kAxesFlagHelp);
  sub->add_option("--profile", f.profile,
                  "Acc/Dec profile: " + profile_forms(" | ") + " (C = cutoff or max)");
  sub->add_option("--tau", f.tau_s, "Acc/Dec time constant tau = (N+1)T, seconds");
  sub->add_option("--period", f.period_s, "Interpolation period T, seconds");
  sub->add_option("--blu", f.blu_mm, "Basic length unit of every axis, mm");
  sub->add_flag("--no-servo", f.no_servo, "Ideal axes: the encoder reads the Acc/Dec output");
  sub->add_flag("--block-delete", f.block_delete, "Skip blocks that start with '/'");
  sub->add_option("--tool-table", f.tool_table,
                  "LinuxCNC tool table (T1 P1 Z50 D6 ;comment), mm; default: the machine's");
  sub->add_option("--user-mcode-dir", f.user_mcode_dir, kUserMcodeDirHelp);
  sub->add_option(
      "--pause-s", f.pause_s,
      "Seconds an M0/M1 program stop holds the run; default: the machine's pause_s (0)");
}

void apply_axes_flag(Machine& m, const std::string& letters) {
  if (letters.empty()) return;
  const std::optional<AxisLayout> l = AxisLayout::of(letters);
  if (!l)
    throw InputError(fmt::format(
        "--axes {}: give axis letters in the order XYZABCUVW, each at most once", letters));
  m.set_axes(*l, default_machine().axes[0]);
}

Machine resolve_machine(const MachineFlags& f) {
  std::optional<IniImport> ini;
  if (!f.machine_file.empty() && is_linuxcnc_ini(f.machine_file)) {
    ini = load_linuxcnc_ini(f.machine_file);
    if (!ini->warnings.empty()) {
      std::string list;
      for (const std::string& w : ini->warnings) list += "\n  " + w;
      fmt::print(stderr, "gmotion: {}: not mapped from the LinuxCNC INI:{}\n", f.machine_file,
                 list);
    }
  }
  Machine m = ini                      ? ini->machine
              : f.machine_file.empty() ? default_machine()
                                       : load_machine_file(f.machine_file);
  apply_axes_flag(m, f.axes);
  auto positive = [](const char* flag, double v) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw InputError(
          fmt::format("{} must be a positive number of seconds or mm (got {})", flag, v));
  };
  if (!f.tool_table.empty()) m.tool_table = load_tool_table(f.tool_table);
  if (!f.user_mcode_dir.empty()) m.user_mcode_dir = f.user_mcode_dir;
  if (f.pause_s) {
    if (!(*f.pause_s >= 0.0) || *f.pause_s > 1e6)
      throw InputError(fmt::format("--pause-s {} is outside 0..1e6 s", *f.pause_s));
    m.pause_s = *f.pause_s;
  }
  if (f.profile) m.profile = *f.profile;
  if (f.tau_s) positive("--tau", *f.tau_s), m.tau_s = *f.tau_s;
  if (f.period_s) positive("--period", *f.period_s), m.period_s = *f.period_s;
  if (f.blu_mm) {
    positive("--blu", *f.blu_mm);
    if (*f.blu_mm < kMinBluMm)
      throw InputError(
          fmt::format("--blu {} is finer than 1e-6 mm (1 nm): positions up "
                      "to ±1e12 mm would not fit int64 counts",
                      *f.blu_mm));
    for (auto& a : m.axes) a.blu_mm = *f.blu_mm;
  }
  // An INI's τ follows its limits, the profile and T: suggested again for the flags' ones.
  if (ini && !f.tau_s && f.axes.empty() && (f.profile || f.period_s))
    m.tau_s = tau_for_accel_limit(m, ini->a_max_mm_s2, m.tau_s);
  return m;
}

double apply_run_limits(Machine& m, std::optional<double> tolerance_mm, double override_pct,
                        double rapid_override_pct) {
  if (tolerance_mm) {
    if (!(*tolerance_mm >= 0.0) || *tolerance_mm > 1000.0)
      throw InputError(fmt::format("--tolerance {} is outside 0..1000 mm", *tolerance_mm));
    m.path_tolerance_mm = *tolerance_mm;
  }
  const double max_pct = m.max_override * 100.0;
  for (auto [flag, v] :
       {std::pair{"--override", override_pct}, std::pair{"--rapid-override", rapid_override_pct}})
    if (!(v >= 0.0) || v > max_pct + 1e-9)
      throw InputError(fmt::format("{} {} is outside 0..{} % (the machine's maximum override)",
                                   flag, v, max_pct));
  return max_pct;
}

ProgramInput::ProgramInput(const std::string& path) : name_(path == "-" ? "<stdin>" : path) {
  std::string open_path = path;
  if (path == "-") {
    // Spooled to a file so control flow can seek in it. Every write is checked: a full disk
    // must not turn into a silently shorter program.
    const char* tmpdir = std::getenv("TMPDIR");
    std::string tmpl = (tmpdir != nullptr && *tmpdir != '\0' ? std::string(tmpdir) : "/tmp") +
                       "/gmotion-stdin-XXXXXX";
    const int fd = mkstemp(tmpl.data());
    if (fd < 0) throw InputError(fmt::format("cannot spool stdin: {}", std::strerror(errno)));
    spool_path_ = tmpl;
    std::FILE* out = fdopen(fd, "wb");
    if (out == nullptr) {
      const int err = errno;
      ::close(fd);
      std::remove(spool_path_.c_str());
      throw InputError(fmt::format("cannot spool stdin: {}", std::strerror(err)));
    }
    char buf[1 << 16];
    std::size_t n;
    int err = 0;  // the first failure's errno
    while (err == 0 && (n = std::fread(buf, 1, sizeof buf, stdin)) > 0)
      if (std::fwrite(buf, 1, n, out) != n) err = errno;
    if (std::fflush(out) != 0 && err == 0) err = errno;
    if (std::fclose(out) != 0 && err == 0) err = errno;
    if (err != 0) {
      std::remove(spool_path_.c_str());  // the destructor does not run for a throwing constructor
      throw InputError(
          fmt::format("cannot spool stdin to {}: {}", spool_path_, std::strerror(err)));
    }
    open_path = spool_path_;
  } else {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
      throw InputError(fmt::format("cannot read program '{}': it is a directory", path));
  }
  // One large buffer: a 27 MB program is read in 27 system calls instead of 3,300, which keeps
  // the slow samples (those that wait for a read) rare.
  buffer_.resize(kBufferBytes);
  file_.rdbuf()->pubsetbuf(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  file_.open(open_path, std::ios::binary);
  if (!file_)
    throw InputError(fmt::format("cannot read program '{}': {}", path, std::strerror(errno)));
  if (!spool_path_.empty()) std::remove(spool_path_.c_str());  // the open stream keeps it alive
}

std::istream& ProgramInput::rewind() {
  file_.clear();
  file_.seekg(0);
  return file_;
}

bool validate_program(ProgramInput& program, const InterpreterOptions& opts) {
  const int errors = count_program_errors(program.rewind(), program.name(), opts, std::cerr);
  if (errors > 0) {
    fmt::print(stderr, "{}: {} error{}\n", program.name(), errors, errors == 1 ? "" : "s");
    return false;
  }
  return true;
}

}  // namespace gm::cli
