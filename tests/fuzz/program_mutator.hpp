// A structure-aware mutator for G-code text: changes a word's number, swaps a code for another of
// its group, inserts a whole construct (O-word blocks, cycles, compensation, offsets, Macro B,
// lathe cycles) or moves lines, so that most mutants stay valid programs and run deep.
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace fuzz {

/// Constructs an insertion writes, each valid on its own where a block may stand ('@' is
/// replaced by a label number unused elsewhere, so that O-words do not clash). The first
/// character says where: 'L' LinuxCNC's O-words only, 'F' Fanuc's Macro B only, 'C' both.
inline constexpr std::string_view kConstructs[] = {
    // O-word flow (LinuxCNC).
    "Lo@ sub\nG1 X#1 Y#2\no@ endsub\no@ call [1.5] [2]\n",
    "L#<n@> = 0\no@ while [#<n@> LT 3]\nG1 X[#<n@> * 2] Y1\n#<n@> = [#<n@> + 1]\no@ endwhile\n",
    "Lo@ repeat [2]\nG91 G1 X1 Y-1\nG90\no@ endrepeat\n",
    "Lo@ if [#5420 GT 1]\nG0 X0\no@ elseif [#5421 LT 0]\nG0 Y1\no@ else\nG0 X1\no@ endif\n",
    "Lo@ do\n#<d@> = [#<d@> + 1]\no@ while [#<d@> LT 2]\n",
    "Lo@ sub\no@ return [#1 * 2]\no@ endsub\no@ call [3]\nG1 X#<_value>\n",
    "L#<_v@> = [SIN[30] * 2 + ATAN[1]/[2]]\nG1 X#<_v@>\n",
    "L(DEBUG, x = #<_x>)\n(PRINT, #5221)\n",
    // Canned cycles.
    "CG98 G81 X5 Y5 Z-2 R1 F300\nX10\nG80\n",
    "CG99 G83 X1 Y1 Z-5 R1 Q1 F200\nX3 Y3\nG80\n",
    "CG82 X2 Y2 Z-3 R1 P0.2 F250\nG80\n",
    "CG73 X0 Y4 Z-4 R1 Q0.7 F180 L2\nG80\n",
    "CM3 S800\nG84 X4 Y0 Z-6 R1 F400\nG80\n",
    // Cutter compensation.
    "CG0 X-8 Y0\nG41.1 D2 G1 X0 Y0 F500\nG1 Y10\nX10\nY0\nX0\nG40 G0 X-8\n",
    "CG0 X-8 Y0\nT1 M6\nG42 G1 X0 Y0 F400\nG2 X0 Y0 I5 J0\nG40 G0 X-8\n",
    // Offsets and tools.
    "CG10 L2 P2 X1 Y2 Z0.5\nG55\nG0 X0 Y0\nG54\n",
    "CG10 L20 P1 X0 Y0\nG0 X1 Y1\n",
    "CG92 X0 Y0\nG0 X1\nG92.1\n",
    "CT2 M6\nG43 H2\nG0 Z5\nG49\n",
    "CG43.1 Z1.5\nG0 Z5\nG49\n",
    // Motion and modes.
    // (arcs incremental, so that they start anywhere)
    "CG91 G2 X10 Y0 I5 J0 F300\nG90\n",
    "CG91 G3 X6 Y0 R5 F300\nG90\n",
    "CG2 I4 J0 F300\n",
    "CG91 G17 G2 X5 Y5 Z-1 I2.5 J2.5 P2 F300\nG90\n",
    "CG91 G18 G3 X0 Z5 I0 K2.5 F300\nG90 G17\n",
    "CG5 X10 Y10 I3 J0 P-3 Q0 F300\n",
    "CG64 P0.01 Q0.005\n",
    "CG61.1\n",
    "CG4 P0.1\n",
    "CG93 G1 X1 Y1 F10\nG94\n",
    "CG20 G0 X0.5\nG21\n",
    "CG91 G1 X1 Y1 F300\nG90\n",
    "CG28\nG30.1\n",
    "CM62 P1\nM66 P0 L0\nM63 P1\n",
    // Lathe cycles (XZ plane).
    "CM3 S500\nG18 G0 X22 Z2\nG76 P-2 Z-10 I-0.5 J0.1 K1 Q29.5 L2\nG17\n",
    "LG18\no@ sub\nG1 X10 Z-1\nG1 Z-8\nG1 X16\no@ endsub\nG0 X20 Z1\nG71 Q@ X20 Z1 D0.5 "
    "I0.2\nG70 Q@ X20 Z1\nG17\n",
    "CM3 S500\nG18 G33 Z-5 K1\nG17\n",
    // Fanuc Macro B.
    "F#100 = 1\nIF [#100 EQ 1] GOTO @\nG0 X1\nN@ G0 X2\n",
    "F#101 = 0\nWHILE [#101 LT 3] DO1\n#101 = #101 + 1\nG1 X#101 F300\nEND1\n",
    "FIF [#4001 EQ 1] THEN #102 = 5\nG0 X[#102 + 1]\n",
    "F#103 = [#4001 + 1]\nG0 X#103\n",
};

/// Codes that may stand for one another (one modal group each).
inline const std::vector<std::vector<std::string_view>>& code_groups() {
  static const std::vector<std::vector<std::string_view>> groups = {
      {"G0", "G1"},
      {"G2", "G3"},
      {"G17", "G18", "G19"},
      {"G20", "G21"},
      {"G40", "G41", "G42", "G41.1", "G42.1"},
      {"G43", "G43.1", "G49"},
      {"G54", "G55", "G56", "G59.3"},
      {"G61", "G61.1", "G64"},
      {"G73", "G81", "G82", "G83", "G85"},
      {"G90", "G91"},
      {"G93", "G94", "G95"},
      {"G98", "G99"},
      {"M3", "M4", "M5"},
      {"M7", "M8", "M9"},
  };
  return groups;
}

/// Mutates program text at the level of words, lines and constructs; seeded, deterministic.
class ProgramMutator {
 public:
  explicit ProgramMutator(std::uint32_t seed) : rng_(seed) {}

  /// One mutant of `text` (lines end in '\n'), or "" when none could be made.
  std::string mutate(std::string_view text) {
    split(text);
    switch (below(8)) {
      case 0:
      case 1:
      case 2:
        if (!tweak_number()) insert_construct();
        break;
      case 3:
        if (!swap_code()) tweak_number();
        break;
      case 4:
      case 5:
        insert_construct();
        break;
      case 6:
        copy_line();
        break;
      default:
        if (below(2) == 0)
          delete_line();
        else
          swap_lines();
        break;
    }
    return join();
  }

  /// Lines 0..a of `a`, a run of lines of `b`, the rest of `a`: a block from another program.
  std::string cross(std::string_view a, std::string_view b) {
    split(b);
    const std::vector<std::string> from = std::move(lines_);
    split(a);
    if (from.empty()) return join();
    const std::size_t first = below(from.size());
    const std::size_t count = 1 + below(std::min<std::size_t>(8, from.size() - first));
    lines_.insert(lines_.begin() + static_cast<long>(insert_at()),
                  from.begin() + static_cast<long>(first),
                  from.begin() + static_cast<long>(first + count));
    return join();
  }

 private:
  std::size_t below(std::size_t n) { return n <= 1 ? 0 : rng_() % n; }

  void split(std::string_view text) {
    lines_.clear();
    std::size_t start = 0;
    while (start < text.size()) {
      const std::size_t end = std::min(text.find('\n', start), text.size());
      lines_.emplace_back(text.substr(start, end - start));
      start = end + 1;
    }
  }
  std::string join() const {
    std::string out;
    for (const std::string& l : lines_) out.append(l).push_back('\n');
    return out;
  }

  // Where a line may go: before the program's end (M2, M30, '%') when it has one near its end.
  std::size_t insert_at() {
    std::size_t end = lines_.size();
    for (std::size_t i = lines_.size(); i > 0 && i + 6 > lines_.size(); --i) {
      const std::string& l = lines_[i - 1];
      if (l.find("M2") != std::string::npos || l.find("M30") != std::string::npos ||
          l.find("m2") != std::string::npos || l.find("m30") != std::string::npos ||
          (!l.empty() && l[0] == '%'))
        end = i - 1;
    }
    return below(end + 1);
  }

  // A word's number (after a letter, '=' or '['), replaced by a neighbour of it or a new value.
  bool tweak_number() {
    if (lines_.empty()) return false;
    for (int attempt = 0; attempt < 8; ++attempt) {
      std::string& l = lines_[below(lines_.size())];
      // An arc's end and centre agree to 0.0005 mm: moving one mostly makes an error.
      if (l.find("G2") != std::string::npos || l.find("G3") != std::string::npos) continue;
      // Lathe cycles (G70-G76) multiply their passes by depth and extent: a halved depth or a
      // doubled extent soon reaches the cycle's bound of 200,000 moves, 1-2 s under ASan+UBSan
      // where most inputs take milliseconds (libFuzzer's byte mutations still change them).
      if (l.find("G7") != std::string::npos || l.find("g7") != std::string::npos) continue;
      std::vector<std::pair<std::size_t, std::size_t>> numbers;  // start, length
      for (std::size_t i = 0; i < l.size(); ++i) {
        // A value word's number (not a code's, a label's or a keyword's such as END1).
        const char before =
            i > 0 ? static_cast<char>(std::toupper(static_cast<unsigned char>(l[i - 1]))) : '\n';
        const bool word_letter = std::isalpha(static_cast<unsigned char>(before)) != 0 &&
                                 std::string_view("GMNO").find(before) == std::string_view::npos &&
                                 (i < 2 || std::isalpha(static_cast<unsigned char>(l[i - 2])) == 0);
        const bool starts = (std::isdigit(static_cast<unsigned char>(l[i])) != 0 ||
                             (l[i] == '.' && i + 1 < l.size() &&
                              std::isdigit(static_cast<unsigned char>(l[i + 1])) != 0)) &&
                            (word_letter || before == '=' || before == '[' || before == '-');
        if (!starts) continue;
        std::size_t j = i;
        while (j < l.size() && (std::isdigit(static_cast<unsigned char>(l[j])) || l[j] == '.')) ++j;
        numbers.emplace_back(i, j - i);
        i = j;
      }
      if (numbers.empty()) continue;
      const auto [at, len] = numbers[below(numbers.size())];
      double v = 0;
      try {
        v = std::stod(l.substr(at, len));
      } catch (...) {
        continue;
      }
      // A repeat count (L) stays below 10: L99999 on a canned cycle is 100,000 moves, the
      // block's bound, and seconds under the sanitizers.
      const bool count = at > 0 && (l[at - 1] == 'L' || l[at - 1] == 'l');
      l.replace(at, len,
                count ? std::to_string(below(10)) : new_number(v, l.find('.', at) < at + len));
      return true;
    }
    return false;
  }
  std::string new_number(double v, bool decimal) {
    static constexpr double kEdges[] = {0, 1, 2, 3, 0.001, 0.5, 10, 90, 360, 1000, 99999, 1e6};
    double w = v;
    switch (below(7)) {
      case 0:
        w = v + 1;
        break;
      case 1:
        w = v > 1 ? v - 1 : v + 0.5;
        break;
      case 2:
        w = v * 2;
        break;
      case 3:
        w = v / 2;
        break;
      case 4:
        w = kEdges[below(std::size(kEdges))];
        break;
      case 5:
        w = static_cast<double>(below(10));
        break;
      default:
        w = static_cast<double>(below(200001)) / 1000.0;
        break;
    }
    // Integers stay integers (labels, codes, P and L counts); a number with a point keeps one.
    // (a program may hold 1e308: the integer is printed from the double, never cast to an int)
    if (!decimal) return fmt::format("{:.0f}", std::trunc(w));
    return fmt::format("{:.3f}", w);
  }

  // A G or M code swapped for another of its modal group.
  bool swap_code() {
    if (lines_.empty()) return false;
    for (int attempt = 0; attempt < 8; ++attempt) {
      std::string& l = lines_[below(lines_.size())];
      std::vector<std::pair<std::size_t, std::size_t>> codes;
      for (std::size_t i = 0; i < l.size(); ++i) {
        const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(l[i])));
        if ((c != 'G' && c != 'M') || (i > 0 && std::isalpha(static_cast<unsigned char>(l[i - 1]))))
          continue;
        std::size_t j = i + 1;
        while (j < l.size() && (std::isdigit(static_cast<unsigned char>(l[j])) || l[j] == '.')) ++j;
        if (j > i + 1) codes.emplace_back(i, j - i);
      }
      if (codes.empty()) continue;
      const auto [at, len] = codes[below(codes.size())];
      std::string code = l.substr(at, len);
      code[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(code[0])));
      for (const auto& group : code_groups()) {
        if (std::find(group.begin(), group.end(), code) == group.end()) continue;
        l.replace(at, len, group[below(group.size())]);
        return true;
      }
    }
    return false;
  }

  // A construct of the program's dialect: LinuxCNC's O-words or Fanuc's Macro B (each only
  // when the text already has some of its own, so that one reading of it stays valid).
  void insert_construct() {
    bool oword = false, macro_b = false;
    for (const std::string& l : lines_) {
      const std::size_t p = l.find_first_not_of(" \t");
      if (p != std::string::npos && l[p] == 'o' && p + 1 < l.size() &&
          (std::isdigit(static_cast<unsigned char>(l[p + 1])) || l[p + 1] == '<'))
        oword = true;
      if (l.find("WHILE") != std::string::npos || l.find("GOTO") != std::string::npos ||
          l.find("G65") != std::string::npos || l.find("M98") != std::string::npos)
        macro_b = true;
    }
    std::string_view pick;
    do {
      pick = kConstructs[below(std::size(kConstructs))];
    } while ((pick[0] == 'L' && macro_b) || (pick[0] == 'F' && (oword || !macro_b)));
    std::string c(pick.substr(1));
    // Mostly back to where it started (the current position, #5420..#5422), so that an arc
    // after it still starts where its centre says (LinuxCNC's parameters; not in Macro B).
    if (!macro_b && below(4) != 0)
      c = "#<_fz@x> = #5420\n#<_fz@y> = #5421\n#<_fz@z> = #5422\n" + c +
          "G90 G0 X#<_fz@x> Y#<_fz@y> Z#<_fz@z>\n";
    const std::string label = std::to_string(900 + below(99));
    for (std::size_t p; (p = c.find('@')) != std::string::npos;) c.replace(p, 1, label);
    std::vector<std::string> block;
    std::size_t start = 0;
    while (start < c.size()) {
      const std::size_t end = c.find('\n', start);
      block.push_back(c.substr(start, end - start));
      start = end + 1;
    }
    lines_.insert(lines_.begin() + static_cast<long>(insert_at()), block.begin(), block.end());
  }

  void copy_line() {
    for (int attempt = 0; attempt < 8 && !lines_.empty(); ++attempt) {
      const std::string l = lines_[below(lines_.size())];
      if (structural(l)) continue;
      lines_.insert(lines_.begin() + static_cast<long>(insert_at()), l);
      return;
    }
  }

  // Lines that hold the program's structure: O-word and Macro B flow, program numbers, the end.
  static bool structural(const std::string& l) {
    const std::size_t p = l.find_first_not_of(" \t");
    if (p == std::string::npos) return false;
    const char c = l[p];
    return c == 'o' || c == 'O' || c == '%' || c == 'N' || l.find("END") != std::string::npos ||
           l.find("WHILE") != std::string::npos || l.find("M2") != std::string::npos ||
           l.find("M30") != std::string::npos || l.find("M99") != std::string::npos;
  }
  void delete_line() {
    for (int attempt = 0; attempt < 8 && lines_.size() > 1; ++attempt) {
      const std::size_t i = below(lines_.size());
      if (structural(lines_[i])) continue;
      lines_.erase(lines_.begin() + static_cast<long>(i));
      return;
    }
  }
  void swap_lines() {
    for (int attempt = 0; attempt < 8 && lines_.size() >= 2; ++attempt) {
      const std::size_t i = below(lines_.size() - 1);
      if (structural(lines_[i]) || structural(lines_[i + 1])) continue;
      std::swap(lines_[i], lines_[i + 1]);
      return;
    }
  }

  std::minstd_rand rng_;
  std::vector<std::string> lines_;
};

}  // namespace fuzz
