// Streaming: a generated program is interpreted line by line without ever existing as a whole.
#include "gcode_helpers.hpp"
#include "interp/line_reader.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <istream>
#include <streambuf>
#include <string>

namespace {
// A streambuf that produces "G1 X<i%100> Y<i%7> F1000\n" lines on demand, then "M2\n".
class GeneratedProgram : public std::streambuf {
 public:
  explicit GeneratedProgram(long lines) : lines_(lines) {}
  long produced() const { return i_; }

 protected:
  int_type underflow() override {
    if (i_ > lines_) return traits_type::eof();
    if (i_ == lines_) {
      line_ = "M2\n";
    } else {
      char buf[64];
      std::snprintf(buf, sizeof buf, "G1 X%ld Y%ld F1000\n", i_ % 100, i_ % 7);
      line_ = buf;
    }
    ++i_;
    setg(line_.data(), line_.data(), line_.data() + line_.size());
    return traits_type::to_int_type(line_[0]);
  }

 private:
  long lines_;
  long i_ = 0;
  std::string line_;
};
}  // namespace

TEST_CASE("a generated 300000-line program streams with the source read one chunk ahead at most") {
  const long n = 300000;
  GeneratedProgram gen(n);
  std::istream in(&gen);
  gm::Machine m;
  gm::ProgramStream s(in, "generated", gm::InterpreterOptions{&m, false});
  gm::Canon c;
  long moves = 0;
  gm::Motion last;
  bool ended = false;
  while (s.next(c)) {
    if (const auto* mo = std::get_if<gm::Motion>(&c)) {
      ++moves;
      // Each command is handed on while the generator has produced at most one read chunk
      // beyond its own line (every generated line has at least 15 bytes).
      CHECK(gen.produced() <= mo->line + 1 + static_cast<long>(gm::LineReader::kChunkBytes / 15));
      last = *mo;
    } else if (std::get_if<gm::Event>(&c)) {
      ended = true;
    }
  }
  CHECK(ended);
  // Zero-length moves are dropped: i and i-1 give the same point only when both i%100 and
  // i%7 repeat, which never happens for consecutive i. The first line (X0 Y0) is zero length.
  CHECK(moves == n - 1);
  CHECK(last.end_mm[0] == double((n - 1) % 100));
  CHECK(last.end_mm[1] == double((n - 1) % 7));
}
