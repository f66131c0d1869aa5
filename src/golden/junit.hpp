// JUnit XML for CI systems (Jenkins, GitLab, GitHub actions): one <testcase> per golden case.
#pragma once

#include "golden/golden_runner.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace gm::golden {

/// <testsuites><testsuite name=SUITE ...><testcase classname="golden.SUITE" name=CASE time=S>
/// with <failure> for a divergence or a changed set-up and <error> for a run that failed.
std::string junit_xml(const std::string& suite_name, const std::vector<CaseResult>& results,
                      double seconds);

}  // namespace gm::golden
