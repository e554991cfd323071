#pragma once
// Backbone curves: the undamped, unforced periodic solutions of a structure by amplitude (the
// nonlinear normal modes a user of NLvib computes with its NMA). For a harmonic-balance system
// without damping and forcing, the unknowns are the coefficients z and the frequency w; the phase
// is fixed by setting the first sine coefficient of a reference unknown to zero and the amplitude
// by its first cosine coefficient. The system h(z, w) = 0 then has one equation more than unknowns,
// and one of them is redundant (the autonomous system's phase invariance), so it is solved by
// Gauss-Newton, converging quadratically to a zero residual; the amplitude is continued from the
// linear mode, each solution predicting the next.

#include <nlmech/solvers/hbm/harmonic_balance.h>

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace nlmech
{
  struct BackbonePoint
  {
    double          amplitude  = 0; // first cosine coefficient of the reference unknown
    double          omega      = 0; // [rad/s]
    double          residual   = 0; // |h|_inf relative to the inertial force scale
    unsigned int    iterations = 0;
    bool            converged  = false;
    Eigen::VectorXd z;
  };

  struct BackboneSettings
  {
    std::size_t  reference      = 0; // free index of the unknown whose amplitude is prescribed
    unsigned int mode           = 1; // the linear mode the curve starts from (1: lowest)
    double       tolerance      = 1e-10;
    unsigned int max_iterations = 30;
    unsigned int substeps       = 4; // continuation steps between two requested amplitudes
  };

  /// The backbone at the requested amplitudes (ascending from the smallest), from the linear mode
  /// of `hb`'s model about `static_state`. `hb` must have no forcing, drives or damping. The curve
  /// stops at the first amplitude that does not converge (the remaining points are not returned).
  std::vector<BackbonePoint> trace_backbone(const HarmonicBalance &hb, const Eigen::VectorXd &static_state,
                                            const std::vector<double> &amplitudes,
                                            const BackboneSettings    &settings,
                                            std::string               *stop_reason = nullptr);
} // namespace nlmech
