#pragma once
// The baselines of the inverse-design comparison (ANM paper, section 6 and Table 2): Newton on the
// residual with adaptive load steps, and Levenberg-Marquardt from the paper's two initial guesses
// (the target shape; the equilibrium of the target taken as rest shape under the reversed load),
// capped in iterations and time. Each reports its figures into summary.json.

#include <nlmech/models/equilibrium_system.h>
#include <nlmech/models/model.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace nlmech
{
  class RunContext;

  struct InverseBaselineSettings
  {
    unsigned int             newton_load_steps = 5; // the first increment is 1 / this
    NewtonSettings           newton;
    std::vector<std::string> lm_initial_guesses = {"target", "reversed-load"};
    unsigned int             lm_max_iterations  = 2000;
    double                   lm_max_seconds     = 1800;

    /// Entries in the current subsection (the scene's "Solver").
    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(const dealii::ParameterHandler &prm);
  };

  /// What both baselines solve: r(X) = g for the rest shape X of the target x, to |R| <= tolerance |g|.
  struct InverseBaselineProblem
  {
    const EquilibriumSystem &system;
    const Eigen::VectorXd   &load;
    const Eigen::VectorXd   &target;
    double                   tolerance;
    /// The target as the rest shape of a forward problem (for the reversed-load initial guess).
    const Model       &forward_from_target;
    const AnmSettings &anm;
  };

  /// Newton from X = x; the rest shape, or an empty vector when it failed (then summary.json says
  /// why; when `required`, i.e. the only method, the failure is an error).
  Eigen::VectorXd inverse_newton_baseline(RunContext &context, const InverseBaselineSettings &settings,
                                          const InverseBaselineProblem &problem, bool required);

  /// Levenberg-Marquardt from each initial guess in turn; the rest shape from the first one. When
  /// `primary` (the first method) and that one did not converge, the run is marked partial.
  Eigen::VectorXd inverse_levenberg_marquardt_baseline(RunContext                    &context,
                                                       const InverseBaselineSettings &settings,
                                                       const InverseBaselineProblem &problem, bool primary);
} // namespace nlmech
