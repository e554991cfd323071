#pragma once
// Pseudo-arclength continuation of harmonic-balance solutions in the frequency (thesis 2.3.19) as
// its four parts: the predictor (the unit tangent of the bordered system), the corrector (chord
// Newton on the hyperplane through the prediction), step control (distance from the prediction,
// turning angle, corrector effort) and the refinement of resonance peaks on the curve.
// trace_frequency_response (periodic_solvers.h) runs it.

#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <chrono>

namespace nlmech
{
  class PseudoArclengthContinuation
  {
  public:
    PseudoArclengthContinuation(const HarmonicBalance &hb, const ContinuationSettings &settings);
    /// Solves at omega_start from z, then follows the curve towards omega_end.
    FrequencyResponse trace(Eigen::VectorXd z);

  private:
    /// A point of the path with its unit tangent (weighted norm), the border row of its bordered
    /// system and the amplitude slope dA/ds.
    struct PathPoint
    {
      Eigen::VectorXd z, tz, row_z;
      double          omega = 0, tomega = 0, amplitude = 0, dA_ds = 0, row_omega = 0, scale = 1;
      double          step       = 0; // the predictor step along tz that led to the next point
      unsigned int    iterations = 0;
    };

    // Predictor: the tangent at p with the sign of (row_z, row_omega), the previous tangent in the
    // weighted inner product; leaves the bordered factorisation at p in `at_current`.
    void tangent(PathPoint &p, const Eigen::VectorXd &row_z, double row_omega);
    // Corrector from the prediction from.z + ds from.tz on the hyperplane through it. `chord`
    // reuses `at_current` (the factorisation at `from`), refactorising when the iteration stalls.
    bool correct(const PathPoint &from, double ds, PathPoint &to, bool chord);
    // Step control: one predictor-corrector step of length ds, accepted when the corrected point
    // lies near the prediction and the curve turns by less than about 30 degrees.
    bool step(const PathPoint &current, double ds, PathPoint &next, double &distance);
    // The next step length after an accepted step.
    double next_step_length(const PathPoint &next, double ds, double distance) const;
    // The weight of z follows the size of the motion (never below the start's).
    void reweight(PathPoint &current);
    // Stability of a point (Hill from the bordered factorisation, or Floquet) and its record.
    void record(const PathPoint &p);
    // A root of dA/ds (fold = false) or of dw/ds (fold = true) between path[i] and path[i + 1],
    // located to the corrector's tolerance; false when the corrector fails on the way (`root` is
    // then the best point so far).
    bool refine_root(std::size_t i, bool fold, PathPoint &root);
    // Resonance peaks: dA/ds from + to - between path points, located exactly (refine_root).
    void refine_peaks();
    // Folds: dw/ds changes sign between path points; each located exactly and inserted into the
    // curve's points with its fold mark.
    void refine_folds();

    double norm(const Eigen::VectorXd &dz, double dw) const
    {
      return std::sqrt(wz * dz.squaredNorm() + ww * dw * dw);
    }
    Eigen::VectorXd             residual(const Eigen::VectorXd &z, double w);
    Eigen::SparseMatrix<double> jacobian(const Eigen::VectorXd &z, double w, Eigen::VectorXd &h_omega);

    const HarmonicBalance     &hb;
    const ContinuationSettings settings;
    PeriodicSolveSettings      fixed; // fixed-frequency solves at the ends
    double                     direction = 1;
    double                     z_ref = 1, z_ref_start = 1, w_ref = 1, wz = 1, ww = 1, floor = 0;
    // The bordered matrix of the last tangent, [J(y_i), h_w(y_i); r_i^T] with r_i = W t_{i-1},
    // and a second one for corrector refactorisations.
    SparseFactorization    at_current, work;
    std::vector<PathPoint> path;
    unsigned int           hill_request = 0; // eigenvalues asked of ARPACK at the last point
    FrequencyResponse      response;
  };
} // namespace nlmech
