// Fuzz target: G-code text (LinuxCNC, Fanuc Macro B) through parser and interpreter, checked,
// streamed; the same text as a tool table and as a `.var` parameter file (table_check.hpp).
// Under libFuzzer, most mutants come from a structure-aware mutator (program_mutator.hpp).
#include "fuzz_target.hpp"

#include "breed_pool.hpp"
#include "program_check.hpp"
#include "program_mutator.hpp"
#include "table_check.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

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

// Readings of a program worth breeding from: valid and at most this many moves. A valid program
// of 200,000 moves (a lathe cycle at its bound) takes 1-2 s under ASan+UBSan where the median
// input takes 2 ms, and its mutants are as long: such a program runs, but does not breed.
constexpr std::int64_t kBreedMoves = 10'000;

#ifdef GMOTION_LIBFUZZER
// Mutants are made from valid programs, tables and parameter files (breed_pool.hpp), unless
// GMOTION_FUZZ_KEEP_INVALID=1 (libFuzzer's parents as it chooses them, invalid or not).
fuzz::BreedPool pool;
const bool keep_invalid = std::getenv("GMOTION_FUZZ_KEEP_INVALID") != nullptr;

// The parent to mutate, copied into `data` when the pool chose another.
std::size_t parent(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed) {
  if (keep_invalid) return size;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string_view p = pool.choose(text, max_size, seed);
  if (p.data() == text.data()) return size;
  std::memcpy(data, p.data(), p.size());
  return p.size();
}
#endif

}  // namespace

#ifdef GMOTION_LIBFUZZER
extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

// Four mutants in five are made line by line and word by word (ProgramMutator), the fifth by
// libFuzzer's byte-level mutations (for what no construct table holds: the parser's errors).
extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed) {
  size = parent(data, size, max_size, seed);
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
  const std::string_view first(reinterpret_cast<const char*>(data1), size1);
  const std::string text = m.cross(keep_invalid ? first : pool.choose(first, max_out_size, seed),
                                   {reinterpret_cast<const char*>(data2), size2});
  const std::size_t n = std::min(text.size(), max_out_size);
  std::memcpy(out, text.data(), n);
  return n;
}
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ++stats.inputs;
  bool breed = false;  // a reading worth mutating further
  const auto read = [&](bool block_delete, gm::Dialect dialect) {
    const std::int64_t moves = fuzz::check_and_stream(text, block_delete, dialect);
    breed = breed || (moves >= 0 && moves <= kBreedMoves);
    return moves >= 0;
  };
  bool valid = read(false, gm::Dialect::LinuxCNC);
  if (text.find('/') != std::string::npos) read(true, gm::Dialect::LinuxCNC);
  // Fanuc Macro B (variables, IF/GOTO, WHILE/DO/END, G65, ':' program numbers) under its own
  // dialect, when the text holds what it is written with.
  if (text.find_first_of("#:") != std::string::npos || text.find("GOTO") != std::string::npos ||
      text.find("G65") != std::string::npos)
    valid = read(false, gm::Dialect::Fanuc) || valid;
  // Haas's codes and Fanuc's modal rules (G15/G16, G50/G51, G68/G69, M97, G154, G187), Mach3's
  // (G31, M47): only when the text holds one of them, so most inputs are read once or twice.
  for (const char* code : {"G15", "G16", "G50", "G51", "G68", "G69", "M97", "G154", "G187"})
    if (text.find(code) != std::string::npos) {
      read(false, gm::Dialect::Haas);
      break;
    }
  if (text.find("G31") != std::string::npos || text.find("M47") != std::string::npos)
    read(false, gm::Dialect::Mach3);
  if (valid) ++stats.valid;
  // The machine's side files: tool-table and parameter-file seeds are in this target's corpus.
  breed = fuzz::check_tool_table(text) || breed;
  breed = fuzz::check_var_file(text) || breed;
#ifdef GMOTION_LIBFUZZER
  pool.ran(text, breed);
#endif
  return 0;
}
