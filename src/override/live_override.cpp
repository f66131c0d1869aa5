// Non-blocking line reader for live feed/rapid override changes.
#include "override/live_override.hpp"

#include <fmt/format.h>

#include <poll.h>
#include <unistd.h>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace gm {

LiveOverride::LiveOverride(int fd, double max_percent) : fd_(fd), max_percent_(max_percent) {}

bool LiveOverride::poll(double& feed, double& rapid) {
  while (open_) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 0) <= 0 || (p.revents & (POLLIN | POLLHUP)) == 0) break;
    char buf[256];
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n <= 0) {
      open_ = false;
      break;
    }
    pending_.append(buf, static_cast<std::size_t>(n));
    std::size_t nl;
    while ((nl = pending_.find('\n')) != std::string::npos) {
      apply(pending_.substr(0, nl), feed, rapid);
      pending_.erase(0, nl + 1);
    }
  }
  return open_;
}

void LiveOverride::apply(const std::string& raw, double& feed, double& rapid) const {
  std::string line;
  for (char c : raw)
    if (c != ' ' && c != '\t' && c != '\r' && c != '%') line += c;
  if (line.empty()) return;
  if (line == "+") return void(feed = std::min(feed + 10.0, max_percent_));
  if (line == "-") return void(feed = std::max(feed - 10.0, 0.0));
  if (line == "hold") return void(feed = 0.0);
  bool is_rapid = false;
  std::string_view v = line;
  if (v.substr(0, 5) == "rapid") {
    is_rapid = true;
    v.remove_prefix(5);
    if (!v.empty() && v.front() == '=') v.remove_prefix(1);
  }
  double pct = 0;
  auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), pct);
  if (ec != std::errc() || p != v.data() + v.size() || !std::isfinite(pct)) {
    fmt::print(stderr, "override: '{}' is not a command (a percentage, rapid N, +, -, hold)\n",
               raw);
    return;
  }
  if (pct < 0 || pct > max_percent_) {
    fmt::print(stderr, "override: {} % is outside 0..{} %; ignored\n", pct, max_percent_);
    return;
  }
  (is_rapid ? rapid : feed) = pct;
}

}  // namespace gm
