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
  return 0;
}
