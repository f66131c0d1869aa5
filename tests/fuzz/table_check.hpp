// What the machine's side files promise: a LinuxCNC tool table and a `.var` parameter file that
// the readers accept are written back so that they read the same, and a program runs with them.
#pragma once

#include "program_check.hpp"

#include "common/diagnostic.hpp"
#include "common/status.hpp"
#include "interp/parameters.hpp"
#include "machine/tool_table.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <unistd.h>

namespace fuzz {

[[noreturn]] inline void table_broken(const std::string& what, const std::string& text) {
  std::fprintf(stderr, "fuzz: %s\n--- file ---\n%s\n", what.c_str(), text.c_str());
  std::abort();
}

/// a and b agree to the `digits` decimals a writer printed (and the double's own rounding).
inline bool near(double a, double b, int digits) {
  return std::abs(a - b) <=
         0.5 * std::pow(10.0, -digits) + 4 * std::numeric_limits<double>::epsilon() * std::abs(a);
}

/// Reads `text` as a tool table; when the reader accepts it, the table format_tool_table writes
/// must read back to the same tools (lengths and diameters to its 9 decimals). True when the
/// reader accepts it.
inline bool check_tool_table(const std::string& text) {
  gm::ToolTable t;
  try {
    std::istringstream in(text);
    t = gm::read_tool_table(in, "fuzz.tbl");
  } catch (const gm::InputError&) {
    return false;
  }
  const std::string written = gm::format_tool_table(t);
  gm::ToolTable back;
  try {
    std::istringstream in(written);
    back = gm::read_tool_table(in, "written.tbl");
  } catch (const gm::InputError& e) {
    table_broken(
        fmt::format("the tool table written back does not read: {}\n{}", e.what(), written), text);
  }
  if (back.tools.size() != t.tools.size())
    table_broken("the tool table written back has another number of tools", text);
  for (std::size_t i = 0; i < t.tools.size(); ++i) {
    const gm::ToolEntry &a = t.tools[i], &b = back.tools[i];
    bool same = a.number == b.number && a.pocket == b.pocket && a.orientation == b.orientation &&
                a.comment == b.comment && near(a.diameter_mm, b.diameter_mm, 9) &&
                a.front_angle_deg == b.front_angle_deg && a.back_angle_deg == b.back_angle_deg;
    for (std::size_t k = 0; k < 9; ++k) same = same && near(a.offset_mm[k], b.offset_mm[k], 9);
    if (!same)
      table_broken(fmt::format("tool T{} reads back otherwise:\n{}", a.number, written), text);
  }
  return true;
}

/// A file's bytes ("" when it cannot be read).
inline std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// True when a line of `text` starts (after blanks) with a number: the `.var` reader passes over
/// every other line, so only such a text is worth reading as a parameter file.
inline bool has_numbered_line(const std::string& text) {
  bool at_start = true;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      at_start = true;
    } else if (at_start && c != ' ' && c != '\t') {
      const char d = (c == '+' || c == '-') && i + 1 < text.size() ? text[i + 1] : c;
      if (d >= '0' && d <= '9') return true;
      at_start = false;
    }
  }
  return false;
}

/// The two files check_var_file writes: made by the first input that needs them, overwritten by
/// the next (not created and removed for every input), removed at exit.
struct VarFiles {
  std::string path, saved;
  VarFiles() {
    const char* dir = std::getenv("TMPDIR");
    const std::string base =
        fmt::format("{}/gmotion-fuzz-var-{}", dir && *dir ? dir : "/tmp", getpid());
    path = base + ".var";
    saved = base + "-saved.var";
  }
  VarFiles(const VarFiles&) = delete;
  VarFiles& operator=(const VarFiles&) = delete;
  ~VarFiles() {
    std::remove(path.c_str());
    std::remove(saved.c_str());
  }
};

/// Reads `text` as a LinuxCNC `.var` file; when the reader accepts it, the file save_var_file
/// writes reads back to the same parameters (to its 6 decimals) and writes the same bytes again,
/// and, when `with_program`, a program that reads and sets the G54/G55 offsets runs with it
/// (checked and streamed alike; the stream saves the file at its end, which must read again).
/// True when the reader accepts it.
inline bool check_var_file(const std::string& text, bool with_program = true) {
  if (!has_numbered_line(text)) return false;
  static const VarFiles files;
  const std::string& path = files.path;
  const std::string& saved = files.saved;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
  }
  gm::ParameterStore params;
  gm::Diagnostic error;
  if (!params.load_var_file(path, error)) {
    (void)gm::format_diagnostic(path, error);
    return false;
  }
  std::string why;
  if (!params.save_var_file(saved, why)) table_broken("cannot save the parameters: " + why, text);
  const std::string first = file_text(saved);
  gm::ParameterStore back;
  if (!back.load_var_file(saved, error))
    table_broken(
        fmt::format("the parameter file written back does not read: {}\n{}", error.message, first),
        text);
  for (int n = gm::ParameterStore::kFirst; n <= gm::ParameterStore::kLast; ++n)
    if (params.from_file(n) && !near(params.get(n), back.get(n), 6))
      table_broken(fmt::format("#{} reads back as {} where {} was saved\n{}", n, back.get(n),
                               params.get(n), first),
                   text);
  if (!back.save_var_file(saved, why) || file_text(saved) != first)
    table_broken("the parameter file saved twice differs:\n" + first, text);

  if (!with_program) return true;
  // A program with the file: the offsets in it apply, and G10 writes persistent ones back.
  static constexpr const char* kProgram =
      "G10 L2 P2 X[#5241 + 1] Y#5222\nG55 G0 X1 Y[#31 + 1]\n#5243 = [#5243 + 0.5]\nG54 G1 X2 "
      "F600\nM2\n";
  gm::InterpreterOptions opts;
  opts.parameter_file = path;
  opts.save_parameters = true;
  check_and_stream(kProgram, false, gm::Dialect::LinuxCNC, opts);
  if (!back.load_var_file(path, error))
    table_broken(fmt::format("the parameter file a program saved does not read: {}\n{}",
                             error.message, file_text(path)),
                 text);
  return true;
}

}  // namespace fuzz
