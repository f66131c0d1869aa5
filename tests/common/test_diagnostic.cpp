// Diagnostics render as file:line:col with the source line and a caret under the column.
#include "common/diagnostic.hpp"

#include <catch2/catch.hpp>

TEST_CASE("diagnostic renders location, source line and caret") {
  gm::Diagnostic d;
  d.loc = {3, 5};
  d.message = "unknown G code G7";
  d.source_line = "N10 G7 X1";
  CHECK(gm::format_diagnostic("part.nc", d) ==
        "part.nc:3:5: error: unknown G code G7\n"
        "  N10 G7 X1\n"
        "      ^\n");
}

TEST_CASE("caret keeps tabs so it lines up under tabbed source") {
  gm::Diagnostic d;
  d.loc = {1, 3};
  d.message = "m";
  d.source_line = "\tG7\r";
  CHECK(gm::format_diagnostic("f", d) == "f:1:3: error: m\n  \tG7\n  \t ^\n");
}
