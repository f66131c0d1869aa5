// Fuzz target: an override schedule through its reader, then played back sample by sample.
#include "fuzz_target.hpp"

#include "common/status.hpp"
#include "override/override_schedule.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace {

constexpr double kMaxPercent = 200.0;  // the default machine's maximum override

[[noreturn]] void broken(const char* what) {
  std::fprintf(stderr, "fuzz_override: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  gm::OverrideSchedule schedule;
  try {
    schedule = gm::OverrideSchedule::parse(text, "fuzz.csv", kMaxPercent);
  } catch (const gm::InputError&) {
    return 0;
  }
  // What the reader promises: percentages within 0..max, times >= 0 and not going back.
  double last_t = 0.0;
  for (const gm::OverrideChange& c : schedule.changes()) {
    if (!(c.percent >= 0.0 && c.percent <= kMaxPercent)) broken("a percentage outside 0..max");
    if (c.trigger == gm::OverrideChange::Trigger::Time) {
      if (!std::isfinite(c.t_s) || c.t_s < last_t)
        broken("a time entry goes back or is not finite");
      last_t = c.t_s;
    } else if (c.line < 1) {
      broken("a line entry before line 1");
    }
  }
  // Playback over a few hundred samples, walking the source lines.
  gm::OverridePlayer player(schedule, 0.004);
  for (std::int64_t k = 0; k < 512; ++k) {
    player.advance(k, static_cast<int>(k / 4) + 1);
    if (!(player.feed_percent() >= 0.0 && player.feed_percent() <= kMaxPercent) ||
        !(player.rapid_percent() >= 0.0 && player.rapid_percent() <= kMaxPercent))
      broken("playback left 0..max");
  }
  return 0;
}
