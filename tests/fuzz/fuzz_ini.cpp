// Fuzz target: a LinuxCNC INI through its reader (includes, units, scales), the INI writer, and
// what a run builds from the machine it gives.
#include "fuzz_target.hpp"

#include "machine_run.hpp"

#include "common/status.hpp"
#include "machine/linuxcnc_ini.hpp"

#include <unistd.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace fs = std::filesystem;

namespace {

[[noreturn]] void broken(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_ini: %s\n%s\n", what, detail.c_str());
  std::abort();
}

// The input as fuzz.ini in a folder of this process's own, so that its #INCLUDE, TOOL_TABLE and
// PARAMETER_FILE lines can name it (itself, in a loop); the reader only reads. The folder is
// removed at exit.
struct ScratchDir {
  fs::path path = fs::temp_directory_path() / ("gmotion-fuzz-ini-" + std::to_string(getpid()));
  ScratchDir() { fs::create_directories(path); }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

fs::path write_input(const std::uint8_t* data, std::size_t size, const char* name) {
  static const ScratchDir dir;
  const fs::path p = dir.path / name;
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gm::IniImport imp;
  try {
    imp = gm::load_linuxcnc_ini(write_input(data, size, "fuzz.ini"));
  } catch (const gm::InputError&) {
    return 0;
  }
  // The writer's contract: the sections it writes for the machine read back without an error.
  const std::string written = gm::machine_to_linuxcnc_ini(imp.machine);
  try {
    (void)gm::load_linuxcnc_ini(write_input(reinterpret_cast<const std::uint8_t*>(written.data()),
                                            written.size(), "written.ini"));
  } catch (const gm::InputError& e) {
    broken("machine_to_linuxcnc_ini wrote an INI the reader rejects",
           std::string(e.what()) + "\n" + written);
  }
  // An INI's tau follows its limits and is often long; fuzz_machine covers the filters, so a
  // tenth of its work here keeps the reader's inputs coming.
  fuzz::run_machine(imp.machine, fuzz::kTapSampleBudget / 10);
  return 0;
}
