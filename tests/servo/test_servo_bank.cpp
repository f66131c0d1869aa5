// ServoBank: the axes in SIMD lanes give what ServoAxis gives sample by sample, bit for bit, on
// every instruction set, block size, plant order, loop form, substep count and axis count; and
// the fallbacks (Coulomb friction, third-order plants, mixed orders, references beyond 2^51,
// a divergence) agree too.
#include "common/rounding.hpp"
#include "common/status.hpp"
#include "machine/machine_file.hpp"
#include "servo/servo_bank.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

using gm::AxisConfig;
using gm::BluColumns;
using gm::Isa;
using gm::RealColumns;

namespace {

constexpr double kBankT = 0.004;

// A machine of `n` axes whose servos differ (gains, plant, form, backlash, drive limit,
// feedforward), with plants of order `order` (1 or 2, or 3 for the fallback).
gm::Machine varied_machine(int n, int order, std::mt19937_64& rng, bool coulomb = false) {
  gm::Machine m = gm::default_machine();
  m.set_axes(*gm::AxisLayout::of(std::string("XYZABCUVW").substr(0, static_cast<std::size_t>(n))),
             m.axes[0]);
  std::uniform_real_distribution<double> f(0.7, 1.4);
  for (int a = 0; a < n; ++a) {
    AxisConfig& c = m.axes[static_cast<std::size_t>(a)];
    c = m.axes[0];
    c.kvp *= f(rng);
    c.kvi *= f(rng);
    c.kp_1_s *= f(rng);
    c.kv_form = a % 2 == 0 ? gm::VelocityLoopForm::Ip : gm::VelocityLoopForm::Pi;
    c.backlash_blu = a % 3 == 1 ? 3.0 : 0.0;
    c.f_max_N = a % 4 == 2 ? 300.0 : 4000.0;  // saturates on fast moves
    c.coulomb_N = coulomb && a == 1 ? 40.0 : 0.0;
    // Feedforward on some axes (none, the shipped pair, velocity only, acceleration only).
    c.ff1 = a % 4 == 1 ? 0.857 : a % 4 == 2 ? 1.0 : 0.0;
    c.ff2_s = a % 4 == 1 ? 0.01431 : a % 4 == 3 ? 0.02 : 0.0;
    const double p = 14.45 * f(rng);
    if (order == 1) {
      c.plant_num = {33.518};
      c.plant_den = {1.0, p};
    } else if (order == 2) {
      c.plant_num = {33.518 * 400.0};
      c.plant_den = {1.0, p + 400.0, 400.0 * p};
    } else {
      c.plant_num = {33.518 * 400.0 * 900.0};
      c.plant_den = {1.0, p + 1300.0, 1300.0 * p + 360000.0, 360000.0 * p};
    }
    c.drive_N_per_unit = 400.0;
  }
  return m;
}

// References like an Acc/Dec output: smooth moves, steps (saturation), reversals, standstill.
std::vector<std::int64_t> reference(int samples, std::mt19937_64& rng) {
  std::vector<std::int64_t> r(static_cast<std::size_t>(samples));
  double x = 0.0, v = 0.0;
  for (int i = 0; i < samples; ++i) {
    const auto phase = (i / 300) % 4;
    if (phase == 0) v += std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
    if (phase == 1) v = 0.0;                                                 // standstill: hunting
    if (phase == 2 && i % 300 == 0) x += (rng() % 2 ? 1.0 : -1.0) * 4000.0;  // a step
    if (phase == 3) v = -v * 0.99;                                           // reversals
    x += v;
    r[static_cast<std::size_t>(i)] = std::llround(x);
  }
  return r;
}

struct Outcome {
  std::vector<std::int64_t> enc;
  std::vector<double> table;
  std::vector<int> quiet;
  int rows = 0;
  std::string error;
};

// The reference: one ServoAxis per axis, stepped sample by sample as the pipeline did.
template <int N>
Outcome per_axis(const gm::Machine& m, int substeps,
                 const std::vector<std::vector<std::int64_t>>& ref) {
  std::vector<gm::ServoAxis> axes;
  for (int a = 0; a < N; ++a)
    axes.emplace_back(m.axes[static_cast<std::size_t>(a)], kBankT, substeps, 0);
  Outcome o;
  int quiet = 0;
  for (std::size_t i = 0; i < ref[0].size(); ++i, ++o.rows) {
    bool q = true;
    for (int a = 0; a < N; ++a) {
      auto& s = axes[static_cast<std::size_t>(a)];
      o.table.push_back(s.table_blu());
      try {
        const std::int64_t e = s.step(ref[static_cast<std::size_t>(a)][i]);
        o.enc.push_back(e);
        q = q && std::llabs(e - ref[static_cast<std::size_t>(a)][i]) <= 1;
      } catch (const gm::InputError& e) {
        o.error = std::to_string(a) + ": " + e.what();
        o.table.resize(o.table.size() - static_cast<std::size_t>(a + 1));
        o.enc.resize(o.enc.size() - static_cast<std::size_t>(a));
        return o;
      }
    }
    quiet = q ? quiet + 1 : 0;
    o.quiet.push_back(quiet);
  }
  return o;
}

// The bank over blocks of random sizes (1..256, from random first rows).
template <int N>
Outcome banked(const gm::Machine& m, int substeps,
               const std::vector<std::vector<std::int64_t>>& ref, Isa isa, std::mt19937_64& rng,
               bool* used_lanes = nullptr) {
  gm::ServoBank bank(m, N, kBankT, substeps);
  bank.set_isa_for_testing(isa);
  if (used_lanes != nullptr) *used_lanes = bank.lanes();
  auto in = std::make_unique<BluColumns>();
  auto enc = std::make_unique<BluColumns>();
  auto table = std::make_unique<RealColumns>();
  Outcome o;
  const int total = static_cast<int>(ref[0].size());
  int k = 0;
  while (k < total) {
    const int first = static_cast<int>(rng() % 64);
    const int n = std::min({total - k, gm::kBlockSamples - first,
                            1 + static_cast<int>(rng() % (rng() % 2 ? 256 : 4))});
    for (int a = 0; a < N; ++a)
      for (int i = 0; i < n; ++i)
        in->v[a][first + i] = ref[static_cast<std::size_t>(a)][static_cast<std::size_t>(k + i)];
    const int done = bank.step_block<N>(*in, *enc, *table, first, n);
    for (int i = 0; i < done; ++i) {
      for (int a = 0; a < N; ++a) {
        o.table.push_back(table->v[a][first + i]);
        o.enc.push_back(enc->v[a][first + i]);
      }
    }
    o.rows += done;
    if (done < n) {
      o.error = std::to_string(bank.diverged_axis()) + ": " + bank.divergence();
      return o;
    }
    // quiet_run after each block equals the reference's count after that block's last row.
    o.quiet.resize(static_cast<std::size_t>(k + n), -1);
    o.quiet.back() = bank.quiet_run();
    k += n;
  }
  return o;
}

template <int N>
void require_same(const gm::Machine& m, int substeps, std::mt19937_64& rng, int samples = 3000) {
  std::vector<std::vector<std::int64_t>> ref;
  for (int a = 0; a < N; ++a) ref.push_back(reference(samples, rng));
  const Outcome want = per_axis<N>(m, substeps, ref);
  for (Isa isa : {Isa::Portable, Isa::Avx2, Isa::Avx512}) {
    INFO("isa " << gm::isa_name(isa) << ", " << N << " axes, substeps " << substeps);
    const Outcome got = banked<N>(m, substeps, ref, isa, rng);
    REQUIRE(got.rows == want.rows);
    CHECK(got.error == want.error);
    REQUIRE(got.enc.size() == want.enc.size());
    CHECK(got.enc == want.enc);
    CHECK(std::memcmp(got.table.data(), want.table.data(), got.table.size() * sizeof(double)) == 0);
    std::size_t quiet_wrong = 0;
    for (std::size_t i = 0; i < got.quiet.size(); ++i)
      if (got.quiet[i] >= 0 && got.quiet[i] != want.quiet[i]) ++quiet_wrong;
    CHECK(quiet_wrong == 0);
  }
}

}  // namespace

TEST_CASE("servo bank: lanes equal ServoAxis, plant order 1 and 2, 1 to 9 axes") {
  std::mt19937_64 rng(20261126);
  for (int order : {1, 2})
    for (int substeps : {1, 4}) {
      INFO("order " << order);
      require_same<1>(varied_machine(1, order, rng), substeps, rng);
      require_same<2>(varied_machine(2, order, rng), substeps, rng);
      require_same<3>(varied_machine(3, order, rng), substeps, rng);
      require_same<4>(varied_machine(4, order, rng), substeps, rng);
      require_same<6>(varied_machine(6, order, rng), substeps, rng);
      require_same<8>(varied_machine(8, order, rng), substeps, rng);
      require_same<9>(varied_machine(9, order, rng), substeps, rng);
    }
  require_same<5>(varied_machine(5, 2, rng), 2, rng);  // odd pieces: 2+2+1, 4+1 lanes
  require_same<7>(varied_machine(7, 1, rng), 3, rng);
  for (Isa isa : {Isa::Portable, Isa::Avx2, Isa::Avx512}) {
    bool lanes = false;
    std::vector<std::vector<std::int64_t>> ref(9, std::vector<std::int64_t>(10, 0));
    banked<3>(varied_machine(3, 1, rng), 1, ref, isa, rng, &lanes);
    CHECK(lanes);  // this suite runs the lanes, not the fallback
    banked<9>(varied_machine(9, 2, rng), 1, ref, isa, rng, &lanes);
    CHECK(lanes);
  }
}

TEST_CASE("servo bank: a reference beyond 2^51 BLU runs in ServoAxis, the same") {
  // The lanes carry counts and references as doubles, exact below 2^51: a row with a reference
  // beyond runs in ServoAxis, and the bank stays there once a count or reference is that far.
  std::mt19937_64 rng(5);
  for (std::int64_t far :
       {std::int64_t{1} << 51, (std::int64_t{1} << 51) - 1, -(std::int64_t{1} << 52) - 3}) {
    INFO("far " << far);
    const gm::Machine m = varied_machine(3, 2, rng);
    std::vector<std::vector<std::int64_t>> ref;
    for (int a = 0; a < 3; ++a) ref.push_back(reference(1200, rng));
    for (std::size_t i = 500; i < 1200; ++i) ref[2][i] = far;
    const Outcome want = per_axis<3>(m, 2, ref);
    for (Isa isa : {Isa::Portable, Isa::Avx2, Isa::Avx512}) {
      const Outcome got = banked<3>(m, 2, ref, isa, rng);
      CHECK(got.rows == want.rows);
      CHECK(got.error == want.error);
      CHECK(got.enc == want.enc);
      REQUIRE(got.table.size() == want.table.size());
      CHECK(std::memcmp(got.table.data(), want.table.data(), got.table.size() * sizeof(double)) ==
            0);
    }
  }
}

TEST_CASE("servo bank: the fallbacks (Coulomb, third order, mixed orders) equal ServoAxis") {
  std::mt19937_64 rng(7);
  bool lanes = true;
  std::vector<std::vector<std::int64_t>> ref(9, std::vector<std::int64_t>(10, 0));
  const gm::Machine coulomb = varied_machine(3, 1, rng, true);
  banked<3>(coulomb, 1, ref, Isa::Portable, rng, &lanes);
  CHECK_FALSE(lanes);
  require_same<3>(coulomb, 1, rng, 1500);
  const gm::Machine third = varied_machine(3, 3, rng);
  banked<3>(third, 1, ref, Isa::Portable, rng, &lanes);
  CHECK_FALSE(lanes);
  require_same<3>(third, 2, rng, 1500);
  gm::Machine mixed = varied_machine(4, 1, rng);
  mixed.axes[3] = varied_machine(4, 2, rng).axes[3];
  banked<4>(mixed, 1, ref, Isa::Portable, rng, &lanes);
  CHECK_FALSE(lanes);
  require_same<4>(mixed, 4, rng, 1500);
  require_same<9>(varied_machine(9, 1, rng, true), 1, rng, 1500);  // nine axes, one Coulomb
}

TEST_CASE("servo bank: a diverging loop stops at the same sample with ServoAxis's message") {
  std::mt19937_64 rng(11);
  for (int substeps : {1, 8}) {
    gm::Machine m = varied_machine(3, 1, rng);
    // An open-loop unstable plant (a pole at +50/s) under gains far too weak to hold it.
    m.axes[1].plant_den = {1.0, -50.0};
    m.axes[1].kp_1_s = 0.5;
    m.axes[1].kvp = 1e-4;
    m.axes[1].kvi = 0.0;
    m.axes[1].f_max_N = 1e30;
    std::vector<std::vector<std::int64_t>> ref;
    for (int a = 0; a < 3; ++a) ref.push_back(reference(2000, rng));
    const Outcome want = per_axis<3>(m, substeps, ref);
    REQUIRE_FALSE(want.error.empty());
    CHECK(want.error.find("1: servo diverged") == 0);
    for (Isa isa : {Isa::Portable, Isa::Avx2, Isa::Avx512}) {
      const Outcome got = banked<3>(m, substeps, ref, isa, rng);
      CHECK(got.rows == want.rows);
      CHECK(got.error == want.error);
      CHECK(got.enc == want.enc);
    }
  }
}

TEST_CASE("servo bank: the lanes' rounding is round_half_away, ties and signed zeros included") {
  std::vector<double> xs = {0.0,
                            -0.0,
                            0.5,
                            -0.5,
                            1.5,
                            -1.5,
                            2.5,
                            -2.5,
                            0.49999999999999994,
                            -0.49999999999999994,
                            1e15 + 0.5,
                            -1e15 - 0.5,
                            2251799813685247.5,
                            -2251799813685247.5,
                            2251799813685247.0,
                            3.5,
                            -3.5,
                            1e-300,
                            -1e-300};
  std::mt19937_64 rng(3);
  for (int i = 0; i < 20000; ++i) {
    const double scale = std::ldexp(1.0, static_cast<int>(rng() % 52));
    xs.push_back(std::uniform_real_distribution<double>(-scale, scale)(rng));
    xs.push_back(std::floor(xs.back()) + 0.5);  // a tie
  }
  for (Isa isa : {Isa::Portable, Isa::Avx2, Isa::Avx512}) {
    INFO("isa " << gm::isa_name(isa));
    std::size_t wrong = 0, flagged = 0;
    for (std::size_t k = 0; k + 8 <= xs.size(); k += 8) {
      double out[8];
      std::int64_t bad[8];
      const int w = gm::ServoBank::round_for_testing(isa, &xs[k], out, bad);
      for (int l = 0; l < w; ++l) {
        if (bad[l] != 0) {
          ++flagged;
          continue;
        }
        const double want =
            static_cast<double>(gm::round_half_away(xs[k + static_cast<std::size_t>(l)]));
        if (std::memcmp(&out[l], &want, sizeof want) != 0) ++wrong;  // +0.0, never -0.0
      }
    }
    CHECK(wrong == 0);
    CHECK(flagged == 0);  // everything here is below 2^51
  }
  double far[8] = {
      2251799813685248.0, -2251799813685248.0, std::nan(""), 1e300, 0.0, 1.0, -1.0, 2.0};
  for (Isa isa : {Isa::Portable, Isa::Avx2, Isa::Avx512}) {
    for (int o = 0; o < 8; o += 2) {
      double out[8];
      std::int64_t bad[8];
      double x[8] = {};
      x[0] = far[o];
      x[1] = far[o + 1];
      gm::ServoBank::round_for_testing(isa, x, out, bad);
      CHECK((bad[0] != 0) == (o < 4));
      CHECK((bad[1] != 0) == (o < 4));
    }
  }
}
