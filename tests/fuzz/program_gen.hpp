// Well-formed G-code from a fuzzer's bytes: each byte chooses the next construct, so most inputs
// reach the interpreter's depths (loops, subroutines, cycles, compensation, offsets) instead of
// stopping at the parser.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include <fmt/format.h>

namespace fuzz {

/// Reads choices from the fuzzer's bytes; past the end every choice is 0.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  /// A whole number in [0, n).
  int below(int n) { return n <= 1 ? 0 : static_cast<int>(byte() % static_cast<unsigned>(n)); }
  bool chance(int percent) { return below(100) < percent; }
  /// A number in [lo, hi] with 1/1000 of the range as its step (programs write 3 decimals).
  double in(double lo, double hi) {
    const unsigned v = (static_cast<unsigned>(byte()) << 8) | byte();
    return lo + (hi - lo) * std::round(v / 65535.0 * 1000.0) / 1000.0;
  }
  bool done() const { return pos_ >= size_; }
  std::size_t left() const { return size_ - std::min(pos_, size_); }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// What the generator may write.
struct GenOptions {
  bool language = true;   ///< parameters, expressions, O-word loops, subroutines, conditions
  bool machine = true;    ///< offsets, tools, cycles, cutter compensation, I/O codes
  bool raw_lines = true;  ///< now and then a line of the input's bytes as they are (errors)
  int max_statements = 60;
  double extent_mm = 50;            ///< moves stay within about ±extent in X and Y
  double min_tolerance_mm = 0.001;  ///< the smallest G64 P written
  bool tolerances = true;           ///< G64 P… in the program (else only G61, G61.1 and G64)
  /// Rotary axis letters ("A", "BC", ...) the machine has: lines and rapids now and then turn
  /// them too, in degrees (none: the program is the same as without this option).
  std::string rotary_axes;
};

/// Writes a program (G21, G17, absolute) that the generator tracks the position of, so that its
/// arcs are consistent: every arc starts where the table is. After anything that moves the
/// program's coordinates (offsets, G92, units) the generator moves back to a known point.
class ProgramGen {
 public:
  ProgramGen(ByteReader& in, GenOptions opts) : in_(in), opts_(opts), e_(opts.extent_mm / 50) {}

  std::string generate() {
    out_ = "%\n(generated)\nG21 G17 G40 G49 G80 G90 G94 G54\n";
    out_ += fmt::format("F{:.0f}\n", in_.in(100, 6000));
    out_ += in_.chance(80) ? "S1000 M3\n" : "M5\n";
    out_ += "G0 X0 Y0 Z5\n";
    const int n = 1 + in_.below(opts_.max_statements);
    for (int i = 0; i < n && !in_.done(); ++i) statement(0);
    if (comp_on_) out_ += "G40 G0 X0 Y0\n";
    out_ += in_.chance(50) ? "M2\n" : "M30\n%\n";
    return out_;
  }

 private:
  // One statement: depth bounds loop and subroutine nesting.
  void statement(int depth) {
    switch (in_.below(opts_.language && opts_.machine ? 22 : (opts_.machine ? 16 : 12))) {
      case 0:
      case 1:
        line();
        break;
      case 2:
      case 3:
        arc_ijk();
        break;
      case 4:
        arc_r();
        break;
      case 5:
        rapid();
        break;
      case 6:
        path_mode();
        break;
      case 7:
        helix();
        break;
      case 8:
        feed();
        break;
      case 9:
        comment();
        break;
      case 10:
        dwell();
        break;
      case 11:
        if (opts_.raw_lines && in_.chance(25))
          raw();
        else
          line();
        break;
      // Machine codes.
      case 12:
        cycle();
        break;
      case 13:
        offsets();
        break;
      case 14:
        tool();
        break;
      case 15:
        comp();
        break;
      // The language.
      case 16:
        parameter();
        break;
      case 17:
        expression_move();
        break;
      case 18:
        if (depth < 3)
          loop(depth);
        else
          line();
        break;
      case 19:
        if (depth < 2)
          subroutine(depth);
        else
          line();
        break;
      case 20:
        if (depth < 3)
          condition(depth);
        else
          line();
        break;
      default:
        io();
        break;
    }
  }

  std::string num(double v) { return fmt::format("{:.3f}", v); }
  // Arc ends and centres: four decimals keep the two radii within LinuxCNC's 0.0005 mm.
  std::string num4(double v) { return fmt::format("{:.4f}", v); }
  void move_to(double x, double y, double z) { x_ = x, y_ = y, z_ = z; }
  /// An X or Y coordinate (or offset) in [lo, hi] · extent / 50.
  double xy(double lo, double hi) { return in_.in(lo * e_, hi * e_); }

  void line() {
    const double x = xy(-50, 50), y = xy(-50, 50);
    std::string l = fmt::format("G1 X{} Y{}", num(x), num(y));
    double z = z_;
    if (in_.chance(30)) {
      z = in_.in(-5, 5);
      l += " Z" + num(z);
    }
    out_ += l + rotary() + "\n";
    move_to(x, y, z);
  }
  void rapid() {
    const double x = xy(-50, 50), y = xy(-50, 50), z = in_.in(0, 10);
    out_ += fmt::format("G0 X{} Y{} Z{}{}\n", num(x), num(y), num(z), rotary());
    move_to(x, y, z);
  }
  // Words turning the rotary axes (when the options name some): " A12.5", degrees.
  std::string rotary() {
    std::string w;
    for (const char c : opts_.rotary_axes)
      if (in_.chance(40)) w += fmt::format(" {}{}", c, num(in_.in(-360, 360)));
    return w;
  }
  // An arc from here about a centre at (i, j) from here, ending on its circle (G17, G90).
  void arc_ijk(bool helix = false) {
    const double i = xy(-20, 20), j = xy(-20, 20);
    const double r = std::hypot(i, j);
    if (r < 0.5 * e_) return line();
    const double cx = x_ + i, cy = y_ + j;
    const double a = in_.in(0, 6.283);
    const double x = cx + r * std::cos(a), y = cy + r * std::sin(a);
    const bool ccw = in_.chance(50);
    std::string l =
        fmt::format("G{} X{} Y{} I{} J{}", ccw ? 3 : 2, num4(x), num4(y), num(i), num(j));
    double z = z_;
    if (helix) {
      z = in_.in(-5, 5);
      l += " Z" + num(z);
      if (in_.chance(30)) l += fmt::format(" P{}", 1 + in_.below(3));
    }
    out_ += l + "\n";
    move_to(std::stod(num4(x)), std::stod(num4(y)), z);
  }
  void helix() { arc_ijk(true); }
  void arc_r() {
    const double x = xy(-50, 50), y = xy(-50, 50);
    const double chord = std::hypot(x - x_, y - y_);
    if (chord < 0.1) return line();
    const double r = chord / 2 * (1.0 + in_.in(0, 3));
    out_ += fmt::format("G{} X{} Y{} R{}\n", in_.chance(50) ? 2 : 3, num(x), num(y),
                        (in_.chance(20) ? "-" : "") + num(r + 0.001));
    move_to(x, y, z_);
  }
  void path_mode() {
    static constexpr const char* kModes[] = {"G61", "G61.1", "G64"};
    const double p = in_.in(opts_.min_tolerance_mm, 0.5);
    switch (opts_.tolerances ? in_.below(5) : 2 + in_.below(3)) {
      case 0:
        out_ += fmt::format("G64 P{}\n", num(p));
        break;
      case 1:
        out_ += fmt::format("G64 P{} Q{}\n", num(p), num(in_.in(0.001, 0.2)));
        break;
      default:
        out_ += fmt::format("{}\n", kModes[in_.below(3)]);
        break;
    }
  }
  void feed() {
    if (in_.chance(20)) {  // inverse time for one move, then back
      const double x = xy(-50, 50), y = xy(-50, 50);
      out_ += fmt::format("G93 G1 X{} Y{} F{}\nG94 F{:.0f}\n", num(x), num(y), num(in_.in(1, 600)),
                          in_.in(100, 6000));
      move_to(x, y, z_);
    } else {
      out_ += fmt::format("F{:.0f}\n", in_.in(10, 8000));
    }
  }
  void comment() {
    static constexpr const char* kComments[] = {"(roughing)", "; finish pass", "(MSG, next op)",
                                                "(DEBUG, z=#<_z>)", "(PRINT, #1)"};
    out_ += fmt::format("{}\n", kComments[in_.below(5)]);
  }
  void dwell() { out_ += fmt::format("G4 P{}\n", num(in_.in(0, 0.5))); }
  void raw() {
    std::string l;
    const int n = in_.below(24);
    for (int k = 0; k < n && !in_.done(); ++k) {
      const char c = static_cast<char>(in_.byte());
      if (c != '\n' && c != '\r' && c != '\0') l += c;
    }
    out_ += l + "\n";
  }
  // A canned cycle at one or more holes, then G80; drilling leaves Z at R or the initial level.
  void cycle() {
    static constexpr const char* kCycles[] = {"G81", "G82", "G83", "G73", "G85", "G89", "G86"};
    const char* g = kCycles[in_.below(7)];
    if (g[2] == '6' && in_.chance(90)) out_ += "M3\n";  // G86 needs the spindle turning
    out_ += fmt::format("G0 Z5\n{} {} X{} Y{} Z{} R2", in_.chance(50) ? "G98" : "G99", g,
                        num(xy(-40, 40)), num(xy(-40, 40)), num(in_.in(-10, -0.5)));
    if (g[2] == '3') out_ += fmt::format(" Q{}", num(in_.in(0.2, 3)));
    if (g[2] == '2' || g[2] == '9' || g[2] == '6') out_ += fmt::format(" P{}", num(in_.in(0, 1)));
    if (in_.chance(20)) out_ += fmt::format(" L{}", 1 + in_.below(4));
    out_ += "\n";
    for (int h = in_.below(3); h > 0; --h)
      out_ += fmt::format("X{} Y{}\n", num(xy(-40, 40)), num(xy(-40, 40)));
    out_ += "G80\n";
    resync();
  }
  void offsets() {
    switch (in_.below(4)) {
      case 0:
        out_ += fmt::format("G10 L2 P{} X{} Y{} Z{}\n", 1 + in_.below(9), num(xy(-20, 20)),
                            num(xy(-20, 20)), num(in_.in(-5, 5)));
        break;
      case 1:
        out_ += fmt::format("G{}\n", 54 + in_.below(6));
        break;
      case 2:
        out_ += fmt::format("G92 X{} Y{}\n", num(xy(-10, 10)), num(xy(-10, 10)));
        break;
      default:
        out_ += in_.chance(50) ? "G92.1\n" : "G92.2\n";
        break;
    }
    resync();
  }
  void tool() {
    const int t = 1 + in_.below(4);
    out_ += fmt::format("G0 Z10\nT{} M6\nG43 H{}\n", t, t);
    resync();
  }
  // Cutter compensation by a diameter given in the block (no tool table needed): a rectangle
  // (or a circle) at least four diameters wide, on either side of the tool, entered by a lead-in
  // line and left with G40.
  void comp() {
    if (comp_on_) return line();
    const double d = in_.in(0.5, 6);
    const bool left = in_.chance(50), ccw = in_.chance(50);
    const double x0 = xy(-40, 0), y0 = xy(-40, 0);
    const double w = 4 * d + xy(1, 30), h = 4 * d + xy(1, 30);
    out_ += fmt::format("G0 X{} Y{}\nG{}.1 D{}\n", num(x0 - 2 * d - 2), num(y0), left ? 41 : 42,
                        num(d));
    comp_on_ = true;
    out_ += fmt::format("G1 X{} Y{}\n", num(x0), num(y0));
    if (in_.chance(30)) {  // a full circle from the rectangle's corner
      out_ += fmt::format("G{} X{} Y{} I{} J0\n", ccw ? 3 : 2, num(x0), num(y0), num(w / 2));
    } else {
      const double ccw_x[] = {x0 + w, x0 + w, x0, x0}, ccw_y[] = {y0, y0 + h, y0 + h, y0};
      const double cw_x[] = {x0, x0 + w, x0 + w, x0}, cw_y[] = {y0 + h, y0 + h, y0, y0};
      for (int k = 0; k < 4; ++k)
        out_ += fmt::format("G1 X{} Y{}\n", num(ccw ? ccw_x[k] : cw_x[k]),
                            num(ccw ? ccw_y[k] : cw_y[k]));
    }
    out_ += fmt::format("G40 G0 X{} Y{}\n", num(x0 - 2 * d - 2), num(y0));
    comp_on_ = false;
    move_to(std::stod(num(x0 - 2 * d - 2)), y0, z_);
    resync();
  }
  void parameter() {
    const int p = 1 + in_.below(30);
    out_ += fmt::format("#{} = {}\n", p, expression(2));
    if (in_.chance(30)) out_ += fmt::format("#<depth> = [#{} * {}]\n", p, num(in_.in(-1, 1)));
  }
  std::string expression(int depth) {
    static constexpr const char* kOps[] = {"+",  "-",   "*",  "/",  "MOD",
                                           "**", "AND", "OR", "GT", "LE"};
    static constexpr const char* kFns[] = {"SIN", "COS", "ABS", "ROUND", "FIX", "FUP", "ASIN"};
    switch (depth <= 0 ? 0 : in_.below(4)) {
      case 0:
        return num(in_.in(-100, 100));
      case 1:
        return fmt::format("#{}", 1 + in_.below(30));
      case 2:
        switch (in_.below(10)) {  // mostly arguments in the function's domain
          case 0:
            return fmt::format("SQRT[ABS[{}]]", expression(depth - 1));
          case 1:
            return fmt::format("LN[[ABS[{}] + 1]]", expression(depth - 1));
          case 2:
            return fmt::format("ATAN[{}]/[{}]", expression(depth - 1), expression(depth - 1));
          case 3:
            return fmt::format("EXP[[{} MOD 5]]", expression(depth - 1));
          default: {
            const char* f = kFns[in_.below(7)];
            if (f[0] == 'A' && f[1] == 'S')
              return fmt::format("ASIN[[{} MOD 1]]", expression(depth - 1));
            return fmt::format("{}[{}]", f, expression(depth - 1));
          }
        }
      default:
        return fmt::format("[{} {} {}]", expression(depth - 1), kOps[in_.below(10)],
                           expression(depth - 1));
    }
  }
  // A move whose coordinates are expressions: the position is no longer known, so move back.
  void expression_move() {
    out_ += fmt::format("G1 X[{}] Y[{} + {}]\n", expression(2), num(xy(-20, 20)), expression(1));
    resync();
  }
  // A loop whose body starts from a known point, so each pass draws the same arcs.
  void loop(int depth) {
    const int label = next_label_++;
    const int count = 1 + in_.below(5);
    resync();
    if (in_.chance(50)) {
      out_ += fmt::format("o{} repeat [{}]\n", label, count);
      body(depth, label, false);
      out_ += fmt::format("o{} endrepeat\n", label);
    } else {
      const int p = 31 + depth;
      out_ += fmt::format("#{} = 0\no{} while [#{} LT {}]\n", p, label, p, count);
      body(depth, label, true);
      out_ += fmt::format("#{} = [#{} + 1]\no{} endwhile\n", p, p, label);
    }
    resync();
  }
  void body(int depth, int label, bool can_break) {
    resync();
    for (int k = 1 + in_.below(4); k > 0 && !in_.done(); --k) statement(depth + 1);
    if (can_break && in_.chance(10)) out_ += fmt::format("o{} break\n", label);
    resync();
  }
  // A subroutine defined and called at once (a definition may not be nested: only at depth 0).
  void subroutine(int depth) {
    if (depth > 0) return line();
    const int label = next_label_++;
    out_ += fmt::format("o{} sub\n", label);
    resync();
    for (int k = 1 + in_.below(4); k > 0 && !in_.done(); --k) statement(2);
    if (in_.chance(20)) out_ += fmt::format("o{} return [{}]\n", label, expression(1));
    resync();
    out_ += fmt::format("o{} endsub\n", label);
    for (int c = 1 + in_.below(2); c > 0; --c)
      out_ += fmt::format("o{} call [{}] [{}]\n", label, num(in_.in(-5, 5)), expression(1));
    resync();
  }
  void condition(int depth) {
    const int label = next_label_++;
    out_ += fmt::format("o{} if [{} GT {}]\n", label, expression(1), num(in_.in(-50, 50)));
    resync();
    statement(depth + 1);
    resync();
    if (in_.chance(50)) {
      out_ += fmt::format("o{} else\n", label);
      resync();  // the else branch starts where the if did, not where its branch ended
      statement(depth + 1);
      resync();
    }
    out_ += fmt::format("o{} endif\n", label);
    resync();
  }
  void io() {
    static constexpr const char* kCodes[] = {"M3 S1000", "M4 S500", "M5",     "M7",     "M8", "M9",
                                             "M62 P1",   "M63 P1",  "M64 P2", "M65 P2", "M1", "M0"};
    out_ += fmt::format("{}\n", kCodes[in_.below(12)]);
  }
  // Back to a known point in the current coordinates (after what made the position unknown).
  void resync() {
    const double x = xy(-30, 30), y = xy(-30, 30);
    out_ += fmt::format("G0 X{} Y{} Z5\n", num(x), num(y));
    move_to(x, y, 5);
  }

  ByteReader& in_;
  GenOptions opts_;
  std::string out_;
  double e_;  ///< the extent's scale: coordinates are drawn for ±50 mm and scaled by it
  double x_ = 0, y_ = 0, z_ = 5;
  int next_label_ = 100;
  bool comp_on_ = false;
};

/// The program `data` chooses.
inline std::string generate_program(const std::uint8_t* data, std::size_t size,
                                    GenOptions opts = {}) {
  ByteReader in(data, size);
  return ProgramGen(in, opts).generate();
}

}  // namespace fuzz
