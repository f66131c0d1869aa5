// Writes the results of a golden verify as JUnit XML (the Ant/Jenkins schema's common subset).
#include "golden/junit.hpp"

#include "report/escape.hpp"

#include <fmt/format.h>

#include <iterator>

namespace gm::golden {

std::string junit_xml(const std::string& suite_name, const std::vector<CaseResult>& results,
                      double seconds) {
  int failures = 0, errors = 0;
  for (const CaseResult& r : results) {
    failures += r.outcome == Outcome::Fail ? 1 : 0;
    errors += r.outcome == Outcome::Error ? 1 : 0;
  }
  std::string x;
  auto out = std::back_inserter(x);
  const std::string name = report::html_escape(suite_name);
  fmt::format_to(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  fmt::format_to(out,
                 "<testsuites name=\"gmotion golden\" tests=\"{}\" failures=\"{}\" errors=\"{}\" "
                 "time=\"{:.3f}\">\n",
                 results.size(), failures, errors, seconds);
  fmt::format_to(out,
                 "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" "
                 "skipped=\"0\" time=\"{:.3f}\">\n",
                 name, results.size(), failures, errors, seconds);
  for (const CaseResult& r : results) {
    fmt::format_to(out, "    <testcase classname=\"golden.{}\" name=\"{}\" time=\"{:.3f}\"", name,
                   report::html_escape(r.name), r.seconds);
    if (!outcome_failed(r.outcome)) {
      x += "/>\n";
      continue;
    }
    const char* tag = r.outcome == Outcome::Fail ? "failure" : "error";
    std::string body = r.headline;
    for (const std::string& d : r.details) body += "\n" + d;
    fmt::format_to(out, ">\n      <{} message=\"{}\" type=\"{}\">{}</{}>\n    </testcase>\n", tag,
                   report::html_escape(r.headline), report::html_escape(r.kind),
                   report::html_escape(body), tag);
  }
  x += "  </testsuite>\n</testsuites>\n";
  return x;
}

}  // namespace gm::golden
