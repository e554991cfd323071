#pragma once
// Harmonic-balance design (thesis 2.4.1-2.4.8): design parameters p that change a structure's
// masses, stiffnesses and excitation; the sensitivity S = dz/dp = -(dh/dz)^-1 dh/dp of the periodic
// state (2.4.3) and first-order predictions z + S dp (2.4.4); objectives on the motion (the
// amplitude 2.4.8 and phase-free trajectory matching 2.4.6-2.4.7); and their gradient by the
// adjoint of (2.4.5), one transposed solve with the Jacobian's factorisation whatever the number
// of parameters.
//
// dh/dp is exact and comes from the code that computes h: the residual h = A(w) z - F[f] is linear
// in the lumped masses and in the sampled time-domain forces, so a parameter declares its change
// of the masses and of f(x, v, theta) at fixed motion (element forces by the elements' own forward
// AD, see models/scaled_energy.h), and dh/dp is A's mass part with that change minus the
// coefficients of the sampled force change.

#include <nlmech/solvers/hbm/harmonic_balance.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/lu_factorization.h>

#include <Eigen/Dense>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nlmech
{
  /// One scalar design parameter with its bounds.
  class DesignParameter
  {
  public:
    DesignParameter(std::string name, double lower, double upper);
    virtual ~DesignParameter() = default;

    const std::string &name() const { return label; }
    double             lower, upper;

    virtual double value() const = 0;
    /// Changes the structure the parameter was made for (its HarmonicBalance is rebuilt after).
    virtual void set(double p) = 0;
    /// d(lumped mass)/dp, full length (empty: the masses do not depend on p).
    virtual Eigen::VectorXd mass_change(std::size_t n_unknowns) const;
    /// Whether add_force_change does anything.
    virtual bool changes_force() const { return false; }
    /// df += df/dp at one sample at fixed motion, full length, for the time-domain force
    /// f(x, v, theta) = -grad E(x) - D_beta K(x) v + f_ext(theta) - drive penalties.
    virtual void add_force_change(const HarmonicBalance &hb, const Eigen::VectorXd &x,
                                  const Eigen::VectorXd &v, double theta, double omega,
                                  Eigen::VectorXd &df) const;

  private:
    std::string label;
  };

  /// dh/dp of one parameter at fixed (z, w): a column of dh/dp.
  Eigen::VectorXd parameter_derivative(const HarmonicBalance &hb, const DesignParameter &p,
                                       const Eigen::VectorXd &z, double omega);

  /// dh/dp d = sum_k d_k dh/dp_k for a direction d in parameter space, from one sampling of the state.
  Eigen::VectorXd
  directional_parameter_derivative(const HarmonicBalance                               &hb,
                                   const std::vector<std::shared_ptr<DesignParameter>> &parameters,
                                   const Eigen::VectorXd &direction, const Eigen::VectorXd &z, double omega);

  /// lambda^T dh/dp for every parameter from one sampling of the state: the adjoint's weights on
  /// the sampled forces (HarmonicBalance::adjoint_sample_weights) against each parameter's force
  /// change, and lambda against the mass part. No column of dh/dp is formed.
  Eigen::VectorXd adjoint_parameter_products(const HarmonicBalance                               &hb,
                                             const std::vector<std::shared_ptr<DesignParameter>> &parameters,
                                             const Eigen::VectorXd &z, double omega,
                                             const Eigen::VectorXd &lambda);

  /// An objective on one periodic state: its value and df/dz.
  class DesignObjective
  {
  public:
    virtual ~DesignObjective()                                    = default;
    virtual std::string name() const                              = 0;
    virtual double      evaluate(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega,
                                 Eigen::VectorXd *gradient) const = 0;
    /// df/dw at fixed z: only where the frequency is an unknown (a resonance peak's case).
    virtual double omega_derivative(const HarmonicBalance &, const Eigen::VectorXd &, double) const
    {
      return 0;
    }
  };

  /// (A_k(z) - A_target)^2 (2.4.8) with A_k the amplitude (2.3.14) of the chosen coordinates of a
  /// vertex (all three, or the axes chosen); a large target maximises the amplitude.
  class AmplitudeObjective : public DesignObjective
  {
  public:
    AmplitudeObjective(std::vector<std::size_t> dofs, double target);
    std::string name() const override { return "amplitude"; }
    double      evaluate(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega,
                         Eigen::VectorXd *gradient) const override;

  private:
    std::vector<std::size_t> dofs;
    double                   target;
  };

  /// Trajectory matching in frequency space (2.4.6) made phase-free by the smooth minimum (2.4.7)
  /// over N phase offsets of the target: f = sum_i d_i e^{-alpha d_i} / sum_i e^{-alpha d_i}, d_i the
  /// distance of harmonics 1..N_H to the target shifted by phi_i = 2 pi i / N. The mean position
  /// (harmonic 0) is left free, as in the thesis.
  class TrajectoryObjective : public DesignObjective
  {
  public:
    /// `samples` (coordinates x M): the target at M equally spaced times of one period, one row per
    /// coordinate in `dofs`. Its Fourier coefficients up to `harmonics` by the trapezoidal rule.
    /// `sharpness` sets alpha = sharpness / (target's squared size) (0: 50).
    TrajectoryObjective(std::vector<std::size_t> dofs, const Eigen::MatrixXd &samples, unsigned int harmonics,
                        unsigned int phases = 64, double sharpness = 0);
    std::string name() const override { return "trajectory"; }
    double      evaluate(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega,
                         Eigen::VectorXd *gradient) const override;
    /// The target's coefficients (s_k, c_k), k = 1..N_H, of coordinate j.
    const Eigen::MatrixXd &target_sine() const { return sine; }
    const Eigen::MatrixXd &target_cosine() const { return cosine; }

  private:
    std::vector<std::size_t> dofs;
    Eigen::MatrixXd          sine, cosine; // coordinates x harmonics (column k - 1)
    unsigned int             phases;
    double                   alpha;
  };

  /// (w* - w_target)^2 for the frequency w* of a resonance peak (a case with `peak` set): the
  /// peak placed at a target frequency.
  class PeakFrequencyObjective : public DesignObjective
  {
  public:
    explicit PeakFrequencyObjective(double target);
    std::string name() const override { return "peak frequency"; }
    double      evaluate(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega,
                         Eigen::VectorXd *gradient) const override;
    double omega_derivative(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega) const override;

  private:
    double target;
  };

  /// A driving frequency with its objectives (several frequencies: several cases).
  ///
  /// With `peak` set the case is a resonance peak instead: the state where the amplitude (2.3.14)
  /// of `peak_dofs` is largest over the frequency near `omega`, inside [omega_low, omega_high].
  /// `omega` then follows the peak: after every parameter change the peak is found again by a
  /// local frequency-response curve from the last one, uphill, refined to dA/ds = 0 exactly.
  /// The objectives' gradient is the adjoint of the peak's extended system
  ///   h(z, w, p) = 0,  h_z phi + h_w = 0,  grad A(z) . phi = 0     (phi = dz/dw on the curve),
  /// whose transposed solve needs three solves with dh/dz's factorisation and, when an objective
  /// depends on w* (or on another point's motion), the directional derivatives of dh/dz, dh/dw
  /// and dh/dp along the curve's tangent (phi, 1), by central differences of the exact ones.
  /// Without them (the peak's own amplitude) the envelope theorem holds: the fixed-w adjoint.
  struct DesignCase
  {
    double                                              omega = 0;
    std::vector<std::shared_ptr<const DesignObjective>> objectives;
    bool                                                peak      = false;
    double                                              omega_low = 0, omega_high = 0;
    std::vector<std::size_t>                            peak_dofs;
  };

  struct DesignSettings
  {
    PeriodicSolveSettings solve;
    /// Weight of the penalty sum_k ((p_k - p0_k) / (upper_k - lower_k))^2 on the parameter change.
    double change_penalty = 0;
    /// Parameter continuation when a re-solve from the last state fails: pseudo-arclength steps
    /// (at most this many) along the segment from the last solved parameters to the new ones.
    unsigned int continuation_steps = 200;
    /// Largest step of the local frequency-response curve that finds a peak again (scaled).
    double peak_search_step = 0.05;
  };

  /// The design problem: parameters, cases and their periodic states. `rebuild` makes the
  /// HarmonicBalance of the structure as the parameters left it (called after every change).
  class HarmonicDesign
  {
  public:
    using Rebuild = std::function<std::unique_ptr<HarmonicBalance>()>;

    /// `states`: a solved periodic state per case for the current parameters.
    HarmonicDesign(Rebuild rebuild, std::vector<std::shared_ptr<DesignParameter>> parameters,
                   std::vector<DesignCase> cases, std::vector<Eigen::VectorXd> states,
                   DesignSettings settings = {});

    std::size_t                                          n_parameters() const { return parameters.size(); }
    const std::vector<std::shared_ptr<DesignParameter>> &design_parameters() const { return parameters; }
    const std::vector<DesignCase>                       &design_cases() const { return cases; }
    Eigen::VectorXd                                      values() const;
    const Eigen::VectorXd                               &initial_values() const { return start; }
    const Eigen::VectorXd                               &state(std::size_t c) const { return states[c]; }
    /// Case c's frequency: its driving frequency, or its peak's frequency for the current design.
    double                 omega(std::size_t c) const { return cases[c].omega; }
    const HarmonicBalance &balance() const { return *hb; }

    /// Sets the parameters and re-solves every case from its last state; where that fails (a fold
    /// of the state over the parameters lies between), follows the solution curve of each case
    /// over the segment from the last solved parameters by pseudo-arclength continuation, around
    /// the folds, to the new ones. False, with the parameters and states of the last solved design
    /// restored and `why` set, when the curve cannot be followed there.
    bool update(const Eigen::VectorXd &p, std::string *why = nullptr);
    /// The parameter continuation of update alone (no direct re-solve first): every case's state
    /// followed from the current design to p. Same result contract as update.
    bool continue_to(const Eigen::VectorXd &p, std::string *why = nullptr);

    /// The objective at the current design: the cases' objectives plus the change penalty, with its
    /// gradient by the adjoint (one transposed solve per case).
    double objective(Eigen::VectorXd *gradient = nullptr);
    /// S = dz/dp of case c (n_z x n_p), one solve per parameter with one factorisation.
    Eigen::MatrixXd sensitivity(std::size_t c);

    /// The first-order prediction z + S (p - current) (2.4.4) of the state for the case whose
    /// factorisation is at hand (that of the last objective gradient or sensitivity, at its state
    /// and the current parameters); empty entries for the others and where there is none.
    std::vector<Eigen::VectorXd> predicted_states(const Eigen::VectorXd &p);

    /// Counters for the benchmark: HBM residual solves (Newton iterations) and gradients;
    /// updates that needed the parameter continuation, its steps, and updates that failed.
    unsigned int newton_iterations = 0, gradients = 0, failed_updates = 0;
    unsigned int continued_updates = 0, continuation_steps = 0, continuation_folds = 0;
    unsigned int peak_searches = 0, peak_search_points = 0;
    /// Re-solves started from the first-order prediction z + S dp (the gradient's factorisation
    /// at hand), and those of them that fell back to the last state.
    unsigned int predicted_starts = 0, failed_predictions = 0;
    std::string  last_failure; // why the last failed update failed
    double       gradient_seconds = 0, solve_seconds = 0;

  private:
    /// Re-solves every case for the current parameters, case c from predicted[c] when given
    /// (non-empty), else (or where that fails) from its last state.
    bool solve_all(std::string *why, const std::vector<Eigen::VectorXd> &predicted = {});
    /// Sets the parameters to p (no solve).
    void apply(const Eigen::VectorXd &p);
    /// Case c from its state at parameters `from` (solved) to `to` by pseudo-arclength continuation
    /// in t along p(t) = from + t (to - from) (design_continuation.cc); the parameters are left at
    /// `to` and states[c] set on success.
    bool continue_case(std::size_t c, const Eigen::VectorXd &from, const Eigen::VectorXd &to,
                       std::string *why);
    /// A peak case's peak for the current parameters, from its state (solved at its last peak
    /// frequency): sets omega and the state (design_peak.cc).
    bool locate_peak(std::size_t c, std::string *why);
    /// d(objectives of peak case c)/dp by the adjoint of the peak's extended system; df_dz and
    /// df_dw the objectives' derivatives at the peak, `lu` factorised at it (design_peak.cc).
    Eigen::VectorXd peak_gradient(std::size_t c, const Eigen::VectorXd &df_dz, double df_dw);

    Rebuild                                       rebuild;
    std::vector<std::shared_ptr<DesignParameter>> parameters;
    std::vector<DesignCase>                       cases;
    std::vector<Eigen::VectorXd>                  states;
    DesignSettings                                settings;
    std::unique_ptr<HarmonicBalance>              hb;
    Eigen::VectorXd                               start;
    LuFactorization                               lu;
    /// What `lu` was factorised at: case, its state and the parameters (case -1: nothing).
    long            factorized_case = -1;
    Eigen::VectorXd factorized_state, factorized_parameters;
  };

  /// The optimiser's record of one accepted iterate.
  struct DesignIterate
  {
    unsigned int    iteration = 0;
    double          objective = 0, gradient_norm = 0, seconds = 0;
    Eigen::VectorXd parameters;
  };

  struct OptimizationSettings
  {
    unsigned int max_iterations     = 200;  // objective evaluations
    double       relative_tolerance = 1e-8; // on the objective
    double       time_limit         = 0;    // [s]; 0: none
    /// Called after every evaluation (progress).
    std::function<void(const DesignIterate &)> progress;
  };

  struct OptimizationResult
  {
    bool          converged = false; // NLopt stopped on its tolerance (not on a limit or failure)
    std::string   stop_reason;
    DesignIterate best;
    std::vector<DesignIterate> history;
    unsigned int               evaluations = 0;
  };

  /// Bound-constrained L-BFGS (NLopt's LD_LBFGS, the low-storage BFGS of Nocedal and Liu with box
  /// constraints) on the design objective with its adjoint gradient. Every evaluation re-solves
  /// the states (HarmonicDesign::update); a design whose state cannot be found gets an infinite
  /// objective, so the line search steps back. The best design found is left set in `design`
  /// whatever made the optimiser stop.
  OptimizationResult optimize_design(HarmonicDesign &design, const OptimizationSettings &settings = {});
} // namespace nlmech
