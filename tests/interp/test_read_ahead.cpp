// ProgramStream with read-ahead (lines read and parsed on a second thread until the first jump)
// hands on exactly the canon, and throws exactly the error, of the one-thread stream.
#include "interp/line_source.hpp"
#include "interp/program.hpp"
#include "machine/machine.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace {

// Every field the later stages read, doubles in hexadecimal (exact).
std::string describe_canon(const gm::Canon& c) {
  if (const auto* m = std::get_if<gm::Motion>(&c)) {
    std::string s =
        fmt::format("M {} {} f{:a} it{:a} ccw{} t{} p{} pm{} tol{:a} q{:a} cap{:a}", m->line,
                    static_cast<int>(m->kind), m->feed_mm_min, m->inverse_time_s, m->ccw, m->turns,
                    static_cast<int>(m->plane), static_cast<int>(m->path_mode),
                    m->path_tolerance_mm, m->naive_cam_tolerance_mm, m->speed_cap_mm_s);
    for (int a = 0; a < 9; ++a)
      s += fmt::format(" {:a},{:a},{:a}", m->start_mm[a], m->end_mm[a], m->center_mm[a]);
    return s;
  }
  if (const auto* d = std::get_if<gm::Dwell>(&c))
    return fmt::format("D {} {:a} {}", d->line, d->seconds, d->pause);
  const auto& e = std::get<gm::Event>(c);
  return fmt::format("E {} {} {} {} {:a} {:a} {}", e.line, static_cast<int>(e.kind), e.text,
                     e.index, e.value, e.value2, e.mode);
}

struct StreamedCanon {
  std::vector<std::string> canon;
  std::string error;  ///< the InputError's message, if one was thrown
};

StreamedCanon stream_canon(const std::string& text, bool read_ahead, const std::string& dir = {}) {
  std::istringstream in(text);
  gm::Machine m;
  gm::InterpreterOptions opts;
  opts.machine = &m;
  opts.read_ahead = read_ahead;
  if (!dir.empty()) opts.subroutine_path = {dir};
  StreamedCanon r;
  try {
    gm::ProgramStream s(in, "p.nc", opts);
    gm::Canon c;
    while (s.next(c)) r.canon.push_back(describe_canon(c));
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  return r;
}

void require_same_stream(const std::string& text, const std::string& dir = {}) {
  const StreamedCanon a = stream_canon(text, false, dir);
  const StreamedCanon b = stream_canon(text, true, dir);
  REQUIRE(b.error == a.error);
  REQUIRE(b.canon.size() == a.canon.size());
  for (std::size_t i = 0; i < a.canon.size(); ++i) {
    INFO("canon " << i);
    REQUIRE(b.canon[i] == a.canon[i]);
  }
}

}  // namespace

TEST_CASE("read-ahead streams the bundled, bad and language programs as one thread does") {
  namespace fs = std::filesystem;
  int files = 0, with_error = 0;
  for (const char* sub : {"../programs", "bad", "diff/lang", "diff/lang-errors"}) {
    const fs::path dir = fs::path(GMOTION_TESTS_DIR) / sub;
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.path().extension() != ".nc" && e.path().extension() != ".ngc") continue;
      std::ifstream f(e.path(), std::ios::binary);
      std::stringstream ss;
      ss << f.rdbuf();
      INFO(e.path().string());
      require_same_stream(ss.str(), dir.string());
      ++files;
      if (!stream_canon(ss.str(), true, dir.string()).error.empty()) ++with_error;
    }
  }
  CHECK(files >= 50);
  CHECK(with_error >= 10);
}

TEST_CASE("read-ahead across batches: a long program, a loop after 3000 lines, ends and errors") {
  std::string straight = "G21 G90 F1000\n";
  for (int i = 0; i < 5000; ++i) straight += fmt::format("G1 X{} Y{}\n", i % 97, (i * 7) % 13);
  require_same_stream(straight + "M2\n");
  require_same_stream(straight);  // no end: a missing-end error on the last line
  require_same_stream(straight + "M2\nG1 X(junk after the end\n");
  require_same_stream(straight + "G2 X1 Y1 R0.01\nM2\n");  // an error after the batches
  // A loop after the reader has read ahead: the reader stops, the rest is read here.
  require_same_stream(straight +
                      "#1=0\no100 while [#1 LT 30]\nG1 X[#1] Y1\n#1=[#1+1]\no100 endwhile\n" +
                      straight + "M2\n");
  const StreamedCanon r = stream_canon(straight + "M2\n", true);
  REQUIRE(r.error.empty());
  REQUIRE(r.canon.size() >= 5000);
  require_same_stream("");
  require_same_stream("%\nG0 X1\n%\nG1 X(not read\n");
}

TEST_CASE("read-ahead batches hold the lines read, not 1,024 made up front") {
  // 3 lines: one batch of 3 (the end of input found in a 4th slot at most).
  std::istringstream small("G0 X1\nG1 Y2 F100\nM2\n");
  gm::ParallelFront three(small);
  gm::ParallelFront::Batch& b = three.acquire();
  CHECK(b.count == 3);
  CHECK(b.eof);
  CHECK(b.last_number == 3);
  CHECK(b.lines.size() <= 4);
  CHECK(b.lines[2].text == "M2");
  three.release();

  // 2,500 lines: 1,024 + 1,024 + 452, each batch at most kBatchLines long.
  std::string text;
  for (int i = 1; i <= 2500; ++i) text += fmt::format("G1 X{}\n", i);
  std::istringstream long_in(text);
  gm::ParallelFront front(long_in);
  const std::size_t counts[] = {1024, 1024, 452};
  for (int k = 0; k < 3; ++k) {
    gm::ParallelFront::Batch& batch = front.acquire();
    CHECK(batch.count == counts[k]);
    CHECK(batch.eof == (k == 2));
    CHECK(batch.lines.size() <= gm::ParallelFront::kBatchLines);
    CHECK(batch.lines[0].number == 1 + 1024 * k);
    front.release();
  }
}
