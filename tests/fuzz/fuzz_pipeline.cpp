// Fuzz target: a generated program (program_gen.hpp) run through the whole pipeline — planner,
// interpolator, Acc/Dec, servo, outputs — on a machine, profile (any of the registry's, shapers
// and compositions too), axes (a rotary one now and then), servo (structural modes,
// feedforward), tolerance and override the bytes choose, asserting what a run promises: finite
// results, no sample lost, the Acc/Dec output ending exactly on the programmed end, the contour
// within G64 P where it is planned, the trace (CSV or binary) reading back row for row and
// column for column, and the HTML report and summary JSON rendering whole.
#include "fuzz_target.hpp"

#include "program_gen.hpp"
#include "trace_check.hpp"

#include "accdec/profile_spec.hpp"
#include "accdec/profiles.hpp"
#include "accdec/taps.hpp"
#include "common/status.hpp"
#include "machine/machine.hpp"
#include "pipeline/run.hpp"
#include "report/report_collector.hpp"
#include "report/report_page.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

// Simulated time one input may run: at T = 1 ms at most 20,000 samples, fewer when the filter is
// long (kTapSampleBudget), about 0.3 s under the sanitizers at the most.
constexpr double kMaxTime_s = 20.0;
// Taps × axes × samples one input may run (a shaper composition has a few hundred taps).
constexpr double kTapSampleBudget = 2e7;

// The smallest tolerance the planner can hold: the interpolator and the filter output each round
// by up to half a BLU per axis, so it keeps ‖BLU‖₂ (0.0017 mm on three 1 µm axes) out of every
// tolerance, and a G64 P below twice that is planned as if it were twice that
// (docs/tolerance.md): such a P is not a promise the run can keep.
constexpr double kMinTolerance_mm = 0.004;

[[noreturn]] void broken(const std::string& what, const std::string& program) {
  std::fprintf(stderr, "fuzz_pipeline: %s\n--- program ---\n%s", what.c_str(), program.c_str());
  std::abort();
}

struct Setup {
  gm::Machine machine;
  bool servo = true;
  double feed_override_pct = 100.0;
  std::string rotary;  ///< the rotary axis letter the machine has, or ""
};

// Profiles beyond the registry's examples: cutoffs, and compositions of windows and shapers.
constexpr const char* kExtraProfiles[] = {"mzv:45+zv:70", "blackman+ei:40", "hann+zvd:40@0.1",
                                          "kaiser:6@max", "blackman@0.8",   "cascade:5,5,6",
                                          "zv:30+zv:90",  "linear+mzv:50"};

// A shaper spec ("ei:37.5@0.05") of a registry shaper at a frequency below Nyquist at T.
std::string choose_shaper(fuzz::ByteReader& in, double period_s) {
  std::vector<std::string_view> shapers;
  for (const gm::ProfileRow& r : gm::profile_rows())
    if (r.takes_damping) shapers.push_back(r.name);
  std::string s = fmt::format(
      "{}:{:.1f}", shapers[static_cast<std::size_t>(in.below(static_cast<int>(shapers.size())))],
      in.in(15, 0.4 / period_s));
  if (in.chance(30)) s += fmt::format("@{:.3f}", in.in(0, 0.2));
  return s;
}

// The profile the bytes choose: a registry row's example, one of kExtraProfiles, a shaper at a
// chosen frequency, or a window followed by one.
std::string choose_profile(fuzz::ByteReader& in, double period_s) {
  const auto rows = gm::profile_rows();
  switch (in.below(4)) {
    case 0:
      return std::string(
          rows[static_cast<std::size_t>(in.below(static_cast<int>(rows.size())))].example);
    case 1:
      return kExtraProfiles[in.below(static_cast<int>(std::size(kExtraProfiles)))];
    case 2:
      return choose_shaper(in, period_s);
    default: {
      static constexpr const char* kWindows[] = {"blackman", "hann", "linear", "scurve2"};
      const char* w = kWindows[in.below(4)];
      return fmt::format("{}+{}", w, choose_shaper(in, period_s));
    }
  }
}

// The machine the first bytes choose: profile, tau, period, axes, servo (modes, feedforward),
// tolerance and override.
Setup choose_setup(fuzz::ByteReader& in) {
  static constexpr double kPeriods_s[] = {0.001, 0.002, 0.004};
  Setup s;
  gm::Machine& m = s.machine;
  m.period_s = kPeriods_s[in.below(3)];
  m.profile = choose_profile(in, m.period_s);
  const int taps = 8 + in.below(72);
  m.tau_s = taps * m.period_s;
  // A spec that fixes its taps (custom, cascade, shapers and their compositions) fixes tau.
  if (const int fixed = gm::parse_profile_spec(m.profile).fixed_length(m.period_s); fixed > 0)
    m.tau_s = fixed * m.period_s;
  if (in.chance(25)) {
    s.rotary = std::string(1, "ABC"[in.below(3)]);
    m.set_axes(*gm::AxisLayout::of("XYZ" + s.rotary), m.axes[0]);
    m.axes[3].wrapped_rotary = in.chance(30);
  }
  s.servo = in.chance(60);
  m.tolerance_on = in.chance(25) ? gm::ToleranceOn::Encoder : gm::ToleranceOn::AccDec;
  if (s.servo) {
    for (gm::AxisConfig& a : m.axes) {
      // One or two structural modes between motor and table, of at least 20 Hz and a damping
      // ratio of 0.05, with either plan. With the encoder plan a 20 Hz mode at 0.05 makes the
      // chain (FIR, servo and modes) about 2,000 weights long, and the planner's corner moments
      // (CornerMomentGrid) cost a few passes over them per pause tried: all N + 1 pauses of a
      // 2,367-weight chain take 0.17 s under ASan+UBSan (docs/testing.md).
      if (in.chance(25)) {
        for (int k = 1 + in.below(2); k > 0; --k) {
          a.mode_hz.push_back(in.in(20, 300));
          a.mode_damping.push_back(in.in(0.05, 0.3));
        }
      }
      if (in.chance(25)) {  // velocity and acceleration feedforward
        a.ff1 = in.in(0, 1);
        a.ff2_s = in.in(0, 0.01);
      }
    }
  }
  if (in.chance(50)) m.path_tolerance_mm = in.in(kMinTolerance_mm, 0.2);
  s.feed_override_pct = in.chance(70) ? 100.0 : in.in(10, 200);
  return s;
}

// A temporary file's path for this process's trace (the writer renames FILE.partial to FILE).
std::string trace_path() {
  const char* dir = std::getenv("TMPDIR");
  return fmt::format("{}/gmotion-fuzz-pipeline-{}.trace", dir && *dir ? dir : "/tmp", getpid());
}

// The texts of `lines` (sorted) in `program`, as the report page names them.
std::map<int, std::string> line_texts(const std::string& program, const std::vector<int>& lines) {
  std::map<int, std::string> texts;
  std::istringstream in(program);
  std::string text;
  for (int n = 1; std::getline(in, text); ++n)
    if (std::binary_search(lines.begin(), lines.end(), n)) texts.emplace(n, text);
  return texts;
}

// The summary JSON is one object (and a line break), its first member the sample count, with no
// bare NaN or infinity (they are written as null).
void check_json(std::string json, std::int64_t samples, const std::string& program) {
  while (!json.empty() && json.back() == '\n') json.pop_back();
  if (json.empty() || json.rfind(fmt::format("{{\"samples\":{},", samples), 0) != 0 ||
      json.back() != '}')
    broken("the summary JSON does not open with its sample count: " + json, program);
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == '[') {
      ++depth;
    } else if (c == '}' || c == ']') {
      if (--depth < 0) break;
    } else if (std::isalpha(static_cast<unsigned char>(c)) && json.compare(i, 4, "null") != 0 &&
               json.compare(i, 4, "true") != 0 && json.compare(i, 5, "false") != 0 && i > 0 &&
               !std::isalnum(static_cast<unsigned char>(json[i - 1])) && json[i - 1] != '.') {
      broken("the summary JSON holds a bare word (nan, inf?): " + json, program);
    }
  }
  if (depth != 0 || in_string) broken("the summary JSON is not balanced: " + json, program);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  Setup setup;
  try {
    setup = choose_setup(in);
  } catch (const gm::InputError&) {  // a profile spec the registry refuses
    return 0;
  }
  const bool write_trace = in.chance(40);
  const gm::TraceFormat format = in.chance(50) ? gm::TraceFormat::Csv : gm::TraceFormat::Binary;
  const bool write_report = in.chance(25);
  fuzz::GenOptions gen;
  gen.raw_lines = false;
  gen.max_statements = 16;
  gen.extent_mm = 10;
  gen.min_tolerance_mm = kMinTolerance_mm;
  gen.rotary_axes = setup.rotary;
  // Tolerances change between blocks (G64 P…, G61, G64): a corner without one is planned for
  // the G64 P block that starts within τ after it (docs/tolerance.md).
  const std::string program = fuzz::ProgramGen(in, gen).generate();
  const bool print = std::getenv("GMOTION_FUZZ_PRINT") != nullptr;
  if (print) {  // to replay by hand
    std::fprintf(stderr, "fuzz_pipeline: profile %s tau %g s T %g s axes %s servo %d\n",
                 setup.machine.profile.c_str(), setup.machine.tau_s, setup.machine.period_s,
                 setup.machine.layout.letters().c_str(), setup.servo ? 1 : 0);
    std::fputs(program.c_str(), stderr);
  }

  gm::RunOptions opts;
  opts.config.machine = setup.machine;
  opts.config.servo = setup.servo;
  opts.program_name = "fuzz.nc";
  opts.feed_override_pct = setup.feed_override_pct;
  opts.consumer_thread = false;
  if (write_trace) {
    opts.trace_path = trace_path();
    opts.trace_format = format;
  }
  gm::InterpreterOptions interp;
  interp.max_iterations = 200;

  std::istringstream text(program);
  gm::RunStatus status = gm::RunStatus::Working;
  std::int64_t k_last = -1;
  try {
    // The samples one input may run: 20 s of simulated time, fewer behind a long filter.
    const gm::Taps taps =
        gm::design_taps(setup.machine.profile, setup.machine.tau_s, setup.machine.period_s);
    const double per_sample = static_cast<double>(taps.integer.size()) * setup.machine.axis_count();
    opts.max_time_s = std::min(kMaxTime_s, kTapSampleBudget / per_sample * setup.machine.period_s);

    gm::Run run(opts, text, interp);
    const gm::TraceColumnSet columns =
        setup.servo && setup.machine.has_modes() ? gm::kTraceModes : gm::kTraceAlways;
    fuzz::TraceExpect expect(setup.machine.axis_count(), setup.machine.period_s, write_trace,
                             columns);
    run.add_sink(expect);
    std::unique_ptr<gm::report::ReportCollector> collector;
    if (write_report) {
      collector = std::make_unique<gm::report::ReportCollector>(run.config().machine);
      run.add_sink(*collector);
    }
    while ((status = run.advance()) == gm::RunStatus::Working) k_last = run.last().k;
    k_last = run.last().k;
    const gm::RunSummary& sum = run.summary();
    if (!std::isfinite(sum.cycle_time_s) || !std::isfinite(sum.contour_err_blu.value) ||
        !std::isfinite(sum.contour_rms_blu))
      broken("a summary value is not finite", program);
    if (sum.samples != k_last + 1) broken("the summary did not see every sample", program);
    if (!expect.error().empty()) broken(expect.error(), program);
    if (expect.rows() != sum.samples) broken("a sink did not see every sample", program);
    if (status == gm::RunStatus::Finished) {
      for (int a = 0; a < run.config().machine.axis_count(); ++a) {
        if (sum.axes[a].final_ref_err_blu != 0)
          broken("the Acc/Dec output did not end on the programmed end", program);
        if (!setup.servo && sum.axes[a].final_enc_err_blu != 0)
          broken("the ideal axes did not end on the programmed end", program);
      }
    }
    // G64 P is planned for the Acc/Dec output: with ideal axes the table is that output.
    if (!setup.servo && setup.machine.tolerance_on == gm::ToleranceOn::AccDec &&
        run.tolerance().exceeded())
      broken("a sample left the G64 P tolerance the planner was given", program);
    const std::string json = sum.json();
    check_json(json, sum.samples, program);
    if (write_trace) {
      const std::string diff =
          fuzz::compare_trace(opts.trace_path, setup.machine.layout.letters(), expect);
      std::remove(opts.trace_path.c_str());
      if (!diff.empty()) broken("the trace read back: " + diff, program);
    }
    if (collector) {
      gm::report::PageInput page_in;
      page_in.program_name = opts.program_name;
      page_in.machine_name = setup.machine.name;
      page_in.profile = setup.machine.profile;
      page_in.tau_s = setup.machine.tau_s;
      page_in.period_s = setup.machine.period_s;
      page_in.servo = setup.servo;
      page_in.summary_json = json;
      page_in.summary_text = sum.text() + run.tolerance().text();
      page_in.status = sum.settled ? "finished" : run.unsettled_reason();
      page_in.taps = &run.pipeline().taps();
      page_in.line_texts = line_texts(program, collector->lines());
      const std::string page = gm::report::render_page(*collector, page_in);
      if (page.rfind("<!DOCTYPE html>", 0) != 0 || !page.ends_with("</body></html>\n"))
        broken("the report page is not one whole HTML document", program);
    }
  } catch (const gm::InputError& e) {
    // A program error, a stop rule (--max-time) or a refused set-up: reported the same way by
    // `gmotion run`.
    if (write_trace) {
      std::remove(opts.trace_path.c_str());
      std::remove((opts.trace_path + ".partial").c_str());
    }
    if (print) std::fprintf(stderr, "fuzz_pipeline: %s\n", e.what());
    return 0;
  }
  if (print)
    std::fprintf(stderr, "fuzz_pipeline: %s after %lld samples\n",
                 status == gm::RunStatus::Finished ? "finished" : "unsettled",
                 static_cast<long long>(k_last + 1));
  return 0;
}
