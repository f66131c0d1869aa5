// Reads a stream one line at a time into a reused buffer, with a length cap (never the whole file).
#pragma once

#include <cstddef>
#include <istream>
#include <string>

namespace gm {

class LineReader {
 public:
  /// `max_length`: bytes kept per line; the rest of a longer line is read and dropped.
  LineReader(std::istream& in, std::size_t max_length) : in_(in), max_(max_length) {}

  /// Reads the next line (without '\n') into line(). False at end of input.
  bool next();
  const std::string& line() const { return line_; }
  /// True if the last line was longer than max_length (line() holds its start).
  bool truncated() const { return truncated_; }
  /// 1-based number of the last line read.
  int number() const { return number_; }

 private:
  std::istream& in_;
  std::size_t max_;
  std::string line_;
  bool truncated_ = false;
  int number_ = 0;
};

}  // namespace gm
