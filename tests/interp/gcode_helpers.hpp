// Test helpers: run a G-code string through the interpreter and collect canon or diagnostics.
#pragma once

#include "common/error_codes.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"

#include <sstream>
#include <string>
#include <vector>

namespace gmtest {

/// All canon of `program` (throws gm::InputError on the first error).
inline std::vector<gm::Canon> run(const std::string& program,
                                  const gm::Machine& m = gm::Machine{}) {
  std::istringstream in(program);
  gm::ProgramStream s(in, "test.ngc", gm::InterpreterOptions{&m, false});
  std::vector<gm::Canon> out;
  gm::Canon c;
  while (s.next(c)) out.push_back(c);
  return out;
}

/// The text of every message event ((MSG,...), (DEBUG,...)) of `program`.
inline std::vector<std::string> messages(const std::string& program) {
  std::vector<std::string> out;
  for (const auto& c : run(program))
    if (const auto* e = std::get_if<gm::Event>(&c); e && e->kind == gm::EventKind::Message)
      out.push_back(e->text);
  return out;
}

/// The motions only.
inline std::vector<gm::Motion> motions(const std::string& program,
                                       const gm::Machine& m = gm::Machine{}) {
  std::vector<gm::Motion> out;
  for (const auto& c : run(program, m))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) out.push_back(*mo);
  return out;
}

/// The diagnostics of checking `program`.
inline std::vector<gm::Diagnostic> diagnose(const std::string& program,
                                            const gm::Machine& m = gm::Machine{},
                                            bool block_delete = false) {
  std::istringstream in(program);
  std::vector<gm::Diagnostic> d;
  gm::check_program_diagnostics(in, "test.ngc", gm::InterpreterOptions{&m, block_delete}, d);
  return d;
}

inline int code(gm::ErrorCode c) {
  return static_cast<int>(c);
}

}  // namespace gmtest
