// JUnit XML for CI systems (Jenkins, GitLab, GitHub actions): one <testcase> per golden case.
#pragma once

#include "golden/golden_runner.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace gm::golden {

/// Text escaped for XML content and attributes; characters XML 1.0 forbids become '?'.
std::string xml_escape(std::string_view s);

/// <testsuites><testsuite name=SUITE ...><testcase classname="golden.SUITE" name=CASE time=S>
/// with <failure> for a divergence or a changed set-up and <error> for a run that failed.
std::string junit_xml(const std::string& suite_name, const std::vector<CaseResult>& results,
                      double seconds);

}  // namespace gm::golden
