// A LinuxCNC tool table (`T1 P1 Z50 D6 ;comment` lines): tool offsets on nine axes, diameters.
#pragma once

#include <array>
#include <istream>
#include <string>
#include <vector>

namespace gm {

/// One tool. Lengths in mm (the table is in machine units; gmotion's are mm).
struct ToolEntry {
  int number = 0;                     ///< T
  int pocket = 0;                     ///< P
  std::array<double, 9> offset_mm{};  ///< X Y Z A B C U V W offsets (Z = tool length)
  double diameter_mm = 0.0;           ///< D
  double front_angle_deg = 0.0;       ///< I (lathe)
  double back_angle_deg = 0.0;        ///< J (lathe)
  int orientation = 0;                ///< Q (lathe)
  std::string comment;                ///< after ';'
};

/// The tools a machine has, looked up by tool number.
struct ToolTable {
  std::string source = "<none>";  ///< file it was read from, or "<built-in default>"
  std::vector<ToolEntry> tools;   ///< in file order; tool numbers unique

  /// The entry of tool `number`, or null.
  const ToolEntry* find(int number) const;
  ToolEntry* find(int number);
  /// Adds or replaces the entry of `e.number`.
  void set(const ToolEntry& e);
};

/// Parses a LinuxCNC tool table. Blank lines and lines that are only a comment are skipped;
/// throws gm::InputError "FILE:LINE: ..." on a bad line or a repeated tool number.
ToolTable read_tool_table(std::istream& in, const std::string& filename);
/// Reads the file (InputError if it cannot be opened).
ToolTable load_tool_table(const std::string& path);
/// The small table of the built-in default machine (as LinuxCNC's sim configurations carry one).
ToolTable default_tool_table();
/// The table in LinuxCNC's format, lengths multiplied by `scale` (1/25.4 writes inches).
std::string format_tool_table(const ToolTable& t, double scale = 1.0);

}  // namespace gm
