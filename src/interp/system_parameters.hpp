// The interpreter's side of the parameter store: the predefined read-only parameters, the
// system parameters (#5161-#5390 offsets, #5061-#5070 probe, #5399 M66) and the parameter file.
#pragma once

#include "common/diagnostic.hpp"
#include "interp/interpreter.hpp"
#include "interp/parameters.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// The predefined read-only parameters (#<_x>, #<_metric>, ..., #5400-#5413, #5420-#5428), read
/// from the interpreter's state when a program asks for them.
class StateParameters : public ParameterProvider {
 public:
  explicit StateParameters(const Interpreter& interp) : interp_(interp) {}
  void set_line(int line) { line_ = line; }

  bool predefined(std::string_view name, double& v) const override;
  bool live(int n, double& v) const override;

 private:
  bool axis_parameter(std::string_view name, double& v) const;
  bool mode_parameter(std::string_view name, double& v) const;
  bool ini_parameter(std::string_view name, double& v) const;
  // Current position in the program's coordinate system and units (axis `i` in X..W order).
  double program_position(int i) const;
  const Interpreter& interp_;
  int line_ = 0;
};

/// The system parameters between the interpreter and the parameter store, both ways, and
/// LinuxCNC's parameter file (`.var`): read before the first line, written when the program is
/// over (rs274 at exit).
class SystemParameters {
 public:
  /// Makes the store read the predefined parameters from `interp`; `file` empty: none.
  SystemParameters(Interpreter& interp, ParameterStore& params, std::string file);
  SystemParameters(const SystemParameters&) = delete;
  SystemParameters& operator=(const SystemParameters&) = delete;

  /// The line being interpreted (#<_line>).
  void set_line(int line) { state_.set_line(line); }
  /// Reads the parameter file (its offsets apply, LinuxCNC Interp::init). A missing file is not
  /// an error; false with `error` when it cannot be read. True when no file is named.
  bool load(Diagnostic& error);
  /// A program that writes the offsets' parameters changes the interpreter's tables.
  void apply_program_writes();
  /// The interpreter's system parameters in machine units (mm): G28 #5161-#5169, G30
  /// #5181-#5189, G92 #5210-#5219, the coordinate system #5220, G54..G59.3 #5221+20k.
  void export_state();
  /// Writes the parameter file (if one is named and it was read), once.
  void save(std::vector<Diagnostic>& diags);

 private:
  Interpreter& interp_;
  ParameterStore& params_;
  StateParameters state_;
  std::string file_;
  bool loaded_ = false;
  bool saved_ = false;
  std::uint64_t tables_seen_ = 1;  // the tables as the interpreter starts: left to the store
};

}  // namespace gm
