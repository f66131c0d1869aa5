// NaiveCamMerger: G64 Q merging of nearly collinear straight feed moves.
#include "planner/naive_cam.hpp"

#include <algorithm>

namespace gm {

namespace {

// Distance of p from the segment a–b (XYZ; the other axes do not move in a run).
double distance_to_segment(const AxisVec& p, const AxisVec& a, const AxisVec& b) {
  const Eigen::Vector3d ab = (b - a).head<3>(), ap = (p - a).head<3>();
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(ap.dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (ap - t * ab).norm();
}

}  // namespace

bool NaiveCamMerger::mergeable(const Motion& m) const {
  if (m.kind != MotionKind::Line || m.inverse_time_s > 0.0 || !(m.naive_cam_tolerance_mm > 0.0) ||
      m.path_mode != PathMode::Continuous || m.speed_cap_mm_s > 0.0)
    return false;
  for (Eigen::Index i = 3; i < m.end_mm.size(); ++i)
    if (m.end_mm[i] != m.start_mm[i]) return false;  // XYZ moves only
  return (m.end_mm - m.start_mm).head<3>().norm() > 0.0;
}

bool NaiveCamMerger::extends(const Motion& m) const {
  if (!active_ || vertices_.size() + 1 >= max_run_) return false;
  if (m.feed_mm_min != run_.feed_mm_min ||
      m.naive_cam_tolerance_mm != run_.naive_cam_tolerance_mm ||
      m.path_tolerance_mm != run_.path_tolerance_mm || m.start_mm != run_.end_mm)
    return false;
  const double q = m.naive_cam_tolerance_mm;
  // Every vertex of the run, the current end included, within Q of start–new end.
  if (distance_to_segment(run_.end_mm, run_.start_mm, m.end_mm) > q) return false;
  for (const AxisVec& v : vertices_)
    if (distance_to_segment(v, run_.start_mm, m.end_mm) > q) return false;
  return true;
}

void NaiveCamMerger::flush() {
  if (!active_) return;
  ready_.push_back(run_);
  ++moves_out_;
  active_ = false;
  vertices_.clear();
}

bool NaiveCamMerger::next(Canon& out) {
  if (ready_.empty() && !active_ && !ended_) {
    // Nothing held (no G64 Q run open): read straight into `out`, no copy through the queue.
    if (!upstream_.next(out)) {
      ended_ = true;
      return false;
    }
    const Motion* m = std::get_if<Motion>(&out);
    if (m == nullptr) return true;
    if (!mergeable(*m)) {
      ++moves_out_;
      return true;
    }
    run_ = *m;  // a G64 Q run starts
    active_ = true;
  }
  while (ready_.empty() && !ended_) {
    if (!upstream_.next(scratch_)) {
      ended_ = true;
      flush();
      break;
    }
    const Motion* m = std::get_if<Motion>(&scratch_);
    if (m != nullptr && mergeable(*m)) {
      if (extends(*m)) {
        vertices_.push_back(run_.end_mm);
        run_.end_mm = m->end_mm;
        continue;
      }
      flush();
      run_ = *m;
      active_ = true;
      continue;
    }
    flush();
    if (m != nullptr) ++moves_out_;
    ready_.push_back(scratch_);
  }
  if (ready_.empty()) return false;
  out = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

}  // namespace gm
