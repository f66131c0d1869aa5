// Fuzz target: G-code text through the parser and interpreter, checked whole and then streamed.
#include "fuzz_target.hpp"

#include "program_check.hpp"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::check_and_stream(text, false);
  if (text.find('/') != std::string::npos) fuzz::check_and_stream(text, true);
  return 0;
}
