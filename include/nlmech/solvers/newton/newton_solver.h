#pragma once
// Energy minimisation by Newton's method with a backtracking (Armijo) line search, on any Model.
// The Hessian of the free unknowns is factorised by CHOLMOD (supernodal Cholesky); where it is not
// positive definite a diagonal shift is added, starting from a tenth of the last one that worked
// (so a run of indefinite Hessians does not pay for the whole search each time; the shift falls
// back to zero as the Hessian turns definite near a stable minimum), or its element blocks are
// projected to positive semi-definite first (NewtonSettings::project_element_hessians). Steps are
// capped by the Model's safe step.

#include <nlmech/models/model.h>

#include <Eigen/Core>

#include <functional>

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
    /// Levenberg-Marquardt-like damping of near-null directions: when the safe step (a collision
    /// bound) cuts two steps in a row below half, the next shift starts ten times higher (it still
    /// falls by ten per unhindered iteration). Without it, a Hessian that is singular along free motions
    /// (slack elements in contact problems) gives huge steps that the collision bound cuts to crawling.
    bool grow_shift_on_short_steps = false;
    /// Where the exact Hessian is not positive definite, use the one with every element block
    /// projected to positive semi-definite (Model::projected_hessian) instead of shifting it by a
    /// multiple of the identity. For problems with many locally non-convex elements (a wrinkling
    /// sheet under compression), where one global shift large enough for the worst element damps
    /// all the others too and Newton crawls. The exact Hessian is tried first in every iteration,
    /// so convergence near a stable minimum stays quadratic; the shift remains as a fallback.
    bool project_element_hessians = false;
    /// Per-unknown weights of the diagonal shift (empty: identity). Unknowns of different kinds
    /// (lengths, angles, strains) need a shift in consistent units: the squared length of motion a
    /// unit change of each causes.
    Eigen::VectorXd shift_metric;
    /// Called with every accepted state (for checks and monitoring).
    std::function<void(const Eigen::VectorXd &)> on_accepted;
    /// An additional convergence test after every accepted step, given the state and the free
    /// gradient's norm now and at the start (for example on the quantities of interest of a
    /// problem with near-null motions that keep drifting; empty: none).
    std::function<bool(const Eigen::VectorXd &x, double gradient_norm, double initial_gradient_norm)>
        converged;
  };

  struct NewtonResult
  {
    unsigned int iterations     = 0;
    unsigned int factorizations = 0;
    double       gradient_norm  = 0;
    double       energy         = 0;
  };

  /// Minimises the Model's energy from x (fixed unknowns are set first). Throws a clear error when
  /// it does not converge.
  NewtonResult minimize_with_newton(const Model &model, Eigen::VectorXd &x,
                                    const NewtonSettings &settings = {});
} // namespace nlmech
