// Fuzz target: G-code text (LinuxCNC, Fanuc Macro B) through parser and interpreter, checked,
// streamed; the same text as a tool table and as a `.var` parameter file (table_check.hpp).
// Under libFuzzer, most mutants come from a structure-aware mutator (program_mutator.hpp).
#include "fuzz_target.hpp"

#include "program_check.hpp"
#include "program_mutator.hpp"
#include "table_check.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

// GMOTION_FUZZ_STATS=1: at exit, how many inputs ran and how many were valid programs.
struct Stats {
  long long inputs = 0, valid = 0;
  bool on = std::getenv("GMOTION_FUZZ_STATS") != nullptr;
  ~Stats() {
    if (on)
      std::fprintf(stderr, "fuzz_program: %lld inputs, %lld valid LinuxCNC or Fanuc programs\n",
                   inputs, valid);
  }
} stats;

}  // namespace

#ifdef GMOTION_LIBFUZZER
extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

// Four mutants in five are made line by line and word by word (ProgramMutator), the fifth by
// libFuzzer's byte-level mutations (for what no construct table holds: the parser's errors).
extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed) {
  if (seed % 5 == 0 || size == 0) return LLVMFuzzerMutate(data, size, max_size);
  fuzz::ProgramMutator m(seed / 5);
  const std::string out = m.mutate({reinterpret_cast<const char*>(data), size});
  if (out.empty() || out.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, out.data(), out.size());
  return out.size();
}

// A run of lines of one program spliced into another.
extern "C" std::size_t LLVMFuzzerCustomCrossOver(const std::uint8_t* data1, std::size_t size1,
                                                 const std::uint8_t* data2, std::size_t size2,
                                                 std::uint8_t* out, std::size_t max_out_size,
                                                 unsigned int seed) {
  fuzz::ProgramMutator m(seed);
  const std::string text = m.cross({reinterpret_cast<const char*>(data1), size1},
                                   {reinterpret_cast<const char*>(data2), size2});
  const std::size_t n = std::min(text.size(), max_out_size);
  std::memcpy(out, text.data(), n);
  return n;
}
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ++stats.inputs;
  bool valid = fuzz::check_and_stream(text, false);
  if (text.find('/') != std::string::npos) fuzz::check_and_stream(text, true);
  // Fanuc Macro B (variables, IF/GOTO, WHILE/DO/END, G65, ':' program numbers) under its own
  // dialect, when the text holds what it is written with.
  if (text.find_first_of("#:") != std::string::npos || text.find("GOTO") != std::string::npos ||
      text.find("G65") != std::string::npos)
    valid = fuzz::check_and_stream(text, false, gm::Dialect::Fanuc) || valid;
  // Haas's codes and Fanuc's modal rules (G15/G16, G50/G51, G68/G69, M97, G154, G187), Mach3's
  // (G31, M47): only when the text holds one of them, so most inputs are read once or twice.
  for (const char* code : {"G15", "G16", "G50", "G51", "G68", "G69", "M97", "G154", "G187"})
    if (text.find(code) != std::string::npos) {
      fuzz::check_and_stream(text, false, gm::Dialect::Haas);
      break;
    }
  if (text.find("G31") != std::string::npos || text.find("M47") != std::string::npos)
    fuzz::check_and_stream(text, false, gm::Dialect::Mach3);
  if (valid) ++stats.valid;
  // The machine's side files: tool-table and parameter-file seeds are in this target's corpus.
  fuzz::check_tool_table(text);
  fuzz::check_var_file(text);
  return 0;
}
