// Override schedules: syntax, located errors, and when each change takes effect.
#include "common/status.hpp"
#include "override/override_schedule.hpp"

#include <catch2/catch.hpp>

using gm::OverridePlayer;
using gm::OverrideSchedule;

TEST_CASE("schedule lines: time, line and rapid entries with comments") {
  const auto s = OverrideSchedule::parse(
      "# a comment\n"
      "0.5,50\n"
      "  line:12 , 150   # from line 12\n"
      "\n"
      "1.0,rapid=25\r\n"
      "2,feed=0\n",
      "s.csv", 200);
  REQUIRE(s.changes().size() == 4);
  CHECK(s.changes()[0].t_s == 0.5);
  CHECK(s.changes()[0].percent == 50);
  CHECK(s.changes()[1].trigger == gm::OverrideChange::Trigger::Line);
  CHECK(s.changes()[1].line == 12);
  CHECK(s.changes()[2].rapid);
  CHECK(s.changes()[2].percent == 25);
  CHECK(s.changes()[3].percent == 0);
  CHECK(s.changes()[3].source_line == 6);
}

TEST_CASE("bad schedule lines are errors with file:line, never silent clamps") {
  auto msg = [](const char* text) {
    try {
      OverrideSchedule::parse(text, "s.csv", 200);
    } catch (const gm::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(msg("0,50\n1,250\n"),
             Catch::StartsWith("s.csv:2: override 250 % is outside 0..200 %"));
  CHECK_THAT(msg("0,-5\n"), Catch::StartsWith("s.csv:1: override -5 % is outside"));
  CHECK_THAT(msg("abc,50\n"), Catch::StartsWith("s.csv:1: 'abc' is not a time"));
  CHECK_THAT(msg("1,fifty\n"), Catch::StartsWith("s.csv:1: 'fifty' is not a percentage"));
  CHECK_THAT(msg("\n\n2,50\n1,60\n"), Catch::StartsWith("s.csv:4: time 1 s goes back before 2 s"));
  CHECK_THAT(msg("line:0,50\n"), Catch::StartsWith("s.csv:1: '0' is not a source line number"));
  CHECK_THAT(msg("1 50\n"), Catch::StartsWith("s.csv:1: expected WHEN,PERCENT"));
  CHECK_THAT(msg("1,nan\n"), Catch::StartsWith("s.csv:1: 'nan' is not a percentage"));
}

TEST_CASE("a time change applies from the first sample at or after its time") {
  const auto s = OverrideSchedule::parse("0.010,50\n0.012,rapid=10\n", "s", 200);
  OverridePlayer p(s, 0.004);
  p.advance(2, 1);  // t = 0.008
  CHECK(p.feed_scale() == 1.0);
  p.advance(3, 1);  // t = 0.012 >= 0.010
  CHECK(p.feed_scale() == 0.5);
  CHECK(p.rapid_scale() ==
        0.1);  // 3 * 0.004 is 0.012 up to rounding: recorded times replay exactly
}

TEST_CASE("a line change applies when that line starts") {
  const auto s = OverrideSchedule::parse("line:5,150\n", "s", 200);
  OverridePlayer p(s, 0.004, 80.0);
  p.advance(0, 4);
  CHECK(p.feed_scale() == Approx(0.8));
  p.advance(1, 5);
  CHECK(p.feed_scale() == Approx(1.5));
}
