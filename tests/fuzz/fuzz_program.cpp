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
#include <ctime>
#include <functional>
#include <string>
#include <string_view>

namespace {

// GMOTION_FUZZ_STATS=1: at exit, how many inputs ran, how many readings (each checked and
// streamed) they made, and how many inputs were valid programs.
// And the CPU seconds the target spent: in all, on the side files, on inputs of 0.1 s or more.
struct Stats {
  long long inputs = 0, readings = 0, fanuc = 0, valid = 0, slow = 0, tables = 0, var_files = 0;
  double cpu_s = 0, files_s = 0, slow_s = 0;
  bool on = std::getenv("GMOTION_FUZZ_STATS") != nullptr;
  static double now_s() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }
  ~Stats() {
    if (on)
      std::fprintf(
          stderr,
          "fuzz_program: %lld inputs, %lld readings (%lld as Fanuc's), %lld valid "
          "LinuxCNC or Fanuc programs, %lld tool tables, %lld parameter files; target %.1f "
          "CPU-s (side files %.1f, %lld inputs of 0.1 s or more %.1f)\n",
          inputs, readings, fanuc, valid, tables, var_files, cpu_s, files_s, slow, slow_s);
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

// True when a line starts with '/' (after blanks), the only place the parser reads it as block
// delete: only then does reading with block delete on differ. ('/' anywhere, as in a division,
// read a third of the inputs twice for the same result.)
bool has_block_delete_line(const std::string& text) {
  bool at_start = true;
  for (const char c : text) {
    if (c == '\n' || c == '\r')
      at_start = true;
    else if (at_start && c == '/')
      return true;
    else if (c != ' ' && c != '\t')
      at_start = false;
  }
  return false;
}

// Fanuc Macro B (variables, IF/GOTO, WHILE/DO/END, G65, ':' program numbers) is read under its
// own dialect when the text holds one of its own words (':' opening a line); a text whose only
// sign of it is '#' (as LinuxCNC's parameters are written: nearly every mutant, since the
// constructs the mutator inserts set some) when LinuxCNC's reading refused it, else one time in
// four, chosen by content so that a replay reads it alike. (Read as Fanuc's whenever it held
// '#', 96 % of the inputs were read twice.)
bool read_as_fanuc(const std::string& text, bool valid_linuxcnc) {
  for (std::size_t at = text.find(':'); at != std::string::npos; at = text.find(':', at + 1)) {
    const std::size_t line = text.find_last_of('\n', at);  // ':' opening a line (not a comment's)
    const std::size_t first =
        text.find_first_not_of(" \t", line == std::string::npos ? 0 : line + 1);
    if (first == at) return true;
  }
  for (const char* word : {"GOTO", "G65", "THEN", "DO1", "DO2", "DO3", "END1", "END2", "END3"})
    if (text.find(word) != std::string::npos) return true;
  return text.find('#') != std::string::npos &&
         (!valid_linuxcnc || (std::hash<std::string>{}(text) >> 8) % 4 == 0);
}

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
  const double start_s = stats.on ? Stats::now_s() : 0.0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  ++stats.inputs;
  bool breed = false;  // a reading worth mutating further
  const auto read = [&](bool block_delete, gm::Dialect dialect) {
    ++stats.readings;
    if (dialect == gm::Dialect::Fanuc) ++stats.fanuc;
    const std::int64_t moves = fuzz::check_and_stream(text, block_delete, dialect);
    breed = breed || (moves >= 0 && moves <= kBreedMoves);
    return moves >= 0;
  };
  bool valid = read(false, gm::Dialect::LinuxCNC);
  if (has_block_delete_line(text)) read(true, gm::Dialect::LinuxCNC);
  if (read_as_fanuc(text, valid)) valid = read(false, gm::Dialect::Fanuc) || valid;
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
  const double files_s = stats.on ? Stats::now_s() : 0.0;
  // The side files cost more than a program's reading (a parameter file is written, read and
  // saved six times, and a program runs with it: 4.8 ms under ASan+UBSan), and their mutants are
  // side files again: in two 180 s runs they took over the pool, 40-50 % of the inputs and half
  // the CPU. So the program runs with one parameter file in four, and an accepted side file is
  // bred from one time in four (both chosen by content, so that a replay does the same).
  const std::size_t h = std::hash<std::string>{}(text);
  const bool table = fuzz::check_tool_table(text);
  const bool var_file = fuzz::check_var_file(text, (h >> 12) % 4 == 0);
  breed = breed || ((table || var_file) && (h >> 16) % 4 == 0);
  stats.tables += table ? 1 : 0;
  stats.var_files += var_file ? 1 : 0;
  if (stats.on) {
    const double end_s = Stats::now_s();
    stats.cpu_s += end_s - start_s;
    stats.files_s += end_s - files_s;
    if (end_s - start_s >= 0.1) {
      ++stats.slow;
      stats.slow_s += end_s - start_s;
      std::fprintf(stderr,
                   "fuzz_program: an input of %zu bytes took %.2f CPU-s (%.2f side files)\n", size,
                   end_s - start_s, end_s - files_s);
      if (const char* dir = std::getenv("GMOTION_FUZZ_SLOW_DIR")) {  // kept to look at
        const std::string path =
            std::string(dir) + "/slow-" + std::to_string(std::hash<std::string>{}(text));
        if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
          std::fwrite(text.data(), 1, text.size(), f);
          std::fclose(f);
        }
      }
    }
  }
#ifdef GMOTION_LIBFUZZER
  pool.ran(text, breed);
#endif
  return 0;
}
