#pragma once
// What is done with a HarmonicBalance: periodic states at one frequency (SUNDIALS KINSOL with a
// sparse direct solve of the Jacobian 2.3.13), frequency-response curves by pseudo-arclength
// continuation (2.3.19) with adaptive steps through folds, resonance peaks (local maxima of the
// amplitude 2.3.14 along the curve, refined on the curve), stability by Hill's method (the Floquet
// exponents from the HBM Jacobian, any size; the monodromy matrix's Floquet multipliers as the
// time-domain cross-check for small models), and
// the time-domain reference (solvers/time/newmark.h). NLMECH_HBM_DEBUG=1 in the environment prints the
// continuation corrector's and the excitation ramp's residuals to stderr.

#include <nlmech/solvers/hbm/harmonic_balance.h>
#include <nlmech/solvers/time/newmark.h>

#include <complex>
#include <functional>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace nlmech
{
  struct PeriodicSolveSettings
  {
    double       relative_tolerance = 1e-10; // |h| <= tol * force scale
    unsigned int max_iterations     = 50;
  };

  struct PeriodicSolveResult
  {
    bool         converged  = false;
    unsigned int iterations = 0;
    double       residual   = 0; // |h|_inf / force scale
    std::string  message;
  };

  /// Force scale for relative tolerances: the largest of the forcing amplitudes, drive forces and
  /// the inertial force w^2 m |z|.
  double force_scale(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega);

  /// Round-off level of the residual: the elastic forces of positions |x| through stiffnesses k
  /// cancel to about eps k |x| (100 eps k_max |x|_inf). Thin, stiff structures reach it long before
  /// a relative tolerance on the (small) inertial forces.
  double residual_floor(const HarmonicBalance &hb, const Eigen::VectorXd &z);

  /// Newton (KINSOL, line search, Jacobian every iteration) for h(z, w) = 0 at fixed w, to the
  /// relative tolerance or the round-off floor.
  PeriodicSolveResult solve_periodic_state(const HarmonicBalance &hb, Eigen::VectorXd &z, double omega,
                                           const PeriodicSolveSettings &settings = {});

  /// solve_periodic_state, and where it fails from `z`, the same with the excitation ramped up from
  /// a tenth of its amplitude (steps adapted).
  PeriodicSolveResult solve_with_excitation_ramp(const HarmonicBalance &hb, Eigen::VectorXd &z, double omega,
                                                 const PeriodicSolveSettings &settings = {});

  struct FloquetResult
  {
    double max_multiplier = 0; // largest |mu|
    bool   stable         = false;
  };
  /// Floquet multipliers of the periodic solution: the monodromy matrix of the linearised
  /// equations over one period (classical RK4, at least `steps` steps and enough for the fastest
  /// eigenvalue of the linearised system, |lambda| dt <= 1), dense; for up to a few hundred
  /// free unknowns. Stable when every |mu| <= 1 + tolerance.
  FloquetResult floquet_stability(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega,
                                  unsigned int steps = 400, double tolerance = 1e-6);

  struct HillResult
  {
    bool         determined        = false; // every exponent within the radius converged
    bool         stable            = false; // max Re lambda T <= log(1 + tolerance)
    double       max_real_part     = 0;     // largest Re lambda found [1/s]
    double       max_multiplier    = 0;     // exp(max_real_part T), comparable with Floquet's |mu|
    unsigned int krylov_dimension  = 0;     // ARPACK's basis in the last attempt (the dimension if dense)
    unsigned int requested         = 0;     // eigenvalues ARPACK was asked for in the last attempt
    unsigned int operator_products = 0;     // solves with the Jacobian over all attempts
    unsigned int within_radius     = 0;     // eigenvalues found with |lambda| < w
    /// Converged Floquet exponents in the fundamental strip |Im lambda| <= w/2 within the radius.
    std::vector<std::complex<double>> exponents;
  };

  /// Hill's method: the Floquet exponents lambda of the periodic solution are eigenvalues of the
  /// quadratic problem (Delta_0 + lambda Delta_1 + lambda^2 Delta_2) u = 0 in the harmonic basis
  /// (Delta_0 the HBM Jacobian, HarmonicBalance::jacobian documents Delta_1 and Delta_2). Its
  /// first-order form is solved with shift-and-invert at 0 by ARPACK's implicitly restarted
  /// Arnoldi method, which needs only solves with the Jacobian (`solve_jacobian`: the
  /// continuation's factorisation; empty: it is factorised here): the eigenvalues nearest 0 come
  /// first, and the ones that decide stability lie there. Every eigenvalue within the radius w of 0
  /// must converge (ARPACK's relative residual 1e-12; `first_request` (0: 24) are requested first
  /// and twice as many until the smallest one returned lies outside the radius, the Krylov basis
  /// at most max_krylov_dimension; a problem that small is solved densely instead); those in the
  /// strip |Im| <= w/2 are the exponents (the
  /// truncation's spurious eigenvalues sit near |Im| = N_H w, outside). An exponent with a real part
  /// beyond about 0.87 w (a multiplier above e^5) is outside the radius and not seen. Stable when
  /// max Re lambda T <= log(1 + tolerance), as for the Floquet multipliers.
  HillResult
  hill_stability(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega,
                 const std::function<Eigen::VectorXd(const Eigen::VectorXd &)> &solve_jacobian = {},
                 double tolerance = 1e-6, unsigned int max_krylov_dimension = 400,
                 unsigned int first_request = 0);

  /// How the continuation decides stability. Hill's method reuses the continuation's factorisation
  /// and is the default at every size (on the three-link mechanism it classifies all 449 points as
  /// Floquet does, 10x faster); Floquet's monodromy (dense, explicit RK4, cost growing with n^3) is
  /// the time-domain cross-check for small models.
  enum class StabilityMethod
  {
    hill,
    floquet,
    none
  };

  struct ContinuationSettings
  {
    double                   omega_start = 0, omega_end = 0; // [rad/s]
    double                   initial_step = 0.01;            // scaled arclength
    double                   min_step = 1e-6, max_step = 0.1;
    unsigned int             max_points         = 2000;
    double                   relative_tolerance = 1e-9;
    double                   max_amplitude = 0; // stop beyond this (tracked dofs' half range) [m]; 0: none
    std::vector<std::size_t> tracked_dofs;      // amplitude (2.3.14) of these unknowns
    StabilityMethod          stability = StabilityMethod::hill;
    /// Stop once the curve has passed its first resonance peak (located exactly as every peak):
    /// the local search of a design's peak (design.h).
    bool stop_after_first_peak = false;
    /// Called after every point with (fraction of the frequency range done).
    std::function<void(double)> progress;

    /// "Frequency range", "Maximum step", "Maximum amplitude", "Tolerance", "Maximum points" and
    /// "Stability" in the current subsection.
    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(const dealii::ParameterHandler &prm);
  };

  struct ResponsePoint
  {
    double          omega = 0, amplitude = 0, half_range = 0;
    double          d_omega_ds     = 0;     // sign changes at folds
    bool            fold           = false; // this point is a fold (located exactly)
    int             stable         = -1;    // 1 stable, 0 unstable, -1 not computed or not determined
    double          max_multiplier = 0;     // Floquet: largest |mu|; Hill: exp(max Re lambda T)
    bool            hill           = false; // stability from Hill's method (else Floquet)
    unsigned int    iterations     = 0;
    Eigen::VectorXd z;
  };

  struct Resonance
  {
    double          omega = 0, amplitude = 0;
    Eigen::VectorXd z;
  };

  /// A turning point of the curve in the frequency (a saddle-node fold): dh/dz is singular there.
  struct TurningPoint
  {
    double          omega = 0, amplitude = 0;
    Eigen::VectorXd z;
  };

  struct FrequencyResponse
  {
    /// The curve's points in order; each fold is a point of its own (fold = true), located on the
    /// curve to the corrector's tolerance, as are the peaks.
    std::vector<ResponsePoint> points;
    std::vector<Resonance>     peaks;
    std::vector<TurningPoint>  folds;
    bool                       completed = false;
    std::string                stop_reason;
    unsigned int               factorizations = 0, rejected_steps = 0;
    unsigned int               residuals = 0, jacobians = 0;
    double residual_seconds = 0, jacobian_seconds = 0, factorization_seconds = 0, solve_seconds = 0,
           stability_seconds = 0, seconds = 0;
  };

  /// Traces the curve from a solution z at omega_start (solved first) towards omega_end.
  FrequencyResponse trace_frequency_response(const HarmonicBalance &hb, Eigen::VectorXd z,
                                             const ContinuationSettings &settings);

  struct HarmonicsChoice
  {
    unsigned int                                 n_harmonics = 0; // the first N_H that met the threshold
    bool                                         converged   = false;
    std::vector<std::pair<unsigned int, double>> changes; // (N_H, trajectory change from the previous N_H)
    Eigen::VectorXd                              z;       // the solution at the chosen N_H
  };

  /// The thesis's strategy for the number of harmonics (section 2.5.1): solve at frequency w with
  /// N_H = first, first + step, ... (each started from the previous solution) until the trajectory of
  /// the free unknowns over a period changes by less than `threshold` times its size (the largest
  /// peak-to-peak range), or N_H exceeds `last`. `settings.n_harmonics` is ignored; N_AFT follows
  /// N_H (4 N_H + 2) unless set.
  HarmonicsChoice choose_harmonics(const Model &model, const HarmonicBalanceSettings &settings,
                                   const std::vector<HarmonicForce> &forces,
                                   const std::vector<HarmonicDrive> &drives,
                                   const Eigen::VectorXd &static_state, double omega, double threshold = 1e-3,
                                   unsigned int first = 3, unsigned int last = 15, unsigned int step = 2);
} // namespace nlmech
