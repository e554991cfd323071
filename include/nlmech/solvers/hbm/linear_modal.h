#pragma once
// Linear modal analysis (LMA), the reference the thesis compares HBM against (section 2.5.1,
// Fig. 2.5): the equations of motion linearised about a static state x_s,
//   M u'' + D u' + K u = F e^{i w t},  K = Hessian of E at x_s, D = D_alpha M + D_beta K,
// solved by superposition of the undamped modes K phi = w_k^2 M phi (dense generalised symmetric
// eigenproblem, Eigen's GeneralizedSelfAdjointEigenSolver), each mode damped by
// D_alpha + D_beta w_k^2. Harmonic forces enter with amplitude and phase, exactly driven unknowns
// through the coupling -(1 + i w D_beta) K_fd U_d, penalty drives through their spring. Only the
// first harmonic of a drive is linear, so higher ones are ignored.

#include <nlmech/solvers/hbm/harmonic_balance.h>

#include <Eigen/Dense>

#include <complex>

namespace nlmech
{
  struct LinearModes
  {
    Eigen::VectorXd frequencies;  // w_k [rad/s], ascending
    Eigen::MatrixXd shapes;       // free x modes, M-orthonormal
    Eigen::VectorXd static_state; // full-length x_s
  };

  /// All modes of the free unknowns of `hb` about the static state x_s (full length). Dense: for up
  /// to a few thousand free unknowns. Throws if K is not positive definite on them (an unstable or
  /// unconstrained static state).
  LinearModes linear_modes(const HarmonicBalance &hb, const Eigen::VectorXd &static_state);

  /// Complex amplitudes U of the free unknowns, u(t) = Re(U e^{i w t}), at frequency w, from the
  /// lowest `n_modes` modes (0: all; all modes give the exact linear response).
  Eigen::VectorXcd linear_modal_response(const HarmonicBalance &hb, const LinearModes &modes, double omega,
                                         unsigned int n_modes = 0);

  /// The HBM measures of a linear response: amplitude (2.3.14, integral of |v| over a period) of a
  /// group of unknowns (free indices), and the half range of one free unknown (|U_i|).
  double linear_amplitude(const Eigen::VectorXcd &U, double omega,
                          const std::vector<std::size_t> &free_indices);
} // namespace nlmech
