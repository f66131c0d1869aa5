// Escaping untrusted text (program names, source lines) for HTML/XML and for JSON in <script>.
#pragma once

#include <string>
#include <string_view>

namespace gm::report {

/// `s` for HTML or XML text and attribute values: & < > " ' as character references; invalid
/// UTF-8 bytes and the control characters XML 1.0 forbids (below U+0020 but tab, LF, CR) become
/// U+FFFD. The HTML report and the golden suites' JUnit XML both use it.
std::string html_escape(std::string_view s);

/// `s` as a JSON string literal (with the quotes) that is safe inside a <script> element:
/// < > & are written \u003c \u003e \u0026, control characters \uXXXX, and invalid UTF-8 bytes
/// become \ufffd, so JSON.parse gives back the text whatever bytes the program holds.
std::string json_string(std::string_view s);

/// Length of the valid UTF-8 sequence at the start of `s` (1..4), or 0 when it is invalid
/// (overlong, surrogate, past U+10FFFF, truncated, or a stray continuation byte).
int utf8_sequence_length(std::string_view s);

}  // namespace gm::report
