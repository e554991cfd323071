#pragma once
// The Asymptotic Numerical Method for static equilibrium, grad E(x) = lambda g (ANM paper, sections
// 4 and 5.3). From a solution (x0, lambda0), (x, lambda) are expanded as power series in a path
// parameter a up to order n; every order solves with the one factorisation of the tangent at the
// series origin, the right-hand sides coming from Taylor-mode arithmetic on the energy terms
// (Model::gradient_series_coefficient). The step ends where the series stops being reliable
// (paper eqs. 19-20), or before any element would invert (first root of det F(a)); a few Newton
// corrections follow; lambda = target is landed on exactly by root finding on lambda(a).

#include <deal.II/base/parameter_handler.h>
#include <nlmech/models/equilibrium_system.h>

#include <nlmech/models/model.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <memory>
#include <string>
#include <vector>

namespace nlmech
{
  struct AnmSettings
  {
    unsigned int order              = 20;   // truncation order n
    double       series_tolerance   = 1e-6; // r of eq. (19)
    double       residual_tolerance = 1e-9; // at lambda = target: |R_free| <= tol * |g_free|
    double       path_tolerance     = 1e-6; // on the way there: corrections only above this
    unsigned int max_corrections    = 4;
    unsigned int max_steps          = 200;
    double       min_step           = 1e-12; // a step shorter than this counts as a collapse
    bool         pade               = false; // Pade approximants where they reach further than the series

    /// ANM order, Series tolerance, Residual tolerance, Path tolerance, Pade approximants, in the
    /// current subsection.
    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

  struct AnmStepRecord
  {
    double       step_length   = 0; // a at the end of the step
    double       series_radius = 0; // a_r of eq. (20)
    double       lambda_begin = 0, lambda_end = 0;
    unsigned int corrections          = 0;
    double       residual             = 0; // |R_free| / |g_free| after the corrections
    bool         limited_by_inversion = false;
    double       pade_radius          = 0; // how far the Pade approximants were trusted (0: not used)
    bool         used_pade            = false;
  };

  struct AnmResult
  {
    bool                       completed      = false;
    double                     lambda         = 0;
    double                     extreme_lambda = 0; // largest lambda met along the path (a limit load)
    std::string                stop_reason;
    std::vector<AnmStepRecord> steps;
    unsigned int               factorizations = 0, back_substitutions = 0;
    double series_seconds = 0, factorization_seconds = 0, solve_seconds = 0, total_seconds = 0;
  };

  /// Newton with line search at increasing load factors (the baseline): fixed steps i / n_steps
  /// for energies, adaptive ones for equilibrium systems.
  struct LoadSteppingResult
  {
    unsigned int iterations = 0, factorizations = 0;
    unsigned int load_steps = 0, rejected_steps = 0; // accepted and cut-back load increments
    double       smallest_increment = 1;             // of the accepted load increments
    double       seconds            = 0;
  };

  /// One ANM series (x(a), lambda(a)) = sum_k a^k (x_k, lambda_k) around a known solution, with the
  /// radius a_r of eq. (20) within which it is trusted.
  struct AnmSeries
  {
    std::vector<Eigen::VectorXd> x;      // full-length coefficients, x[0] the origin
    std::vector<Eigen::VectorXd> free_x; // the same on the free unknowns
    std::vector<double>          lambda; // lambda[0] the origin's load factor
    double                       radius = 0;

    Eigen::VectorXd state(double a) const;
    double          load_factor(double a) const;
    /// The a nearest to 0 with lambda(a) = target inside [-radius, radius]; NaN if there is none
    /// (then a new continuation is needed). Paper section 5.1: a load-scale change is a polynomial
    /// root and a series evaluation.
    double parameter_for(double target) const;
  };

  /// Paper section 5.2: one rest shape for several targets. U gathers the series coefficients
  /// X_{t,0..n} of every target's solution; the rest shape is U q with q minimising
  /// sum_t |U q - X_t|^2 (a small dense least-squares solve, Householder QR). Since every X_t = X_{t,0}
  /// is a column of U, the minimiser is the mean of the X_t; computing it through U keeps the
  /// paper's formulation and checks that claim (see the test).
  Eigen::VectorXd reduced_basis_rest_shape(const std::vector<AnmSeries> &series_at_solutions);

  class SparseFactorization;
  class FreeDofMap;

  class AnmSolver
  {
  public:
    /// `system`: r(q) and its tangent; `load`: g (a full-length vector).
    AnmSolver(const EquilibriumSystem &system, const Eigen::VectorXd &load, const AnmSettings &settings);
    /// Forward statics of a Model; steps stop short of the first state its terms call invalid
    /// along the series (an inverted hyperelastic element).
    AnmSolver(const Model &internal, const Eigen::VectorXd &load, const AnmSettings &settings);

    /// Follows the branch from (x, lambda_start) to lambda_target; x is updated. Never throws for a
    /// branch that cannot be followed: the result says how far it got and why it stopped.
    AnmResult solve(Eigen::VectorXd &x, double lambda_start = 0, double lambda_target = 1) const;

    /// The series at a known solution (x, lambda), e.g. at lambda = 1 after solve(), for fast
    /// load-scale changes (section 5.1).
    AnmSeries series_at(const Eigen::VectorXd &x, double lambda) const;

  private:
    AnmSeries expand(const Eigen::VectorXd &x, double lambda, double direction,
                     const Eigen::VectorXd &previous_x1, double previous_lambda1,
                     SparseFactorization &factorization, const FreeDofMap &free, const Eigen::VectorXd &g,
                     double &series_seconds) const;

    std::shared_ptr<const EquilibriumSystem> owned;
    const EquilibriumSystem                 &system;
    Eigen::VectorXd                          load;
    AnmSettings                              settings;
  };

  /// Newton with backtracking on |R| for r(q) = g (works for non-symmetric tangents), load stepped
  /// adaptively: increments from 1 / n_steps, halved after a failed step (down to 1/1024 of that,
  /// then it throws) and doubled after one that took at most four iterations; each step starts from
  /// the tangent predictor. `newton` gives the iteration and line-search limits per load step.
  LoadSteppingResult solve_equilibrium_with_newton(const EquilibriumSystem &system,
                                                   const Eigen::VectorXd &load, Eigen::VectorXd &q,
                                                   unsigned int n_steps, double relative_tolerance = 1e-9,
                                                   const NewtonSettings &newton = {});

  /// Newton on the energy (newton_solver.h), load stepped; `newton` gives the iteration limits,
  /// the tolerance is |g_free| <= relative_tolerance |load_free| at every step.
  LoadSteppingResult solve_with_load_stepping(const Model &internal, const Eigen::VectorXd &load,
                                              Eigen::VectorXd &x, unsigned int n_steps,
                                              double                relative_tolerance = 1e-9,
                                              const NewtonSettings &newton             = {});
} // namespace nlmech
