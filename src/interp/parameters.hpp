// The parameter store: numbered parameters #1-#5601 with LinuxCNC's table, named local and global
// parameters, predefined read-only ones supplied by the interpreter, and the `.var` file.
#pragma once

#include "common/diagnostic.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace gm {

/// What the interpreter supplies: the predefined read-only parameters that reflect its state.
class ParameterProvider {
 public:
  virtual ~ParameterProvider() = default;
  /// The value of predefined named parameter `name` (lower case, leading '_', e.g. "_x");
  /// false if `name` is not predefined.
  virtual bool predefined(std::string_view name, double& value) const = 0;
  /// The value of a live numbered parameter (#5400-#5413 tool data, #5420-#5428 position);
  /// false to use the stored value.
  virtual bool live(int number, double& value) const = 0;
};

/// Numbered parameters (LinuxCNC 2.9's table; see docs/gcode-language.md):
///   #1-#30 subroutine arguments (local to a call), #31-#5000 user, #5061-#5070 probe,
///   #5161-#5169 G28 and #5181-#5189 G30 positions, #5210-#5219 G92, #5220 coordinate system,
///   #5221-#5390 G54-G59.3 (persistent), #5399 M66, #5400-#5413 tool (read-only),
///   #5420-#5428 current position (read-only), #5599-#5601 flags.
/// Named parameters: `#<name>` is local to the current call frame, `#<_name>` is global.
/// Names are stored in lower case (the grammar lower-cases them).
class ParameterStore {
 public:
  static constexpr int kFirst = 1;
  static constexpr int kLast = 5601;
  static constexpr int kArgs = 30;                      ///< #1-#30: subroutine arguments
  static constexpr int kMacroLocals = 33;               ///< Fanuc Macro B's locals #1-#33
  static constexpr std::size_t kMaxSystemWrites = 256;  ///< per line (a line holds fewer)

  ParameterStore();

  static bool valid(int n) { return n >= kFirst && n <= kLast; }
  /// #5400-#5413 and #5420-#5428: a program cannot set them.
  static bool read_only(int n) { return (n >= 5400 && n <= 5413) || (n >= 5420 && n <= 5428); }
  /// Always saved in the parameter file (LinuxCNC's _required_parameters): G28 #5161-#5169,
  /// G30 #5181-#5189, G92 #5210-#5219, the coordinate system #5220 and, for each of G54-G59.3,
  /// #5221+20k .. #5230+20k (X..W and the XY rotation R).
  static bool persistent(int n) {
    if ((n >= 5161 && n <= 5169) || (n >= 5181 && n <= 5189) || (n >= 5210 && n <= 5220))
      return true;
    return n >= 5221 && n <= 5390 && (n - 5221) % 20 < 10;
  }

  /// The value of #n (`n` must be valid): live values come from the provider.
  double get(int n) const;
  /// Sets #n from a program (`n` valid and not read-only: checked by the caller). Settings of
  /// #5161-#5390 (offsets, G28/G30, G92) are also kept for the interpreter (system_writes).
  void set(int n, double v) {
    numbered_[static_cast<std::size_t>(n)] = v;
    if (n >= 5161 && n <= 5390 && system_writes_.size() < kMaxSystemWrites)
      system_writes_.emplace_back(n, v);
  }
  /// The settings of #5161-#5390 since clear_system_writes(), in order.
  const std::vector<std::pair<int, double>>& system_writes() const { return system_writes_; }
  void clear_system_writes() { system_writes_.clear(); }
  /// Sets #n from the interpreter (read-only ones included).
  void set_system(int n, double v) { numbered_[static_cast<std::size_t>(n)] = v; }

  /// Reads named parameter `name`: a predefined one, a global (`_name`) or a local of the
  /// current frame. False if it was never set.
  bool get_named(std::string_view name, double& value) const;
  /// True if `name` is predefined (read-only).
  bool predefined(std::string_view name) const;
  /// Sets a named parameter (global if it starts with '_', else local to the current frame).
  /// False if it is predefined (read-only).
  bool set_named(std::string_view name, double value);

  /// The interpreter's live values (may be null: then predefined names are unset).
  void set_provider(const ParameterProvider* p) { provider_ = p; }

  /// What the last subroutine returned: #<_value> and #<_value_returned>.
  void set_returned(double value, bool returned) {
    value_ = value;
    value_returned_ = returned ? 1.0 : 0.0;
  }

  /// Call frames (O-word subroutines): a new frame has no named locals and saves #1-#30 (an
  /// M98 subprogram's does not: #1-#30 stay global, LinuxCNC's Fanuc-style rule); a G65 macro
  /// call's saves #1-#33 (`saved` = kMacroLocals). pop_frame restores what was saved.
  void push_frame(bool save_args = true, int saved = kArgs);
  void pop_frame();
  std::size_t depth() const { return frames_.size() - 1; }

  /// Reads a LinuxCNC `.var` file as Interp::restore_parameters does: lines `number value`
  /// with increasing numbers in 1..5601 set those parameters, every other numbered parameter
  /// becomes 0, lines that do not start with a number are ignored. A missing file is not an
  /// error (nothing changes). False with `error` located in the file (`error.file` = path)
  /// when it cannot be read or is corrupt: a number out of range or out of order, a number
  /// without a finite value. The numbers read are remembered and written back by save_var_file.
  bool load_var_file(const std::string& path, Diagnostic& error);
  /// Writes the persistent parameters and those loaded, in increasing order, `number<TAB>%f`
  /// (Interp::save_parameters' lines). Writes that one file only (no backup, no temporary).
  bool save_var_file(const std::string& path, std::string& error) const;
  /// True when #n was read from the parameter file.
  bool from_file(int n) const { return from_file_[static_cast<std::size_t>(n)]; }
  /// Also saves #first..#last (Fanuc's kept commons #500-#999) in the parameter file, those not
  /// vacant (NaN).
  void keep_in_file(int first, int last) {
    kept_first_ = first;
    kept_last_ = last;
  }

 private:
  struct Hash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  using NameMap = std::unordered_map<std::string, double, Hash, std::equal_to<>>;
  struct Frame {
    NameMap locals;
    std::array<double, kMacroLocals> saved_args{};
    int restores = kArgs;  ///< how many of #1.. pop_frame restores
  };

  std::vector<double> numbered_;
  std::vector<std::pair<int, double>> system_writes_;
  std::vector<bool> from_file_;
  NameMap globals_;
  std::vector<Frame> frames_;
  const ParameterProvider* provider_ = nullptr;
  double value_ = 0.0;
  double value_returned_ = 0.0;
  int kept_first_ = 1, kept_last_ = 0;
};

}  // namespace gm
