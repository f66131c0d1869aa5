// LinuxCNC tool table reading and writing (the format of tooledit / the .tbl files).
#include "machine/tool_table.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>

namespace gm {

const ToolEntry* ToolTable::find(int number) const {
  for (const ToolEntry& e : tools)
    if (e.number == number) return &e;
  return nullptr;
}

ToolEntry* ToolTable::find(int number) {
  for (ToolEntry& e : tools)
    if (e.number == number) return &e;
  return nullptr;
}

void ToolTable::set(const ToolEntry& e) {
  if (ToolEntry* old = find(e.number))
    *old = e;
  else
    tools.push_back(e);
}

namespace {

constexpr const char* kAxisWords = "XYZABCUVW";

bool as_int(double v, int& out) {
  if (!(std::fabs(v) < 1e9) || v != std::floor(v)) return false;
  out = static_cast<int>(v);
  return true;
}

[[noreturn]] void fail_tool_line(const std::string& filename, int lineno, const std::string& why) {
  throw InputError(fmt::format("{}:{}: tool table: {}", filename, lineno, why));
}

// Cuts the `;comment` off `line` and returns it, trailing space dropped.
std::string cut_tool_comment(std::string& line) {
  std::string comment;
  if (const auto semi = line.find(';'); semi != std::string::npos) {
    comment = line.substr(semi + 1);
    line.resize(semi);
    while (!comment.empty() && std::isspace(static_cast<unsigned char>(comment.back())))
      comment.pop_back();
  }
  return comment;
}

// One word of a tool line, letter `c` (upper case) with value `v`, into `e`: false for an
// unknown letter; `error` says why a value does not fit.
bool set_tool_word(ToolEntry& e, char c, double v, bool& have_t, std::string& error) {
  int n = 0;
  switch (c) {
    case 'T':
      if (!as_int(v, e.number) || e.number < 0) error = "T must be a tool number (0 or more)";
      have_t = true;
      return true;
    case 'P':
      if (!as_int(v, e.pocket) || e.pocket < 0) error = "P must be a pocket number (0 or more)";
      return true;
    case 'D':
      e.diameter_mm = v;
      return true;
    case 'I':
      e.front_angle_deg = v;
      return true;
    case 'J':
      e.back_angle_deg = v;
      return true;
    case 'Q':
      if (!as_int(v, n)) error = "Q must be an orientation 0..9";
      e.orientation = n;
      return true;
    default: {
      const char* ax = std::char_traits<char>::find(kAxisWords, 9, c);
      if (!ax) return false;
      e.offset_mm[static_cast<std::size_t>(ax - kAxisWords)] = v;
      return true;
    }
  }
}

}  // namespace

ToolTable read_tool_table(std::istream& in, const std::string& filename) {
  ToolTable t;
  t.source = filename;
  std::string line;
  int lineno = 0;
  auto fail = [&](const std::string& why) { fail_tool_line(filename, lineno, why); };
  while (std::getline(in, line)) {
    ++lineno;
    ToolEntry e;
    e.comment = cut_tool_comment(line);
    bool have_t = false;
    std::size_t i = 0;
    while (i < line.size()) {
      const char raw = line[i];
      if (std::isspace(static_cast<unsigned char>(raw))) {
        ++i;
        continue;
      }
      const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(raw)));
      const char* begin = line.c_str() + i + 1;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin || !std::isfinite(v))
        fail(fmt::format("expected a number after '{}' (column {})", raw, i + 1));
      i = static_cast<std::size_t>(end - line.c_str());
      std::string error;
      if (!set_tool_word(e, c, v, have_t, error)) fail(fmt::format("unknown word '{}'", raw));
      if (!error.empty()) fail(error);
    }
    if (!have_t) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // blank or comment
      fail("a tool line needs T");
    }
    if (t.find(e.number)) fail(fmt::format("tool {} appears twice", e.number));
    t.tools.push_back(std::move(e));
  }
  return t;
}

ToolTable load_tool_table(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(fmt::format("{}: cannot open the tool table", path));
  return read_tool_table(f, path);
}

ToolTable default_tool_table() {
  ToolTable t;
  t.source = "<built-in default>";
  auto add = [&](int n, double z, double d, const char* comment) {
    ToolEntry e;
    e.number = n;
    e.pocket = n;
    e.offset_mm[2] = z;
    e.diameter_mm = d;
    e.comment = comment;
    t.tools.push_back(e);
  };
  add(1, 50.0, 6.0, "6 mm flat end mill");
  add(2, 60.0, 3.0, "3 mm drill");
  add(3, 45.0, 10.0, "10 mm flat end mill");
  add(4, 70.0, 5.0, "5 mm spot drill");
  return t;
}

std::string format_tool_table(const ToolTable& t, double scale) {
  std::string s;
  for (const ToolEntry& e : t.tools) {
    s += fmt::format("T{} P{}", e.number, e.pocket);
    for (std::size_t a = 0; a < 9; ++a)
      if (e.offset_mm[a] != 0.0)
        s += fmt::format(" {}{:.9f}", kAxisWords[a], e.offset_mm[a] * scale);
    s += fmt::format(" D{:.9f}", e.diameter_mm * scale);
    if (e.front_angle_deg != 0.0) s += fmt::format(" I{}", e.front_angle_deg);
    if (e.back_angle_deg != 0.0) s += fmt::format(" J{}", e.back_angle_deg);
    if (e.orientation != 0) s += fmt::format(" Q{}", e.orientation);
    s += " ;" + e.comment + "\n";
  }
  return s;
}

}  // namespace gm
