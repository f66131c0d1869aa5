// ArcEndRows: the end shapes' knots fitted per rate over the join's phases on first use, read
// linearly.
#include "interpolator/arc_end_rows.hpp"

#include "interpolator/arc_end_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

namespace gm {

void ArcEndRows::basis(double u, double& fixed, std::array<double, kInner>& hat) {
  hat.fill(0.0);
  fixed = 0.0;
  if (!(u > 0.0)) return;
  if (u >= kSpan) {
    fixed = 1.0;
    return;
  }
  // Between knots k and k + 1 (knot 0 at u = 0, knot kSpan at u = kSpan).
  const int k = std::min(static_cast<int>(u), kSpan - 1);
  const double f = u - static_cast<double>(k);
  if (k >= 1) hat[static_cast<std::size_t>(k - 1)] += 1.0 - f;
  if (k + 1 <= kInner)
    hat[static_cast<std::size_t>(k)] += f;
  else
    fixed = f;  // towards the steady (1, 0)
}

ArcEndRows::ArcEndRows(const std::vector<double>& weights, double period_s, double limit_x)
    : weights_(weights),
      period_s_(period_s),
      limit_x_(limit_x),
      enabled_(weights.size() >= 2 && limit_x > 0.0) {}

ArcEndRows::~ArcEndRows() {
  stop_.store(true, std::memory_order_relaxed);
  if (rest_.joinable()) rest_.join();
}

bool ArcEndRows::claim_and_fit(std::size_t rate, std::size_t way) const {
  Lazy& l = lazy_[rate][way];
  int expected = kNotBegun;
  if (!l.state.compare_exchange_strong(expected, kFitting, std::memory_order_acq_rel)) return false;
  l.k = fit(rate, static_cast<Way>(way));
  {
    const std::lock_guard<std::mutex> hold(done_lock_);
    l.state.store(kDone, std::memory_order_release);
  }
  done_.notify_all();
  return true;
}

void ArcEndRows::fit_the_rest() const {
  // The distance's sets only once one of them is asked for (private arcs are rarer).
  for (std::size_t way = 0; way < kWays; ++way)
    for (std::size_t rate = 0; rate < kRateKnots.size(); ++rate) {
      if (stop_.load(std::memory_order_relaxed)) return;
      if (static_cast<Way>(way) == Way::MovingDistance &&
          !distance_wanted_.load(std::memory_order_relaxed))
        return;
      claim_and_fit(rate, way);
    }
}

const ArcEndRows::Knots& ArcEndRows::knots(std::size_t rate, Way way) const {
  const auto w = static_cast<std::size_t>(way);
  Lazy& l = lazy_[rate][w];
  if (l.state.load(std::memory_order_acquire) == kDone) return l.k;
  if (way == Way::MovingDistance) distance_wanted_.store(true, std::memory_order_relaxed);
  std::call_once(rest_started_, [this] { rest_ = std::thread([this] { fit_the_rest(); }); });
  if (!claim_and_fit(rate, w)) {  // the other thread has it in hand
    std::unique_lock<std::mutex> hold(done_lock_);
    done_.wait(hold, [&l] { return l.state.load(std::memory_order_acquire) == kDone; });
  }
  return l.k;
}

ArcEndRows::Knots ArcEndRows::fit(std::size_t rate, Way way) const {
  const ArcEndFit fitter(weights_, period_s_);
  const int window = static_cast<int>(weights_.size());
  const double endless = std::numeric_limits<double>::infinity();
  const double x = kRateKnots[rate] * limit_x_, v = x / period_s_;
  std::vector<ArcRun> runs;
  std::vector<ArcCommandModel> models;
  // The command of a run by the rule: the steady part fixed, the inner knots unknown (along
  // in units of c/x: the weight μ then sees the command's step along the path, about c/x
  // for an advance x·r).
  const auto add = [&](ArcRun run) {
    const std::vector<ArcSample> smp = fitter.samples(run);
    const std::size_t n = smp.size();
    ArcCommandModel model{{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)}, {}};
    model.columns.assign(2 * kInner, model.base);
    int since_first = -1;
    double phase_in = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!smp[i].on) continue;
      // The interpolator's advances from the start: the count since the arc's first
      // sample plus how far past the start that one lay, of its advance (Stopping, the
      // mirror of an end: of the advance at speed v, as the end's are counted).
      if (since_first < 0) phase_in = smp[i].s_mm / (way != Way::Stopping ? smp[i].advance_mm : x);
      ++since_first;
      double fixed;
      std::array<double, kInner> hat;
      basis(since_first + phase_in, fixed, hat);
      model.base.radial_mm[i] = fixed * smp[i].c_mm;
      for (std::size_t q = 0; q < kInner; ++q) {
        model.columns[q].radial_mm[i] = hat[q] * smp[i].c_mm;
        model.columns[kInner + q].along_mm[i] = hat[q] * smp[i].c_mm / x;
      }
    }
    runs.push_back(std::move(run));
    models.push_back(std::move(model));
  };
  // At constant speed over kPhases phases; and, at half of them, the speed falling at the
  // ramp's rate (v/(N + 1) a sample) from `fall` samples after the join on (seen backwards
  // in time, an end reached while the speed still ramps up: an arc begun from rest), or
  // rising at that rate to reach v `fall` − 10 samples after it (an override lowered near
  // an end).
  for (int p = 0; p < kPhases; ++p)
    for (const int fall : {-1, 0, 2, 4, 10, 12, 14}) {
      if (fall >= 0 && p % 2 == 1) continue;
      const double phase = (static_cast<double>(p) + 0.5) / kPhases;
      ArcRun run = ArcRun::constant(1.0, endless, v, period_s_, phase, window);
      if (fall >= 0 && fall < 10)
        for (std::size_t i = static_cast<std::size_t>(run.first + fall); i < run.speed_mm_s.size();
             ++i)
          run.speed_mm_s[i] =
              v * std::max(0.5, 1.0 - (static_cast<double>(i) - run.first - fall) / window);
      if (fall >= 10)  // rising to v at fall - 10 samples after the join
        for (std::size_t i = 0; i < run.speed_mm_s.size(); ++i)
          run.speed_mm_s[i] =
              v * std::clamp(1.0 + (static_cast<double>(i) - run.first - (fall - 10)) / window, 0.5,
                             1.0);
      // Stopping, backwards in time: held on the join, then at speed at once (the first
      // sample `phase` of an advance past it).
      if (way == Way::Stopping) {
        std::fill(run.speed_mm_s.begin(), run.speed_mm_s.begin() + run.first, 0.0);
        run.speed_mm_s[static_cast<std::size_t>(run.first)] *= phase;
        run.phase = 1.0;
      }
      add(std::move(run));
    }
  // The distance's rows command large offsets along the path, which hold only for the speeds
  // they were fitted for: the line before a private arc takes a change of the override by the
  // arc's ramp too (Motion::override_ramp_mm_s), so also the speed falling at that rate from
  // `k` samples before the join on, and rising at it to reach v `k` samples before the join
  // (seen backwards in time: a fall begun on the line after an end).
  if (way == Way::MovingDistance)
    for (int p = 0; p < kPhases; p += 2)
      for (const int k : {1, 2, 4, 8, 16, 24})
        for (const bool falling : {true, false}) {
          const double phase = (static_cast<double>(p) + 0.5) / kPhases;
          ArcRun run = ArcRun::constant(1.0, endless, v, period_s_, phase, window);
          const int at = run.first - k;  // the ramp's first sample (falling) or last (rising)
          for (std::size_t i = 0; i < run.speed_mm_s.size(); ++i) {
            const double d = static_cast<double>(static_cast<int>(i) - at) / window;
            run.speed_mm_s[i] = v * std::clamp(falling ? 1.0 - d : 1.0 + d, 0.0, 1.0);
          }
          add(std::move(run));
        }
  if (way != Way::Stopping) {
    // From rest at the arc's start, the speed ramped as the interpolator does (v/(N + 1) a
    // sample): its first sample one advance past the start.
    ArcRun rest = ArcRun::constant(1.0, endless, v, period_s_, 1.0, window);
    for (int i = 0; i < rest.first + window; ++i)
      rest.speed_mm_s[static_cast<std::size_t>(i)] =
          v * std::clamp(static_cast<double>(i - rest.first + 1) / window, 0.0, 1.0);
    add(std::move(rest));
  }
  const std::vector<double> u = fitter.fit_shared(
      runs, models, kMu,
      way == Way::MovingDistance ? ArcEndMeasure::Distance : ArcEndMeasure::FromMean);
  Knots k{};
  for (std::size_t q = 0; q < kInner; ++q) {
    k[q] = u[q];
    k[kInner + q] = u[kInner + q] / x;  // kept in units of c, finite as x → 0
  }
  return k;
}

std::shared_ptr<const ArcEndRows> ArcEndRows::shared(const std::vector<double>& weights,
                                                     double period_s, double limit_x) {
  struct Entry {
    std::vector<double> weights;
    double period_s = 0.0;
    std::shared_ptr<const ArcEndRows> rows;
  };
  static std::mutex lock;
  static std::array<Entry, 8> cache;  // replaced in turn: memory stays flat over many filters
  static std::size_t next = 0;
  const std::lock_guard<std::mutex> hold(lock);
  for (const Entry& e : cache)
    if (e.rows && e.period_s == period_s && e.weights == weights) return e.rows;
  Entry& e = cache[next];
  next = (next + 1) % cache.size();
  e = Entry{weights, period_s, std::make_shared<const ArcEndRows>(weights, period_s, limit_x)};
  return e.rows;
}

ArcEndRows::RateKnots ArcEndRows::rate_knots(double x, Way way) const {
  // The rate knots below and above x/limit, linear between, clamped.
  const double r = x / limit_x_;
  std::size_t j = 0;
  while (j + 2 < kRateKnots.size() && kRateKnots[j + 1] <= r) ++j;
  const double f = std::clamp((r - kRateKnots[j]) / (kRateKnots[j + 1] - kRateKnots[j]), 0.0, 1.0);
  return {&knots(j, way), &knots(j + 1, way), f, kRateKnots[j] * limit_x_,
          kRateKnots[j + 1] * limit_x_};
}

double ArcEndRows::largest_deviation(double x, Way way) const {
  if (!enabled_) return 0.0;  // at() is then (1, 0) for every u > 0
  // As at(): basis(u) is hat_{u−1} = 1, the others and `fixed` 0 at whole u < kSpan, so its
  // sums are the knot's value exactly.
  const RateKnots k = rate_knots(x, way);
  const Knots &lo = *k.lo, &hi = *k.hi;
  const double f = k.f;
  double worst = 0.0;
  for (std::size_t q = 0; q < kInner; ++q) {
    const double rad = lo[q] + f * (hi[q] - lo[q]);
    worst = std::max(worst, std::abs(rad - 1.0) + std::abs(along_at(k, kInner + q, way)));
  }
  return worst;
}

double ArcEndRows::along_at(const RateKnots& k, std::size_t i, Way way) {
  const Knots &lo = *k.lo, &hi = *k.hi;
  if (way != Way::MovingDistance) return lo[i] + k.f * (hi[i] - lo[i]);
  // The distance's along knots go about as 1/x (its drift along the path, in samples' advances,
  // changes little with the rate): read linearly in along·x.
  return (lo[i] * k.x_lo + k.f * (hi[i] * k.x_hi - lo[i] * k.x_lo)) /
         (k.x_lo + k.f * (k.x_hi - k.x_lo));
}

ArcEndRows::Shape ArcEndRows::at(double u, double x, Way way) const {
  double fixed;
  std::array<double, kInner> hat;
  basis(u, fixed, hat);
  if (!enabled_) return {u > 0.0 ? 1.0 : 0.0, 0.0};
  const RateKnots k = rate_knots(x, way);
  const Knots &lo = *k.lo, &hi = *k.hi;
  const double f = k.f;
  const auto knot = [&](std::size_t i) { return lo[i] + f * (hi[i] - lo[i]); };
  Shape s{fixed, 0.0};
  for (std::size_t q = 0; q < kInner; ++q) {
    const double rad = knot(q), along = along_at(k, kInner + q, way);
    s.radial += hat[q] * rad;
    s.along += hat[q] * along;
  }
  return s;
}

}  // namespace gm
