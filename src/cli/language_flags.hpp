// The flags of every command that reads a program: subroutine path, iteration bound, dialect.
#pragma once

#include "interp/program.hpp"
#include "machine/machine.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace gm::cli {

/// How the program's language is read (issue 15).
struct LanguageFlags {
  std::string subroutine_path;               ///< --subroutine-path DIR[:DIR...]
  std::int64_t max_iterations = 10'000'000;  ///< --max-iterations N
  std::string dialect;                       ///< --dialect linuxcnc|fanuc|grbl (else the machine's)
  std::string parameter_file;                ///< --parameter-file FILE (else the machine's)
  bool no_parameter_file = false;            ///< --no-parameter-file: none read or written
};

/// Adds --subroutine-path, --max-iterations, --dialect, --parameter-file and --no-parameter-file
/// to `sub`.
void add_language_flags(CLI::App* sub, LanguageFlags& flags);

/// Sets the options' subroutine path (the flag's directories, then the machine's), bound,
/// parameter file (the flag's, else the machine's, none under --no-parameter-file) and dialect (the
/// flag's, else the machine's).
void apply_language_flags(const LanguageFlags& flags, const Machine& machine,
                          InterpreterOptions& opts);

}  // namespace gm::cli
