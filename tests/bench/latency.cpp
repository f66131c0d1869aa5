// gmotion_latency: wall time of each pipeline step, one sample at a time as a real-time loop
// would call it (block reading, parsing and interpretation included), as percentiles.
//
// Usage: gmotion_latency PROGRAM [MACHINE.toml] [--no-servo] [--summary] [--repeat R]
//   --summary  also feed each sample to the run summary, one record at a time
//   --repeat   run the program R times (default 3) and also report, per sample, the fastest of
//              the R runs: the pipeline is deterministic, so that removes the steps the machine
//              interrupted (timer ticks, other processes) and leaves the cost of the work itself
// Prints mean, p50, p99, p99.9, p99.99 and max in microseconds, and how often the machine
// interrupts a loop that only reads the clock. Each step is timed with steady_clock (a pair of
// reads costs ~30 ns here, included); the step times are kept in a vector filled outside the
// timed span.
#include "interp/program.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/pipeline.hpp"
#include "support/sample_stepper.hpp"
#include "support/summary_reference.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::int64_t kBinNs = 10;
constexpr std::size_t kBins = 100000;  // 10 ns .. 1 ms; the last bin holds everything slower

struct Histogram {
  std::vector<std::uint64_t> bins = std::vector<std::uint64_t>(kBins, 0);
  std::uint64_t count = 0;
  std::int64_t max_ns = 0;
  long double sum_ns = 0;

  void add(std::int64_t ns) {
    ++bins[std::min<std::size_t>(static_cast<std::size_t>(std::max<std::int64_t>(ns, 0) / kBinNs),
                                 kBins - 1)];
    ++count;
    max_ns = std::max(max_ns, ns);
    sum_ns += static_cast<long double>(ns);
  }
  /// Number of values above `ns`.
  std::uint64_t over(std::int64_t ns) const {
    std::uint64_t n = 0;
    for (std::size_t i = static_cast<std::size_t>(ns / kBinNs) + 1; i < kBins; ++i) n += bins[i];
    return n;
  }
  /// Upper edge of the bin holding the q-quantile, µs.
  double quantile_us(double q) const {
    const auto target = static_cast<std::uint64_t>(q * static_cast<double>(count));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
      seen += bins[i];
      if (seen > target)
        return static_cast<double>((static_cast<std::int64_t>(i) + 1) * kBinNs) / 1000.0;
    }
    return static_cast<double>(max_ns) / 1000.0;
  }
};

struct Options {
  std::string program, machine_path;
  bool servo = true, with_summary = false;
  int repeat = 3;
};

/// One whole run; step_ns[k] = min(step_ns[k], time of step k). Returns the run's wall time.
double timed_run(const Options& o, const gm::RunConfig& cfg, std::vector<std::uint32_t>& step_ns) {
  std::vector<char> buffer(std::size_t{1} << 20);  // as gmotion run reads programs
  std::ifstream in;
  in.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  in.open(o.program, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot open '{}'", o.program));
  gm::InterpreterOptions opts;
  opts.machine = &cfg.machine;
  gm::ProgramStream stream(in, o.program, opts);
  gmtest::SampleStepper pipeline(cfg, stream);
  gmtest::SummaryReference summary(cfg.machine);
  gm::SampleRecord rec;
  const gm::OverrideInput ovr;
  const bool first = step_ns.empty();
  std::size_t k = 0;
  const auto wall0 = Clock::now();
  for (;; ++k) {
    const auto t0 = Clock::now();
    const gm::PipelineStatus st = pipeline.step(ovr, rec);
    if (o.with_summary && st == gm::PipelineStatus::Working) summary.add(rec);
    const auto t1 = Clock::now();
    if (st != gm::PipelineStatus::Working) break;
    const auto ns = static_cast<std::uint32_t>(std::min<std::int64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count(), UINT32_MAX));
    if (first)
      step_ns.push_back(ns);  // outside the timed span; later runs write in place
    else if (k < step_ns.size())
      step_ns[k] = std::min(step_ns[k], ns);
  }
  return std::chrono::duration<double>(Clock::now() - wall0).count();
}

Histogram histogram(const std::vector<std::uint32_t>& ns) {
  Histogram h;
  for (auto v : ns) h.add(v);
  return h;
}

void print_percentiles(const char* what, const Histogram& h) {
  fmt::print(
      "{}, us: mean {:.3f}  p50 {:.2f}  p99 {:.2f}  p99.9 {:.2f}  p99.99 {:.2f}  max {:.1f}  (over "
      "5 us: {})\n",
      what,
      static_cast<double>(h.sum_ns /
                          static_cast<long double>(std::max<std::uint64_t>(h.count, 1))) /
          1000.0,
      h.quantile_us(0.5), h.quantile_us(0.99), h.quantile_us(0.999), h.quantile_us(0.9999),
      static_cast<double>(h.max_ns) / 1000.0, h.over(5000));
}

int run(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--no-servo") == 0)
      o.servo = false;
    else if (std::strcmp(argv[i], "--summary") == 0)
      o.with_summary = true;
    else if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
      o.repeat = std::max(1, std::atoi(argv[++i]));
    else if (o.program.empty())
      o.program = argv[i];
    else
      o.machine_path = argv[i];
  }
  if (o.program.empty()) {
    fmt::print(
        stderr,
        "usage: gmotion_latency PROGRAM [MACHINE.toml] [--no-servo] [--summary] [--repeat R]\n");
    return 2;
  }
  gm::RunConfig cfg;
  cfg.machine =
      o.machine_path.empty() ? gm::default_machine() : gm::load_machine_file(o.machine_path);
  cfg.servo = o.servo;

  std::vector<std::uint32_t> step_ns;
  const double wall_s = timed_run(o, cfg, step_ns);
  const Histogram first = histogram(step_ns);
  for (int r = 1; r < o.repeat; ++r) timed_run(o, cfg, step_ns);
  const Histogram best = histogram(step_ns);

  // The machine's own interruptions: spin as long as one run took, reading the clock, and count
  // the gaps over 5 us (timer ticks, other processes, the hypervisor).
  std::uint64_t gaps = 0;
  const auto spin_end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(wall_s));
  for (auto prev = Clock::now(); prev < spin_end;) {
    const auto now = Clock::now();
    if (now - prev > std::chrono::microseconds(5)) ++gaps;
    prev = now;
  }

  fmt::print("program {}: {} samples, {:.3f} s a run ({:.2f} M samples/s; {}, servo {}{})\n",
             o.program, first.count, wall_s, static_cast<double>(first.count) / wall_s / 1e6,
             cfg.machine.profile, o.servo ? "on" : "off",
             o.with_summary ? ", with run summary" : "");
  print_percentiles("step, one run", first);
  if (o.repeat > 1)
    print_percentiles(fmt::format("step, fastest of {} runs per sample", o.repeat).c_str(), best);
  fmt::print(
      "machine: {} gaps over 5 us while only reading the clock for {:.3f} s ({:.0f}/s; the run: "
      "{:.0f}/s)\n",
      gaps, wall_s, static_cast<double>(gaps) / wall_s,
      static_cast<double>(first.over(5000)) / wall_s);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    fmt::print(stderr, "gmotion_latency: {}\n", e.what());
    return 1;
  }
}
