// Trace files: header, CSV rows, binary layout, decimation, and the temp-file-then-rename rule.
#include "common/status.hpp"
#include "trace/trace_reader.hpp"
#include "trace/trace_writer.hpp"

#include "support/read_file.hpp"
#include "support/scratch_dir.hpp"
#include "support/trace_rows.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
gm::TraceMeta meta() {
  gm::TraceMeta m;
  m.program = "p.nc";
  m.machine_name = "paper";
  m.machine_source = "paper.toml";
  m.profile = "linear";
  m.taps = 41;
  m.tau_s = 0.164;
  m.period_s = 0.004;
  m.blu_mm = gm::AxisVec::Constant(0.001);
  return m;
}
gm::SampleRecord sample(std::int64_t k) {
  gm::SampleRecord s;
  s.k = k;
  s.t_s = static_cast<double>(k) * 0.004;
  s.line = 7;
  s.cmd_blu = gm::blu3(10, -20, 3);
  s.ref_blu = gm::blu3(9, -19, 3);
  s.enc_blu = gm::blu3(8, -18, 3);
  s.ferr_blu = s.ref_blu - s.enc_blu;
  s.contour_err_blu = -1.25;
  s.feed_scale = 1.5;
  return s;
}
using gmtest::slurp;
fs::path temp_dir() {
  return gmtest::scratch_dir("trace-test");
}
}  // namespace

TEST_CASE("CSV trace: header then one row per sample, renamed into place by finish()") {
  const fs::path p = temp_dir() / "t.csv";
  {
    gm::TraceWriter w(p.string(), gm::TraceFormat::Csv, meta());
    gmtest::write_record(w, sample(0));
    gmtest::write_record(w, sample(1));
    CHECK_FALSE(fs::exists(p));  // only the .partial exists until finish()
    CHECK(fs::exists(p.string() + ".partial"));
    w.finish();
  }
  const std::string text = slurp(p);
  CHECK(text.rfind("# gmotion ", 0) == 0);
  CHECK(text.find(
            "\nt_s,line,x_cmd,x_ref,x_enc,x_ferr,y_cmd,y_ref,y_enc,y_ferr,z_cmd,z_ref,z_enc,z_ferr,"
            "contour_err,override\n") != std::string::npos);
  CHECK(text.find("\n0.004000,7,10,9,8,1,-20,-19,-18,-1,3,3,3,0,-1.250,150\n") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(p.string() + ".partial"));
}

TEST_CASE("a writer destroyed without finish() leaves no file behind") {
  const fs::path p = temp_dir() / "abandoned.csv";
  {
    gm::TraceWriter w(p.string(), gm::TraceFormat::Csv, meta());
    gmtest::write_record(w, sample(0));
  }
  CHECK_FALSE(fs::exists(p));
  CHECK_FALSE(fs::exists(p.string() + ".partial"));
}

TEST_CASE("decimation keeps every K-th sample") {
  const fs::path p = temp_dir() / "dec.csv";
  auto m = meta();
  m.decimate = 3;
  gm::TraceWriter w(p.string(), gm::TraceFormat::Csv, m);
  for (int k = 0; k < 10; ++k) gmtest::write_record(w, sample(k));
  w.finish();
  CHECK(w.rows() == 4);  // k = 0, 3, 6, 9
}

TEST_CASE("binary trace: magic, header length, fixed little-endian records") {
  const fs::path p = temp_dir() / "t.bin";
  gm::TraceWriter w(p.string(), gm::TraceFormat::Binary, meta());
  gmtest::write_record(w, sample(5));
  w.finish();
  const std::string b = slurp(p);
  REQUIRE(b.substr(0, 8) == "GMTRACE1");
  std::uint32_t hlen = 0;
  std::memcpy(&hlen, b.data() + 8, 4);
  CHECK(hlen == gm::trace_header(meta()).size());
  const std::size_t rec = 8 + 4 + 4 * 8 * 3 + 8 + 8;
  REQUIRE(b.size() == 12 + hlen + rec);
  const char* r = b.data() + 12 + hlen;
  std::int64_t k = 0, y_enc = 0;
  double contour = 0;
  std::memcpy(&k, r, 8);
  std::memcpy(&y_enc, r + 12 + (4 + 2) * 8, 8);
  std::memcpy(&contour, r + 12 + 12 * 8, 8);
  CHECK(k == 5);
  CHECK(y_enc == -18);
  CHECK(contour == -1.25);
}

TEST_CASE("an unwritable trace path is a clear input error") {
  CHECK_THROWS_AS(gm::TraceWriter("/nonexistent-dir/x.csv", gm::TraceFormat::Csv, meta()),
                  gm::InputError);
}

TEST_CASE(
    "the status line: fixed width, padded, one line, cut with '...' between UTF-8 characters") {
  const std::string done = gm::trace_status_line("complete");
  CHECK(done.size() == gm::kTraceStatusWidth + 1);
  CHECK(done.rfind("# status: complete   ", 0) == 0);
  CHECK(done.back() == '\n');
  CHECK(done.find_first_not_of(' ', 18) == done.size() - 1);  // spaces up to the '\n'
  CHECK(gm::trace_status_line("partial: a\nb\rc") ==
        "# status: partial: a b c" + std::string(gm::kTraceStatusWidth - 24, ' ') + "\n");
  // 200 × "é" (2 bytes each) does not fit: cut after a whole character, then "...".
  std::string long_text;
  for (int i = 0; i < 200; ++i) long_text += "\xc3\xa9";
  const std::string cut = gm::trace_status_line(long_text);
  REQUIRE(cut.size() == gm::kTraceStatusWidth + 1);
  const std::size_t dots = cut.find("...");
  REQUIRE(dots != std::string::npos);
  CHECK((dots - 10) % 2 == 0);  // "# status: " then whole 2-byte characters
  CHECK(cut.substr(10, 2) == "\xc3\xa9");
  CHECK(cut.find_first_not_of(' ', dots + 3) == cut.size() - 1);
  // A text that fits exactly is not cut.
  const std::string exact(gm::kTraceStatusWidth - 10, 'x');
  CHECK(gm::trace_status_line(exact) == "# status: " + exact + "\n");
}

TEST_CASE(
    "with a status line the trace says 'partial, run in progress' until finish() writes 'complete' "
    "in place") {
  for (const auto format : {gm::TraceFormat::Csv, gm::TraceFormat::Binary}) {
    const bool bin = format == gm::TraceFormat::Binary;
    DYNAMIC_SECTION((bin ? "binary" : "CSV")) {
      const fs::path p = temp_dir() / (bin ? "status.bin" : "status.csv");
      auto m = meta();
      m.status_line = true;
      const std::string header = gm::trace_header(m);
      const std::size_t first = header.find('\n') + 1;
      CHECK(header.substr(first, gm::kTraceStatusWidth + 1) ==
            gm::trace_status_line("partial, run in progress"));
      auto plain = meta();
      CHECK(header.substr(0, first) + header.substr(first + gm::kTraceStatusWidth + 1) ==
            gm::trace_header(plain));

      gm::TraceWriter w(p.string(), format, m);
      for (int k = 0; k < 30000; ++k)
        gmtest::write_record(w, sample(k));  // more than 1 MiB: flushed at least once
      const std::string before = slurp(p.string() + ".partial");
      const std::size_t at = (bin ? 12 : 0) + first;
      REQUIRE(before.size() > at + gm::kTraceStatusWidth);
      CHECK(before.substr(at, gm::kTraceStatusWidth + 1) ==
            gm::trace_status_line("partial, run in progress"));
      w.finish();
      CHECK_FALSE(w.open());
      CHECK_FALSE(fs::exists(p.string() + ".partial"));
      const std::string after = slurp(p);
      CHECK(after.substr(at, gm::kTraceStatusWidth + 1) == gm::trace_status_line("complete"));
      if (bin) {
        std::uint32_t hlen = 0;
        std::memcpy(&hlen, after.data() + 8, 4);
        CHECK(hlen == header.size());
        const std::size_t rec = 8 + 4 + 4 * 8 * 3 + 8 + 8;
        CHECK(after.size() == 12 + hlen + 30000 * rec);
      } else {
        CHECK(after.compare(0, at, header, 0, at) == 0);
        CHECK(after.compare(at + gm::kTraceStatusWidth + 1,
                            header.size() - at - gm::kTraceStatusWidth - 1, header,
                            at + gm::kTraceStatusWidth + 1) == 0);
      }
    }
  }
}

TEST_CASE(
    "keep_partial() leaves path.partial with the reason in its header and whole rows, never path") {
  for (const auto format : {gm::TraceFormat::Csv, gm::TraceFormat::Binary}) {
    const bool bin = format == gm::TraceFormat::Binary;
    DYNAMIC_SECTION((bin ? "binary" : "CSV")) {
      const fs::path p = temp_dir() / (bin ? "kept.bin" : "kept.csv");
      auto m = meta();
      m.status_line = true;
      std::string kept;
      {
        gm::TraceWriter w(p.string(), format, m);
        for (int k = 0; k < 7; ++k) gmtest::write_record(w, sample(k));
        kept = w.keep_partial("interrupted at t = 0.028 s (line 7)");
        CHECK_FALSE(w.open());
      }  // the destructor leaves the kept file alone
      CHECK(kept == p.string() + ".partial");
      CHECK_FALSE(fs::exists(p));
      const std::string text = slurp(kept);
      const std::string header = gm::trace_header(m);
      const std::size_t at = (bin ? 12 : 0) + header.find('\n') + 1;
      CHECK(text.substr(at, gm::kTraceStatusWidth + 1) ==
            gm::trace_status_line("partial: interrupted at t = 0.028 s (line 7)"));
      const std::size_t rows_at = (bin ? 12 : 0) + header.size();
      if (bin) {
        CHECK(text.size() == rows_at + 7 * (8 + 4 + 4 * 8 * 3 + 8 + 8));
      } else {
        const std::string rows = text.substr(rows_at);
        CHECK(std::count(rows.begin(), rows.end(), '\n') == 7);
        CHECK(rows.back() == '\n');
      }
      gm::TraceReader r(kept);
      CHECK(r.partial());
      CHECK(r.status() == "partial: interrupted at t = 0.028 s (line 7)");
      std::vector<double> v;
      int n = 0;
      while (r.next(v)) ++n;
      CHECK(n == 7);
      CHECK_FALSE(r.dropped_tail());
    }
  }
}

TEST_CASE(
    "a status line is refused for a trace written in place, and written_in_place() says which "
    "are") {
  auto m = meta();
  m.status_line = true;
  CHECK_THROWS_AS(gm::TraceWriter("-", gm::TraceFormat::Csv, m), gm::InputError);
  CHECK_THROWS_AS(gm::TraceWriter("/dev/null", gm::TraceFormat::Csv, m), gm::InputError);
  CHECK(gm::TraceWriter::written_in_place("-"));
  CHECK(gm::TraceWriter::written_in_place("/dev/null"));
  CHECK_FALSE(gm::TraceWriter::written_in_place((temp_dir() / "new.csv").string()));
  CHECK_FALSE(
      gm::TraceWriter::written_in_place(temp_dir().string()));  // a directory: its own error
  // Without a status line nothing is kept: the writer goes on, and its destructor removes the file.
  const fs::path p = temp_dir() / "plain.csv";
  {
    gm::TraceWriter w(p.string(), gm::TraceFormat::Csv, meta());
    gmtest::write_record(w, sample(0));
    CHECK(w.keep_partial("x").empty());
    CHECK(w.open());
  }
  CHECK_FALSE(fs::exists(p.string() + ".partial"));
  CHECK_FALSE(fs::exists(p));
}

TEST_CASE(
    "the reader: status(), partial(), and an incomplete last row is left out of partial traces "
    "only") {
  for (const auto format : {gm::TraceFormat::Csv, gm::TraceFormat::Binary}) {
    const bool bin = format == gm::TraceFormat::Binary;
    DYNAMIC_SECTION((bin ? "binary" : "CSV")) {
      const fs::path p = temp_dir() / (bin ? "cut.bin" : "cut.csv");
      auto m = meta();
      m.status_line = true;
      gm::TraceWriter w(p.string(), format, m);
      for (int k = 0; k < 5; ++k) gmtest::write_record(w, sample(k));
      const std::string kept = w.keep_partial("run stopped");
      // What a killed run may leave: the status line of a run in progress and half a row.
      std::string text = slurp(kept);
      const std::size_t at = (bin ? 12 : 0) + gm::trace_header(m).find('\n') + 1;
      text.replace(at, gm::kTraceStatusWidth + 1,
                   gm::trace_status_line("partial, run in progress"));
      text.resize(text.size() - 5);
      const fs::path cut = temp_dir() / (bin ? "cut-killed.bin" : "cut-killed.csv");
      std::ofstream(cut, std::ios::binary) << text;
      gm::TraceReader r(cut.string());
      CHECK(r.partial());
      CHECK(r.status() == "partial, run in progress");
      std::vector<double> v;
      int n = 0;
      while (r.next(v)) ++n;
      CHECK(n == 4);
      CHECK(r.dropped_tail());
      // The same cut in a complete trace is an error.
      text.replace(at, gm::kTraceStatusWidth + 1, gm::trace_status_line("complete"));
      std::ofstream(cut, std::ios::binary | std::ios::trunc) << text;
      gm::TraceReader c(cut.string());
      CHECK_FALSE(c.partial());
      CHECK(c.status() == "complete");
      for (int i = 0; i < 4; ++i) REQUIRE(c.next(v));
      CHECK_THROWS_AS(c.next(v), gm::InputError);  // CSV: read as it is, a malformed row
    }
  }
}
