// Test helpers: a program written to a scratch file, `gmotion moves` over it, each move's kind
// and end point (X Y Z) and the output to search.
#pragma once

#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace gmtest {

using Point3 = std::array<double, 3>;

struct CliMoves {
  int code = 0;
  std::string out;  ///< stdout and stderr
  std::vector<std::string> kinds;
  std::vector<Point3> ends;
  std::vector<Point3> centres;  ///< arcs: the centre; others: zeros
};

/// Writes `text` to scratch folder `dir` as `name` (loops and calls re-read the program).
inline std::string scratch_program(const std::string& dir, const std::string& name,
                                   const std::string& text) {
  const auto path = scratch_dir(dir) / name;
  std::ofstream(path) << text;
  return path.string();
}

/// `gmotion moves FILE ARGS`: each move's kind, end point and (arcs) centre.
inline CliMoves cli_moves(const std::string& file, const std::string& args) {
  CliMoves m;
  const auto r = sh(gmotion_bin() + " moves " + file + " " + args + " 2>&1");
  m.code = r.code;
  m.out = r.out;
  const auto read3 = [&r](std::size_t at) {
    Point3 p{};
    const char* c = r.out.c_str() + at;
    for (double& v : p) {
      char* next = nullptr;
      v = std::strtod(c, &next);
      c = next + 1;
    }
    return p;
  };
  for (std::size_t at = r.out.find("\"kind\":\""); at != std::string::npos;
       at = r.out.find("\"kind\":\"", at + 1)) {
    const std::size_t k = at + 8;
    const std::size_t line_end = r.out.find('\n', at);
    const std::size_t end = r.out.find("\"end\":[", at);
    if (end > line_end) continue;  // an --io record
    m.kinds.push_back(r.out.substr(k, r.out.find('"', k) - k));
    m.ends.push_back(read3(end + 7));
    const std::size_t c = r.out.find("\"center\":[", at);
    m.centres.push_back(c < line_end ? read3(c + 10) : Point3{});
  }
  return m;
}

/// Each end point equals `want` (within 1e-9).
inline void check_points(const CliMoves& m, const std::vector<Point3>& got,
                         const std::vector<Point3>& want) {
  INFO(m.out);
  REQUIRE(got.size() == want.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    for (std::size_t a = 0; a < 3; ++a) {
      INFO("move " << i << " axis " << a);
      CHECK(std::abs(got[i][a] - want[i][a]) < 1e-9);
    }
}

}  // namespace gmtest
