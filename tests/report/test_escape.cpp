// Escaping program text for the page: nothing a program holds can end a <script> or an element.
#include "report/escape.hpp"

#include <catch2/catch.hpp>

using gm::report::html_escape;
using gm::report::json_string;
using gm::report::utf8_sequence_length;

TEST_CASE("json_string: script end, quotes, backslashes and control characters", "[report]") {
  CHECK(json_string("(</script><b>)") == R"~("(\u003c/script\u003e\u003cb\u003e)")~");
  CHECK(json_string("a\"b\\c\td\n") == R"~("a\"b\\c\u0009d\u000a")~");
  CHECK(json_string("#<x>=1 & 2") == R"~("#\u003cx\u003e=1 \u0026 2")~");
  CHECK(json_string("") == R"~("")~");
}

TEST_CASE("json_string and html_escape: invalid UTF-8 becomes U+FFFD, valid text is kept",
          "[report]") {
  CHECK(json_string("(\xC3\x98 6 mm)") == "\"(\xC3\x98 6 mm)\"");  // Ø
  CHECK(json_string("\xFF") == R"~("\ufffd")~");
  CHECK(json_string("\xC0\xAF") == R"~("\ufffd\ufffd")~");            // overlong '/'
  CHECK(json_string("\xED\xA0\x80") == R"~("\ufffd\ufffd\ufffd")~");  // a surrogate
  CHECK(json_string("x\xE2\x82") == R"~("x\ufffd\ufffd")~");          // truncated €
  CHECK(html_escape("\xE2\x82\xAC\xFF") == "\xE2\x82\xAC&#xFFFD;");
  CHECK(utf8_sequence_length("\xF0\x9F\x98\x80") == 4);
  CHECK(utf8_sequence_length("\xF4\x90\x80\x80") == 0);  // past U+10FFFF
}

TEST_CASE("html_escape: control characters XML 1.0 forbids become U+FFFD, tab LF CR stay",
          "[report]") {
  CHECK(html_escape("a\x01"
                    "b\x1F\tc\nd\re") == "a&#xFFFD;b&#xFFFD;\tc\nd\re");
}

TEST_CASE("html_escape: the five special characters", "[report]") {
  CHECK(html_escape(R"~(<b a="1">&'</b>)~") == "&lt;b a=&quot;1&quot;&gt;&amp;&#39;&lt;/b&gt;");
}
