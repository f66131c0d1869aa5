// Escaping untrusted text (program names, source lines) for HTML/XML and for JSON in <script>.
#include "report/escape.hpp"

#include <fmt/format.h>

namespace gm::report {

int utf8_sequence_length(std::string_view s) {
  if (s.empty()) return 0;
  const auto b = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  int n = 0;
  unsigned cp = 0;
  if ((c & 0xE0) == 0xC0)
    n = 2, cp = c & 0x1Fu;
  else if ((c & 0xF0) == 0xE0)
    n = 3, cp = c & 0x0Fu;
  else if ((c & 0xF8) == 0xF0)
    n = 4, cp = c & 0x07u;
  else
    return 0;
  if (s.size() < static_cast<std::size_t>(n)) return 0;
  for (int i = 1; i < n; ++i) {
    if ((b(static_cast<std::size_t>(i)) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b(static_cast<std::size_t>(i)) & 0x3Fu);
  }
  const unsigned min_cp = n == 2 ? 0x80u : n == 3 ? 0x800u : 0x10000u;
  if (cp < min_cp || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

std::string html_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const int n = utf8_sequence_length(s.substr(i));
    const auto c = static_cast<unsigned char>(s[i]);
    if (n == 0 || (c < 0x20 && c != '\t' && c != '\n' && c != '\r')) {
      out += "&#xFFFD;";
      ++i;
      continue;
    }
    switch (s[i]) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out.append(s.substr(i, static_cast<std::size_t>(n)));
    }
    i += static_cast<std::size_t>(n);
  }
  return out;
}

std::string json_string(std::string_view s) {
  std::string out = "\"";
  out.reserve(s.size() + 2);
  for (std::size_t i = 0; i < s.size();) {
    const int n = utf8_sequence_length(s.substr(i));
    if (n == 0) {
      out += "\\ufffd";
      ++i;
      continue;
    }
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == '"')
      out += "\\\"";
    else if (c == '\\')
      out += "\\\\";
    else if (c < 0x20 || c == '<' || c == '>' || c == '&' || c == 0x7F)
      out += fmt::format("\\u{:04x}", c);
    else
      out.append(s.substr(i, static_cast<std::size_t>(n)));
    i += static_cast<std::size_t>(n);
  }
  out += '"';
  return out;
}

}  // namespace gm::report
