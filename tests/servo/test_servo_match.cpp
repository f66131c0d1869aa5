// ServoMatch: a matched axis's Acc/Dec and matching taps applied together, rounded once.
#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "common/status.hpp"
#include "servo/servo_match.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <memory>
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
