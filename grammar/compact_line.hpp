// Compaction of a comment-free line: spaces and tabs dropped, letters upper-cased, columns kept.
#pragma once

#include <cstddef>
#include <cstring>
#include <string_view>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace gm::grammar {

/// Bytes (chars and ints) past the end of the output that compact_plain_line may write.
inline constexpr std::size_t kCompactSlack = 16;

/// The one-at-a-time definition: every character but ' ' and '\t' is appended to `cp`,
/// 'a'..'z' as 'A'..'Z', and its 1-based column in `text` to `colp`. Both advance.
inline void compact_plain_scalar(std::string_view text, std::size_t from, char*& cp, int*& colp) {
  for (std::size_t i = from; i < text.size(); ++i) {
    char c = text[i];
    if (c == ' ' || c == '\t') continue;
    if (static_cast<unsigned char>(c - 'a') < 26u) c = static_cast<char>(c - 'a' + 'A');
    *cp++ = c;
    *colp++ = static_cast<int>(i) + 1;
  }
}

/// compact_plain_scalar's output, 16 characters at a time where SSE2 is there: in each chunk the
/// letters are upper-cased in one vector, and each run of kept characters is copied whole (16
/// chars and 16 columns stored, the pointers advanced by the run's length). The buffers behind
/// `cp` and `colp` must have kCompactSlack entries to spare past the output.
inline void compact_plain_line(std::string_view text, char*& cp, int*& colp) {
  std::size_t i = 0;
#if defined(__SSE2__)
  const __m128i space = _mm_set1_epi8(' '), tab = _mm_set1_epi8('\t');
  const __m128i below_a = _mm_set1_epi8('a' - 1), above_z = _mm_set1_epi8('z' + 1);
  const __m128i case_bit = _mm_set1_epi8(0x20);
  const __m128i iota = _mm_setr_epi32(0, 1, 2, 3), four = _mm_set1_epi32(4);
  alignas(16) char up[32] = {};  // the chunk upper-cased; a run is copied as 16 bytes from it
  for (; i + 16 <= text.size(); i += 16) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(text.data() + i));
    // Signed compares: bytes >= 0x80 are negative, never a lower-case letter.
    const __m128i lower = _mm_and_si128(_mm_cmpgt_epi8(v, below_a), _mm_cmplt_epi8(v, above_z));
    _mm_store_si128(reinterpret_cast<__m128i*>(up),
                    _mm_sub_epi8(v, _mm_and_si128(lower, case_bit)));
    const __m128i blank = _mm_or_si128(_mm_cmpeq_epi8(v, space), _mm_cmpeq_epi8(v, tab));
    unsigned keep = ~static_cast<unsigned>(_mm_movemask_epi8(blank)) & 0xFFFFu;
    while (keep != 0) {
      const int s = __builtin_ctz(keep);
      const int len = __builtin_ctz(~(keep >> s));  // the run's length: ones from bit s
      std::memcpy(cp, up + s, 16);
      __m128i col = _mm_add_epi32(_mm_set1_epi32(static_cast<int>(i) + s + 1), iota);
      for (int q = 0; q < 4; ++q, col = _mm_add_epi32(col, four))
        _mm_storeu_si128(reinterpret_cast<__m128i*>(colp + 4 * q), col);
      cp += len;
      colp += len;
      keep &= ~(((1u << len) - 1u) << s);
    }
  }
#endif
  compact_plain_scalar(text, i, cp, colp);
}

}  // namespace gm::grammar
