// Micro-benchmarks per stage: parse+interpret MB/s, interpolator, FIR per profile and tap
// count, servo, CSV trace rows and the whole pipeline, in samples (or bytes) per second.
#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "common/block_columns.hpp"
#include "common/isa.hpp"
#include "grammar/parse.hpp"
#include "interp/program.hpp"
#include "interpolator/interpolator.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/pipeline.hpp"
#include "planner/arc_residual_table.hpp"
#include "planner/filter_moments.hpp"
#include "servo/servo_axis.hpp"
#include "servo/servo_bank.hpp"
#include "support/sample_stepper.hpp"
#include "trace/trace_writer.hpp"

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace {

// A program of `blocks` blocks mixing G1 and G2/G3 (IJK and R), deterministic.
std::string program_text(int blocks) {
  std::string t = "G21 G90 G64 G17 F1200\n";
  double x = 0, y = 0;
  for (int i = 0; i < blocks; ++i) {
    switch (i % 4) {
      case 0:
        x += 1.5;
        t += fmt::format("G1 X{:.3f} Y{:.3f}\n", x, y);
        break;
      case 1:
        t += fmt::format("G2 X{:.3f} Y{:.3f} I0.5 J0\n", x + 1.0, y);
        x += 1.0;
        break;
      case 2:
        y += 1.0;
        t += fmt::format("G1 X{:.3f} Y{:.3f} F1500\n", x, y);
        break;
      default:
        t += fmt::format("G3 X{:.3f} Y{:.3f} R0.5\n", x - 1.0, y);
        x -= 1.0;
        break;
    }
  }
  return t + "M2\n";
}

void BM_ParseInterpret(benchmark::State& state) {
  const std::string text = program_text(20000);
  const gm::Machine m = gm::default_machine();
  for (auto _ : state) {
    std::istringstream in(text);
    std::ostringstream diag;
    const auto s = gm::check_program(in, "bench.nc", gm::InterpreterOptions{&m, false}, diag);
    benchmark::DoNotOptimize(s.moves);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
  state.SetItemsProcessed(state.iterations() * 20000);  // blocks
}
BENCHMARK(BM_ParseInterpret)->Unit(benchmark::kMillisecond)->UseRealTime();  // two threads

void BM_Parse(benchmark::State& state) {
  // The grammar alone (compaction, X3 rule, number conversion), line by line.
  const std::string text = program_text(20000);
  std::vector<std::string_view> lines;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t nl = text.find('\n', at);
    lines.emplace_back(text.data() + at, nl - at);
    at = nl + 1;
  }
  gm::grammar::BlockParser parser;
  gm::grammar::Block block;
  for (auto _ : state) {
    int n = 0;
    for (const auto& l : lines) parser.parse(l, ++n, block);
    benchmark::DoNotOptimize(block.words.size());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * lines.size()));  // lines
}
BENCHMARK(BM_Parse)->Unit(benchmark::kMillisecond);

void BM_Fir(benchmark::State& state, const char* profile) {
  const double tau = static_cast<double>(state.range(0)) * 0.004;
  const gm::Taps taps = gm::design_taps(profile, tau, 0.004);
  gm::FirAccDec fir(taps, gm::AxisBlu::Zero());
  gm::AxisBlu in = gm::AxisBlu::Zero(), out;
  std::int64_t k = 0;
  for (auto _ : state) {
    in += gm::blu3(40 + (k & 7), -20, 3);
    fir.step(in, out);
    benchmark::DoNotOptimize(out);
    ++k;
  }
  state.SetItemsProcessed(state.iterations());  // samples (3 axes each)
}
BENCHMARK_CAPTURE(BM_Fir, linear, "linear")->Arg(11)->Arg(41)->Arg(161);
BENCHMARK_CAPTURE(BM_Fir, blackman, "blackman")->Arg(11)->Arg(41)->Arg(161);
BENCHMARK_CAPTURE(BM_Fir, scurve2, "scurve2")->Arg(41);

// Eight blocks of three axes moving on a circle of `radius_blu` (one turn over the eight
// blocks; Z climbs one BLU every 16 samples), replayed by the FIR benchmarks.
std::vector<gm::BluColumns> circle_blocks(double radius_blu) {
  constexpr int kBlocks = 8;
  std::vector<gm::BluColumns> in(kBlocks);
  for (int b = 0; b < kBlocks; ++b)
    for (int i = 0; i < gm::kBlockSamples; ++i) {
      const double u =
          2 * 3.141592653589793 * (b * gm::kBlockSamples + i) / (kBlocks * gm::kBlockSamples);
      in[static_cast<std::size_t>(b)].v[0][i] = std::llround(radius_blu * std::cos(u));
      in[static_cast<std::size_t>(b)].v[1][i] = std::llround(radius_blu * std::sin(u));
      in[static_cast<std::size_t>(b)].v[2][i] = i / 16;
    }
  return in;
}

// Per-sample step_n<3> against step_block<3> on the same input: eight blocks of three axes
// moving on a circle (radius 4000 BLU, one turn every 2,048 samples), replayed; Arg(0): step_n,
// Arg(1): step_block; the second argument is the instruction set (0 portable, 1 AVX2,
// 2 AVX-512; a set the CPU lacks is skipped). Samples per second count three axes each.
void BM_FirBlock(benchmark::State& state, const char* profile) {
  const gm::Taps taps = gm::design_taps(profile, 0.164, 0.004);  // 41 taps
  gm::FirAccDec fir(taps, gm::AxisBlu::Zero());
  const auto isa = static_cast<gm::Isa>(state.range(1));
  if (static_cast<int>(isa) > static_cast<int>(gm::active_isa())) {
    state.SkipWithError("instruction set not available");
    return;
  }
  fir.set_isa_for_testing(isa);
  std::vector<gm::BluColumns> in = circle_blocks(4000), out(in.size());
  const std::size_t blocks = in.size();
  const bool block = state.range(0) != 0;
  gm::AxisBlu x = gm::AxisBlu::Zero(), y = gm::AxisBlu::Zero();
  std::size_t b = 0;
  for (auto _ : state) {
    const gm::BluColumns& c = in[b];
    gm::BluColumns& o = out[b];
    if (block) {
      fir.step_block<3>(c, o, gm::kBlockSamples);
    } else {
      for (int i = 0; i < gm::kBlockSamples; ++i) {
        x[0] = c.v[0][i], x[1] = c.v[1][i], x[2] = c.v[2][i];
        fir.step_n<3>(x, y);
        o.v[0][i] = y[0], o.v[1][i] = y[1], o.v[2][i] = y[2];
      }
    }
    benchmark::DoNotOptimize(o);
    b = b + 1 == blocks ? 0 : b + 1;
  }
  state.SetItemsProcessed(state.iterations() * gm::kBlockSamples);  // samples (3 axes each)
  state.SetLabel(gm::isa_name(isa));
}
BENCHMARK_CAPTURE(BM_FirBlock, blackman, "blackman")
    ->ArgsProduct({{0, 1}, {0, 1, 2}})
    ->ArgNames({"block", "isa"});
BENCHMARK_CAPTURE(BM_FirBlock, linear, "linear")
    ->ArgsProduct({{0, 1}, {0, 1, 2}})
    ->ArgNames({"block", "isa"});

void BM_Servo(benchmark::State& state) {
  const gm::Machine m = gm::default_machine();
  gm::ServoAxis s(m.axes[0], m.period_s, 1, 0);
  std::int64_t ref = 0, k = 0;
  for (auto _ : state) {
    ref = static_cast<std::int64_t>(4000 * std::sin(0.015 * static_cast<double>(k++)));
    benchmark::DoNotOptimize(s.step(ref));
  }
  state.SetItemsProcessed(state.iterations());  // samples of one axis
}
BENCHMARK(BM_Servo);

// The servo references of `axes` axes over a block: sines of different phases (axis a lags
// by a), 4000 BLU amplitude, so the loop moves, reverses and sometimes saturates.
void servo_refs(gm::BluColumns& ref, int axes, std::int64_t k0) {
  for (int a = 0; a < axes; ++a)
    for (int i = 0; i < gm::kBlockSamples; ++i)
      ref.v[a][i] =
          static_cast<std::int64_t>(4000 * std::sin(0.015 * static_cast<double>(k0 + i) + 0.7 * a));
}

// Three ServoAxis objects stepped sample by sample (the pipeline's servo before ServoBank),
// on the built-in machine; items = samples (of all three axes).
void BM_ServoAxes3(benchmark::State& state) {
  const gm::Machine m = gm::default_machine();
  std::vector<gm::ServoAxis> s;
  for (int a = 0; a < 3; ++a)
    s.emplace_back(m.axes[static_cast<std::size_t>(a)], m.period_s, m.servo_substeps, 0);
  auto ref = std::make_unique<gm::BluColumns>();
  auto enc = std::make_unique<gm::BluColumns>();
  auto table = std::make_unique<gm::RealColumns>();
  std::int64_t k = 0;
  for (auto _ : state) {
    state.PauseTiming();
    servo_refs(*ref, 3, k);
    state.ResumeTiming();
    for (int i = 0; i < gm::kBlockSamples; ++i)
      for (int a = 0; a < 3; ++a) {
        auto& x = s[static_cast<std::size_t>(a)];
        table->v[a][i] = x.table_blu();
        enc->v[a][i] = x.step(ref->v[a][i]);
      }
    benchmark::DoNotOptimize(enc->v[0][gm::kBlockSamples - 1]);
    k += gm::kBlockSamples;
  }
  state.SetItemsProcessed(state.iterations() * gm::kBlockSamples);
}
BENCHMARK(BM_ServoAxes3);

// ServoBank::step_block<N> on the built-in machine's axes (copied to N axes), on instruction
// set Arg(0) (0 portable, 1 AVX2, 2 AVX-512; skipped when the CPU lacks it), Arg(1) rows per
// call (256: whole blocks; 1: the pipeline's single-sample path). Items = samples (N axes each).
template <int N>
void BM_ServoBank(benchmark::State& state) {
  const auto isa = static_cast<gm::Isa>(state.range(0));
  if (static_cast<int>(isa) > static_cast<int>(gm::active_isa())) {
    state.SkipWithError("the CPU lacks this instruction set");
    return;
  }
  const int rows = static_cast<int>(state.range(1));
  gm::Machine m = gm::default_machine();
  if (N > m.axis_count())
    m.set_axes(*gm::AxisLayout::of(std::string("XYZABCUVW").substr(0, N)), m.axes[0]);
  gm::ServoBank bank(m, N, m.period_s, m.servo_substeps);
  bank.set_isa_for_testing(isa);
  auto ref = std::make_unique<gm::BluColumns>();
  auto enc = std::make_unique<gm::BluColumns>();
  auto table = std::make_unique<gm::RealColumns>();
  std::int64_t k = 0;
  for (auto _ : state) {
    state.PauseTiming();
    servo_refs(*ref, N, k);
    state.ResumeTiming();
    for (int first = 0; first < gm::kBlockSamples; first += rows)
      benchmark::DoNotOptimize(bank.step_block<N>(*ref, *enc, *table, first, rows));
    benchmark::DoNotOptimize(enc->v[0][gm::kBlockSamples - 1]);
    k += gm::kBlockSamples;
  }
  state.SetLabel(std::string(gm::isa_name(isa)) + (bank.lanes() ? ", lanes" : ", ServoAxis"));
  state.SetItemsProcessed(state.iterations() * gm::kBlockSamples);
}
BENCHMARK_TEMPLATE(BM_ServoBank, 3)->ArgsProduct({{0, 1, 2}, {256, 1}});
BENCHMARK_TEMPLATE(BM_ServoBank, 6)->ArgsProduct({{0, 1, 2}, {256, 1}});
BENCHMARK_TEMPLATE(BM_ServoBank, 9)->ArgsProduct({{0, 1, 2}, {256, 1}});

// The FIR (Blackman, 41 taps) then the servo lanes over a block, three axes, the pipeline's
// order, on the circle of BM_FirBlock scaled up (radius 40,000 BLU). Arg(0) = 0: the whole
// block through the FIR, then through the servo (stage after stage). Arg(0) = C: chunks of C
// rows, the FIR one chunk ahead of the servo, so the FIR's independent work can run in the
// servo's dependency chain. Items = samples (three axes each).
void BM_FirServo(benchmark::State& state) {
  const int chunk = static_cast<int>(state.range(0));
  const gm::Machine m = gm::default_machine();
  gm::FirAccDec fir(gm::design_taps("blackman", 0.164, m.period_s), gm::AxisBlu::Zero());
  gm::ServoBank bank(m, 3, m.period_s, m.servo_substeps);
  const std::vector<gm::BluColumns> in = circle_blocks(40000);
  const std::size_t blocks = in.size();
  auto ref = std::make_unique<gm::BluColumns>();
  auto enc = std::make_unique<gm::BluColumns>();
  auto table = std::make_unique<gm::RealColumns>();
  std::size_t b = 0;
  constexpr int n = gm::kBlockSamples;
  for (auto _ : state) {
    const gm::BluColumns& c = in[b];
    if (chunk == 0) {
      fir.step_block<3>(c, *ref, 0, n);
      benchmark::DoNotOptimize(bank.step_block<3>(*ref, *enc, *table, 0, n));
    } else {
      fir.step_block<3>(c, *ref, 0, chunk);
      for (int f = 0; f < n; f += chunk) {
        if (f + chunk < n) fir.step_block<3>(c, *ref, f + chunk, std::min(chunk, n - f - chunk));
        benchmark::DoNotOptimize(bank.step_block<3>(*ref, *enc, *table, f, std::min(chunk, n - f)));
      }
    }
    benchmark::DoNotOptimize(enc->v[0][n - 1]);
    b = b + 1 == blocks ? 0 : b + 1;
  }
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_FirServo)->Arg(0)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Arg(128);

// The tolerance planner's residual table (docs/tolerance.md, "Planning cost"): nodes simulated
// per second, the default machine's filter (blackman, tau 0.164 s, T 4 ms). Each iteration fills
// the 64 nodes about 16 arcs of R 10 mm (sweeps 0.1 to 3 rad, rates near the planner's arc
// speeds) in a fresh table, as a program's first arcs do.
void BM_ArcResidualNodes(benchmark::State& state) {
  const gm::FilterMoments filter(gm::design_taps("blackman", 0.164, 0.004), 0.004);
  const gm::ArcPrecompCheck check(filter.weights(), filter.period_s());
  std::size_t nodes = 0;
  for (auto _ : state) {
    const gm::ArcResidualTable table(check);
    double sum = 0.0;
    for (int a = 0; a < 16; ++a) {
      const double sweep = 0.1 * std::pow(30.0, a / 15.0), R = 10.0, v = 20.0 + 7.0 * a;
      sum += table.error_bound_mm(check, R, sweep, R * sweep, v);
    }
    benchmark::DoNotOptimize(sum);
    nodes += table.nodes_filled();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(nodes));  // nodes
}
BENCHMARK(BM_ArcResidualNodes)->Unit(benchmark::kMillisecond);

class TextSource : public gm::CanonSource {
 public:
  explicit TextSource(const std::string& text, const gm::Machine& m)
      : in_(text), stream_(in_, "bench.nc", gm::InterpreterOptions{&m, false}) {}
  bool next(gm::Canon& c) override { return stream_.next(c); }

 private:
  std::istringstream in_;
  gm::ProgramStream stream_;
};

void BM_Interpolator(benchmark::State& state) {
  const gm::Machine m = gm::default_machine();
  const std::string text = program_text(2000);
  std::int64_t samples = 0;
  for (auto _ : state) {
    TextSource src(text, m);
    gm::InterpolatorConfig cfg;
    gm::Interpolator ip(cfg, src);
    gm::CommandSample s;
    while (ip.step(gm::OverrideInput{}, s) == gm::InterpStatus::Working) ++samples;
  }
  state.SetItemsProcessed(samples);
}
BENCHMARK(BM_Interpolator)->Unit(benchmark::kMillisecond);

void BM_Pipeline(benchmark::State& state) {
  const gm::Machine m = gm::default_machine();
  const std::string text = program_text(2000);
  std::int64_t samples = 0;
  for (auto _ : state) {
    TextSource src(text, m);
    gm::RunConfig cfg;
    cfg.machine = m;
    cfg.servo = state.range(0) != 0;
    gmtest::SampleStepper p(cfg, src);
    gm::SampleRecord r;
    while (p.step(gm::OverrideInput{}, r) == gm::PipelineStatus::Working) ++samples;
  }
  state.SetItemsProcessed(samples);
}
BENCHMARK(BM_Pipeline)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_TraceCsv(benchmark::State& state) {
  gm::TraceMeta meta;
  meta.period_s = 0.004;
  gm::TraceWriter w("/dev/null", gm::TraceFormat::Csv, meta);
  // Blocks of rows as a run hands them on: x_cmd climbing, the other columns constant.
  auto b = std::make_unique<gm::SampleBlock>();
  b->reset(1);
  b->count = gm::kBlockSamples;
  for (int i = 0; i < gm::kBlockSamples; ++i) {
    for (int a = 0; a < 3; ++a) b->cmd_blu.v[a][i] = b->enc_blu.v[a][i] = 0;
    b->cmd_blu.v[0][i] = 40 * (i + 1);
    b->cmd_blu.v[1][i] = -3 * (i + 1);
    b->cmd_blu.v[2][i] = i + 1;
    b->ref_blu.v[0][i] = 123456;
    b->ref_blu.v[1][i] = -7890;
    b->ref_blu.v[2][i] = 12;
    b->line[i] = 0;
    b->feed_scale[i] = 1.0;
    b->contour_err_blu[i] = 0.0;
  }
  for (auto _ : state) {
    w.consume(*b, 0);
    b->k0 += gm::kBlockSamples;
  }
  w.finish();
  state.SetItemsProcessed(state.iterations() * gm::kBlockSamples);  // rows
}
BENCHMARK(BM_TraceCsv);

}  // namespace

BENCHMARK_MAIN();
