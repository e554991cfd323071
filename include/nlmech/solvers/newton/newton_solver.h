#pragma once
// Energy minimisation by Newton's method with a backtracking (Armijo) line search, on any Model.
// The Hessian of the free unknowns is factorised by CHOLMOD (supernodal Cholesky). Two parts are
// strategies a client picks instead of flags:
//   - the regularisation, what is done where the Hessian is not positive definite: a diagonal
//     shift (DiagonalShift: starting from a tenth of the last shift that worked, optionally in a
//     metric and growing after collision-bounded steps), or element blocks projected to positive
//     semi-definite first (ProjectedElementHessians);
//   - the step bound, the largest fraction of a Newton step that may be taken (ModelSafeStep: the
//     Model's own bound, collisions and inversions).

#include <nlmech/models/model.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace nlmech
{
  struct NewtonSettings
  {
    double       relative_tolerance = 1e-10; // on |g_free| relative to the first iterate's
    double       absolute_tolerance = 1e-14; // on |g_free|
    unsigned int max_iterations     = 50;
    unsigned int max_line_search    = 40;
    /// Also converged when a full Newton step is accepted whose largest entry is at most this (0:
    /// off). Barrier problems need it: their gradient stalls at a round-off level set by the barrier's
    /// curvature, far above any useful absolute tolerance.
    double step_tolerance = 0;
    /// Also converged when |g_free| is at most this and fell by less than half in the last
    /// iteration (0: off): the round-off floor of a large model's gradient, which no further
    /// iteration lowers, reached below an accuracy the caller can accept.
    double stagnation_tolerance = 0;
    /// Called with every accepted state (for checks and monitoring).
    std::function<void(const Eigen::VectorXd &)> on_accepted;
    /// An additional convergence test after every accepted step, given the state and the free
    /// gradient's norm now and at the start (for example on the quantities of interest of a
    /// problem with near-null motions that keep drifting; empty: none).
    std::function<bool(const Eigen::VectorXd &x, double gradient_norm, double initial_gradient_norm)>
        converged;

    /// "Newton max iterations" and "Newton max line search" in the current subsection, with this
    /// struct's defaults (the tolerances are the scene's: one residual tolerance for every method
    /// it compares).
    static void declare_parameters(dealii::ParameterHandler &prm, const NewtonSettings &defaults);
    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(const dealii::ParameterHandler &prm);
  };

  struct NewtonResult
  {
    unsigned int iterations     = 0;
    unsigned int factorizations = 0;
    double       gradient_norm  = 0;
    double       energy         = 0;
  };

  /// The linear algebra of one Newton iteration as the regularisation sees it: the Hessian of the
  /// free unknowns (exact, or element-projected on request) and a Cholesky solve of H + shift W
  /// for the direction (the symbolic analysis is kept while the pattern does not change).
  class NewtonSystem
  {
  public:
    /// The exact free Hessian at the current state.
    const Eigen::SparseMatrix<double> &exact_hessian() const { return exact; }
    /// The free Hessian with every element block projected to positive semi-definite
    /// (Model::projected_hessian), assembled on the first call of an iteration.
    const Eigen::SparseMatrix<double> &projected_hessian();
    /// Largest absolute diagonal entry of the exact free Hessian (the scale of sensible shifts).
    double diagonal_scale() const { return diagonal; }
    /// Factorises H + shift W (W = diag(metric) over the free unknowns, identity when the metric is
    /// empty; the metric is indexed by all unknowns) and solves for the step. True when the
    /// factorisation exists and the step is a descent direction.
    bool   solve(const Eigen::SparseMatrix<double> &H, double shift, const Eigen::VectorXd &metric = {});
    double gradient_norm() const { return gradient.norm(); }
    double initial_gradient_norm() const { return initial_norm; }

  private:
    friend class NewtonSolver;
    const Model                *model = nullptr;
    const Eigen::VectorXd      *state = nullptr;
    std::vector<long>           free_index;
    std::vector<std::size_t>    free_dofs;
    Eigen::VectorXd             gradient, direction;
    Eigen::SparseMatrix<double> exact, projected;
    bool                        has_projected = false;
    double                      diagonal = 0, initial_norm = 0;
    unsigned int                factorizations = 0;
    struct Factorization;
    std::shared_ptr<Factorization> factorization;
    Eigen::SparseMatrix<double>    free_matrix(const Eigen::SparseMatrix<double> &H, double *scale) const;
  };

  /// What Newton does where the exact Hessian of the free unknowns is not positive definite.
  class HessianRegularization
  {
  public:
    enum class Outcome
    {
      direction, // NewtonSystem::solve succeeded last
      stationary // no regularisation gives descent at a numerically stationary point: converged
    };
    virtual ~HessianRegularization() = default;
    virtual std::string name() const = 0;
    /// Before the first iteration of a solve.
    virtual void start() {}
    /// Finds a descent direction by NewtonSystem::solve; throws where none can be found away from
    /// a stationary point.
    virtual Outcome find_direction(NewtonSystem &system) = 0;
    /// Whether the last direction came from a model stiffer than the energy (projected blocks):
    /// then accepted full steps are extended while the energy keeps falling.
    virtual bool model_stiffer_than_energy() const { return false; }
    /// The shift of the last direction (for monitoring).
    virtual double last_shift() const { return 0; }
    /// After each accepted step, with the fraction of the full step the step bound allowed.
    virtual void step_accepted(double /*bound*/) {}
  };

  /// A diagonal shift H + s W, s from a tenth of the last one that worked (so a run of indefinite
  /// Hessians does not pay for the whole search each time; s falls back to zero as the Hessian
  /// turns definite near a stable minimum), multiplied by ten until the factorisation exists.
  class DiagonalShift : public HessianRegularization
  {
  public:
    struct Settings
    {
      /// Per-unknown weights W of the shift (empty: identity). Unknowns of different kinds
      /// (lengths, angles, strains) need a shift in consistent units: the squared length of
      /// motion a unit change of each causes.
      Eigen::VectorXd metric;
      /// Levenberg-Marquardt-like damping of near-null directions: when the step bound cuts two
      /// steps in a row below half, the next shift starts ten times higher (it still falls
      /// by ten per unhindered iteration). Without it, a Hessian that is singular along free
      /// motions (slack elements in contact problems) gives huge steps that the collision bound
      /// cuts to crawling.
      bool grow_on_short_steps = false;
    };
    DiagonalShift() = default;
    explicit DiagonalShift(Settings settings)
        : settings(std::move(settings))
    {
    }
    std::string name() const override { return "diagonal shift"; }
    void        start() override;
    Outcome     find_direction(NewtonSystem &system) override;
    double      last_shift() const override { return shift; }
    void        step_accepted(double bound) override;

    /// Shifts H + s W from s0 up by tens until solve succeeds (s0 = 0 tries H itself first).
    Outcome shift_until_descent(NewtonSystem &system, const Eigen::SparseMatrix<double> &H, double s0);

  private:
    Settings     settings;
    double       shift = 0, previous = 0, floor = 0, scale = 0;
    unsigned int short_steps = 0;
  };

  /// The exact Hessian where it is positive definite (quadratic convergence near a stable
  /// minimum), else the one with every element block projected to positive semi-definite, shifted
  /// only if that is still singular. For problems with many locally non-convex elements (a wrinkling
  /// sheet under compression), where one global shift large enough for the worst element damps all
  /// the others too and Newton crawls.
  class ProjectedElementHessians : public HessianRegularization
  {
  public:
    std::string name() const override { return "projected element Hessians"; }
    Outcome     find_direction(NewtonSystem &system) override;
    bool        model_stiffer_than_energy() const override { return projected; }
    double      last_shift() const override { return projected ? fallback.last_shift() : 0.0; }

  private:
    DiagonalShift fallback;
    bool          projected = false;
  };

  /// The largest fraction of a Newton step that may be taken from x (1: the full step).
  class StepBound
  {
  public:
    virtual ~StepBound()                                             = default;
    virtual double largest_fraction(const Model &model, const Eigen::VectorXd &x,
                                    const Eigen::VectorXd &dx) const = 0;
  };

  /// The Model's own bound (Model::max_safe_step: collisions, inversions).
  class ModelSafeStep : public StepBound
  {
  public:
    double largest_fraction(const Model &model, const Eigen::VectorXd &x,
                            const Eigen::VectorXd &dx) const override
    {
      return model.max_safe_step(x, dx);
    }
  };

  /// Newton's method with a line search and the given strategies (default: a diagonal shift and
  /// the Model's safe step). Not for concurrent use: the strategies keep state across iterations.
  class NewtonSolver
  {
  public:
    explicit NewtonSolver(NewtonSettings                         settings       = {},
                          std::shared_ptr<HessianRegularization> regularization = nullptr,
                          std::shared_ptr<const StepBound>       step_bound     = nullptr);
    /// Minimises the Model's energy from x (fixed unknowns are set first). Throws a clear error
    /// when it does not converge.
    NewtonResult minimize(const Model &model, Eigen::VectorXd &x);

  private:
    NewtonSettings                         settings;
    std::shared_ptr<HessianRegularization> regularization;
    std::shared_ptr<const StepBound>       step_bound;
  };

  /// NewtonSolver(settings) with a diagonal shift and the Model's safe step.
  NewtonResult minimize_with_newton(const Model &model, Eigen::VectorXd &x,
                                    const NewtonSettings &settings = {});
} // namespace nlmech
