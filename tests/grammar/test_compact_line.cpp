// compact_plain_line (16 characters at a time) gives exactly compact_plain_scalar's output.
#include "grammar/compact_line.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <string>
#include <vector>

namespace {

struct Compacted {
  std::string text;
  std::vector<int> columns;
};

template <class F>
Compacted run(const std::string& line, F&& f) {
  std::vector<char> buf(line.size() + gm::grammar::kCompactSlack);
  std::vector<int> cols(line.size() + gm::grammar::kCompactSlack);
  char* cp = buf.data();
  int* colp = cols.data();
  f(line, cp, colp);
  const auto n = static_cast<std::size_t>(cp - buf.data());
  REQUIRE(colp - cols.data() == cp - buf.data());
  return {std::string(buf.data(), n),
          std::vector<int>(cols.data(), cols.data() + (colp - cols.data()))};
}

void require_same(const std::string& line) {
  INFO("line '" << line << "'");
  const Compacted fast = run(line, [](std::string_view t, char*& cp, int*& colp) {
    gm::grammar::compact_plain_line(t, cp, colp);
  });
  const Compacted ref = run(line, [](std::string_view t, char*& cp, int*& colp) {
    gm::grammar::compact_plain_scalar(t, 0, cp, colp);
  });
  REQUIRE(fast.text == ref.text);
  REQUIRE(fast.columns == ref.columns);
}

}  // namespace

TEST_CASE("compact_plain_line: known lines") {
  const Compacted c =
      run("g1 x0.905  Y-1.2888\tz3 f1200 ", [](std::string_view t, char*& cp, int*& colp) {
        gm::grammar::compact_plain_line(t, cp, colp);
      });
  REQUIRE(c.text == "G1X0.905Y-1.2888Z3F1200");
  REQUIRE(c.columns == std::vector<int>{1,  2,  4,  5,  6,  7,  8,  9,  12, 13, 14, 15,
                                        16, 17, 18, 19, 21, 22, 24, 25, 26, 27, 28});
  for (const char* l :
       {"", " ", "G1", "                                ", "G1X0.905Y-1.2888Z3F1200Q",
        "abcdefghijklmnopqrstuvwxyz{|}~`@ABCDEFGHIJKLMNOPQRSTUVWXYZ[",
        "\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\tx", "x               y               z"})
    require_same(l);
}

TEST_CASE("compact_plain_line equals the scalar definition on random lines (seeded)") {
  std::mt19937 rng(2026);
  const std::string alphabet = " \t\t  abcxyzABCXYZ019.-+#[]=@^\x7f\x80\xe9\xff`{";
  for (int round = 0; round < 20000; ++round) {
    std::string line(rng() % 80, ' ');
    for (char& c : line) c = alphabet[rng() % alphabet.size()];
    require_same(line);
  }
  for (int c = 0; c < 256; ++c) require_same(std::string(17, static_cast<char>(c)) + "a b");
}
