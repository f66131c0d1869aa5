// --subroutine-path and --max-iterations, shared by check, moves, run and compare.
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
}

void apply_language_flags(const LanguageFlags& f, const Machine& machine,
                          InterpreterOptions& opts) {
  opts.subroutine_path = SubroutinePath::split(f.subroutine_path);
  for (const std::string& dir : machine.subroutine_path) opts.subroutine_path.push_back(dir);
  opts.max_iterations = f.max_iterations;
  opts.parameter_file = machine.parameter_file;
}

}  // namespace gm::cli
