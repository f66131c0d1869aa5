// Reads a stream one line at a time into a reused buffer, with a length cap (never the whole file).
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <memory>
#include <string>

namespace gm {

/// Lines from a stream, read in chunks of kChunkBytes and split with memchr: one copy per line,
/// at most max_length bytes of it; the memory held is the chunk plus the longest kept line.
class LineReader {
 public:
  static constexpr std::size_t kChunkBytes = std::size_t{1} << 18;

  /// `max_length`: bytes kept per line; the rest of a longer line is read and dropped.
  LineReader(std::istream& in, std::size_t max_length)
      : in_(in), max_(max_length), chunk_(new char[kChunkBytes]) {}

  /// Reads the next line (without '\n') into `line`, replacing its content (its capacity is
  /// reused). False at end of input. The stream is read ahead by up to one chunk.
  bool next(std::string& line);
  /// True if the last line was longer than max_length (`line` got its start).
  bool truncated() const { return truncated_; }
  /// 1-based number of the last line read.
  int number() const { return number_; }
  /// Byte offset of the last line read, and of the line after it.
  std::uint64_t line_offset() const { return line_offset_; }
  std::uint64_t next_offset() const { return next_offset_; }
  /// Continues at byte `offset` of a seekable stream, numbering the next line `number` + 1.
  /// False if the stream cannot seek (a pipe).
  bool restart(std::uint64_t offset, int number);

 private:
  bool fill();  // reads the next chunk; false at end of input
  void keep(std::string& line, const char* first, const char* last);  // appends up to max_

  std::istream& in_;
  std::size_t max_;
  std::unique_ptr<char[]> chunk_;
  const char* pos_ = nullptr;  ///< next unread byte of the chunk
  const char* end_ = nullptr;  ///< end of the bytes in the chunk
  bool truncated_ = false;
  int number_ = 0;
  std::uint64_t line_offset_ = 0;
  std::uint64_t next_offset_ = 0;
  std::uint64_t chunk_offset_ = 0;  ///< input offset of chunk_[0]
};

}  // namespace gm
