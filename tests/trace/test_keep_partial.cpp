// run --keep-partial from the command line: a failed run keeps FILE.partial whose header says why,
// with whole rows only; a completed run's trace differs from one without the flag only by its
// status.
#include "common/axis.hpp"
#include "trace/trace_reader.hpp"
#include "trace/trace_writer.hpp"

#include "support/long_program.hpp"
#include "support/read_file.hpp"
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"
#include "support/small_tmpfs.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kRepoDir = fs::path(GMOTION_TESTS_DIR).parent_path().string();
const std::string kPocketNc = kRepoDir + "/programs/pocket.nc";
constexpr std::size_t kStatusLine = gm::kTraceStatusWidth + 1;  // with its '\n'
constexpr std::size_t kRecord = 8 + 4 + 4 * 8 * 3 + 8 + 8;      // one binary row
constexpr std::size_t kCsvColumns = 2 + 4 * 3 + 2;              // t_s, line, ..., override
fs::path partial_scratch() {
  return gmtest::scratch_dir("keep-partial");
}

// A trace split into its parts: '#' lines (each with its '\n'), then the rows.
struct Trace {
  std::vector<std::string> header;  ///< '#' lines, then the column line
  std::string rows;                 ///< everything after the column line, as bytes
};

Trace split(const std::string& bytes, bool bin) {
  Trace t;
  std::string text = bytes;
  if (bin) {
    REQUIRE(bytes.size() >= 12);
    REQUIRE(bytes.compare(0, 8, "GMTRACE1") == 0);
    std::uint32_t hlen = 0;
    std::memcpy(&hlen, bytes.data() + 8, 4);
    REQUIRE(bytes.size() >= 12 + hlen);
    text = bytes.substr(12, hlen);
    t.rows = bytes.substr(12 + hlen);
  }
  std::size_t at = 0;
  for (;;) {
    const std::size_t end = text.find('\n', at);
    REQUIRE(end != std::string::npos);
    t.header.push_back(text.substr(at, end + 1 - at));
    at = end + 1;
    if (t.header.back()[0] != '#') break;
  }
  if (!bin) t.rows = text.substr(at);
  return t;
}

// Every CSV row has all its columns and its '\n'; returns the rows.
std::vector<std::string> whole_csv_rows(const std::string& rows) {
  std::vector<std::string> out;
  if (!rows.empty()) CHECK(rows.back() == '\n');
  std::size_t at = 0;
  for (std::size_t end; (end = rows.find('\n', at)) != std::string::npos; at = end + 1) {
    out.push_back(rows.substr(at, end - at));
    REQUIRE(static_cast<std::size_t>(std::count(out.back().begin(), out.back().end(), ',')) ==
            kCsvColumns - 1);
  }
  CHECK(at == rows.size());
  return out;
}

// The status the header of a kept trace gives: its second line, which has the fixed width.
std::string status_of(const Trace& t) {
  REQUIRE(t.header.size() > 2);
  const std::string& s = t.header[1];
  REQUIRE(s.size() == kStatusLine);
  REQUIRE(s.rfind("# status: ", 0) == 0);
  std::string v = s.substr(10, s.size() - 11);
  while (!v.empty() && v.back() == ' ') v.pop_back();
  return v;
}

// Runs gmotion `args` in the background, sends `sig` once `watch` has data, waits; output with
// "exit=N".
gmtest::CommandResult run_and_signal(const std::string& args, const std::string& watch,
                                     const char* sig) {
  return gmtest::sh("(" + std::string(GMOTION_BIN) + " " + args +
                    " 2>&1 & pid=$!; i=0; while [ ! -s " + watch +
                    " ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done; kill -" + sig +
                    " $pid; wait $pid; echo \"exit=$?\")");
}

double number_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  REQUIRE(at != std::string::npos);
  return std::strtod(text.c_str() + at + key.size(), nullptr);
}

}  // namespace

TEST_CASE(
    "run --keep-partial: SIGINT keeps FILE.partial saying 'partial: interrupted ...', whole rows, "
    "no FILE") {
  const fs::path dir = partial_scratch();
  const std::string prog = (dir / "long.nc").string();
  gmtest::write_long_program(prog);
  for (const bool bin : {false, true}) {
    DYNAMIC_SECTION((bin ? "binary" : "CSV")) {
      const std::string trace = (dir / (bin ? "int.bin" : "int.csv")).string(),
                        kept = trace + ".partial";
      const auto r = run_and_signal(
          "run " + prog + " --keep-partial --trace " + trace + (bin ? " --trace-format bin" : ""),
          kept, "INT");
      INFO(r.out);
      CHECK_THAT(r.out, Catch::Contains("exit=1"));
      CHECK_THAT(r.out, Catch::Contains("gmotion: error: interrupted at t = "));
      CHECK_THAT(r.out, !Catch::Contains("no trace was kept"));
      CHECK_THAT(r.out, Catch::EndsWith("gmotion: partial trace kept at " + kept + "\nexit=1\n"));
      CHECK_FALSE(fs::exists(trace));
      REQUIRE(fs::exists(kept));
      const Trace t = split(gmtest::slurp(kept), bin);
      const std::string status = status_of(t);
      CHECK_THAT(status, Catch::StartsWith("partial: interrupted at t = "));
      const double t_stop = number_after(status, "interrupted at t = ");
      CHECK_THAT(r.out, Catch::Contains(status.substr(9)));  // the same reason as the message
      // Whole rows only, and every sample before the interrupted one (the queue was drained).
      double last_t = -1.0;
      if (bin) {
        CHECK(t.rows.size() % kRecord == 0);
        REQUIRE(t.rows.size() >= kRecord);
        std::int64_t k = 0;
        std::memcpy(&k, t.rows.data() + t.rows.size() - kRecord, 8);
        last_t = static_cast<double>(k) * 0.004;
        CHECK(static_cast<std::int64_t>(t.rows.size() / kRecord) == k + 1);  // no row missing
      } else {
        const auto rows = whole_csv_rows(t.rows);
        REQUIRE_FALSE(rows.empty());
        last_t = std::strtod(rows.back().c_str(), nullptr);
        CHECK(std::abs(std::strtod(rows.front().c_str(), nullptr)) < 1e-9);  // starts at k = 0
        CHECK(static_cast<double>(rows.size()) == Approx(last_t / 0.004 + 1).margin(0.01));
      }
      CHECK(last_t + 0.004 == Approx(t_stop).margin(0.0006));
      // The reader and gmotion diff take it as a partial trace.
      gm::TraceReader reader(kept);
      CHECK(reader.partial());
      std::vector<double> v;
      while (reader.next(v)) {
      }
      CHECK_FALSE(reader.dropped_tail());
    }
  }
}

TEST_CASE(
    "run --keep-partial: --max-time keeps FILE.partial with that reason and the complete run's "
    "first rows") {
  const fs::path dir = partial_scratch();
  for (const bool bin : {false, true}) {
    DYNAMIC_SECTION((bin ? "binary" : "CSV")) {
      const std::string fmt_flag = bin ? " --trace-format bin" : "";
      const std::string full = (dir / (bin ? "full.bin" : "full.csv")).string();
      const std::string trace = (dir / (bin ? "max.bin" : "max.csv")).string(),
                        kept = trace + ".partial";
      REQUIRE(gmtest::run_gmotion("run " + kPocketNc + " --trace " + full + fmt_flag).code == 0);
      const auto r = gmtest::run_gmotion(
          "run " + kPocketNc + " --max-time 5 --keep-partial --trace " + trace + fmt_flag);
      INFO(r.out);
      CHECK(r.code == 1);
      CHECK_THAT(r.out, Catch::Contains("gmotion: error: run stopped at --max-time 5 s (line "));
      CHECK_THAT(r.out, Catch::EndsWith("gmotion: partial trace kept at " + kept + "\n"));
      CHECK_FALSE(fs::exists(trace));
      REQUIRE(fs::exists(kept));
      const Trace t = split(gmtest::slurp(kept), bin), f = split(gmtest::slurp(full), bin);
      CHECK_THAT(status_of(t), Catch::StartsWith("partial: run stopped at --max-time 5 s (line "));
      // The header is the complete run's, status line aside.
      std::vector<std::string> h = t.header;
      h.erase(h.begin() + 1);
      CHECK(h == f.header);
      // Rows: exactly those of the complete run up to t = 5 s.
      std::size_t expect = 0;
      if (bin) {
        CHECK(t.rows.size() % kRecord == 0);
        for (std::size_t at = 0; at < f.rows.size(); at += kRecord, ++expect) {
          std::int64_t k = 0;
          std::memcpy(&k, f.rows.data() + at, 8);
          if (static_cast<double>(k) * 0.004 > 5.0) break;
        }
        CHECK(t.rows.size() == expect * kRecord);
        CHECK(f.rows.compare(0, t.rows.size(), t.rows) == 0);
      } else {
        const auto rows = whole_csv_rows(t.rows), full_rows = whole_csv_rows(f.rows);
        while (expect < full_rows.size() && std::strtod(full_rows[expect].c_str(), nullptr) <= 5.0)
          ++expect;
        CHECK(rows.size() == expect);
        CHECK(f.rows.compare(0, t.rows.size(), t.rows) == 0);
      }
      CHECK(expect >= 1249);
      CHECK(expect < 1300);
    }
  }
}

TEST_CASE(
    "run --keep-partial: a completed run gives FILE with 'status: complete', else as without the "
    "flag") {
  const fs::path dir = partial_scratch();
  for (const bool bin : {false, true}) {
    DYNAMIC_SECTION((bin ? "binary" : "CSV")) {
      const std::string fmt_flag = bin ? " --trace-format bin" : "";
      const std::string plain = (dir / (bin ? "plain.bin" : "plain.csv")).string();
      const std::string trace = (dir / (bin ? "done.bin" : "done.csv")).string();
      const auto a = gmtest::run_gmotion("run " + kPocketNc + " --trace " + plain + fmt_flag);
      const auto b =
          gmtest::run_gmotion("run " + kPocketNc + " --keep-partial --trace " + trace + fmt_flag);
      REQUIRE(a.code == 0);
      CHECK(b.code == 0);
      CHECK(b.out == a.out);  // same summary, no note
      CHECK_FALSE(fs::exists(trace + ".partial"));
      const std::string with = gmtest::slurp(trace), without = gmtest::slurp(plain);
      const Trace t = split(with, bin), p = split(without, bin);
      CHECK(status_of(t) == "complete");
      std::vector<std::string> h = t.header;
      h.erase(h.begin() + 1);
      CHECK(h == p.header);
      CHECK(t.rows == p.rows);
      CHECK(t.rows.size() > 6000 * (bin ? kRecord : 60));
      // Byte for byte: the flagged file is the plain one with the status line in (binary: and a
      // header length 121 bytes longer).
      const std::size_t first = with.find('\n') + 1;
      std::string stripped = with.substr(0, first) + with.substr(first + kStatusLine);
      if (bin) {
        std::uint32_t hlen = 0;
        std::memcpy(&hlen, stripped.data() + 8, 4);
        hlen -= static_cast<std::uint32_t>(kStatusLine);
        std::memcpy(stripped.data() + 8, &hlen, 4);
      }
      CHECK(stripped == without);
    }
  }
}

TEST_CASE("run --keep-partial: servo divergence keeps FILE.partial saying why") {
  // The default machine with the x plant gain that made fuzz_machine's loop diverge.
  const fs::path dir = partial_scratch();
  const std::string machine = (dir / "diverging.toml").string(), trace = (dir / "div.csv").string();
  std::string toml = gmtest::slurp(kRepoDir + "/programs/machines/default.toml");
  const std::size_t at = toml.find("plant_num = [33.518]");
  REQUIRE(at != std::string::npos);
  toml.replace(at, 20, "plant_num = [3.3e306]");
  std::ofstream(machine) << toml;
  const auto r = gmtest::run_gmotion("run " + kPocketNc + " --machine " + machine +
                                     " --keep-partial --trace " + trace);
  INFO(r.out);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("servo diverged"));
  CHECK_THAT(r.out, Catch::EndsWith("gmotion: partial trace kept at " + trace + ".partial\n"));
  CHECK_FALSE(fs::exists(trace));
  const Trace t = split(gmtest::slurp(trace + ".partial"), false);
  const std::string status = status_of(t);
  CHECK_THAT(status, Catch::StartsWith("partial: axis X at t = "));
  // The message is longer than the line: cut, with "...", and the start of the same text.
  REQUIRE(status.size() > 12);
  CHECK_THAT(status, Catch::EndsWith("..."));
  CHECK_THAT(r.out, Catch::Contains("gmotion: error: " + status.substr(9, status.size() - 12)));
  whole_csv_rows(t.rows);
}

TEST_CASE(
    "run --keep-partial: axes that do not settle keep FILE.partial saying so, rows as without the "
    "flag") {
  // Coulomb friction of 3000 N on x: the encoder hunts around the target past the settle timeout.
  const fs::path dir = partial_scratch();
  const std::string machine = (dir / "sticky.toml").string(), trace = (dir / "uns.csv").string();
  const std::string plain = (dir / "uns-plain.csv").string();
  std::string toml = gmtest::slurp(kRepoDir + "/programs/machines/default.toml");
  const std::size_t at = toml.find("coulomb_N = 0 ");
  REQUIRE(at != std::string::npos);
  toml.replace(at, 14, "coulomb_N = 3000 ");
  std::ofstream(machine) << toml;
  const std::string args = "run " + kRepoDir + "/programs/square.nc --machine " + machine;
  const auto a = gmtest::run_gmotion(args + " --trace " + plain);
  const auto r = gmtest::run_gmotion(args + " --keep-partial --trace " + trace);
  INFO(r.out);
  REQUIRE(a.code == 1);
  REQUIRE_THAT(a.out, Catch::Contains("NOT SETTLED"));
  CHECK(r.code == 1);
  CHECK(r.out == a.out + "gmotion: partial trace kept at " + trace +
                     ".partial\n");  // the summary, then the note
  CHECK_FALSE(fs::exists(trace));
  const Trace t = split(gmtest::slurp(trace + ".partial"), false),
              p = split(gmtest::slurp(plain), false);
  CHECK(status_of(t) == "partial: the axes did not settle within 10 s of the program end");
  CHECK(t.rows == p.rows);
  CHECK(whole_csv_rows(t.rows).size() > 3000);
}

TEST_CASE(
    "run --keep-partial: a full file system keeps FILE.partial cut back to its last whole row") {
  const fs::path mnt = partial_scratch() / "small";
  gmtest::SmallTmpfs fs_small(mnt);
  if (!fs_small.mounted()) {
    WARN("cannot mount a small tmpfs here (not root?): case skipped");
    return;
  }
  const std::string trace = (mnt / "t.csv").string();
  const auto r = gmtest::run_gmotion("run " + kPocketNc + " --keep-partial --trace " + trace);
  const std::string kept = gmtest::slurp(trace + ".partial");
  const bool whole_exists = fs::exists(trace);
  fs_small.unmount();
  INFO(r.out);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("No space left on device"));
  CHECK_FALSE(whole_exists);
  REQUIRE_FALSE(kept.empty());
  CHECK_THAT(r.out, Catch::EndsWith("gmotion: partial trace kept at " + trace + ".partial\n"));
  const Trace t = split(kept, false);
  CHECK_THAT(status_of(t), Catch::StartsWith("partial: cannot write trace '" + trace +
                                             "': No space left on device"));
  CHECK(whole_csv_rows(t.rows).size() > 100);
}

TEST_CASE("run --keep-partial with --trace -, a device or no --trace is a usage error") {
  for (const std::string& path : {std::string("-"), std::string("/dev/null")}) {
    const auto r = gmtest::run_gmotion("run " + kPocketNc + " --keep-partial --trace " + path);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--keep-partial: --trace " + path + " is written in place"));
    CHECK_THAT(r.out, !Catch::Contains("samples "));  // nothing ran
  }
  const auto r = gmtest::run_gmotion("run " + kPocketNc + " --keep-partial");
  CHECK(r.code == 2);
  CHECK_THAT(r.out, Catch::Contains("--keep-partial requires --trace"));
}

TEST_CASE("gmotion diff warns which trace is partial and why, and compares the rows it has") {
  const fs::path dir = partial_scratch();
  const std::string full = (dir / "d-full.csv").string(), trace = (dir / "d-max.csv").string();
  const std::string kept = trace + ".partial";
  REQUIRE(gmtest::run_gmotion("run " + kPocketNc + " --trace " + full).code == 0);
  REQUIRE(gmtest::run_gmotion("run " + kPocketNc + " --max-time 5 --keep-partial --trace " + trace)
              .code == 1);
  const std::size_t rows = whole_csv_rows(split(gmtest::slurp(kept), false).rows).size();
  const auto r = gmtest::run_gmotion("diff " + full + " " + kept);
  INFO(r.out);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("warning: B = " + kept +
                                    " is a partial trace (run stopped at --max-time 5 s (line "));
  CHECK_THAT(r.out, Catch::Contains("comparing the rows it has"));
  CHECK_THAT(r.out, !Catch::Contains("warning: A ="));
  CHECK_THAT(r.out, Catch::Contains(std::to_string(rows) + " rows compared"));
  CHECK_THAT(r.out, Catch::Contains("first divergence: " + kept + " ends after " +
                                    std::to_string(rows) + " rows"));
  // A partial trace against itself: both warned about, the rows agree.
  const auto same = gmtest::run_gmotion("diff " + kept + " " + kept);
  CHECK(same.code == 0);
  CHECK_THAT(same.out, Catch::Contains("warning: A = " + kept));
  CHECK_THAT(same.out, Catch::Contains("warning: B = " + kept));
  CHECK_THAT(same.out, Catch::Contains("traces agree within the tolerance"));
}

TEST_CASE(
    "run --keep-partial: a SIGKILLed run leaves FILE.partial whose header says 'partial, run in "
    "progress'") {
  const fs::path dir = partial_scratch();
  const std::string prog = (dir / "long-kill.nc").string(), trace = (dir / "kill.csv").string();
  const std::string kept = trace + ".partial";
  gmtest::write_long_program(prog);
  const auto r = run_and_signal("run " + prog + " --keep-partial --trace " + trace, kept, "KILL");
  INFO(r.out);
  CHECK_THAT(r.out, Catch::Contains("exit=137"));
  CHECK_FALSE(fs::exists(trace));
  REQUIRE(fs::exists(kept));
  CHECK(status_of(split(gmtest::slurp(kept), false)) == "partial, run in progress");
  const auto d = gmtest::run_gmotion("diff " + kept + " " + kept);
  CHECK_THAT(d.out, Catch::Contains(
                        "warning: A = " + kept +
                        " is a partial trace (its run never finished: killed, or still running)"));
  CHECK(d.code == 0);
}
