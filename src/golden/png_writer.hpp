// A small RGB raster with lines, points and 5x7 text, written as PNG (zlib; no image library).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gm::golden {

struct Rgb {
  std::uint8_t r, g, b;
};

class Raster {
 public:
  Raster(int width, int height, Rgb background = {255, 255, 255});
  int width() const { return w_; }
  int height() const { return h_; }
  void set(int x, int y, Rgb c);
  void line(double x0, double y0, double x1, double y1, Rgb c);  ///< 1 px, clipped
  void rect(int x0, int y0, int x1, int y1, Rgb c);              ///< outline
  /// Text from the 5x7 font (letters, digits, common punctuation; others as '?'), `scale`
  /// pixels per font pixel, top-left at (x, y).
  void text(int x, int y, std::string_view s, Rgb c, int scale = 1);
  /// The PNG file's bytes (8-bit RGB, zlib-compressed, CRC-checked chunks).
  std::string png() const;

 private:
  int w_, h_;
  std::vector<std::uint8_t> px_;
};

/// Writes the raster to `path`; returns "" or why not.
std::string write_png(const Raster& r, const std::string& path);

}  // namespace gm::golden
