#pragma once
// Macroscopic deformation tests on native-scale models (thesis section 4.3.2) and the strain-space
// sampling built on them (section 4.3.3).
//
// In-plane: a periodic cell in the principal frame of a direction theta, lattice vectors
// t = U tbar with U = I + eps_p d_p d_p^T + eps_o d_o d_o^T (zero shear, eq. 4.3.2). A test solves
// the target-strain problem (eq. 4.3.3) min 1/2 sum w_k (eps_k - target_k)^2 + E_coll(q, eps): for a
// target outside the feasible set its solution is the nearest feasible strain, a point on the
// boundary, so the solve stops at the limit instead of failing.
// Bending: a finite patch whose centres lie on z = A x^2 + B y^2 + C x y, in the principal frame
// of theta: (A, B, C) = A' (c^2, s^2, 2 c s) + B' (s^2, c^2, -2 c s), curvatures kappa_p = 2 A',
// kappa_o = 2 B' [1/mm]; gravity acts on the elements (eq. 4.3.4).
// Results are converted to Green strain E = sum_k 1/2 ((1 + eps_k)^2 - 1) d_k d_k^T, stored as
// (E_xx, E_yy, E_xy) (tensor components), and curvatures to (kappa_xx, kappa_yy, kappa_xy).

#include <nlmech/dim/patterns.h>
#include <nlmech/models/model.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace nlmech::dim
{
  struct NativeSolveSettings
  {
    ContactSettings contact;
    double          target_weight  = 1.0;  // w of the driven component [N mm]
    double          hold_weight    = 100.0; // w of a component held at a level [N mm]
    unsigned int    max_iterations = 400;
    double          step_tolerance = 1e-9; // mm and rad
    double          gravity        = 9.81e-3; // N/kg, so that m g z is in N mm with z in mm
  };

  /// The outcome of one macroscopic test: the principal values reached, in the principal frame.
  struct TestOutcome
  {
    double       principal = 0, orthogonal = 0; // strains eps_p, eps_o or curvatures kappa_p, kappa_o
    unsigned int iterations = 0;
    double       seconds = 0, smallest_gap = 0;
  };

  /// One direction's in-plane test on a periodic cell.
  class InPlaneTest
  {
  public:
    InPlaneTest(const Pattern &pattern, double theta, NativeSolveSettings settings);
    /// Drives (eps_p, eps_o) towards the targets with the given weights (0: free), from the rest
    /// state (or from the last solution with `continue_from_last`).
    TestOutcome solve(double target_p, double weight_p, double target_o, double weight_o,
                      bool continue_from_last = false);
    const RigidAssembly &assembly() const { return *cell.assembly; }
    const Eigen::VectorXd &state() const { return q; }
    double                 theta() const { return angle; }

  private:
    PlacedAssembly      cell;
    double              angle;
    NativeSolveSettings settings;
    Eigen::VectorXd     q;
  };

  /// One direction's bending test on a finite disk patch.
  class BendingTest
  {
  public:
    BendingTest(const Pattern &pattern, unsigned int n_elements, double theta, NativeSolveSettings settings);
    TestOutcome solve(double target_p, double weight_p, double target_o, double weight_o,
                      bool continue_from_last = false);
    const RigidAssembly &assembly() const { return *patch.assembly; }
    const Eigen::VectorXd &state() const { return q; }

  private:
    PlacedAssembly      patch;
    double              angle;
    NativeSolveSettings settings;
    Eigen::VectorXd     q;
    std::vector<Eigen::Vector3d> gravity_forces;
  };

  /// Green strain (E_xx, E_yy, E_xy) of principal stretches 1 + eps_p along theta and 1 + eps_o
  /// across it.
  Eigen::Vector3d green_strain(double theta, double eps_p, double eps_o);
  /// Curvature (kappa_xx, kappa_yy, kappa_xy) of principal curvatures kappa_p along theta, kappa_o
  /// across it.
  Eigen::Vector3d curvature_tensor(double theta, double kappa_p, double kappa_o);
  /// Green strain of a 2x2 deformation gradient F: 1/2 (F^T F - I) as (E_xx, E_yy, E_xy).
  Eigen::Vector3d green_strain(const Eigen::Matrix2d &F);
  /// Deformation gradient of a periodic cell from its current lattice vectors: F = [t1 t2][tbar1 tbar2]^-1.
  Eigen::Matrix2d cell_deformation_gradient(const Eigen::Vector2d &t1, const Eigen::Vector2d &t2,
                                            const Eigen::Vector2d &tbar1, const Eigen::Vector2d &tbar2);

  /// The directional Cauchy-like metric of thesis eq. 4.4.1, c = (eps_s - eps_c) / (1 + eps_c).
  double travel_metric(double eps_stretch, double eps_compress);
} // namespace nlmech::dim
