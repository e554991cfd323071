#pragma once
// Levenberg-Marquardt on |r(q) - g|^2 for an EquilibriumSystem: the baseline of the ANM paper's
// inverse-design comparison (the paper ran levmar), by Ceres' trust-region Levenberg-Marquardt
// with sparse normal Cholesky (SuiteSparse). A trial point with an inverted element is a rejected
// step. Converged when |r - g| <= relative_tolerance |g|.

#include <nlmech/models/equilibrium_system.h>

namespace nlmech
{
  struct LevenbergMarquardtSettings
  {
    double       relative_tolerance = 1e-9;
    unsigned int max_iterations     = 2000;
    double       max_seconds        = 1e9;  // wall-time cap (Ceres' solver time limit)
    double       initial_damping    = 1e-3; // 1 / Ceres' initial trust-region radius
  };

  struct LevenbergMarquardtResult
  {
    bool         converged      = false;
    bool         capped         = false; // stopped by the iteration or time cap
    unsigned int iterations     = 0;
    unsigned int factorizations = 0;
    double       residual       = 0; // relative
    double       seconds        = 0;
  };

  LevenbergMarquardtResult solve_with_levenberg_marquardt(const EquilibriumSystem &system,
                                                          const Eigen::VectorXd &load, Eigen::VectorXd &q,
                                                          const LevenbergMarquardtSettings &settings = {});
} // namespace nlmech
