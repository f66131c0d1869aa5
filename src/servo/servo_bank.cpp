// ServoBank: ServoAxis's sample, the axes in SIMD lanes, one kernel per instruction set.
#include "servo/servo_bank.hpp"

#include "common/status.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>

namespace gm {

namespace {

template <int L>
struct LaneTypes;
template <>
struct LaneTypes<4> {
  typedef double V __attribute__((vector_size(32)));
  typedef std::int64_t I __attribute__((vector_size(32)));
};
template <>
struct LaneTypes<8> {
  typedef double V __attribute__((vector_size(64)));
  typedef std::int64_t I __attribute__((vector_size(64)));
};

#define GM_INLINE __attribute__((always_inline)) inline

// The lanes of one sample: the state as vectors (in registers) and the parameters. Everything
// by reference: no vector crosses a call (the kernel is one inlined function per instruction set).
template <int L, int M>
struct Lanes {
  using V = typename LaneTypes<L>::V;
  using I = typename LaneTypes<L>::I;

  struct State {
    V z[M], integ, u, table_rel;
    I prev_count, prev_ref, start;
  };
  State s;  // what a sample changes (saved before a row, to take it back)
  V a[M * M], bd[M];
  V kp, kvp, kvi, kv_period, kv_over_h, h_over_kv, u_max, hb;
  I ip;

  template <typename T, typename S>
  static GM_INLINE void load(T& v, const S* p) {
    std::memcpy(&v, p, sizeof v);
  }
  template <typename T, typename S>
  static GM_INLINE void store(S* p, const T& v) {
    std::memcpy(p, &v, sizeof v);
  }

  GM_INLINE void load_state(const ServoBank::LaneState& from) {
    for (int k = 0; k < M; ++k) load(s.z[k], from.z[k]);
    load(s.integ, from.integ);
    load(s.u, from.u);
    load(s.table_rel, from.table_rel);
    load(s.prev_count, from.prev_count);
    load(s.prev_ref, from.prev_ref);
    load(s.start, from.start);
  }
  GM_INLINE void store_state(ServoBank::LaneState& to) const {
    for (int k = 0; k < M; ++k) store(to.z[k], s.z[k]);
    store(to.integ, s.integ);
    store(to.u, s.u);
    store(to.table_rel, s.table_rel);
    store(to.prev_count, s.prev_count);
    store(to.prev_ref, s.prev_ref);
    store(to.start, s.start);
  }
  GM_INLINE void load_params(const ServoBank::LaneParams& p) {
    for (int k = 0; k < M * M; ++k) load(a[k], p.a[k]);
    for (int k = 0; k < M; ++k) load(bd[k], p.bd[k]);
    load(kp, p.kp);
    load(kvp, p.kvp);
    load(kvi, p.kvi);
    load(kv_period, p.kv_period);
    load(kv_over_h, p.kv_over_h);
    load(h_over_kv, p.h_over_kv);
    load(u_max, p.u_max);
    load(hb, p.hb);
    load(ip, p.ip);
  }

  // round_half_away (common/rounding.hpp) for lanes with |x| < 9.2e18; the others are marked
  // in `bad` (their sample then runs in ServoAxis, whose rounding handles them).
  static GM_INLINE void round(const V& x, I& out, I& bad) {
    const V ax = x < 0.0 ? -x : x;
    bad |= ~(ax < 9.2e18);
    const V safe = ax < 9.2e18 ? x : 0.0;
    const I i = __builtin_convertvector(safe, I);  // truncated toward zero
    const V frac = safe - __builtin_convertvector(i, V);
    out = i - (frac >= 0.5) + (frac <= -0.5);  // masks are -1 where true
  }

  // ServoAxis::servo_sample, lane by lane in its order.
  GM_INLINE void sample(const I& count, const V& pos_ref) {
    const V y = __builtin_convertvector(count - s.prev_count, V) * kv_over_h;
    s.prev_count = count;
    const V vref = kp * (pos_ref - __builtin_convertvector(count, V));
    const V r_v = vref * kv_period;
    const V e = r_v - y;
    const V di = e * h_over_kv;
    V in = s.integ + di;
    const V u_ip = kvi * in - kvp * y;
    const V u_pi = kvp * e + kvi * in;
    V uu = ip != 0 ? u_ip : u_pi;
    const I over = uu > u_max, under = uu < -u_max;
    const V sat = over != 0 ? u_max : under != 0 ? -u_max : uu;  // std::clamp
    const I keep = (over & (di > 0.0)) | (under & (di < 0.0));   // conditional integration
    in = keep != 0 ? s.integ : in;
    uu = (over | under) != 0 ? sat : uu;
    s.integ = in;
    s.u = uu;
    // DiscretePlant::step_sized<M>: each row summed in column order, then + Bd·u.
    V next[M];
    for (int i = 0; i < M; ++i) {
      V sum = a[i] * s.z[0];
      for (int j = 1; j < M; ++j) sum += a[j * M + i] * s.z[j];
      next[i] = sum + bd[i] * uu;
    }
    for (int i = 0; i < M; ++i) s.z[i] = next[i];
    // Lost motion.
    const V p = s.z[M - 1];
    const V d = p - s.table_rel;
    s.table_rel = d > hb ? p - hb : d < -hb ? p + hb : s.table_rel;
  }
};

// Rows first.. of the block with the lanes; stops before a row in which a lane left the exact
// rounding range (`bad_row` = that row, the state as before it) or diverged (`diverged` = its
// lane, rows done before it returned). Returns the rows done.
template <int N, int L, int M>
GM_INLINE int lane_rows(ServoBank::LaneState& st, const ServoBank::LaneParams& pa, int substeps,
                        const BluColumns& ref, BluColumns& enc, RealColumns& table, int first,
                        int n, int& quiet_run, int& bad_row, int& diverged) {
  using K = Lanes<L, M>;
  using V = typename K::V;
  using I = typename K::I;
  K k;
  k.load_params(pa);
  k.load_state(st);
  const V sub = V{} + static_cast<double>(substeps);
  int done = 0;
  for (int i = first; i < first + n; ++i, ++done) {
    const typename K::State before = k.s;
    std::int64_t r[L] = {};
    for (int a = 0; a < N; ++a) r[a] = ref.v[a][i];
    I refi;
    std::memcpy(&refi, r, sizeof refi);
    double tab[L];
    const V table_now = __builtin_convertvector(k.s.start, V) + k.s.table_rel;
    std::memcpy(tab, &table_now, sizeof tab);
    for (int a = 0; a < N; ++a) table.v[a][i] = tab[a];
    I bad = I{} + 0;
    I count0, count;
    K::round(k.s.z[M - 1], count0, bad);
    count0 += k.s.start;
    const V refd = __builtin_convertvector(refi, V);
    const V delta = __builtin_convertvector(refi - k.s.prev_ref, V);
    k.sample(count0, refd);
    for (int j = 1; j < substeps; ++j) {
      K::round(k.s.z[M - 1], count, bad);
      k.sample(count + k.s.start, refd + delta * static_cast<double>(j) / sub);
    }
    k.s.prev_ref = refi;
    std::int64_t badl[L];
    std::memcpy(badl, &bad, sizeof badl);
    double pos[L];
    std::memcpy(pos, &k.s.z[M - 1], sizeof pos);
    bool any_bad = false;
    for (int a = 0; a < N; ++a) any_bad = any_bad || badl[a] != 0;
    if (any_bad) {
      k.s = before;
      bad_row = i;
      break;
    }
    for (int a = 0; a < N; ++a)
      if (!(std::fabs(pos[a]) < ServoAxis::kMaxPositionBlu)) {
        diverged = a;
        k.store_state(st);
        return done;
      }
    std::int64_t c0[L];
    std::memcpy(c0, &count0, sizeof c0);
    bool quiet = true;
    for (int a = 0; a < N; ++a) {
      enc.v[a][i] = c0[a];
      quiet = quiet && std::llabs(c0[a] - r[a]) <= 1;
    }
    quiet_run = quiet ? quiet_run + 1 : 0;
  }
  k.store_state(st);
  return done;
}

// One kernel per instruction set: the whole row loop is inside the attributed function.
#define GM_SERVO_KERNEL(NAME, TARGET)                                                           \
  template <int N, int L, int M>                                                                \
  TARGET int NAME(ServoBank::LaneState& st, const ServoBank::LaneParams& pa, int substeps,      \
                  const BluColumns& ref, BluColumns& enc, RealColumns& table, int first, int n, \
                  int& quiet_run, int& bad_row, int& diverged) {                                \
    return lane_rows<N, L, M>(st, pa, substeps, ref, enc, table, first, n, quiet_run, bad_row,  \
                              diverged);                                                        \
  }
#if defined(__x86_64__)
GM_SERVO_KERNEL(lanes_avx512, __attribute__((target("avx512f,avx512dq,avx512vl"))))
GM_SERVO_KERNEL(lanes_avx2, __attribute__((target("avx2"))))
#endif
GM_SERVO_KERNEL(lanes_portable, )
#undef GM_SERVO_KERNEL

}  // namespace

ServoBank::ServoBank(const Machine& m, int axes, double period_s, int substeps)
    : count_(axes), substeps_(substeps), isa_(active_isa()) {
  axes_.reserve(static_cast<std::size_t>(axes));
  for (int a = 0; a < axes; ++a)
    axes_.emplace_back(m.axes[static_cast<std::size_t>(a)], period_s, substeps, 0);
  // Lanes when every axis is alike in structure: plant order 1 or 2, no Coulomb friction.
  order_ = axes_.empty() ? 0 : axes_[0].plant().order();
  bool alike = axes >= 1 && axes <= 8 && (order_ == 1 || order_ == 2);
  for (const ServoAxis& s : axes_)
    alike = alike && s.plant().order() == order_ && !(s.coulomb_drive() > 0.0);
  if (!alike) return;
  lanes_ = axes <= 4 ? 4 : 8;
  const int m_size = order_ + 1;
  for (int l = 0; l < 8; ++l) {
    const ServoAxis& s = axes_[static_cast<std::size_t>(l < axes ? l : 0)];
    const auto& ad = s.plant().ad();
    for (int j = 0; j < m_size; ++j)
      for (int i = 0; i < m_size; ++i) params_.a[j * m_size + i][l] = ad(i, j);
    for (int i = 0; i < m_size; ++i) params_.bd[i][l] = s.plant().bd()[i];
    params_.kp[l] = s.kp();
    params_.kvp[l] = s.kvp();
    params_.kvi[l] = s.kvi();
    params_.kv_period[l] = s.kv_period_s();
    params_.kv_over_h[l] = s.kv_over_h();
    params_.h_over_kv[l] = s.h_over_kv();
    params_.u_max[l] = s.drive_limit();
    params_.hb[l] = s.half_backlash_blu();
    params_.ip[l] = s.form() == VelocityLoopForm::Ip ? -1 : 0;
  }
  from_axes(state_);
}

void ServoBank::set_isa_for_testing(Isa isa) {
  isa_ = static_cast<int>(isa) < static_cast<int>(active_isa()) ? isa : active_isa();
}

void ServoBank::to_axes(const LaneState& s) {
  for (int a = 0; a < count_; ++a) {
    ServoAxis& x = axes_[static_cast<std::size_t>(a)];
    ServoAxis::Dynamic d = x.dynamic();
    for (int k = 0; k <= order_; ++k) d.z[k] = s.z[k][a];
    d.prev_count = s.prev_count[a];
    d.prev_ref = s.prev_ref[a];
    d.have_ref = have_ref_;
    d.integ = s.integ[a];
    d.u = s.u[a];
    d.table_rel = s.table_rel[a];
    x.set_dynamic(d);
  }
}

void ServoBank::from_axes(LaneState& s) const {
  for (int l = 0; l < 8; ++l) {
    const bool used = l < count_;
    const ServoAxis& x = axes_[static_cast<std::size_t>(used ? l : 0)];
    const ServoAxis::Dynamic d = x.dynamic();
    for (int k = 0; k <= order_; ++k) s.z[k][l] = used ? d.z[k] : 0.0;
    s.prev_count[l] = used ? d.prev_count : 0;
    s.prev_ref[l] = used ? d.prev_ref : 0;
    s.start[l] = used ? x.start_blu() : 0;
    s.integ[l] = used ? d.integ : 0.0;
    s.u[l] = used ? d.u : 0.0;
    s.table_rel[l] = used ? d.table_rel : 0.0;
  }
}

template <int N>
int ServoBank::step_axes(const BluColumns& ref, BluColumns& enc, RealColumns& table, int first,
                         int n) {
  for (int i = first; i < first + n; ++i) {
    bool quiet = true;
    for (int a = 0; a < N; ++a) {
      ServoAxis& s = axes_[static_cast<std::size_t>(a)];
      table.v[a][i] = s.table_blu();  // at the start of the period, the instant the count is read
      try {
        enc.v[a][i] = s.step(ref.v[a][i]);
      } catch (const InputError& e) {
        diverged_axis_ = a;
        divergence_ = e.what();
        return i - first;
      }
      quiet = quiet && std::llabs(enc.v[a][i] - ref.v[a][i]) <= 1;
    }
    quiet_run_ = quiet ? quiet_run_ + 1 : 0;
  }
  have_ref_ = true;
  return n;
}

template <int N>
int ServoBank::step_block(const BluColumns& ref, BluColumns& enc, RealColumns& table, int first,
                          int n) {
  if (lanes_ == 0 || N > 8) return step_axes<N>(ref, enc, table, first, n);
  if (!have_ref_ && n > 0) {  // ServoAxis::step's first call: the reference has no past yet
    for (int a = 0; a < N; ++a) state_.prev_ref[a] = ref.v[a][first];
    have_ref_ = true;
  }
  constexpr int kMaxN = N > 8 ? 8 : N;        // (N > 8 never reaches here)
  constexpr int kLanes = kMaxN <= 4 ? 4 : 8;  // = lanes_
  int done = 0;
  while (done < n) {
    int bad_row = -1, diverged = -1, rows = 0;
    const int at = first + done, left = n - done;
#define GM_SERVO_CALL(KERNEL, L, M)                                                             \
  rows = KERNEL<kMaxN, L, M>(state_, params_, substeps_, ref, enc, table, at, left, quiet_run_, \
                             bad_row, diverged)
#define GM_SERVO_BY_SHAPE(KERNEL)     \
  if (order_ == 1)                    \
    GM_SERVO_CALL(KERNEL, kLanes, 2); \
  else                                \
    GM_SERVO_CALL(KERNEL, kLanes, 3)
#if defined(__x86_64__)
    if (isa_ == Isa::Avx512) {
      GM_SERVO_BY_SHAPE(lanes_avx512);
    } else if (isa_ == Isa::Avx2) {
      GM_SERVO_BY_SHAPE(lanes_avx2);
    } else {
      GM_SERVO_BY_SHAPE(lanes_portable);
    }
#else
    GM_SERVO_BY_SHAPE(lanes_portable);
#endif
#undef GM_SERVO_BY_SHAPE
#undef GM_SERVO_CALL
    done += rows;
    if (diverged >= 0) {
      // The lanes stopped after the sample in which the axis diverged: ServoAxis's message.
      diverged_axis_ = diverged;
      divergence_ =
          ServoAxis::divergence_message(state_.z[order_][diverged], ref.v[diverged][first + done]);
      return done;
    }
    if (bad_row >= 0) {  // a sample the lanes cannot round exactly: ServoAxis runs it
      to_axes(state_);
      const int one = step_axes<kMaxN>(ref, enc, table, bad_row, 1);
      if (one == 0) return done;
      from_axes(state_);
      ++done;
    }
  }
  return n;
}

#define GM_SERVO_BANK_STEP(N)                                                   \
  template int ServoBank::step_block<N>(const BluColumns& ref, BluColumns& enc, \
                                        RealColumns& table, int first, int n);
GM_FOR_EACH_AXIS_COUNT(GM_SERVO_BANK_STEP)
#undef GM_SERVO_BANK_STEP

}  // namespace gm
