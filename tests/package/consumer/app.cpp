// app PROGRAM [MACHINE.toml]: runs a program through gmotion sample by sample from its own loop.
#include "machine/machine_file.hpp"
#include "pipeline/run.hpp"

#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: app PROGRAM [MACHINE.toml]\n";
    return 2;
  }
  try {
    gm::RunOptions options;
    options.config.machine = argc == 3 ? gm::load_machine_file(argv[2]) : gm::default_machine();
    options.program_name = argv[1];
    std::ifstream program(argv[1]);
    if (!program) {
      std::cerr << "cannot read " << argv[1] << "\n";
      return 2;
    }
    gm::Run run(std::move(options), program, gm::InterpreterOptions{});
    std::int64_t samples = 0;
    int last_line = 0, line_changes = 0;
    while (run.step() == gm::RunStatus::Working) {
      const gm::SampleRecord& s = run.last();  // what your controller would log or act on
      ++samples;
      if (s.line != last_line) ++line_changes, last_line = s.line;
    }
    std::cout << run.summary().json();
    std::cerr << "app: " << samples << " samples, " << line_changes << " line changes\n";
    return run.summary().settled ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "app: " << e.what() << "\n";
    return 1;
  }
}
