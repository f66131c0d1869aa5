// Fuzz target: G-code text (LinuxCNC, Fanuc Macro B) through parser and interpreter, checked,
// streamed.
#include "fuzz_target.hpp"

#include "program_check.hpp"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::check_and_stream(text, false);
  if (text.find('/') != std::string::npos) fuzz::check_and_stream(text, true);
  // Fanuc Macro B (variables, IF/GOTO, WHILE/DO/END, G65, ':' program numbers) under its own
  // dialect, when the text holds what it is written with.
  if (text.find_first_of("#:") != std::string::npos || text.find("GOTO") != std::string::npos ||
      text.find("G65") != std::string::npos)
    fuzz::check_and_stream(text, false, gm::Dialect::Fanuc);
  // Haas's codes and Fanuc's modal rules (G15/G16, G50/G51, G68/G69, M97, G154, G187), Mach3's.
  for (const char* code : {"G1", "G5", "G6", "M97"})
    if (text.find(code) != std::string::npos) {
      fuzz::check_and_stream(text, false, gm::Dialect::Haas);
      fuzz::check_and_stream(text, false, gm::Dialect::Mach3);
      break;
    }
  return 0;
}
