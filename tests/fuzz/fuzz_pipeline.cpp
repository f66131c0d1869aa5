// Fuzz target: a generated program (program_gen.hpp) run through the whole pipeline — planner,
// interpolator, Acc/Dec, servo, outputs — on a machine, profile, tolerance and override the
// bytes choose, asserting what a run promises: finite results, no sample lost, the Acc/Dec
// output ending exactly on the programmed end, and the contour within G64 P where it is planned.
#include "fuzz_target.hpp"

#include "program_gen.hpp"

#include "common/status.hpp"
#include "machine/machine.hpp"
#include "pipeline/run.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace {

// Simulated time one input may run: at T = 4 ms at most 5,000 samples of three axes through a
// filter of at most 80 taps and the servo, about 0.1 s under the sanitizers.
constexpr double kMaxTime_s = 20.0;

// The smallest tolerance the planner can hold: the interpolator and the filter output each round
// by up to half a BLU per axis, so it keeps ‖BLU‖₂ (0.0017 mm on three 1 µm axes) out of every
// tolerance, and a G64 P below twice that is planned as if it were twice that
// (docs/tolerance.md): such a P is not a promise the run can keep.
constexpr double kMinTolerance_mm = 0.004;

[[noreturn]] void broken(const char* what, const std::string& program) {
  std::fprintf(stderr, "fuzz_pipeline: %s\n--- program ---\n%s", what, program.c_str());
  std::abort();
}

struct Setup {
  gm::Machine machine;
  bool servo = true;
  double feed_override_pct = 100.0;
};

// The machine the first bytes choose: profile, tau, period, servo, tolerance and override.
Setup choose_setup(fuzz::ByteReader& in) {
  static constexpr const char* kProfiles[] = {"blackman", "linear",        "scurve2",
                                              "hann",     "cascade:5,5,6", "hamming"};
  static constexpr double kPeriods_s[] = {0.001, 0.002, 0.004};
  Setup s;
  gm::Machine& m = s.machine;
  m.profile = kProfiles[in.below(6)];
  m.period_s = kPeriods_s[in.below(3)];
  const int taps = 8 + in.below(72);
  m.tau_s = taps * m.period_s;
  if (m.profile.rfind("cascade", 0) == 0) m.tau_s = 14 * m.period_s;  // 5 + 5 + 6 - 2 taps
  s.servo = in.chance(60);
  if (in.chance(50)) m.path_tolerance_mm = in.in(kMinTolerance_mm, 0.2);
  m.tolerance_on = in.chance(25) ? gm::ToleranceOn::Encoder : gm::ToleranceOn::AccDec;
  s.feed_override_pct = in.chance(70) ? 100.0 : in.in(10, 200);
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  Setup setup = choose_setup(in);
  fuzz::GenOptions gen;
  gen.raw_lines = false;
  gen.max_statements = 16;
  gen.extent_mm = 10;
  gen.min_tolerance_mm = kMinTolerance_mm;
  // One tolerance for the whole program, the machine's (G64 without P): a corner between two
  // blocks without a tolerance is not planned, yet when a block with G64 P starts within τ after
  // it the corner's rounding is judged against that P (G0 X10 / G0 X10 Y1 / G64 P0.1 / G1 X20
  // F3000: 548 % of P; docs/tolerance.md).
  gen.tolerances = false;
  const std::string program = fuzz::ProgramGen(in, gen).generate();
  if (std::getenv("GMOTION_FUZZ_PRINT")) std::fputs(program.c_str(), stderr);  // to replay by hand

  gm::RunOptions opts;
  opts.config.machine = setup.machine;
  opts.config.servo = setup.servo;
  opts.program_name = "fuzz.nc";
  opts.feed_override_pct = setup.feed_override_pct;
  opts.max_time_s = kMaxTime_s;
  opts.consumer_thread = false;
  gm::InterpreterOptions interp;
  interp.max_iterations = 200;

  std::istringstream text(program);
  gm::RunStatus status = gm::RunStatus::Working;
  std::int64_t k_last = -1;
  try {
    gm::Run run(opts, text, interp);
    while ((status = run.advance()) == gm::RunStatus::Working) k_last = run.last().k;
    k_last = run.last().k;
    const gm::RunSummary& sum = run.summary();
    if (!std::isfinite(sum.cycle_time_s) || !std::isfinite(sum.contour_err_blu.value) ||
        !std::isfinite(sum.contour_rms_blu))
      broken("a summary value is not finite", program);
    if (sum.samples != k_last + 1) broken("the summary did not see every sample", program);
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
  } catch (const gm::InputError& e) {
    // A program error, a stop rule (--max-time) or a refused set-up: reported the same way by
    // `gmotion run`.
    if (std::getenv("GMOTION_FUZZ_PRINT")) std::fprintf(stderr, "fuzz_pipeline: %s\n", e.what());
    return 0;
  }
  if (std::getenv("GMOTION_FUZZ_PRINT"))
    std::fprintf(stderr, "fuzz_pipeline: %s after %lld samples\n",
                 status == gm::RunStatus::Finished ? "finished" : "unsettled",
                 static_cast<long long>(k_last + 1));
  return 0;
}
