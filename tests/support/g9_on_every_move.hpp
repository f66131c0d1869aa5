// Test helper: a program with a G9 on every move (an exact stop at each block end; under G64 P
// the tolerance is kept along each block).
#pragma once

#include <sstream>
#include <string>

namespace gmtest {

/// `text` with " G9" appended to every line that has an X word (the moves of the generated
/// test programs).
inline std::string g9_on_every_move(const std::string& text) {
  std::string out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    out += line + (line.find('X') != std::string::npos ? " G9\n" : "\n");
  return out;
}

}  // namespace gmtest
