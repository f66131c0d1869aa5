// Fuzz target: a machine file through its reader, its writer, and what a run builds from it.
#include "fuzz_target.hpp"

#include "machine_run.hpp"

#include "common/status.hpp"
#include "machine/machine_file.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace {

[[noreturn]] void broken(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_machine: %s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  gm::Machine m;
  try {
    m = gm::parse_machine_toml(text, "fuzz.toml");
  } catch (const gm::InputError&) {
    return 0;
  }
  // The writer's contract: what it writes reads back to an equal machine (so writes the same).
  const std::string written = gm::machine_to_toml(m);
  try {
    const gm::Machine again = gm::parse_machine_toml(written, "fuzz.toml");
    if (gm::machine_to_toml(again) != written)
      broken("machine_to_toml does not round-trip", written);
  } catch (const gm::InputError& e) {
    broken("machine_to_toml wrote a file the reader rejects",
           std::string(e.what()) + "\n" + written);
  }
  fuzz::run_machine(m);
  return 0;
}
