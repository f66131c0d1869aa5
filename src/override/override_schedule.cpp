// Parsing and playback of override schedules (`t_s,percent` and `line:N,percent` lines).
#include "override/override_schedule.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace gm {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

// A finite decimal number taking the whole of `s`.
bool parse_number(std::string_view s, double& out) {
  s = trim(s);
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && p == end && std::isfinite(out);
}

}  // namespace

OverrideSchedule OverrideSchedule::parse(std::string_view text, std::string_view source,
                                         double max_percent) {
  OverrideSchedule sched;
  int line_no = 0;
  double last_t = -1.0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++line_no;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    auto fail = [&](const std::string& msg) {
      return InputError(fmt::format("{}:{}: {} (in '{}')", source, line_no, msg, line));
    };
    const std::size_t comma = line.find(',');
    if (comma == std::string_view::npos) throw fail("expected WHEN,PERCENT");
    std::string_view when = trim(line.substr(0, comma));
    std::string_view value = trim(line.substr(comma + 1));

    OverrideChange c;
    c.source_line = line_no;
    if (when.substr(0, 5) == "line:") {
      double n = 0;
      if (!parse_number(when.substr(5), n) || n < 1 || n != std::floor(n) || n > 1e9)
        throw fail(
            fmt::format("'{}' is not a source line number (line:N, N >= 1)", when.substr(5)));
      c.trigger = OverrideChange::Trigger::Line;
      c.line = static_cast<int>(n);
    } else {
      if (!parse_number(when, c.t_s) || c.t_s < 0)
        throw fail(fmt::format("'{}' is not a time in seconds >= 0 (or line:N)", when));
      if (c.t_s < last_t) throw fail(fmt::format("time {} s goes back before {} s", c.t_s, last_t));
      last_t = c.t_s;
    }
    if (value.substr(0, 6) == "rapid=") {
      c.rapid = true;
      value.remove_prefix(6);
    } else if (value.substr(0, 5) == "feed=") {
      value.remove_prefix(5);
    }
    if (!parse_number(value, c.percent)) throw fail(fmt::format("'{}' is not a percentage", value));
    if (c.percent < 0 || c.percent > max_percent)
      throw fail(fmt::format("override {} % is outside 0..{} % (the machine's maximum)", c.percent,
                             max_percent));
    sched.changes_.push_back(c);
  }
  return sched;
}

OverrideSchedule OverrideSchedule::load(const std::string& path, double max_percent) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(fmt::format("cannot read override schedule '{}'", path));
  std::stringstream ss;
  ss << f.rdbuf();
  return parse(ss.str(), path, max_percent);
}

OverridePlayer::OverridePlayer(const OverrideSchedule& s, double period_s, double feed_percent,
                               double rapid_percent)
    : period_s_(period_s), feed_percent_(feed_percent), rapid_percent_(rapid_percent) {
  for (const OverrideChange& c : s.changes())
    (c.trigger == OverrideChange::Trigger::Time ? time_changes_ : line_changes_).push_back(c);
}

void OverridePlayer::advance(std::int64_t k, int current_line) {
  // A time change applies from the first sample at or after its time: k·T >= t (with a margin of
  // 1e-9 T so a time written as k·T by --record-override replays at exactly sample k).
  while (next_time_ < time_changes_.size() &&
         static_cast<double>(k) * period_s_ >= time_changes_[next_time_].t_s - 1e-9 * period_s_) {
    const OverrideChange& c = time_changes_[next_time_++];
    (c.rapid ? rapid_percent_ : feed_percent_) = c.percent;
  }
  if (current_line != last_line_) {
    last_line_ = current_line;
    for (const OverrideChange& c : line_changes_)
      if (c.line == current_line) (c.rapid ? rapid_percent_ : feed_percent_) = c.percent;
  }
}

int OverridePlayer::steady_samples(std::int64_t k, int current_line, int max) const {
  if (current_line != last_line_) return 0;
  if (next_time_ >= time_changes_.size()) return max;
  const double t = time_changes_[next_time_].t_s - 1e-9 * period_s_;  // advance()'s test
  int n = 0;
  while (n < max && !(static_cast<double>(k + n) * period_s_ >= t)) ++n;
  return n;
}

}  // namespace gm
