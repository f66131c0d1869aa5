// Fuzz target: a machine file through its reader, its writer, and what a run builds from it.
#include "fuzz_target.hpp"

#include "accdec/taps.hpp"
#include "common/status.hpp"
#include "interp/canon.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace {

[[noreturn]] void broken(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_machine: %s\n%s\n", what, detail.c_str());
  std::abort();
}

/// A fixed list of canonical commands (no interpreter involved).
class ListSource : public gm::CanonSource {
 public:
  explicit ListSource(std::vector<gm::Canon> items) : items_(std::move(items)) {}
  bool next(gm::Canon& out) override {
    if (next_ >= items_.size()) return false;
    out = items_[next_++];
    return true;
  }

 private:
  std::vector<gm::Canon> items_;
  std::size_t next_ = 0;
};

// Steps a pipeline until it finishes or `max_steps` samples have passed.
void run_pipeline(const gm::Machine& m, bool servo, std::vector<gm::Canon> program, int max_steps) {
  gm::RunConfig cfg{m, servo, 1.0};
  ListSource source(std::move(program));
  gm::Pipeline pipeline(cfg, source);
  gm::SampleRecord rec;
  for (int i = 0; i < max_steps; ++i)
    if (pipeline.step(gm::OverrideInput{}, rec) != gm::PipelineStatus::Working) break;
}

// Taps × axes × samples one input may run (about 0.1 s under the sanitizers).
constexpr std::size_t kTapSampleBudget = 2'000'000;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  gm::Machine m;
  try {
    m = gm::parse_machine_toml(text, "fuzz.toml");
  } catch (const gm::InputError&) {
    return 0;
  }
  // The writer's contract: what it writes reads back to an equal machine (so writes the same).
  const std::string written = gm::machine_to_toml(m);
  try {
    const gm::Machine again = gm::parse_machine_toml(written, "fuzz.toml");
    if (gm::machine_to_toml(again) != written)
      broken("machine_to_toml does not round-trip", written);
  } catch (const gm::InputError& e) {
    broken("machine_to_toml wrote a file the reader rejects",
           std::string(e.what()) + "\n" + written);
  }
  // What a run builds from the machine: the taps, then the pipeline (interpolator, Acc/Dec,
  // servo axes, contour window). A tap design the reader let through may still be refused
  // with gm::InputError (e.g. tau not a whole number of periods): a run reports it the same way.
  try {
    const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
    // A sample costs a multiply per tap and axis: a 23,000-tap filter (tau 9.2 s at T 0.4 ms)
    // took 9 s of the 10 s timeout under the sanitizers for 4,096 samples. The work an input
    // may ask is bounded instead (at least 32 samples, so every stage still runs).
    const std::size_t per_sample = taps.integer.size() * static_cast<std::size_t>(m.axis_count());
    const int steps = static_cast<int>(
        std::clamp<std::size_t>(kTapSampleBudget / std::max<std::size_t>(per_sample, 1), 32, 4096));
    run_pipeline(m, true, {}, steps);
    gm::Motion line;
    line.line = 1;
    line.end_mm = gm::AxisVec::Constant(0.5);
    line.feed_mm_min = 600.0;
    run_pipeline(m, false, {gm::Canon{line}}, steps);
  } catch (const gm::InputError&) {
  }
  return 0;
}
