// --subroutine-path, --max-iterations, --dialect and the parameter file flags, shared by check,
// moves, run and compare.
#include "cli/language_flags.hpp"

#include "interp/subroutine_path.hpp"

namespace gm::cli {

void add_language_flags(CLI::App* sub, LanguageFlags& f) {
  sub->add_option("--subroutine-path", f.subroutine_path,
                  "directories (DIR[:DIR...]) where 'o<name> call' finds name.ngc, searched "
                  "before the machine's subroutine_path");
  sub->add_option("--max-iterations", f.max_iterations,
                  "loop iterations and subroutine calls before the program is stopped")
      ->check(CLI::PositiveNumber);
  sub->add_option("--dialect", f.dialect,
                  "what the program is written for: linuxcnc (default: rs274's rules), fanuc "
                  "(Fanuc/Haas posts), grbl (grbl 1.1); docs/dialects.md")
      ->check(CLI::IsMember({"linuxcnc", "fanuc", "grbl"}, CLI::ignore_case));
  auto* pf = sub->add_option("--parameter-file", f.parameter_file,
                             "LinuxCNC .var parameter file read before the program and written "
                             "after it (run, moves; check only reads), instead of the machine's");
  sub->add_flag("--no-parameter-file", f.no_parameter_file,
                "neither read nor write a parameter file, not even the one the machine names")
      ->excludes(pf);
}

void apply_language_flags(const LanguageFlags& f, const Machine& machine,
                          InterpreterOptions& opts) {
  opts.subroutine_path = SubroutinePath::split(f.subroutine_path);
  for (const std::string& dir : machine.subroutine_path) opts.subroutine_path.push_back(dir);
  opts.max_iterations = f.max_iterations;
  opts.parameter_file = f.no_parameter_file         ? std::string()
                        : !f.parameter_file.empty() ? f.parameter_file
                                                    : machine.parameter_file;
  const std::string& d = f.dialect.empty() ? machine.dialect : f.dialect;
  if (!d.empty()) parse_dialect(d, opts.dialect);  // both checked when read
}

}  // namespace gm::cli
