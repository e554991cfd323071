#pragma once
// Static equilibrium by dynamic relaxation with kinetic damping (the baseline of the ANM paper's
// forward comparison, after Umetani et al. 2011): implicit Euler steps of M x'' = g - grad E(x),
// each solved by Newton, with all velocities reset whenever the kinetic energy passes a peak.
// Stops when |g - grad E| on the free unknowns falls below a relative tolerance.

#include <nlmech/models/model.h>

namespace nlmech
{
  struct KineticDampingSettings
  {
    double       relative_tolerance = 1e-9;
    unsigned int max_time_steps     = 5000;
    /// Time step [s]; 0 picks T/20 with T the period of the load's linear response (Rayleigh quotient).
    double time_step = 0;
  };

  struct KineticDampingResult
  {
    bool         converged         = false;
    unsigned int time_steps        = 0;
    unsigned int newton_iterations = 0;
    unsigned int factorizations    = 0;
    unsigned int velocity_resets   = 0;
    double       time_step         = 0;
    double       residual          = 0; // relative
    double       seconds           = 0;
  };

  /// `internal`: energy terms, lumped mass and fixed unknowns; `load`: g. Needs a positive mass.
  KineticDampingResult solve_with_kinetic_damping(const Model &internal, const Eigen::VectorXd &load,
                                                  Eigen::VectorXd              &x,
                                                  const KineticDampingSettings &settings = {});
} // namespace nlmech
