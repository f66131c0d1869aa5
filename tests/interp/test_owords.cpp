// O-word control flow: subroutines, conditionals and loops (values worked by hand and checked
// against rs274), their errors, and re-reading instead of holding the program.
#include "common/error_codes.hpp"
#include "gcode_helpers.hpp"

#include <catch2/catch.hpp>

#include <sstream>

using namespace gmtest;

namespace {

std::vector<double> xs(const std::string& program) {
  std::vector<double> out;
  for (const auto& m : motions(program)) out.push_back(m.end_mm[0]);
  return out;
}

std::vector<gm::Diagnostic> check_with(const std::string& program, std::int64_t max_iterations,
                                       gm::CheckThreads threads = gm::CheckThreads::Auto) {
  std::istringstream in(program);
  std::vector<gm::Diagnostic> d;
  gm::Machine m;
  gm::InterpreterOptions o{&m, false, max_iterations};
  gm::check_program_diagnostics(in, "t.ngc", o, d, threads);
  return d;
}

}  // namespace

TEST_CASE("while, repeat and do loops run their bodies the documented number of times") {
  // (the first G0 X0 is a zero-length move: not emitted)
  CHECK(xs("#1=0\no1 while [#1 LT 3]\nG0 X#1\n#1=[#1+1]\no1 endwhile\nM2\n") ==
        std::vector<double>{1, 2});
  CHECK(xs("#1=0\no2 repeat [3]\n#1=[#1+1]\nG0 X#1\no2 endrepeat\nM2\n") ==
        std::vector<double>{1, 2, 3});
  CHECK(xs("o2 repeat [0]\nG0 X9\no2 endrepeat\nG0 X1\nM2\n") == std::vector<double>{1});
  // do ... while runs once even when the condition is false at once
  CHECK(xs("#1=5\no3 do\nG0 X#1\n#1=[#1+1]\no3 while [#1 LT 3]\nM2\n") == std::vector<double>{5});
  // break and continue in a while loop
  CHECK(xs("#1=0\no4 while [#1 LT 10]\n#1=[#1+1]\no5 if [#1 EQ 2]\no4 continue\no5 endif\n"
           "o6 if [#1 EQ 4]\no4 break\no6 endif\nG0 X#1\no4 endwhile\nG0 X0\nM2\n") ==
        std::vector<double>{1, 3, 0});
}

TEST_CASE("if, elseif and else pick one branch") {
  const std::string p =
      "o1 if [#1 EQ 1]\nG0 X1\no1 elseif [#1 EQ 2]\nG0 X2\no1 elseif [#1 EQ 2]\nG0 X22\n"
      "o1 else\nG0 X3\no1 endif\nM2\n";
  CHECK(xs("#1=1\n" + p) == std::vector<double>{1});
  CHECK(xs("#1=2\n" + p) == std::vector<double>{2});
  CHECK(xs("#1=7\n" + p) == std::vector<double>{3});
}

TEST_CASE("subroutines: arguments in #1-#30 of a new scope, return values, later definitions") {
  // #1 is restored after the call; #<_value> holds what the sub returned
  const auto m = motions(
      "#1=100\no<twice> call [21]\nG0 X#<_value> Y#1\nM2\n"
      "o<twice> sub\n#<local>=[#1*2]\no<twice> return [#<local>]\no<twice> endsub\n");
  REQUIRE(m.size() == 1);
  CHECK(m[0].end_mm[0] == 42.0);
  CHECK(m[0].end_mm[1] == 100.0);
  // recursion: 5! through the call stack
  const auto f = motions(
      "o<f> sub\no1 if [#1 LE 1]\no<f> return [1]\no1 endif\no<f> call [#1-1]\n"
      "o<f> return [#1*#<_value>]\no<f> endsub\no<f> call [5]\nG0 X#<_value>\nM2\n");
  REQUIRE(f.size() == 1);
  CHECK(f[0].end_mm[0] == 120.0);
}

TEST_CASE("control-flow errors are located and name the O-word") {
  struct Case {
    const char* program;
    gm::ErrorCode code;
    int line;
    const char* says;
  };
  const Case cases[] = {
      {"o1 endwhile\nM2\n", gm::ErrorCode::ControlMismatch, 1, "o1 endwhile without o1 while"},
      {"o1 if [1]\no2 endif\nM2\n", gm::ErrorCode::ControlMismatch, 2, "o2 endif"},
      {"o<nope> call\nM2\n", gm::ErrorCode::UndefinedSubroutine, 1, "nope"},
      {"o1 sub\nG0 X1\n", gm::ErrorCode::UnterminatedControl, 1, "sub"},
      {"o1 endsub\nM2\n", gm::ErrorCode::ControlMismatch, 1, "outside a called subroutine"},
      {"o1 repeat [2]\no1 break\no1 endrepeat\nM2\n", gm::ErrorCode::ControlMismatch, 2,
       "without o1 while or do"},
      {"o<r> sub\no<r> call\no<r> endsub\no<r> call\nM2\n", gm::ErrorCode::CallTooDeep, 2,
       "nested subroutine calls"},
      {"o1 bogus\nM2\n", gm::ErrorCode::BadOWord, 1, "unknown O-word keyword 'BOGUS'"},
      {"o1 if\nM2\n", gm::ErrorCode::BadOWord, 1, "needs a [value]"},
      // rs274: one label per if/while/do/repeat (per subroutine), "duplicate O-word label"
      {"o5 if [1]\no5 endif\no5 if [1]\no5 endif\nM2\n", gm::ErrorCode::ControlMismatch, 3,
       "duplicate O-word label o5: line 1 already used it for a if"},
      {"o5 repeat [1]\no5 endrepeat\no5 while [0]\no5 endwhile\nM2\n",
       gm::ErrorCode::ControlMismatch, 3, "line 1 already used it for a repeat"},
  };
  for (const auto& c : cases) {
    INFO(c.program);
    const auto d = diagnose(c.program);
    REQUIRE(!d.empty());
    CHECK(d[0].code == code(c.code));
    CHECK(d[0].loc.line == c.line);
    CHECK_THAT(d[0].message, Catch::Contains(c.says));
  }
}

TEST_CASE("a sub defined inside another sub's body is an error (rs274: nested definition)") {
  // Read while the outer definition is passed over (rs274: "Nested subroutine definition").
  auto d = diagnose(
      "o<outer> sub\n  G0 X1\n  o<inner> sub\n  G0 X2\n  o<inner> endsub\n"
      "o<outer> endsub\no<outer> call\nM2\n");
  REQUIRE(d.size() == 2);  // the error, then the note that checking stopped there
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[0].code == code(gm::ErrorCode::ControlMismatch));
  CHECK(d[0].loc.line == 3);
  CHECK(d[0].loc.column == 3);
  CHECK(d[0].message ==
        "nested subroutine definition: o<inner> sub inside o<outer> sub (line 1); a sub is "
        "defined outside every other sub");
  // Reached while the sub runs (called before its definition): the same error, at that line.
  d = diagnose("o20 call\nM2\no20 sub\nG0 X1\n o21 sub\no21 endsub\no20 endsub\n");
  REQUIRE(d.size() == 2);  // the error, then the note that checking stopped there
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[0].loc.line == 5);
  CHECK(d[0].loc.column == 2);
  CHECK(d[0].message ==
        "nested subroutine definition: o21 sub inside the body of the called subroutine o20; a "
        "sub is defined outside every other sub");
}

TEST_CASE("a sub after the program end: found after M2, not after the closing % (rs274)") {
  // After M2 a forward call still finds it (rs274 reads on to the definition).
  CHECK(xs("G0 X1\no<late> call\nM2\no<late> sub\nG0 X3\no<late> endsub\n") ==
        std::vector<double>{1, 3});
  // Uncalled, after M2 or after the closing '%': never read.
  CHECK(diagnose("G0 X1\nM2\no<late> sub\nG0 X3\no<late> endsub\n").empty());
  CHECK(diagnose("%\nG0 X1\n%\no<late> sub\nG0 X3\no<late> endsub\n").empty());
  // Called, after the closing '%': rs274 "Failed to find sub 'Olate' before EOF", at the '%'.
  const auto d = diagnose("%\nG0 X1\no<late> call\n%\no<late> sub\nG0 X3\no<late> endsub\n");
  REQUIRE(d.size() == 2);  // the error, then the note that checking stopped there
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[0].code == code(gm::ErrorCode::UndefinedSubroutine));
  CHECK(d[0].loc.line == 4);
  CHECK(d[0].loc.column == 1);
  CHECK(d[0].message ==
        "subroutine o<late> (called at line 3) is not defined before the program's closing '%': "
        "nothing after it is read");
}

TEST_CASE("O[expression]: an O-word number computed when the line is read (rs274)") {
  CHECK(messages("o10 sub\n(DEBUG, sub 10 got #1)\no10 endsub\n#2=1\nO[#2*10] call [7]\nM2\n") ==
        std::vector<std::string>{"sub 10 got 7.000000"});
  // Every O-word takes it: a loop labelled by an expression.
  CHECK(xs("#1=0\nO[5] while [#1 LT 2]\n#1=[#1+1]\nG0 X#1\nO[2+3] endwhile\nM2\n") ==
        std::vector<double>{1, 2});
  const auto d = diagnose("#2=0.25\nO[#2*10] call\nM2\n");
  REQUIRE(d.size() == 2);  // the error, then the note that checking stopped there
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[0].code == code(gm::ErrorCode::BadOWord));
  CHECK(d[0].loc.line == 2);
  CHECK(d[0].loc.column == 1);
  CHECK(d[0].message == "O[...] gives 2.5: an O-word number is a whole number 0..99999999");
}

TEST_CASE("an O-call starts #1-#30 at 0 past its arguments, the caller's return after it (rs274)") {
  CHECK(messages("o<s> sub\n(DEBUG, #1 #2 #30)\n#2=9\no<s> endsub\n#1=5 #2=6 #30=7\n"
                 "o<s> call\no<s> call [1]\n(DEBUG, #1 #2 #30)\nM2\n") ==
        std::vector<std::string>{"0.000000 0.000000 0.000000", "1.000000 0.000000 0.000000",
                                 "5.000000 6.000000 7.000000"});
}

TEST_CASE("o#<name> and o#n: an O-word number held by a parameter (rs274 2.9)") {
  CHECK(messages("o7 sub\n(DEBUG, seven #1)\no7 endsub\no8 sub\n(DEBUG, eight #1)\no8 endsub\n"
                 "#<which>=8\no#<which> call [3]\n#5=7\no#5 call [4]\nM2\n") ==
        std::vector<std::string>{"eight 3.000000", "seven 4.000000"});
  // Inside a definition the name is read before it is set: 0 there, 8 when the sub runs.
  CHECK(messages("o8 sub\n(DEBUG, eight #1)\no8 endsub\no<m> sub\n#<w>=8\no#<w> call [5]\n"
                 "o<m> endsub\no<m> call\nM2\n") == std::vector<std::string>{"eight 5.000000"});
}

TEST_CASE("a comment between the arguments of a call is passed over (rs274)") {
  CHECK(messages("o<s> sub\n(DEBUG, #1 #2 #3)\no<s> endsub\n"
                 "o<s> call [1] (note) [2](two)[3] (end)\nM2\n") ==
        std::vector<std::string>{"1.000000 2.000000 3.000000"});
  // Still nothing but comments after the arguments.
  const auto d = diagnose("o<s> sub\no<s> endsub\no<s> call [1] (note) G0 X1\nM2\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].loc.line == 3);
  CHECK(d[0].loc.column == 22);
  CHECK(d[0].message == "nothing but comments may follow an O-word");
}

TEST_CASE("labels: reused across subroutines and re-run loops, but not within one scope") {
  // The same if inside a loop, the same label at top level and in a sub, a do closed by its
  // while, a sub called twice: all one label per construct and scope, so accepted.
  CHECK(xs("#1=0\no1 while [#1 LT 2]\n#1=[#1+1]\no2 if [1]\nG0 X#1\no2 endif\no1 endwhile\n"
           "o<s> sub\no2 if [1]\nG0 Y1\no2 endif\no<s> endsub\no<s> call\no<s> call\n"
           "o3 do\nG0 X9\no3 while [0]\nM2\n") == std::vector<double>{1, 2, 2, 9});
  // An if whose condition is false at its first line is still recorded (rs274 records on run).
  CHECK(diagnose("o4 if [0]\no4 endif\no4 if [1]\no4 endif\nM2\n").at(0).loc.line == 3);
  // A label in a branch that never runs is not recorded.
  CHECK(diagnose("o4 if [0]\no6 if [1]\no6 endif\no4 endif\no6 if [1]\no6 endif\nM2\n").empty());
}

TEST_CASE("rs274 2.9: after a break, the next do ... while loop runs once") {
  // The break leaves LinuxCNC's doing_break set; the next do loop's while line clears it
  // without looping back. A do loop after that loops normally.
  CHECK(xs("#1=0\no1 while [1]\no1 break\no1 endwhile\n"
           "o2 do\n#1=[#1+1]\nG0 X#1\no2 while [#1 LT 3]\n"
           "o3 do\n#1=[#1+1]\nG0 X#1\no3 while [#1 LT 3]\nM2\n") == std::vector<double>{1, 2, 3});
  // A break out of a do loop is cleared by that loop's own while line.
  CHECK(xs("#1=0\no2 do\no2 break\no2 while [1]\n"
           "o3 do\n#1=[#1+1]\nG0 X#1\no3 while [#1 LT 3]\nM2\n") == std::vector<double>{1, 2, 3});
}

TEST_CASE("an endless loop stops at --max-iterations with a located error") {
  const auto d = check_with("o1 while [1]\no1 endwhile\nM2\n", 1000);
  REQUIRE(d.size() == 2);  // the error, then the note that checking stopped there
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[0].code == code(gm::ErrorCode::TooManyIterations));
  CHECK(d[0].loc.line == 2);
  CHECK_THAT(d[0].message, Catch::Contains("1000"));
}

TEST_CASE("check on two threads gives what one thread gives when the program loops") {
  // The loop starts after more than one batch of lines: the parallel front hands over to the
  // serial re-reading path in the middle of the program.
  std::string p;
  for (int i = 0; i < 3000; ++i) p += "G1 X" + std::to_string(i % 7) + " F100\n";
  p += "#1=0\no9 while [#1 LT 50]\nG1 Y#1\n#1=[#1+1]\no9 endwhile\nG1 X[1/0]\nM2\n";
  std::istringstream a(p), b(p);
  std::vector<gm::Diagnostic> da, db;
  gm::Machine m;
  const auto sa = gm::check_program_diagnostics(a, "t", gm::InterpreterOptions{&m, false}, da,
                                                gm::CheckThreads::Auto);
  const auto sb = gm::check_program_diagnostics(b, "t", gm::InterpreterOptions{&m, false}, db,
                                                gm::CheckThreads::Single);
  CHECK(sa.moves == sb.moves);
  CHECK(sa.moves == 3000 + 50 - 2);  // G1 X0 and G1 Y0 first: zero-length, not emitted
  CHECK(sa.path_length_mm == Approx(sb.path_length_mm));
  REQUIRE(da.size() == 1);
  REQUIRE(db.size() == 1);
  CHECK(da[0].loc.line == 3006);
  CHECK(db[0].loc.line == 3006);
}

TEST_CASE("a loop's lines from the parse cache keep their comments, expressions and errors") {
  // Lines 3-5 are parsed on the first pass and taken from the parse cache on the next two.
  const std::string body = "#1=0\no1 while [#1 LT 3]\n(DEBUG, pass #1)\nG0 X[#1+1] (MSG, moving)\n";
  CHECK(messages(body + "#1=[#1+1]\no1 endwhile\nM2\n") ==
        std::vector<std::string>{"pass 0.000000", "moving", "pass 1.000000", "moving",
                                 "pass 2.000000", "moving"});
  CHECK(xs(body + "#1=[#1+1]\no1 endwhile\nM2\n") == std::vector<double>{1, 2, 3});
  // A line with a syntax error is reported on every pass, at the same place.
  const auto d = check_with(body + "G0 Y1 $\n#1=[#1+1]\no1 endwhile\nM2\n", 1000);
  REQUIRE(d.size() == 3);
  for (const auto& e : d) {
    CHECK(e.loc.line == 5);
    CHECK(e.loc.column == 7);
    CHECK(e.message == "unexpected character '$'");
  }
}
