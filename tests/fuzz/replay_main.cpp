// Runs a fuzz target without libFuzzer: each file named (or each file in a named folder) once.
// GMOTION_REPLAY_TIMES=1 prints each input's CPU seconds on stdout ("cpu_s bytes path").
#include "fuzz_target.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

namespace fs = std::filesystem;

namespace {

// The inputs an argument names: the file itself, or the regular files of a folder (sorted,
// not recursive, hidden files skipped). Empty with a message when it names neither.
std::vector<fs::path> inputs_of(const fs::path& arg, bool& ok) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (fs::is_directory(arg, ec)) {
    for (const auto& e : fs::directory_iterator(arg, ec))
      if (e.is_regular_file() && e.path().filename().string().front() != '.')
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
  } else if (fs::is_regular_file(arg, ec)) {
    files.push_back(arg);
  } else {
    std::fprintf(stderr, "replay: %s: no such file or folder\n", arg.string().c_str());
    ok = false;
  }
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE|FOLDER...  (feeds each file to the fuzz target once)\n",
                 argv[0]);
    return 2;
  }
  bool ok = true;
  int count = 0;
  const bool times = std::getenv("GMOTION_REPLAY_TIMES") != nullptr;
  for (int i = 1; i < argc; ++i) {
    for (const fs::path& p : inputs_of(argv[i], ok)) {
      std::ifstream in(p, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
      if (!in.good() && !in.eof()) {
        std::fprintf(stderr, "replay: %s: cannot read\n", p.string().c_str());
        ok = false;
        continue;
      }
      std::fprintf(stderr, "replay: %s (%zu bytes)\n", p.string().c_str(), bytes.size());
      const std::clock_t start = std::clock();
      LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      if (times)
        std::printf("%.6f %zu %s\n", static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC,
                    bytes.size(), p.string().c_str());
      ++count;
    }
  }
  std::printf("replayed %d input%s\n", count, count == 1 ? "" : "s");
  if (count == 0) {
    std::fprintf(stderr, "replay: no input given\n");
    return 2;
  }
  return ok ? 0 : 1;
}
