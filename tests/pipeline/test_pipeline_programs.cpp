// End to end through the library: every bundled program ends exactly; lost motion shows as
// quadrant protrusions in the contour error (paper Fig. 17).
#include "interp/program.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/pipeline.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct RunResult {
  gm::PipelineStatus status;
  gm::SampleRecord last;
  gm::AxisBlu program_end;
  std::vector<double> contour;  // per sample
  std::vector<gm::AxisVec> commanded_end_mm;
};

RunResult run(const fs::path& program, const gm::Machine& m, bool servo) {
  std::ifstream in(program);
  REQUIRE(in);
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, program.string(), opts);
  gm::RunConfig cfg;
  cfg.machine = m;
  cfg.servo = servo;
  gm::Pipeline p(cfg, stream);
  RunResult r;
  gm::SampleRecord rec;
  while ((r.status = p.step(gm::OverrideInput{}, rec)) == gm::PipelineStatus::Working) {
    r.last = rec;
    r.contour.push_back(rec.contour_err_blu);
  }
  r.program_end = p.program_end_blu();
  return r;
}

// The last motion end point of a program, from `gmotion moves`' source: the interpreter itself.
gm::AxisVec last_end_mm(const fs::path& program, const gm::Machine& m) {
  std::ifstream in(program);
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, program.string(), opts);
  gm::Canon c;
  gm::AxisVec end = gm::AxisVec::Zero();
  while (stream.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) end = mo->end_mm;
  return end;
}

const fs::path kPrograms = fs::path(GMOTION_TESTS_DIR).parent_path() / "programs";

}  // namespace

TEST_CASE("every bundled program ends exactly on its end point, Acc/Dec output and encoder") {
  const gm::Machine m = gm::default_machine();
  for (const auto& entry : fs::directory_iterator(kPrograms)) {
    if (entry.path().extension() != ".nc") continue;
    INFO(entry.path().string());
    const gm::AxisVec end_mm = last_end_mm(entry.path(), m);
    gm::AxisBlu end_blu;
    for (int a = 0; a < gm::kAxes; ++a) end_blu[a] = std::llround(end_mm[a] / m.axes[a].blu_mm);
    for (bool servo : {false, true}) {
      INFO("servo " << servo);
      const RunResult r = run(entry.path(), m, servo);
      CHECK(r.status == gm::PipelineStatus::Finished);
      CHECK(r.program_end == end_blu);
      CHECK(r.last.ref_blu == end_blu);  // the Acc/Dec output converges exactly (Eq. 5)
      for (int a = 0; a < gm::kAxes; ++a) CHECK(std::llabs(r.last.enc_blu[a] - end_blu[a]) <= 1);
    }
  }
}

TEST_CASE("lost motion and friction give outward quadrant protrusions (Fig. 17)") {
  const fs::path circle = kPrograms / "paper-circle.nc";
  const gm::Machine ideal = gm::load_machine_file(kPrograms / "machines" / "paper.toml");
  const gm::Machine worn = gm::load_machine_file(kPrograms / "machines" / "paper-lost-motion.toml");
  // The middle turn of three (1.675 s a turn at T = 4 ms, after the start rapid): steady state.
  auto spread = [](const std::vector<double>& c) {
    const auto [lo, hi] = std::minmax_element(c.begin() + 600, c.begin() + 1000);
    return *hi - *lo;
  };
  const RunResult a = run(circle, ideal, true);
  const RunResult b = run(circle, worn, true);
  // Ideal servo: the radius is steady to within the encoder count and the loop's ripple.
  CHECK(spread(a.contour) < 3.0);
  // 4 BLU lost motion + 100 N friction: a protrusion of tens of BLU at each axis reversal.
  CHECK(spread(b.contour) > 20.0);
}
