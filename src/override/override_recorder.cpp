// The override record: the overrides in effect per change, as a replayable schedule.
#include "override/override_recorder.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

namespace gm {

OverrideRecorder::OverrideRecorder(const std::string& path, double period_s)
    : out_(path), period_s_(period_s) {
  if (!out_) throw InputError(fmt::format("cannot write override record '{}'", path));
  out_ << "# gmotion override record: replay with --override-file (t_s,percent; "
          "t_s,rapid=percent)\n";
}

void OverrideRecorder::sample(std::int64_t k, double feed_pct, double rapid_pct) {
  const double t = static_cast<double>(k) * period_s_;
  if (feed_pct != feed_) out_ << fmt::format("{:.17g},{:.17g}\n", t, feed_pct), feed_ = feed_pct;
  if (rapid_pct != rapid_)
    out_ << fmt::format("{:.17g},rapid={:.17g}\n", t, rapid_pct), rapid_ = rapid_pct;
}

void OverrideRecorder::finish() {
  out_.flush();
  if (!out_) throw InputError("cannot write the override record");
}

}  // namespace gm
