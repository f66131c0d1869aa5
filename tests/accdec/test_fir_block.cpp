// FirAccDec::step_block against step_n: every profile, structure, axis count and instruction set.
#include "accdec/fir_filter.hpp"
#include "accdec/profile_spec.hpp"
#include "accdec/profiles.hpp"
#include "accdec/taps.hpp"
#include "common/block_columns.hpp"
#include "common/isa.hpp"
#include "common/status.hpp"
#include "support/test_scale.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

using gm::AxisBlu;
using gm::BluColumns;
using gm::FirAccDec;
using gm::FirStructure;
using gm::Isa;

namespace {

constexpr std::int64_t kSentinel = 0x5a5a5a5a5a5a5a5a;

struct Case {
  std::string spec;
  int taps;  // tau = taps·T
};

// Every registry row, at lengths around the block size too (history longer than a block), a
// single tap (b_s may be 1: the fast limit is then 2^53 - 1) and two taps.
const std::vector<Case> kCases{{"linear", 41},        {"linear", 1},
                               {"linear", 300},       {"scurve1", 41},
                               {"scurve2", 41},       {"scurve2", 7},
                               {"blackman", 41},      {"blackman", 11},
                               {"blackman", 290},     {"blackman@max", 24},
                               {"hann", 41},          {"hamming", 40},
                               {"kaiser:6", 33},      {"custom:0.5,1,2,1,0.5", 5},
                               {"custom:0,3,0,1", 4}, {"custom:1,1", 2},
                               {"custom:3", 1},       {"cascade:21,21", 41},
                               {"cascade:7,5,3", 13}, {"cascade:1", 1},
                               {"zv:45", 4},          {"zvd:40", 8},
                               {"zvdd:40", 11},       {"mzv:45", 6},
                               {"ei:45", 7},          {"2hei:60", 8},
                               {"3hei:80", 8},        {"blackman+mzv:45", 46},
                               {"zv:45@0+zv:70@0", 6}};

std::vector<Isa> isas() {
  std::vector<Isa> out{Isa::Portable};
  if (static_cast<int>(gm::active_isa()) >= static_cast<int>(Isa::Avx2)) out.push_back(Isa::Avx2);
  if (gm::active_isa() == Isa::Avx512) out.push_back(Isa::Avx512);
  return out;
}

std::vector<FirStructure> structures(const gm::Taps& t) {
  const auto& b = t.integer;
  std::vector<FirStructure> out{FirStructure::Auto, FirStructure::Direct};
  if (std::equal(b.begin(), b.end(), b.rbegin())) out.push_back(FirStructure::Symmetric);
  if (std::all_of(b.begin(), b.end(), [&](std::int64_t x) { return x == b.front(); }))
    out.push_back(FirStructure::RunningSum);
  return out;
}

// Positions (absolute BLU) for one stretch of samples: a mix of what the pipeline sends (walks,
// holds) and what forces the exact paths (beyond the limit, sums near 2^51 and 2^53, near 2^62).
class Source {
 public:
  Source(std::mt19937_64& rng, int axes, std::int64_t limit, const AxisBlu& start)
      : rng_(rng), axes_(axes), limit_(limit), start_(start), pos_(start) {}

  AxisBlu next() {
    if (left_ == 0) pick();
    --left_;
    for (int a = 0; a < axes_; ++a) {
      std::int64_t rel = pos_[a] - start_[a];
      switch (mode_) {
        case 0:  // walk
          vel_[a] = std::clamp<std::int64_t>(vel_[a] + uni(-3, 3), -5000, 5000);
          rel += vel_[a];
          break;
        case 1:  // hold (long equal runs: settled)
          break;
        case 2:  // steps
          if (uni(0, 30) == 0) rel += uni(-100000, 100000);
          break;
        case 3:  // just inside / outside the fast limit
          rel = (uni(0, 1) ? 1 : -1) * (limit_ + uni(-40, 3));
          break;
        case 4:  // sums around 2^51: the quotient moves from double to int64 arithmetic
          rel = (uni(0, 1) ? 1 : -1) * (limit_ / 4 + uni(-3, 3));
          break;
        case 5:  // far beyond (the __int128 path), up to 2^62 - 1 away from the start
          rel = uni(-(std::int64_t{1} << 62) + 1, (std::int64_t{1} << 62) - 1);
          break;
        default:  // small random values
          rel = uni(-5000, 5000);
          break;
      }
      rel = std::clamp(rel, -(std::int64_t{1} << 62) + 1, (std::int64_t{1} << 62) - 1);
      pos_[a] = start_[a] + rel;
    }
    return pos_;
  }

 private:
  std::int64_t uni(std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng_);
  }
  void pick() {
    const int r = static_cast<int>(uni(0, 99));
    // Mostly the fast path (walks, holds, steps); now and then the exact ones.
    mode_ = r < 40 ? 0 : r < 65 ? 1 : r < 80 ? 2 : r < 86 ? 3 : r < 92 ? 4 : r < 95 ? 5 : 6;
    left_ = static_cast<int>(mode_ == 1 ? uni(1, 700) : uni(1, 300));
    if (mode_ > 2) return;
    // Out of the exact stretches: back near the start, so the fast path takes over again.
    for (int a = 0; a < axes_; ++a)
      if (pos_[a] - start_[a] > 10000000 || pos_[a] - start_[a] < -10000000) {
        pos_[a] = start_[a] + uni(-1000, 1000);
        vel_[a] = 0;
      }
  }

  std::mt19937_64& rng_;
  int axes_;
  std::int64_t limit_;
  AxisBlu start_, pos_;
  AxisBlu vel_ = AxisBlu::Zero();
  int mode_ = 0, left_ = 0;
};

// Feeds `samples` positions to a step_n-only filter and to one driven by random block sizes,
// mixed with step_n (unless `blocks_only`); every output and settled() must agree.
void compare(const gm::Taps& taps, FirStructure s, int axes, Isa isa, std::uint64_t seed,
             int samples, bool blocks_only) {
  std::mt19937_64 rng(seed);
  auto uni = [&](std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng);
  };
  AxisBlu start = AxisBlu::Zero();
  const bool far_start = uni(0, 3) == 0;  // starts near ±2^61: absolute values near 2^62
  for (int a = 0; a < axes; ++a)
    start[a] = far_start ? (uni(0, 1) ? 1 : -1) * ((std::int64_t{1} << 61) - uni(0, 1000))
                         : uni(-1000000, 1000000);
  FirAccDec ref(taps, start, s, axes), blk(taps, start, s, axes);
  blk.set_isa_for_testing(isa);
  REQUIRE(blk.isa() == isa);
  Source src(rng, axes, ref.exact_limit(), start);
  auto in = std::make_unique<BluColumns>();
  auto out = std::make_unique<BluColumns>();
  AxisBlu x = AxisBlu::Zero(), y_ref = AxisBlu::Zero(), y = AxisBlu::Zero();
  int done = 0;
  while (done < samples) {
    // Block sizes 1..256: full blocks most often, as the pipeline sends them.
    const int r = static_cast<int>(uni(0, 9));
    const int n = r < 4 ? gm::kBlockSamples : static_cast<int>(uni(1, gm::kBlockSamples));
    const bool per_sample = !blocks_only && uni(0, 4) == 0;
    // A shorter block sometimes sits further down the columns (step_block's `first`).
    const int first = n < gm::kBlockSamples && uni(0, 1) == 1
                          ? static_cast<int>(uni(0, gm::kBlockSamples - n))
                          : 0;
    for (auto& col : out->v) std::fill(std::begin(col), std::end(col), kSentinel);
    std::vector<AxisBlu> expected;
    for (int i = 0; i < n; ++i) {
      x = src.next();
      for (int a = 0; a < gm::kMaxAxes; ++a) in->v[a][first + i] = a < axes ? x[a] : kSentinel;
      gm::with_axis_count(axes, [&](auto c) { ref.step_n<decltype(c)::value>(x, y_ref); });
      expected.push_back(y_ref);
      if (per_sample) {
        gm::with_axis_count(axes, [&](auto c) { blk.step_n<decltype(c)::value>(x, y); });
        for (int a = 0; a < axes; ++a) REQUIRE(y[a] == y_ref[a]);
        REQUIRE(blk.settled() == ref.settled());
      }
    }
    if (!per_sample) {
      gm::with_axis_count(axes,
                          [&](auto c) { blk.step_block<decltype(c)::value>(*in, *out, first, n); });
      for (int i = 0; i < n; ++i)
        for (int a = 0; a < axes; ++a) {
          INFO("sample " << done + i << " of block [" << done << ", " << done + n << ") at row "
                         << first << " axis " << a << " in " << in->v[a][first + i] << " start "
                         << start[a]);
          REQUIRE(out->v[a][first + i] == expected[static_cast<std::size_t>(i)][a]);
        }
      // Nothing outside the block's rows or past the axis count is written.
      for (int a = 0; a < gm::kMaxAxes; ++a)
        for (int i = 0; i < gm::kBlockSamples; ++i)
          if (a >= axes || i < first || i >= first + n) REQUIRE(out->v[a][i] == kSentinel);
    }
    REQUIRE(blk.settled() == ref.settled());
    done += n;
  }
}

std::uint64_t test_seed() {
  // GMOTION_SEED=<n> replays a failing run.
  const char* env = std::getenv("GMOTION_SEED");
  const std::uint64_t seed = env ? std::strtoull(env, nullptr, 10) : std::random_device{}();
  std::cout << "test_fir_block seed = " << seed << " (replay: GMOTION_SEED=" << seed << ")\n";
  return seed;
}

}  // namespace

TEST_CASE("the cases cover every profile of the registry") {
  std::set<std::string> names;
  for (const Case& c : kCases) names.insert(std::string(gm::parse_profile_spec(c.spec).name()));
  for (const gm::ProfileRow& row : gm::profile_rows()) CHECK(names.count(std::string(row.name)));
}

TEST_CASE("step_block gives step_n's outputs and settled(), mixed with step_n, on every ISA") {
  const std::uint64_t seed = test_seed();
  const double T = 0.004;
  const int axis_counts[] = {1, 3, 4, 6, 9};
  int runs = 0;
  for (const Case& c : kCases) {
    const gm::Taps taps = gm::design_taps(c.spec, c.taps * T, T);
    for (const FirStructure s : structures(taps))
      for (const int axes : axis_counts)
        for (const Isa isa : isas()) {
          const std::uint64_t run_seed = seed + static_cast<std::uint64_t>(runs++);
          CAPTURE(seed, run_seed, c.spec, c.taps, static_cast<int>(s), axes, gm::isa_name(isa));
          // At least three full blocks under the sanitizers.
          compare(taps, s, axes, isa, run_seed,
                  std::max(3 * gm::kBlockSamples, gmtest::scaled(1500)), false);
        }
  }
  CHECK(runs > 0);
}

TEST_CASE("step_block alone over long runs: blackman 41 and linear 11, three axes, every ISA") {
  const std::uint64_t seed = test_seed() ^ 0x9e3779b97f4a7c15ULL;
  const double T = 0.004;
  for (const char* spec : {"blackman", "linear", "scurve2"})
    for (const Isa isa : isas()) {
      const gm::Taps taps = gm::design_taps(spec, (spec[0] == 'l' ? 11 : 41) * T, T);
      CAPTURE(seed, spec, gm::isa_name(isa));
      compare(taps, FirStructure::Auto, 3, isa, seed, 60000, true);
    }
}

TEST_CASE("step_block refuses rows outside the block") {
  FirAccDec f(gm::design_taps("blackman", 0.164, 0.004), AxisBlu::Zero());
  auto in = std::make_unique<BluColumns>(), out = std::make_unique<BluColumns>();
  CHECK_THROWS_AS(f.step_block<3>(*in, *out, 0), gm::InputError);
  CHECK_THROWS_AS(f.step_block<3>(*in, *out, gm::kBlockSamples + 1), gm::InputError);
  CHECK_THROWS_AS(f.step_block<3>(*in, *out, -1, 2), gm::InputError);
  CHECK_THROWS_AS(f.step_block<3>(*in, *out, gm::kBlockSamples - 1, 2), gm::InputError);
  CHECK_NOTHROW(f.step_block<3>(*in, *out, gm::kBlockSamples - 2, 2));
}

TEST_CASE("a position int64 cannot hold relative to the start is refused, never wrapped") {
  // Start at INT64_MIN + 1, then INT64_MAX: the distance 2^64 - 2 wraps to -2, which looks like
  // a small move; found by fuzzing (UBSan: signed overflow in the block kernel's check).
  AxisBlu start = AxisBlu::Zero();
  start[0] = INT64_MIN + 1;
  for (const char* spec : {"linear", "blackman"})
    for (const Isa isa : isas())
      for (const int n : {5, 8})
        for (const int bad : {0, n - 1}) {
          CAPTURE(spec, gm::isa_name(isa), n, bad);
          FirAccDec f(gm::design_taps(spec, 0.044, 0.004), start);
          f.set_isa_for_testing(isa);
          auto in = std::make_unique<BluColumns>(), out = std::make_unique<BluColumns>();
          for (int i = 0; i < n; ++i) in->v[0][i] = i == bad ? INT64_MAX : start[0] + i;
          CHECK_THROWS_WITH(f.step_block<3>(*in, *out, 0, n),
                            Catch::Contains("axis 0 at 9223372036854775807 BLU is beyond int64 "
                                            "from its start at -9223372036854775807 BLU"));
        }
  FirAccDec f(gm::design_taps("linear", 0.044, 0.004), start);
  AxisBlu x = start, y;
  x[0] = INT64_MAX;
  CHECK_THROWS_AS(f.step(x, y), gm::InputError);
}

TEST_CASE("set_isa_for_testing never raises the instruction set above the CPU's") {
  FirAccDec f(gm::design_taps("blackman", 0.164, 0.004), AxisBlu::Zero());
  CHECK(f.isa() == gm::active_isa());
  f.set_isa_for_testing(Isa::Portable);
  CHECK(f.isa() == Isa::Portable);
  f.set_isa_for_testing(Isa::Avx512);
  CHECK(f.isa() == gm::active_isa());
  std::cout << "test_fir_block: instruction sets checked:";
  for (const Isa isa : isas()) std::cout << ' ' << gm::isa_name(isa);
  std::cout << '\n';
}
