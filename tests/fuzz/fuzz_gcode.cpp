// Fuzz target: programs generated from the fuzzer's bytes (program_gen.hpp) through the parser and
// interpreter, checked whole and then streamed; reaches loops, subroutines, cycles and
// compensation in most inputs, where raw text mostly stops at the parser.
#include "fuzz_target.hpp"

#include "program_check.hpp"
#include "program_gen.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte: the dialect (LinuxCNC three times in four, grbl once in 16, else Fanuc) and
  // whether raw lines appear.
  const std::uint8_t head = data[0];
  const gm::Dialect dialect = (head & 15) == 15 ? gm::Dialect::Grbl
                              : (head & 3) == 3 ? gm::Dialect::Fanuc
                                                : gm::Dialect::LinuxCNC;
  fuzz::GenOptions opts;
  opts.raw_lines = (head & 8) != 0;
  const std::string text = fuzz::generate_program(data + 1, size - 1, opts);
  if (std::getenv("GMOTION_FUZZ_PRINT")) std::fputs(text.c_str(), stderr);  // to replay by hand
  fuzz::check_and_stream(text, false, dialect);
  return 0;
}
