// VibrationMeter: stops found from the interpolator output, windows of |tip − ref| after them.
#include "measure/vibration_meter.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace gm {

VibrationMeter::VibrationMeter(int axes, int filter_samples, double period_s, double window_s)
    : axes_(axes),
      rest_delay_(std::max(filter_samples, 1) - 1),
      window_samples_(std::max<std::int64_t>(1, std::llround(window_s / period_s))),
      period_s_(period_s),
      window_s_(window_s),
      lead_(static_cast<std::size_t>(std::max<std::int64_t>(1, std::llround(kLeadS / period_s)))) {
  for (int a = 0; a < axes_; ++a) {
    Record& r = rec_[static_cast<std::size_t>(a)];
    r.lead.assign(lead_, 0.0);
    r.cur.assign(lead_ + static_cast<std::size_t>(window_samples_), 0.0);
    r.best.assign(r.cur.size(), 0.0);
  }
}

void VibrationMeter::close(int a) {
  State& s = state_[static_cast<std::size_t>(a)];
  AxisVibration& r = result_[static_cast<std::size_t>(a)];
  ++r.stops;
  if (s.window_defl > r.residual_blu) {
    r.residual_blu = s.window_defl;
    r.residual_line = s.window_line;
    r.residual_t_s = static_cast<double>(s.window_k) * period_s_;
    Record& c = rec_[static_cast<std::size_t>(a)];
    std::swap(c.cur, c.best);  // the vectors' buffers change hands: nothing allocated
    c.best_len = c.cur_len;
    c.best_k0 = c.cur_k0;
  }
  if (s.window_dev > r.settle_blu) {
    r.settle_blu = s.window_dev;
    r.settle_line = s.window_line;
  }
  s.window_left = 0;
}

void VibrationMeter::add_block(const SampleBlock& b, int first) {
  for (int a = 0; a < axes_; ++a) {
    State& s = state_[static_cast<std::size_t>(a)];
    AxisVibration& r = result_[static_cast<std::size_t>(a)];
    const std::int64_t* cmd = b.cmd_blu.v[a];
    const std::int64_t* ref = b.ref_blu.v[a];
    const double* tip = b.table_blu.v[a];
    const double* defl = b.defl_blu.v[a];
    Record& c = rec_[static_cast<std::size_t>(a)];
    for (int i = first; i < b.count; ++i) {
      const std::int64_t k = b.k0 + i;
      if (!s.started) {
        s.prev_cmd = cmd[i];
        s.started = true;
      }
      if (cmd[i] != s.prev_cmd) {  // the axis moves: a window open ends, a stop is pending
        s.prev_cmd = cmd[i];
        if (s.window_left > 0) close(a);
        s.rest_k = k + rest_delay_;
        s.move_line = b.line[i];
      }
      const double dev = tip[i] - static_cast<double>(ref[i]);
      if (k == s.rest_k) {  // the Acc/Dec output is at rest from here: a stop's window opens
        // The record starts with the lead samples before this one, oldest first.
        c.cur_len = 0;
        for (std::size_t j = 0; j < c.lead_len; ++j)
          c.cur[c.cur_len++] = c.lead[(c.lead_pos + lead_ - c.lead_len + j) % lead_];
        c.cur_k0 = k - static_cast<std::int64_t>(c.lead_len);
        s.window_left = window_samples_;
        s.window_defl = 0.0;
        s.window_dev = 0.0;
        s.window_line = s.move_line;
        s.window_k = k;
        s.rest_k = -1;
      }
      const double d = std::abs(defl[i]);
      c.lead[c.lead_pos] = dev;
      c.lead_pos = c.lead_pos + 1 == lead_ ? 0 : c.lead_pos + 1;
      c.lead_len = std::min(c.lead_len + 1, lead_);
      if (s.window_left > 0) {
        s.window_defl = std::max(s.window_defl, d);
        s.window_dev = std::max(s.window_dev, std::abs(dev));
        c.cur[c.cur_len++] = dev;
        if (--s.window_left == 0) close(a);
      }
      if (d > r.deflection_blu) {
        r.deflection_blu = d;
        r.deflection_line = b.line[i];
      }
    }
  }
}

void VibrationMeter::finish() {
  for (int a = 0; a < axes_; ++a)
    if (state_[static_cast<std::size_t>(a)].window_left > 0) close(a);
}

}  // namespace gm
