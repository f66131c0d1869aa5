// The block engine: a run advanced a block at a time, with the interpolator's spans,
// gives the same trace bytes and summary as the same run stepped one sample at a time, with and
// without the consumer thread, through override schedules, holds and the stop rules.
#include "common/status.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/run.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

const fs::path kRepoDir = fs::path(GMOTION_TESTS_DIR).parent_path();

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Outcome {
  std::string trace;    // the binary trace's bytes
  std::string summary;  // the summary's JSON, or the error that stopped the run
  std::int64_t samples = 0;
};

enum class Drive { Step, Advance, AdvanceThreaded };

// Runs `program` with `schedule` (override file text, may be empty) driven as `drive`.
Outcome run(const std::string& program, const std::string& schedule, Drive drive,
            double max_time_s = 0.0, bool servo = true) {
  // ctest runs the test cases as parallel processes: the process id keeps their files apart.
  static int serial = 0;
  const fs::path trace =
      fs::temp_directory_path() /
      ("gm_block_engine_" + std::to_string(::getpid()) + "_" + std::to_string(serial++) + ".bin");
  gm::RunOptions o;
  o.config.machine = gm::default_machine();
  o.config.servo = servo;
  o.program_name = "t.nc";
  o.trace_path = trace.string();
  o.trace_format = gm::TraceFormat::Binary;
  o.keep_partial = max_time_s > 0.0;
  o.max_time_s = max_time_s;
  o.consumer_thread = drive == Drive::AdvanceThreaded;
  if (!schedule.empty()) o.schedule = gm::OverrideSchedule::parse(schedule, "schedule.csv", 200.0);
  Outcome out;
  std::istringstream in(program);
  {
    gm::Run r(std::move(o), in, gm::InterpreterOptions{});
    try {
      gm::RunStatus st;
      if (drive == Drive::Step)
        while ((st = r.step()) == gm::RunStatus::Working) ++out.samples;
      else
        while ((st = r.advance()) == gm::RunStatus::Working) {
        }
      out.summary = r.summary().json();
      out.samples = r.summary().samples;
    } catch (const gm::InputError& e) {
      out.summary = e.what();
      const auto kept = r.keep_partial(e.what());
      out.trace = kept && !kept->empty() ? read_bytes(*kept) : std::string();
      if (kept && !kept->empty()) fs::remove(*kept);
      return out;
    }
  }
  out.trace = read_bytes(trace);
  fs::remove(trace);
  return out;
}

void require_same(const std::string& program, const std::string& schedule, double max_time_s = 0.0,
                  bool servo = true) {
  const Outcome a = run(program, schedule, Drive::Step, max_time_s, servo);
  const Outcome b = run(program, schedule, Drive::Advance, max_time_s, servo);
  const Outcome c = run(program, schedule, Drive::AdvanceThreaded, max_time_s, servo);
  REQUIRE(a.trace.size() > 1000);  // a real run, not two empty outputs
  CHECK(a.summary == b.summary);
  CHECK(a.summary == c.summary);
  CHECK(a.trace.size() == b.trace.size());
  CHECK(a.trace == b.trace);
  CHECK(a.trace == c.trace);
}

}  // namespace

TEST_CASE("block engine: advance() equals step() on the bundled programs") {
  for (const char* name : {"programs/pocket.nc", "programs/corners.nc", "programs/helix.nc",
                           "programs/exact-stop.nc", "programs/inch.nc", "programs/cam-drill.nc"}) {
    INFO(name);
    require_same(read_bytes(kRepoDir / name), "");
  }
}

TEST_CASE("block engine: override changes by time and by line act at the same sample") {
  // The replay golden's schedule: time changes inside an arc, a change when line 7 starts (the
  // span must not run past the player's view of the line), a hold at 0 % and a resume.
  require_same(read_bytes(kRepoDir / "programs/override-replay.nc"),
               read_bytes(kRepoDir / "programs/override-replay.csv"));
  // Changes at sample instants that fall inside one block of 256 samples, servo off.
  require_same("G21 G90 G1 X80 Y30 F3000\nG2 X0 Y0 I-40 J-15\nM2\n",
               "0.004,90\n0.008,110\n0.5,37.5\n0.504,200\n1.0,0\n1.3,100\n", 0.0, false);
}

TEST_CASE("block engine: --max-time stops at the same sample with the same partial trace") {
  const std::string program = "G21 G90 G1 X500 F3000\nM2\n";
  const Outcome a = run(program, "", Drive::Step, 1.2345);
  const Outcome b = run(program, "", Drive::Advance, 1.2345);
  const Outcome c = run(program, "", Drive::AdvanceThreaded, 1.2345);
  CHECK(a.summary.find("--max-time 1.2345 s") != std::string::npos);
  CHECK(a.summary == b.summary);
  CHECK(a.summary == c.summary);
  REQUIRE(a.trace.size() > 1000);
  CHECK(a.trace == b.trace);
  CHECK(a.trace == c.trace);
}
