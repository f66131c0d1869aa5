// Trace integrity from the command line: full disks, unwritable paths and SIGINT give a clear
// message, a non-zero exit and never a file that looks complete.
#include "support/long_program.hpp"
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"
#include "support/small_tmpfs.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {
const std::string kRepo = fs::path(GMOTION_TESTS_DIR).parent_path().string();
const std::string kPocket = kRepo + "/programs/pocket.nc";
fs::path scratch() {
  return gmtest::scratch_dir("integrity");
}
}  // namespace

TEST_CASE("a trace to /dev/full fails with the reason and /dev/full stays a device") {
  const auto r = gmtest::run_gmotion("run " + kPocket + " --trace /dev/full");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("cannot write trace '/dev/full': No space left on device"));
  CHECK(fs::is_character_file("/dev/full"));
  CHECK_FALSE(fs::exists("/dev/full.partial"));
}

TEST_CASE("an unwritable trace path is refused before the run") {
  const auto r = gmtest::run_gmotion("run " + kPocket + " --trace /nonexistent-dir/t.csv");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains(
                        "cannot write trace '/nonexistent-dir/t.csv': No such file or directory"));
  const auto d = gmtest::run_gmotion("run " + kPocket + " --trace " + scratch().string());
  CHECK(d.code == 1);
  CHECK_THAT(d.out, Catch::Contains("it is a directory"));
}

TEST_CASE("a full file system mid-run leaves no trace and no partial file") {
  const fs::path mnt = scratch() / "small";
  gmtest::SmallTmpfs fs_small(mnt);
  if (!fs_small.mounted()) {
    WARN("cannot mount a small tmpfs here (not root?): case skipped");
    return;
  }
  const std::string trace = (mnt / "t.csv").string();
  const auto r = gmtest::run_gmotion("run " + kPocket + " --trace " + trace);
  gmtest::sh("ls " + mnt.string() + " > " + (scratch() / "ls.txt").string());
  fs_small.unmount();
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("No space left on device"));
  std::ifstream ls(scratch() / "ls.txt");
  std::string left((std::istreambuf_iterator<char>(ls)), std::istreambuf_iterator<char>());
  CHECK(left.empty());
}

TEST_CASE("a program on stdin that does not fit the spool directory is refused, not cut short") {
  // 135 KiB of program into a 64 KiB TMPDIR: before, the spool's short write went unnoticed and
  // the first 64 KiB ran as if they were the whole program.
  const fs::path mnt = scratch() / "spool";
  const fs::path prog = scratch() / "big.nc";
  {
    std::ofstream p(prog);
    p << "G21 G90 G64 F3000\n";
    for (int i = 0; i < 10000; ++i) p << "G1 X" << (i % 2 ? 100 : 0) << " Y" << i * 0.01 << "\n";
    p << "M2\n";
  }
  REQUIRE(fs::file_size(prog) > 128 * 1024);
  gmtest::SmallTmpfs fs_small(mnt);
  if (!fs_small.mounted()) {
    WARN("cannot mount a small tmpfs here (not root?): case skipped");
    return;
  }
  const auto r = gmtest::sh("TMPDIR=" + mnt.string() + " " + std::string(GMOTION_BIN) +
                            " check - < " + prog.string() + " 2>&1");
  gmtest::sh("ls " + mnt.string() + " > " + (scratch() / "spool-ls.txt").string());
  fs_small.unmount();
  CHECK(r.code != 0);
  CHECK_THAT(r.out, Catch::Contains("cannot spool stdin to " + mnt.string()));
  CHECK_THAT(r.out, Catch::Contains("No space left on device"));
  CHECK_THAT(r.out, !Catch::Contains("ok:"));
  std::ifstream ls(scratch() / "spool-ls.txt");
  std::string left((std::istreambuf_iterator<char>(ls)), std::istreambuf_iterator<char>());
  CHECK(left.empty());
  // The same program through a spool with room, all of it: the first G1 X0 Y0 is zero length,
  // then 9,999 moves of hypot(100, 0.01) = 100.0000005 mm each.
  const auto ok = gmtest::sh(std::string(GMOTION_BIN) + " check - < " + prog.string());
  CHECK(ok.code == 0);
  CHECK_THAT(ok.out, Catch::Contains("10002 blocks, 9999 moves, path 999900.005 mm"));
}

TEST_CASE("SIGINT stops the run with a message and removes the partial trace") {
  // A long program so the run is still going when SIGINT comes.
  const fs::path dir = scratch();
  const std::string prog = (dir / "long.nc").string(), trace = (dir / "t.csv").string();
  gmtest::write_long_program(prog);
  fs::remove(trace);  // left by an earlier run, it would send the signal too soon
  fs::remove(trace + ".partial");
  // SIGINT once the trace is being written (FILE.partial until it is complete): the handler is
  // in place by then. A fixed sleep raced a slow start under the sanitizers, and a background
  // job's SIGINT is ignored until the handler is installed.
  const auto r = gmtest::sh("(" + std::string(GMOTION_BIN) + " run " + prog + " --trace " + trace +
                            " 2>&1 & pid=$!; i=0; while [ ! -s " + trace +
                            ".partial ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done; kill "
                            "-INT $pid; wait $pid; echo \"exit=$?\")");
  CHECK_THAT(r.out, Catch::Contains("interrupted at t = "));
  CHECK_THAT(r.out, Catch::Contains("; no trace was kept"));
  CHECK_THAT(r.out, !Catch::Contains("partial trace kept"));
  CHECK_THAT(r.out, Catch::Contains("exit=1"));
  CHECK_FALSE(fs::exists(trace));
  CHECK_FALSE(fs::exists(trace + ".partial"));
}

TEST_CASE("the same program and machine give byte-identical traces run after run") {
  const fs::path dir = scratch();
  const std::string a = (dir / "a.csv").string(), b = (dir / "b.csv").string();
  REQUIRE(gmtest::run_gmotion("run " + kPocket + " --trace " + a).code == 0);
  REQUIRE(gmtest::run_gmotion("run " + kPocket + " --trace " + b).code == 0);
  CHECK(gmtest::sh("cmp " + a + " " + b).code == 0);
}
