// ServoMatch: a matched axis's Acc/Dec and matching taps applied together, rounded once.
#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "common/status.hpp"
#include "servo/servo_match.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

namespace {

gm::Taps taps_121() {
  gm::Taps t;
  t.profile = "1 2 1";
  t.N = 2;
  t.integer = {1, 2, 1};
  t.b_s = 4;
  return t;
}

}  // namespace

TEST_CASE("servo matching: b and F together, rounded once (worked by hand)") {
  // b = {1, 2, 1} (b_s = 4), F = {S − 1000, 1000} with S = 2^24: c = b ∗ F = {S − 1000,
  // 2S − 1000, S + 1000, 1000}, Σ = 4S. A step of 10 counts at k = 0:
  //   y0 = 10·(S − 1000)/4S = 2.5 − 0.0015  -> 2   (the FIR alone: 2.5 -> 3)
  //   y1 = 10·(3S − 2000)/4S = 7.5 − 0.0012 -> 7   (the FIR alone: 7.5 -> 8)
  //   y2 = 10·(4S − 1000)/4S = 10 − 0.0006  -> 10
  //   y3 = 10, and the input from there on.
  constexpr std::int64_t S = gm::MatchTaps::kScale;
  gm::MatchTaps f;
  f.axis = 1;
  f.integer = {S - 1000, 1000};
  auto cmd = std::make_unique<gm::BluColumns>();
  auto ref = std::make_unique<gm::BluColumns>();
  for (int i = 0; i < 8; ++i) cmd->v[1][i] = 10, ref->v[1][i] = -99, ref->v[0][i] = -7;
  gm::ServoMatch match(taps_121(), {f});
  CHECK(match.length() == 4);
  match.apply(*cmd, *ref, 0, 3);
  match.apply(*cmd, *ref, 3, 5);  // in two calls: the history carries over
  const std::vector<std::int64_t> want = {2, 7, 10, 10, 10, 10, 10, 10};
  for (int i = 0; i < 8; ++i) {
    CAPTURE(i);
    CHECK(ref->v[1][i] == want[static_cast<std::size_t>(i)]);
    CHECK(ref->v[0][i] == -7);  // other axes untouched
  }
  CHECK(match.settled());
  // The FIR alone rounds half away: 3 and 8.
  gm::FirAccDec fir(taps_121(), gm::AxisBlu::Zero(), gm::FirStructure::Auto, 1);
  gm::AxisBlu in = gm::AxisBlu::Zero(), out = gm::AxisBlu::Zero();
  in[0] = 10;
  fir.step(in, out);
  CHECK(out[0] == 3);
  fir.step(in, out);
  CHECK(out[0] == 8);
}

TEST_CASE("servo matching: the taps must sum to the scale") {
  gm::MatchTaps f;
  f.axis = 0;
  f.integer = {gm::MatchTaps::kScale - 1};
  CHECK_THROWS_AS(gm::ServoMatch(taps_121(), {f}), gm::InputError);
  f.integer = {gm::MatchTaps::kScale};
  f.axis = gm::kMaxAxes;
  CHECK_THROWS_AS(gm::ServoMatch(taps_121(), {f}), gm::InputError);
  // Σ right, but b ∗ F has a weight of 2^62 (b = {1, 2, 1}, F = {S − B, B}: c_2 = F_0 + 2·F_1 =
  // S + B with B = 2^62 − S): refused, where B − 1 is taken.
  f.axis = 0;
  constexpr std::int64_t big = (std::int64_t{1} << 62) - gm::MatchTaps::kScale;
  f.integer = {gm::MatchTaps::kScale - big, big};
  CHECK_THROWS_AS(gm::ServoMatch(taps_121(), {f}), gm::InputError);
  f.integer = {gm::MatchTaps::kScale - (big - 1), big - 1};
  CHECK_NOTHROW(gm::ServoMatch(taps_121(), {f}));
}

TEST_CASE("servo matching: a long move ends exactly where the command does") {
  // The feedforward machine's Y taps are not needed for this: any F with Σ = S. A move of
  // 123,457 counts over 500 samples, then rest: once the last len inputs are equal the output
  // is the input, bit for bit, whatever the rounding before.
  constexpr std::int64_t S = gm::MatchTaps::kScale;
  gm::MatchTaps f;
  f.axis = 0;
  f.integer = {S + 31'000, -52'000, 17'000, 4'000};
  gm::ServoMatch match(gm::design_taps("blackman", 0.164, 0.004), {f});
  auto cmd = std::make_unique<gm::BluColumns>();
  auto ref = std::make_unique<gm::BluColumns>();
  std::int64_t last = 0;
  for (int block = 0; block < 4; ++block) {
    for (int i = 0; i < gm::kBlockSamples; ++i) {
      const int k = block * gm::kBlockSamples + i;
      cmd->v[0][i] = k < 500 ? (123'457LL * k) / 500 : 123'457;
    }
    match.apply(*cmd, *ref, 0, gm::kBlockSamples);
    last = ref->v[0][gm::kBlockSamples - 1];
  }
  CHECK(last == 123'457);
  CHECK(match.settled());
}

TEST_CASE("servo matching: F = identity gives the Acc/Dec filter's output, ties and all") {
  // With F = {S} the matched axis's reference is the FIR's own output, rounded half away as
  // FirAccDec rounds it: a random walk of steps up to ±3,000 counts (ties of b_s = 4 taps
  // {1, 2, 1} are frequent) and the Blackman taps, against FirAccDec bit for bit.
  for (const gm::Taps& taps : {taps_121(), gm::design_taps("blackman", 0.164, 0.004)}) {
    gm::MatchTaps f;
    f.axis = 0;
    f.integer = {gm::MatchTaps::kScale};
    gm::ServoMatch match(taps, {f});
    gm::FirAccDec fir(taps, gm::AxisBlu::Zero(), gm::FirStructure::Auto, 1);
    auto cmd = std::make_unique<gm::BluColumns>();
    auto ref = std::make_unique<gm::BluColumns>();
    std::mt19937_64 rng(20261130);
    std::int64_t x = 0;
    int mismatches = 0;
    for (int block = 0; block < 20; ++block) {
      for (int i = 0; i < gm::kBlockSamples; ++i) {
        x += static_cast<std::int64_t>(rng() % 6001) - 3000;
        cmd->v[0][i] = x;
      }
      match.apply(*cmd, *ref, 0, gm::kBlockSamples);
      for (int i = 0; i < gm::kBlockSamples; ++i) {
        gm::AxisBlu in = gm::AxisBlu::Zero(), out = gm::AxisBlu::Zero();
        in[0] = cmd->v[0][i];
        fir.step(in, out);
        mismatches += out[0] == ref->v[0][i] ? 0 : 1;
      }
    }
    CAPTURE(taps.profile);
    CHECK(mismatches == 0);
  }
}

TEST_CASE("servo matching: the sums against 128-bit integers, far from the origin too") {
  // Random F near the identity and random walks at positions up to 2^50 and past 2^52 (where
  // the double sum is not used): every output equals round_half_away(Σ c_i x[k−i] / (b_s S))
  // computed here in 128 bits from the positions themselves.
  __extension__ using I128 = __int128;
  constexpr std::int64_t S = gm::MatchTaps::kScale;
  const gm::Taps taps = gm::design_taps("hann", 0.08, 0.004);
  std::mt19937_64 rng(7);
  for (const std::int64_t origin :
       {std::int64_t{0}, std::int64_t{1} << 50, std::int64_t{3} << 52}) {
    gm::MatchTaps f;
    f.axis = 2;
    f.integer.assign(12, 0);
    std::int64_t rest = S;
    for (std::size_t j = 1; j < f.integer.size(); ++j) {
      f.integer[j] = static_cast<std::int64_t>(rng() % 200001) - 100000;
      rest -= f.integer[j];
    }
    f.integer[0] = rest;
    std::vector<std::int64_t> c(taps.integer.size() + f.integer.size() - 1, 0);
    for (std::size_t i = 0; i < taps.integer.size(); ++i)
      for (std::size_t j = 0; j < f.integer.size(); ++j) c[i + j] += taps.integer[i] * f.integer[j];
    const I128 scale = static_cast<I128>(taps.b_s) * S;
    gm::ServoMatch match(taps, {f});
    auto cmd = std::make_unique<gm::BluColumns>();
    auto ref = std::make_unique<gm::BluColumns>();
    std::vector<std::int64_t> all;
    std::int64_t x = origin;
    int wrong = 0;
    for (int block = 0; block < 8; ++block) {
      for (int i = 0; i < gm::kBlockSamples; ++i) {
        x += static_cast<std::int64_t>(rng() % 20001) - 10000;
        cmd->v[2][i] = x;
        all.push_back(x);
      }
      match.apply(*cmd, *ref, 0, gm::kBlockSamples);
      for (int i = 0; i < gm::kBlockSamples; ++i) {
        const std::size_t k = all.size() - gm::kBlockSamples + static_cast<std::size_t>(i);
        I128 sum = 0;  // before the first sample the history is 0
        for (std::size_t j = 0; j < c.size(); ++j)
          sum += static_cast<I128>(c[j]) * (j <= k ? all[k - j] : 0);
        const I128 mag = (sum < 0 ? -sum : sum) + scale / 2;
        const auto q = static_cast<std::int64_t>(mag / scale);
        wrong += ref->v[2][i] == (sum < 0 ? -q : q) ? 0 : 1;
      }
    }
    CAPTURE(origin);
    CHECK(wrong == 0);
  }
}
