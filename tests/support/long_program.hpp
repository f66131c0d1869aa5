// Test helper: a G-code program long enough that a run is still going when a signal comes.
#pragma once

#include <fstream>
#include <string>

namespace gmtest {

/// Writes 1 km of feed at 3000 mm/min to `path`: 20,000 s of motion, 5 M samples at T = 4 ms.
inline void write_long_program(const std::string& path) {
  std::ofstream p(path);
  p << "G21 G90 G64 F3000\n";
  for (int i = 0; i < 10000; ++i) p << "G1 X" << (i % 2 ? 100 : 0) << " Y" << i * 0.01 << "\n";
  p << "M2\n";
}

}  // namespace gmtest
