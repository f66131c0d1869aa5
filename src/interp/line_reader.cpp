// Line reading in large chunks split with memchr: a bounded copy per line, nothing else held.
#include "interp/line_reader.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

namespace gm {

bool LineReader::fill() {
  std::streambuf* sb = in_.rdbuf();
  if (sb == nullptr) return false;
  chunk_offset_ = next_offset_;  // the chunk starts where the unread input starts
  const std::streamsize n = sb->sgetn(chunk_.get(), static_cast<std::streamsize>(kChunkBytes));
  pos_ = chunk_.get();
  end_ = pos_ + (n > 0 ? n : 0);
  return n > 0;
}

void LineReader::keep(std::string& line, const char* first, const char* last) {
  const auto len = static_cast<std::size_t>(last - first);
  const std::size_t room = max_ - std::min(max_, line.size());
  if (len > room) truncated_ = true;
  line.append(first, std::min(len, room));
}

bool LineReader::restart(std::uint64_t offset, int number) {
  // A jump back into the chunk in memory (a loop of a few lines) needs no read at all.
  if (end_ != nullptr && offset >= chunk_offset_ &&
      offset < chunk_offset_ + static_cast<std::uint64_t>(end_ - chunk_.get())) {
    pos_ = chunk_.get() + (offset - chunk_offset_);
    number_ = number;
    line_offset_ = next_offset_ = offset;
    return true;
  }
  in_.clear();
  std::streambuf* sb = in_.rdbuf();
  if (sb == nullptr) return false;
  const auto at = sb->pubseekpos(static_cast<std::streamoff>(offset), std::ios::in);
  if (at == std::streampos(std::streamoff(-1))) return false;
  pos_ = end_ = nullptr;
  number_ = number;
  line_offset_ = next_offset_ = offset;
  return true;
}

bool LineReader::next(std::string& line) {
  line.clear();
  truncated_ = false;
  bool any = false;
  line_offset_ = next_offset_;
  for (;;) {
    if (pos_ == end_ && !fill()) break;
    any = true;
    const auto* nl =
        static_cast<const char*>(std::memchr(pos_, '\n', static_cast<std::size_t>(end_ - pos_)));
    if (nl != nullptr) {
      keep(line, pos_, nl);
      next_offset_ += static_cast<std::uint64_t>(nl + 1 - pos_);
      pos_ = nl + 1;
      break;
    }
    keep(line, pos_, end_);
    next_offset_ += static_cast<std::uint64_t>(end_ - pos_);
    pos_ = end_;
  }
  if (!any) {
    in_.setstate(std::ios::eofbit);
    return false;
  }
  if (number_ < std::numeric_limits<int>::max()) ++number_;
  // A UTF-8 byte-order mark opening the input is not part of the first line (every dialect;
  // rs274 2.9 refuses it: "Bad character '\357' used"). Columns count from after it.
  if (line_offset_ == 0 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
  return true;
}

}  // namespace gm
