// Line reading straight from the stream buffer: a bounded copy per line, nothing else held.
#include "interp/line_reader.hpp"

#include <limits>

namespace gm {

bool LineReader::next() {
  line_.clear();
  truncated_ = false;
  std::streambuf* sb = in_.rdbuf();
  if (!sb) return false;
  using traits = std::char_traits<char>;
  auto c = sb->sgetc();
  if (traits::eq_int_type(c, traits::eof())) {
    in_.setstate(std::ios::eofbit);
    return false;
  }
  while (true) {
    c = sb->sbumpc();
    if (traits::eq_int_type(c, traits::eof())) break;
    const char ch = traits::to_char_type(c);
    if (ch == '\n') break;
    if (line_.size() < max_) line_.push_back(ch);
    else truncated_ = true;
  }
  if (number_ < std::numeric_limits<int>::max()) ++number_;
  return true;
}

}  // namespace gm
