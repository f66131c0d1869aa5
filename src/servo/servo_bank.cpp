// ServoBank: ServoAxis's sample, the axes in SIMD lanes, one kernel per instruction set.
#include "servo/servo_bank.hpp"

#include "common/status.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>

namespace gm {

namespace {

// One native vector of W doubles (SSE2: 2, AVX2 and AVX-512: 4; 8, a zmm, was slower on this
// AMD EPYC, see step_block). More axes take several such pieces, stepped side by side: a generic
// vector wider than the hardware's had its selects lowered lane by lane (7x slower).
template <int W>
struct LaneTypes;
template <>
struct LaneTypes<2> {
  typedef double V __attribute__((vector_size(16)));
  typedef std::int64_t I __attribute__((vector_size(16)));
};
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

// Counts and references are carried as doubles in the lanes: integers of magnitude below 2^51
// are exact, and so are their differences, so every lane computes what ServoAxis computes from
// its int64 counts; x86 has no int64 <-> double conversion before AVX-512DQ, and on AVX2 and
// SSE2 the compiler's scalar conversions sat in the middle of the dependency chain. A lane
// whose position or reference leaves that range runs its row in ServoAxis instead.
constexpr double kExactBlu = 2251799813685248.0;  // 2^51 (> ServoAxis::kMaxPositionBlu)

#define GM_INLINE __attribute__((always_inline)) inline
// |x| of a vector x of type V (its integer twin I): the sign bits cleared. A macro: a function
// returning a vector would cross a call boundary without the kernel's instruction set (psabi).
#define GM_ABS(x) ((V)((I)(x) & (I{} + 0x7fffffffffffffff)))

// W lanes (lanes o .. o+W-1 of LaneState/LaneParams) of one sample: the state as vectors (in
// registers) and the parameters. Everything by reference: no vector crosses a call (the kernel
// is one inlined function per instruction set).
template <int W, int M>
struct Lanes {
  using V = typename LaneTypes<W>::V;
  using I = typename LaneTypes<W>::I;

  struct State {
    V z[M], integ, u, table_rel, prev_count, prev_ref, prev_delta;
  };
  State s;  // what a sample changes (saved before a row, to take it back)
  V a[M * M], bd[M];
  V kp, kvp, kvi, kv_period, kv_over_h, h_over_kv, u_max, hb, ff1, ff2;
  I ip;

  template <typename T, typename S>
  static GM_INLINE void load(T& v, const S* p) {
    std::memcpy(&v, p, sizeof v);
  }
  template <typename T, typename S>
  static GM_INLINE void store(S* p, const T& v) {
    std::memcpy(p, &v, sizeof v);
  }

  GM_INLINE void load_state(const ServoBank::LaneState& from, int o) {
    for (int k = 0; k < M; ++k) load(s.z[k], from.z[k] + o);
    load(s.integ, from.integ + o);
    load(s.u, from.u + o);
    load(s.table_rel, from.table_rel + o);
    load(s.prev_count, from.prev_count + o);
    load(s.prev_ref, from.prev_ref + o);
    load(s.prev_delta, from.prev_delta + o);
  }
  GM_INLINE void store_state(ServoBank::LaneState& to, int o) const {
    for (int k = 0; k < M; ++k) store(to.z[k] + o, s.z[k]);
    store(to.integ + o, s.integ);
    store(to.u + o, s.u);
    store(to.table_rel + o, s.table_rel);
    store(to.prev_count + o, s.prev_count);
    store(to.prev_ref + o, s.prev_ref);
    store(to.prev_delta + o, s.prev_delta);
  }
  GM_INLINE void load_params(const ServoBank::LaneParams& p, int o) {
    for (int k = 0; k < M * M; ++k) load(a[k], p.a[k] + o);
    for (int k = 0; k < M; ++k) load(bd[k], p.bd[k] + o);
    load(kp, p.kp + o);
    load(kvp, p.kvp + o);
    load(kvi, p.kvi + o);
    load(kv_period, p.kv_period + o);
    load(kv_over_h, p.kv_over_h + o);
    load(h_over_kv, p.h_over_kv + o);
    load(u_max, p.u_max + o);
    load(hb, p.hb + o);
    load(ff1, p.ff1 + o);
    load(ff2, p.ff2 + o);
    load(ip, p.ip + o);
  }

  // m ? a : b lane by lane for a mask m of all-ones / all-zeros lanes, in bit operations: SSE2
  // has no 64-bit integer compare for the vector select's m != 0.
  static GM_INLINE void sel(V& out, const I& m, const V& a, const V& b) {
    out = (V)(((I)a & m) | ((I)b & ~m));
  }

  // Whether any lane of the mask is set.
  static GM_INLINE bool any(const I& m) {
    std::int64_t l[W];
    std::memcpy(l, &m, sizeof l);
    std::int64_t o = 0;
    for (int k = 0; k < W; ++k) o |= l[k];
    return o != 0;
  }

  // round_half_away (common/rounding.hpp) as a double, for lanes with |x| < 2^51; the others
  // (and NaN) are marked in `bad`: their row then runs in ServoAxis. With a = |x|,
  // (a + 2^52) - 2^52 is a rounded to the nearest integer, ties to even; a tie rounded down
  // (a - r = 0.5) goes up instead, which is ties away from zero. The sign comes back as 0 - r,
  // not -r, so a count of zero is +0.0 like ServoAxis's static_cast<double>(int64 0).
  static GM_INLINE void round(const V& x, V& out, I& bad) {
    const V a = GM_ABS(x);
    bad |= ~(a < kExactBlu);
    const V big = V{} + 4503599627370496.0;  // 2^52
    V r = (a + big) - big;
    r = a - r == 0.5 ? r + 1.0 : r;
    out = x < 0.0 ? 0.0 - r : r;
  }

  // ServoAxis::servo_sample, lane by lane in its order.
  GM_INLINE void sample(const V& count, const V& pos_ref, const V& ff) {
    const V y = (count - s.prev_count) * kv_over_h;
    s.prev_count = count;
    const V vref = kp * (pos_ref - count);
    const V r_v = vref * kv_period + ff;
    const V e = r_v - y;
    const V di = e * h_over_kv;
    V in = s.integ + di;
    const V u_ip = kvi * in - kvp * y;
    const V u_pi = kvp * e + kvi * in;
    V uu;
    sel(uu, ip, u_ip, u_pi);
    const I over = uu > u_max, under = uu < -u_max;
    const I keep = (over & (di > 0.0)) | (under & (di < 0.0));  // conditional integration
    sel(in, keep, s.integ, in);
    uu = uu > u_max ? u_max : uu < -u_max ? -u_max : uu;  // std::clamp when saturated
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

// Rows first.. of the block with the lanes, N axes in pieces of W lanes; stops before a row in
// which a lane left the exact range (`bad_row` = that row, the state as before it) or diverged
// (`diverged` = its lane, rows done before it returned). Returns the rows done.
template <int N, int W, int M>
GM_INLINE int lane_rows(ServoBank::LaneState& st, const ServoBank::LaneParams& pa, int substeps,
                        const BluColumns& ref, BluColumns& enc, RealColumns& table, int first,
                        int n, int& quiet_run, int& bad_row, int& diverged) {
  using K = Lanes<W, M>;
  using V = typename K::V;
  using I = typename K::I;
  constexpr int P = (N + W - 1) / W;  // pieces
  constexpr int L = P * W;            // lanes
  static_assert(L <= ServoBank::kMaxLanes);
  K k[P];
  for (int q = 0; q < P; ++q) {
    k[q].load_params(pa, q * W);
    k[q].load_state(st, q * W);
  }
  const V sub = V{} + static_cast<double>(substeps);
  int done = 0;
  for (int i = first; i < first + n; ++i, ++done) {
    typename K::State before[P];
    for (int q = 0; q < P; ++q) before[q] = k[q].s;
    // The row's references, a lane each (unused lanes stay at 0, at rest).
    double r[L] = {};
    for (int a = 0; a < N; ++a) r[a] = static_cast<double>(ref.v[a][i]);
    V refd[P], delta[P], ff[P], count0[P], count[P];
    double tab[L];
    I bad = I{} + 0;
    for (int q = 0; q < P; ++q) {
      std::memcpy(&refd[q], r + q * W, sizeof(V));
      // A reference at 2^51 or beyond converts to a double at 2^51 or beyond (2^51 is one).
      bad |= ~(GM_ABS(refd[q]) < kExactBlu);
      // The table position at the start of the period (ServoAxis::table_blu(): start 0 + rel).
      const V table_now = V{} + k[q].s.table_rel;
      std::memcpy(tab + q * W, &table_now, sizeof(V));
      K::round(k[q].s.z[M - 1], count0[q], bad);
      delta[q] = refd[q] - k[q].s.prev_ref;  // exact: both below 2^51, as ref - prev_ref in int64
      // Feedforward (ServoAxis::step): delta - prev_delta is exact too (both below 2^52).
      ff[q] = k[q].ff1 * delta[q] + k[q].ff2 * (delta[q] - k[q].s.prev_delta);
      k[q].sample(count0[q], refd[q], ff[q]);
    }
    for (int a = 0; a < N; ++a) table.v[a][i] = tab[a];
    for (int j = 1; j < substeps; ++j)
      for (int q = 0; q < P; ++q) {
        K::round(k[q].s.z[M - 1], count[q], bad);
        k[q].sample(count[q], refd[q] + delta[q] * static_cast<double>(j) / sub, ff[q]);
      }
    // The row's tests as lane masks, one reduction each (unused lanes are at rest: 0 in all).
    I far = I{} + 0, loud = I{} + 0;
    for (int q = 0; q < P; ++q) {
      k[q].s.prev_ref = refd[q];
      k[q].s.prev_delta = delta[q];
      far |= ~(GM_ABS(k[q].s.z[M - 1]) < ServoAxis::kMaxPositionBlu);  // NaN too
      loud |= ~(GM_ABS(count0[q] - refd[q]) <= 1.0);                   // exact: both below 2^51
    }
    if (K::any(bad)) {
      for (int q = 0; q < P; ++q) k[q].s = before[q];
      bad_row = i;
      break;
    }
    if (K::any(far)) {  // ServoAxis throws for the first axis in this row that diverged
      double pos[L];
      for (int q = 0; q < P; ++q) std::memcpy(pos + q * W, &k[q].s.z[M - 1], sizeof(V));
      for (int a = 0; a < N; ++a)
        if (!(std::fabs(pos[a]) < ServoAxis::kMaxPositionBlu)) {
          diverged = a;
          for (int q2 = 0; q2 < P; ++q2) k[q2].store_state(st, q2 * W);
          return done;
        }
    }
    double c0[L];
    for (int q = 0; q < P; ++q) std::memcpy(c0 + q * W, &count0[q], sizeof(V));
    for (int a = 0; a < N; ++a) enc.v[a][i] = static_cast<std::int64_t>(c0[a]);
    quiet_run = K::any(loud) ? 0 : quiet_run + 1;  // |enc - ref| <= 1 on every axis
  }
  for (int q = 0; q < P; ++q) k[q].store_state(st, q * W);
  return done;
}

// One kernel per instruction set: the whole row loop is inside the attributed function.
#define GM_SERVO_KERNEL(NAME, TARGET)                                                           \
  template <int N, int W, int M>                                                                \
  TARGET int NAME(ServoBank::LaneState& st, const ServoBank::LaneParams& pa, int substeps,      \
                  const BluColumns& ref, BluColumns& enc, RealColumns& table, int first, int n, \
                  int& quiet_run, int& bad_row, int& diverged) {                                \
    return lane_rows<N, W, M>(st, pa, substeps, ref, enc, table, first, n, quiet_run, bad_row,  \
                              diverged);                                                        \
  }
#if defined(__x86_64__)
GM_SERVO_KERNEL(lanes_avx512, __attribute__((target("avx512f,avx512dq,avx512vl"))))
GM_SERVO_KERNEL(lanes_avx2, __attribute__((target("avx2"))))
#endif
GM_SERVO_KERNEL(lanes_portable, )
#undef GM_SERVO_KERNEL

// The lanes' rounding alone, for the test of its ties (which servo runs almost never hit).
#define GM_ROUND_KERNEL(NAME, TARGET, W)                              \
  TARGET void NAME(const double* x, double* out, std::int64_t* bad) { \
    using K = Lanes<W, 2>;                                            \
    typename K::V v, r;                                               \
    typename K::I b = typename K::I{} + 0;                            \
    std::memcpy(&v, x, sizeof v);                                     \
    K::round(v, r, b);                                                \
    std::memcpy(out, &r, sizeof r);                                   \
    std::memcpy(bad, &b, sizeof b);                                   \
  }
#if defined(__x86_64__)
GM_ROUND_KERNEL(round_avx512, __attribute__((target("avx512f,avx512dq,avx512vl"))), 4)
GM_ROUND_KERNEL(round_avx2, __attribute__((target("avx2"))), 4)
#endif
GM_ROUND_KERNEL(round_portable, , 2)
#undef GM_ROUND_KERNEL

}  // namespace

ServoBank::ServoBank(const Machine& m, int axes, double period_s, int substeps)
    : count_(axes), substeps_(substeps), isa_(active_isa()) {
  axes_.reserve(static_cast<std::size_t>(axes));
  for (int a = 0; a < axes; ++a)
    axes_.emplace_back(m.axes[static_cast<std::size_t>(a)], period_s, substeps, 0);
  // Lanes when every axis is alike in structure: plant order 1 or 2, no Coulomb friction.
  order_ = axes_.empty() ? 0 : axes_[0].plant().order();
  bool alike = axes >= 1 && axes <= kMaxLanes && (order_ == 1 || order_ == 2);
  for (const ServoAxis& s : axes_)
    alike = alike && s.plant().order() == order_ && !(s.coulomb_drive() > 0.0) && !s.has_modes() &&
            !s.table_encoder();
  if (!alike) return;
  lanes_ = 1;
  const int m_size = order_ + 1;
  for (int l = 0; l < kMaxLanes; ++l) {
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
    params_.ff1[l] = s.ff1_gain();
    params_.ff2[l] = s.ff2_gain();
    params_.ip[l] = s.form() == VelocityLoopForm::Ip ? -1 : 0;
  }
  from_axes(state_);
}

int ServoBank::round_for_testing(Isa isa, const double* x, double* out, std::int64_t* bad) {
#if defined(__x86_64__)
  if (isa == Isa::Avx512 && active_isa() == Isa::Avx512) {
    round_avx512(x, out, bad);
    return 4;
  }
  if (isa != Isa::Portable && active_isa() != Isa::Portable) {
    round_avx2(x, out, bad);
    return 4;
  }
#endif
  (void)isa;
  round_portable(x, out, bad);
  return 2;
}

void ServoBank::set_isa_for_testing(Isa isa) {
  isa_ = static_cast<int>(isa) < static_cast<int>(active_isa()) ? isa : active_isa();
}

void ServoBank::to_axes(const LaneState& s) {
  for (int a = 0; a < count_; ++a) {
    ServoAxis& x = axes_[static_cast<std::size_t>(a)];
    ServoAxis::Dynamic d = x.dynamic();
    for (int k = 0; k <= order_; ++k) d.z[k] = s.z[k][a];
    d.prev_count = static_cast<std::int64_t>(s.prev_count[a]);
    d.prev_ref = static_cast<std::int64_t>(s.prev_ref[a]);
    d.prev_delta = static_cast<std::int64_t>(s.prev_delta[a]);
    d.have_ref = have_ref_;
    d.integ = s.integ[a];
    d.u = s.u[a];
    d.table_rel = s.table_rel[a];
    x.set_dynamic(d);
  }
}

void ServoBank::from_axes(LaneState& s) const {
  for (int l = 0; l < kMaxLanes; ++l) {
    const bool used = l < count_;
    const ServoAxis& x = axes_[static_cast<std::size_t>(used ? l : 0)];
    const ServoAxis::Dynamic d = x.dynamic();
    for (int k = 0; k <= order_; ++k) s.z[k][l] = used ? d.z[k] : 0.0;
    s.prev_count[l] = used ? static_cast<double>(d.prev_count) : 0.0;
    s.prev_ref[l] = used ? static_cast<double>(d.prev_ref) : 0.0;
    s.prev_delta[l] = used ? static_cast<double>(d.prev_delta) : 0.0;
    s.integ[l] = used ? d.integ : 0.0;
    s.u[l] = used ? d.u : 0.0;
    s.table_rel[l] = used ? d.table_rel : 0.0;
  }
}

template <int N>
int ServoBank::step_axes(const BluColumns& ref, BluColumns& enc, RealColumns& table, int first,
                         int n, RealColumns* deflection) {
  for (int i = first; i < first + n; ++i) {
    bool quiet = true;
    for (int a = 0; a < N; ++a) {
      ServoAxis& s = axes_[static_cast<std::size_t>(a)];
      table.v[a][i] = s.table_blu();  // at the start of the period, the instant the count is read
      if (deflection != nullptr) deflection->v[a][i] = s.deflection_blu();
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
                          int n, RealColumns* deflection) {
  if (lanes_ == 0) return step_axes<N>(ref, enc, table, first, n, deflection);
  if (!have_ref_ && n > 0) {  // ServoAxis::step's first call: the reference has no past yet
    // (Converted like every reference; a first reference of 2^51 or more makes that row run
    // in ServoAxis, which then finds prev_ref inexact: the range check below turns the lanes off.)
    for (int a = 0; a < N; ++a) state_.prev_ref[a] = static_cast<double>(ref.v[a][first]);
    have_ref_ = true;
  }
  // Vector width W per instruction set. AVX-512 steps 4-lane (ymm, AVX-512VL) vectors too:
  // measured on an AMD EPYC (256-bit datapath), 8-lane zmm ran 6 axes at 15 M samples/s and
  // 9 at 7.7, two or three ymm at 31 and 24.
  constexpr int kW512 = 4;
  int done = 0;
  while (done < n) {
    int bad_row = -1, diverged = -1, rows = 0;
    const int at = first + done, left = n - done;
#define GM_SERVO_CALL(KERNEL, W, M)                                                         \
  rows = KERNEL<N, W, M>(state_, params_, substeps_, ref, enc, table, at, left, quiet_run_, \
                         bad_row, diverged)
#define GM_SERVO_BY_SHAPE(KERNEL, W) \
  if (order_ == 1)                   \
    GM_SERVO_CALL(KERNEL, W, 2);     \
  else                               \
    GM_SERVO_CALL(KERNEL, W, 3)
#if defined(__x86_64__)
    if (isa_ == Isa::Avx512) {
      GM_SERVO_BY_SHAPE(lanes_avx512, kW512);
    } else if (isa_ == Isa::Avx2) {
      GM_SERVO_BY_SHAPE(lanes_avx2, 4);
    } else {
      GM_SERVO_BY_SHAPE(lanes_portable, 2);
    }
#else
    GM_SERVO_BY_SHAPE(lanes_portable, 2);
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
      const int one = step_axes<N>(ref, enc, table, bad_row, 1, deflection);
      if (one == 0) return done;
      ++done;
      // The lanes carry counts as doubles, exact below 2^51: if this row left a count or a
      // reference beyond that, the axes stay in ServoAxis from now on (a loop this far out has
      // all but diverged; the next rows are theirs).
      bool exact = true;
      for (const ServoAxis& x : axes_) {
        const ServoAxis::Dynamic d = x.dynamic();
        exact = exact && std::llabs(d.prev_count) < static_cast<std::int64_t>(kExactBlu) &&
                std::llabs(d.prev_ref) < static_cast<std::int64_t>(kExactBlu);
      }
      if (!exact) {
        lanes_ = 0;
        return done + step_axes<N>(ref, enc, table, first + done, n - done, deflection);
      }
      from_axes(state_);
    }
  }
  return n;
}

#define GM_SERVO_BANK_STEP(N)                                                   \
  template int ServoBank::step_block<N>(const BluColumns& ref, BluColumns& enc, \
                                        RealColumns& table, int first, int n,   \
                                        RealColumns* deflection);
GM_FOR_EACH_AXIS_COUNT(GM_SERVO_BANK_STEP)
#undef GM_SERVO_BANK_STEP

}  // namespace gm
