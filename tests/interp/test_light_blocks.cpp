// Light blocks (an F word and G0-G3 only, run on the state itself with an undo record): a failing
// block leaves every field as it was, as a block run on a copy of the state does.
#include "common/error_codes.hpp"
#include "grammar/parse.hpp"
#include "interp/interpreter.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

namespace {

struct Runner {
  gm::Machine machine;
  gm::Interpreter interp{machine};
  gm::grammar::BlockParser parser;
  gm::grammar::Block block;
  std::vector<gm::Canon> out;
  gm::InterpError err;
  int line = 0;

  // Runs one line. (interp.state() is one of two states the interpreter alternates between: the
  // tests read it anew after each block.)
  bool exec(const std::string& text) {
    parser.parse(text, ++line, block);
    REQUIRE_FALSE(block.has_errors());
    err = gm::InterpError{};
    return interp.execute(block, out, err);
  }
};

}  // namespace

TEST_CASE("A failing light block leaves the motion mode, feed, position and cycle state") {
  Runner r;
  REQUIRE(r.exec("G21 G90 G17 G94"));
  REQUIRE(r.exec("G0 Z5"));
  REQUIRE(r.exec("G1 X1 Y2 F100"));
  REQUIRE(r.interp.state().motion == 10);
  REQUIRE(r.interp.state().feed_mm_min == 100.0);
  REQUIRE(r.interp.state().position_mm[0] == 1.0);
  REQUIRE(r.out.size() == 2);

  // F500 is taken and G2 becomes the mode before the arc fails: half the chord (2) is beyond R1.
  CHECK_FALSE(r.exec("G2 X5 Y2 R1 F500"));
  CHECK(r.err.code == gm::ErrorCode::ArcRadiusTooSmall);
  CHECK(r.interp.state().motion == 10);
  CHECK(r.interp.state().feed_mm_min == 100.0);
  CHECK(r.interp.state().position_mm[0] == 1.0);
  CHECK(r.interp.state().position_mm[1] == 2.0);
  CHECK(r.out.size() == 2);

  // The rapid's mode is set before its target is found out of range.
  CHECK_FALSE(r.exec("G0 X9999999999999"));
  CHECK(r.err.code == gm::ErrorCode::ValueOutOfRange);
  CHECK(r.interp.state().motion == 10);

  // The same block with an S word runs on a copy of the state: the same error, the same state.
  const std::string light_message = [&] {
    r.exec("G2 X5 Y2 R1 F500");
    return r.err.message;
  }();
  CHECK_FALSE(r.exec("G2 X5 Y2 R1 F500 S1000"));
  CHECK(r.err.message == light_message);
  CHECK(r.interp.state().motion == 10);
  CHECK(r.interp.state().feed_mm_min == 100.0);

  // A modal G1 block (no code) is light too: it moves from (1, 2) to X4 at F100.
  REQUIRE(r.exec("X4"));
  CHECK(r.interp.state().position_mm[0] == 4.0);
  REQUIRE(r.out.size() == 3);
  const auto& last = std::get<gm::Motion>(r.out.back());
  CHECK(last.kind == gm::MotionKind::Line);
  CHECK(last.feed_mm_min == 100.0);

  // A drilling cycle's sticky state survives a failing rapid, which would end the cycle run.
  REQUIRE(r.exec("G81 X4 Y2 R2 Z-1 F200"));
  REQUIRE(r.interp.state().cycle_mode == 810);
  CHECK_FALSE(r.exec("G0 Y9999999999999"));
  CHECK(r.interp.state().cycle_mode == 810);
  CHECK(r.interp.state().motion == 810);
  REQUIRE(r.exec("G0 X0"));
  CHECK(r.interp.state().cycle_mode == -1);
  CHECK(r.interp.state().motion == 0);
  CHECK(r.interp.state().position_mm[0] == 0.0);
}

TEST_CASE("A failing light block after G40 keeps the straight-move rule") {
  Runner r;
  REQUIRE(r.exec("G21 G90 G17 G94 F100"));
  REQUIRE(r.exec("G0 X0 Y0"));
  REQUIRE(r.exec("G41.1 D2 G1 X10 Y0"));
  REQUIRE(r.exec("G1 X20 Y0"));
  REQUIRE(r.exec("G40"));
  REQUIRE(r.interp.state().comp.arc_not_allowed);
  // A straight move clears the rule before its target fails: the rule must still hold.
  CHECK_FALSE(r.exec("G1 X9999999999999"));
  CHECK(r.interp.state().comp.arc_not_allowed);
  CHECK_FALSE(r.exec("G2 X30 Y0 R5"));
  CHECK(r.err.code == gm::ErrorCode::CutterCompMisused);
  REQUIRE(r.exec("G1 X25"));
  CHECK_FALSE(r.interp.state().comp.arc_not_allowed);
}
