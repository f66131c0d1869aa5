// A servo loop's transfer function identified from its step response, and the zero-phase-error
// tracking taps that take its dynamics out of the command.
#pragma once

#include <vector>

namespace gm {

/// A closed loop from the reference to the table as a transfer function of the sample delay,
/// B(z)/A(z) = (Σ_k b_k z^{−k}) / (Σ_j a_j z^{−j}), a_0 = 1. Empty `a`: not identified.
struct LoopModel {
  std::vector<double> a, b;
};

/// The loop's B/A from its step response `step` (s_k: the table at period k after a unit step of
/// the reference at k = 0; a linear, time-invariant model such as servo_step_response's). Its
/// impulse response g_k = s_k − s_{k−1} satisfies Σ_j a_j·g_{k−j} = 0 for every k past deg B:
/// the least order n ≤ 12 whose recurrence, fitted in least squares over the first 2,048
/// samples, reproduces the whole step response within 10⁻⁹; then b_k = Σ_j a_j·g_{k−j}, k ≤ n.
/// Empty where no order up to 12 does (a loop with a delay line, a long velocity window).
LoopModel identify_loop(const std::vector<double>& step);

/// Zero-phase-error tracking taps (Tomizuka 1987, "Zero phase error tracking algorithm for
/// digital control"): F = A(z)·B̃(z)/B(1)², B̃ the taps of B after its delay d, reversed. The
/// loop then follows the command filtered by F as z^{−d}·B′(z)·B̃(z)/B(1)² (B′: B without its
/// delay): the autocorrelation of B′'s taps, symmetric (no phase error), Σ = 1, and finite, so
/// the loop settles exactly deg B′ + d samples after the command does. Every zero of B is
/// reversed, none cancelled (the classic design cancels those inside the unit circle with an
/// IIR part): F stays an FIR, of deg A + deg B′ + 1 taps, Σ F = A(1)/B(1) = 1. Empty where B(1)
/// vanishes.
std::vector<double> zpetc_weights(const LoopModel& loop);

}  // namespace gm
