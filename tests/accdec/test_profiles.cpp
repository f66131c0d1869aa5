// The profile registry: every row parses, designs, is listed in the errors and in the docs.
#include "accdec/profile_spec.hpp"
#include "accdec/profiles.hpp"
#include "accdec/taps.hpp"
#include "common/status.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>

TEST_CASE("profile registry: every row's example designs non-negative taps of DC gain 1") {
  REQUIRE(gm::profile_rows().size() >= 9);
  for (const gm::ProfileRow& row : gm::profile_rows()) {
    INFO(row.name);
    const gm::ProfileSpec spec = gm::parse_profile_spec(row.example);
    CHECK(spec.row == &row);
    CHECK(gm::find_profile(row.name) == &row);
    const double T = 0.004;
    const int fixed = spec.fixed_length(T);
    // A composition of a tau-following profile and a shaper follows tau.
    CHECK((fixed > 0) == (row.fixed_length != nullptr && row.name != gm::kCompositionName));
    const gm::Taps t = gm::design_taps(row.example, (fixed > 0 ? fixed : 41) * T, T);
    CHECK(t.real.size() == static_cast<std::size_t>(fixed > 0 ? fixed : 41));
    double sum = 0;
    for (double b : t.real) {
      sum += b;
      CHECK(b >= 0);
    }
    CHECK(sum == Approx(1.0).epsilon(1e-12));
    // Arguments and cutoffs are refused exactly where the row says so.
    if (row.parse_arg == nullptr)
      CHECK_THROWS_WITH(gm::parse_profile_spec(std::string(row.name) + ":1"),
                        Catch::Matchers::Contains("takes no ':' argument"));
    if (row.takes_damping) {
      CHECK(gm::parse_profile_spec(std::string(row.example) + "@0.15").args.at(1) == 0.15);
      CHECK_THROWS_WITH(gm::parse_profile_spec(std::string(row.example) + "@1.5"),
                        Catch::Matchers::Contains("damping ratio 1.5 is outside"));
    } else if (row.name == gm::kCompositionName)
      CHECK(gm::parse_profile_spec(std::string(row.example) + "@0.15").stages.size() == 2);
    else if (!row.takes_cutoff)
      CHECK_THROWS_WITH(gm::parse_profile_spec(std::string(row.example) + "@0.1"),
                        Catch::Matchers::Contains("takes no '@cutoff'"));
    else
      CHECK(gm::parse_profile_spec(std::string(row.example) + "@max").cutoff_rule ==
            gm::CutoffRule::MaxNonNeg);
  }
}

TEST_CASE("profile registry: an unknown name lists every form, the paper's set is its four") {
  try {
    gm::parse_profile_spec("sinc");
    FAIL("accepted");
  } catch (const gm::InputError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("unknown profile name 'sinc'") != std::string::npos);
    for (const gm::ProfileRow& row : gm::profile_rows())
      CHECK(msg.find(std::string(row.form)) != std::string::npos);
  }
  // Chen & Lee compare linear, S-curve 1, S-curve 2 and Blackman (Fig. 13).
  CHECK(gm::paper_profiles() ==
        std::vector<std::string>{"linear", "scurve1", "scurve2", "blackman"});
}

TEST_CASE("profile registry: docs/pipeline.md documents every row") {
  std::ifstream f(std::string(GMOTION_TESTS_DIR) + "/../docs/pipeline.md");
  REQUIRE(f);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string doc = ss.str();
  for (const gm::ProfileRow& row : gm::profile_rows()) {
    INFO(row.form);
    CHECK(doc.find("| `" + std::string(row.form) + "` |") != std::string::npos);
  }
}
