// The consumer's block forms (measure_block, add_block) give the per-record forms' values bit for
// bit.
#include "interp/program.hpp"
#include "interpolator/interpolator.hpp"
#include "machine/machine_file.hpp"
#include "measure/contour_meter.hpp"
#include "measure/run_summary.hpp"
#include "measure/tolerance_check.hpp"
#include "pipeline/pipeline.hpp"
#include "support/sample_stepper.hpp"
#include "support/summary_reference.hpp"
#include "support/tolerance_reference.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kConsumerRepoDir = fs::path(GMOTION_TESTS_DIR).parent_path();

std::string read_program(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Bitwise equality (NaN equals NaN, 0 differs from -0): what "bit-identical" means.
bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every sample of a program stepped one at a time with the contour left unmeasured, and the motions
// each sample started: the consumer's input, per record.
struct Samples {
  gm::RunConfig cfg;
  std::vector<gm::SampleRecord> recs;
  std::vector<std::vector<gm::Motion>> started;
  std::optional<gm::ContourMeter> meter;  ///< as the pipeline set it up, before any sample
};

Samples simulate(const std::string& program, bool servo) {
  Samples s;
  s.cfg.machine = gm::default_machine();
  s.cfg.servo = servo;
  std::istringstream in(program);
  gm::InterpreterOptions opts;
  opts.machine = &s.cfg.machine;
  gm::ProgramStream stream(in, "t.nc", opts);
  gmtest::SampleStepper p(s.cfg, stream, false);
  s.meter.emplace(p.contour_meter());
  gm::OverrideInput ovr;
  gm::SampleRecord r;
  while (p.step(ovr, r) == gm::PipelineStatus::Working) {
    s.recs.push_back(r);
    const auto m = p.started_motions();
    s.started.emplace_back(m.begin(), m.end());
  }
  return s;
}

// What the consumer reports, compared as text (byte-identical means the same doubles).
struct Outputs {
  std::vector<double> contour, arc_ref, arc_enc;
  std::string summary_json, summary_text, tolerance_json;
};

Outputs per_record(const Samples& s, gm::ContourMeter meter) {
  gmtest::SummaryReference sum(s.cfg.machine);
  gmtest::ToleranceReference tol(s.cfg.machine.contour_blu_mm());
  Outputs o;
  for (std::size_t i = 0; i < s.recs.size(); ++i) {
    gm::SampleRecord r = s.recs[i];
    meter.measure(r, s.started[i]);
    tol.add(r, s.started[i].empty() ? nullptr : &s.started[i].back());
    sum.add(r);
    o.contour.push_back(r.contour_err_blu);
    o.arc_ref.push_back(r.arc_ref_dev_blu);
    o.arc_enc.push_back(r.arc_enc_dev_blu);
  }
  sum.finish(s.recs.back(), gm::AxisBlu::Zero(), true);
  o.summary_json = sum.json(tol.json_member());
  o.summary_text = sum.text() + tol.text();
  return o;
}

// The same samples packed into blocks of 256 rows and handed on in pieces of random length
// (as step() hands one row, advance() a block, a stop rule part of one).
Outputs per_block(const Samples& s, gm::ContourMeter meter, unsigned seed) {
  gm::RunSummary sum(s.cfg.machine);
  gm::ToleranceCheck tol(s.cfg.machine.contour_blu_mm());
  const int n = s.cfg.machine.axis_count();
  const double T = s.cfg.machine.period_s;
  std::mt19937 rng(seed);
  Outputs o;
  auto b = std::make_unique<gm::SampleBlock>();
  b->reset(0);
  int first = 0;
  auto hand_on = [&] {
    meter.measure_block(*b, first);
    tol.add_block(*b, first, T);
    sum.add_block(*b, first);
    for (int i = first; i < b->count; ++i) {
      o.contour.push_back(b->contour_err_blu[i]);
      o.arc_ref.push_back(b->arc_ref_dev_blu[i]);
      o.arc_enc.push_back(b->arc_enc_dev_blu[i]);
    }
    first = b->count;
  };
  std::uniform_int_distribution<int> piece(1, 300);
  int next_hand_on = piece(rng);
  for (std::size_t k = 0; k < s.recs.size(); ++k) {
    const gm::SampleRecord& r = s.recs[k];
    const int i = b->count++;
    for (int a = 0; a < n; ++a) {
      b->cmd_blu.v[a][i] = r.cmd_blu[a];
      b->ref_blu.v[a][i] = r.ref_blu[a];
      b->enc_blu.v[a][i] = r.enc_blu[a];
      b->table_blu.v[a][i] = r.table_blu[a];
    }
    b->line[i] = r.line;
    b->events[i] = r.events;
    b->feed_scale[i] = r.feed_scale;
    b->settling[i] = r.settling;
    for (const gm::Motion& m : s.started[k]) {
      b->motions.push_back(m);
      b->motion_row.push_back(i);
    }
    if (--next_hand_on == 0 || b->full()) {
      hand_on();
      next_hand_on = piece(rng);
    }
    if (b->full()) {
      b->reset(b->k0 + gm::kBlockSamples);
      first = 0;
    }
  }
  hand_on();
  sum.finish(s.recs.back(), gm::AxisBlu::Zero(), true);
  o.summary_json = sum.json(tol.json_member());
  o.summary_text = sum.text() + tol.text();
  return o;
}

// Counts the samples whose three contour values differ in any bit.
std::size_t differing(const Outputs& a, const Outputs& b) {
  std::size_t d = 0;
  for (std::size_t i = 0; i < a.contour.size(); ++i)
    d += !same_bits(a.contour[i], b.contour[i]) || !same_bits(a.arc_ref[i], b.arc_ref[i]) ||
         !same_bits(a.arc_enc[i], b.arc_enc[i]);
  return d;
}

void require_block_equals_record(const std::string& program, bool servo) {
  const Samples s = simulate(program, servo);
  REQUIRE(s.recs.size() > 500);  // a real run, not two empty outputs
  const Outputs a = per_record(s, *s.meter);
  for (unsigned seed : {1u, 2u}) {
    INFO("seed " << seed);
    const Outputs b = per_block(s, *s.meter, seed);
    REQUIRE(b.contour.size() == a.contour.size());
    CHECK(differing(a, b) == 0);
    CHECK(a.summary_json == b.summary_json);
    CHECK(a.summary_text == b.summary_text);
  }
}

// CAM-like and long moves: lines and arcs of random length in XY (some shorter than a sample's
// travel, many blocks in the window), Z steps, under G64 with a tolerance so it is judged.
std::string random_program(unsigned seed, int blocks) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::ostringstream p;
  p.setf(std::ios::fixed);
  p.precision(4);
  p << "G21 G90 G17 G64 P0.02\nG0 X0 Y0 Z1\nG1 Z0 F1500\n";
  double x = 0, y = 0;
  for (int i = 0; i < blocks; ++i) {
    const double len = u(rng) < 0.5 ? 0.02 + 0.3 * u(rng) : 2 + 30 * u(rng);
    const double ang = 6.283185307 * u(rng);
    const double nx = x + len * std::cos(ang), ny = y + len * std::sin(ang);
    const double feed = 600 + 3000 * u(rng);
    if (u(rng) < 0.3 && len > 1) {
      // An arc through the chord's end, centre off to one side.
      const double off = 0.3 + u(rng);
      const double ci = 0.5 * (nx - x) - off * (ny - y), cj = 0.5 * (ny - y) + off * (nx - x);
      p << (u(rng) < 0.5 ? "G2" : "G3") << " X" << nx << " Y" << ny << " I" << ci << " J" << cj
        << " F" << feed << "\n";
    } else if (u(rng) < 0.05) {
      p << "G1 X" << nx << " Y" << ny << " Z" << -u(rng) << " F" << feed << "\n";
    } else {
      p << "G1 X" << nx << " Y" << ny << " F" << feed << "\n";
    }
    x = nx, y = ny;
  }
  p << "G0 Z5\nM2\n";
  return p.str();
}

}  // namespace

TEST_CASE("consumer blocks: measure_block and add_block equal measure and add, bundled programs") {
  for (const char* name : {"programs/pocket.nc", "programs/corners.nc", "programs/helix.nc",
                           "programs/paper-circle.nc", "programs/exact-stop.nc"}) {
    INFO(name);
    require_block_equals_record(read_program(kConsumerRepoDir / name), true);
  }
  require_block_equals_record(read_program(kConsumerRepoDir / "programs/corners.nc"), false);
}

TEST_CASE("consumer blocks: random lines and arcs, short and long, with a tolerance") {
  for (unsigned seed : {7u, 8u}) {
    INFO("program seed " << seed);
    require_block_equals_record(random_program(seed, 300), true);
  }
  require_block_equals_record(random_program(9, 200), false);
}

TEST_CASE("consumer blocks: the comparison sees a one-ulp or one-line difference") {
  // The checks above would pass on two empty outputs; these show they can fail.
  const Samples s = simulate(read_program(kConsumerRepoDir / "programs/corners.nc"), true);
  const Outputs a = per_record(s, *s.meter);
  Outputs b = per_block(s, *s.meter, 3);
  REQUIRE(differing(a, b) == 0);
  b.contour[b.contour.size() / 2] = std::nextafter(b.contour[b.contour.size() / 2], 1e300);
  CHECK(differing(a, b) == 1);
  // A summary whose contour peak sits on another line (a tie taken by the later row).
  Samples t = s;
  std::size_t worst = 0;
  for (std::size_t i = 0; i < a.contour.size(); ++i)
    if (std::abs(a.contour[i]) > std::abs(a.contour[worst])) worst = i;
  t.recs[worst].line += 1000;
  CHECK(per_block(t, *s.meter, 3).summary_json != a.summary_json);
}

TEST_CASE("consumer blocks: add_block equals add on synthetic rows: ties, huge counts, any split") {
  // Small random steps give many equal values (peaks must keep the first row's line); counts
  // beyond 2^51 take add_block's exact-conversion fallback.
  const gm::Machine machine = gm::default_machine();
  const int n = machine.axis_count();
  for (const std::int64_t scale : {std::int64_t{3}, std::int64_t{1} << 40, std::int64_t{1} << 60}) {
    INFO("scale " << scale);
    std::mt19937_64 rng(static_cast<std::uint64_t>(scale));
    std::uniform_int_distribution<std::int64_t> step(-3, 3);
    gmtest::SummaryReference a(machine);
    gm::RunSummary b(machine);
    auto block = std::make_unique<gm::SampleBlock>();
    gm::SampleRecord r;
    for (int blk = 0; blk < 6; ++blk) {
      block->reset(blk * gm::kBlockSamples);
      for (int i = 0; i < gm::kBlockSamples; ++i) {
        for (int ax = 0; ax < n; ++ax) {
          const std::int64_t prev = i > 0 ? block->ref_blu.v[ax][i - 1] : 0;
          block->ref_blu.v[ax][i] =
              scale > 3 && rng() % 50 == 0 ? step(rng) * scale : prev + step(rng);
          block->enc_blu.v[ax][i] = block->ref_blu.v[ax][i] - step(rng) * (rng() % 3 ? 1 : scale);
          block->cmd_blu.v[ax][i] = block->ref_blu.v[ax][i];
          block->table_blu.v[ax][i] = static_cast<double>(block->enc_blu.v[ax][i]);
        }
        block->line[i] = 1 + i;
        block->events[i] = rng() % 7 == 0 ? gm::kEventHold : 0u;
        block->feed_scale[i] = 1.0;
        block->settling[i] = false;
        block->contour_err_blu[i] = static_cast<double>(step(rng));
        block->arc_ref_dev_blu[i] = rng() % 2 ? std::nan("") : static_cast<double>(step(rng));
        block->arc_enc_dev_blu[i] = static_cast<double>(step(rng));
      }
      block->count = gm::kBlockSamples;
      for (int first = 0; first < gm::kBlockSamples;) {
        const int count =
            std::min<int>(gm::kBlockSamples, first + 1 + static_cast<int>(rng() % 90));
        block->count = count;
        b.add_block(*block, first);
        for (int i = first; i < count; ++i) {
          block->record<3>(i, machine.period_s, r);
          r.contour_err_blu = block->contour_err_blu[i];
          r.arc_ref_dev_blu = block->arc_ref_dev_blu[i];
          r.arc_enc_dev_blu = block->arc_enc_dev_blu[i];
          a.add(r);
        }
        first = count;
      }
    }
    a.finish(r, gm::AxisBlu::Zero(), true);
    b.finish(r, gm::AxisBlu::Zero(), true);
    CHECK(a.json() == b.json());
    CHECK(a.text() == b.text());
  }
}
