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
    double          target_weight  = 1.0;   // w of the driven component [N mm]
    double          hold_weight    = 100.0; // w of a component held at a level [N mm]
    unsigned int    max_iterations = 400;
    double          step_tolerance = 1e-7; // mm and rad (projected Newton converges linearly at the end)
    /// A test also ends when the strains (curvatures) reached changed by at most this over the last
    /// 10 accepted steps while the forces are balanced to `force_tolerance` of the first gradient:
    /// slack elements can keep drifting along near-null motions (steps above step_tolerance, the
    /// gradient stalled at round-off) long after the limit itself has converged.
    double parameter_tolerance = 1e-7;
    double force_tolerance     = 1e-4;
    double gravity             = 9.81e-3; // N/kg, so that m g z is in N mm with z in mm
  };

  /// The outcome of one macroscopic test: the principal values reached, in the principal frame.
  struct TestOutcome
  {
    double       principal = 0, orthogonal = 0; // strains eps_p, eps_o or curvatures kappa_p, kappa_o
    unsigned int iterations = 0;
    double       seconds = 0, smallest_gap = 0;
    /// The state reached (in memory only: checkpoints keep the figures above, not the state).
    Eigen::VectorXd state;
  };

  /// One direction's in-plane test on a periodic cell.
  class InPlaneTest
  {
  public:
    InPlaneTest(const Pattern &pattern, double theta, NativeSolveSettings settings);
    /// Drives (eps_p, eps_o) towards the targets with the given weights (0: free), from the rest
    /// state (or from the last solution with `continue_from_last`).
    TestOutcome            solve(double target_p, double weight_p, double target_o, double weight_o,
                                 bool continue_from_last = false);
    const RigidAssembly   &assembly() const { return *cell.assembly; }
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
    TestOutcome            solve(double target_p, double weight_p, double target_o, double weight_o,
                                 bool continue_from_last = false);
    const RigidAssembly   &assembly() const { return *patch.assembly; }
    const Eigen::VectorXd &state() const { return q; }
    /// The generalised gravity force on a curvature parameter at rest, sum_b m_b g x_b'^2 with x_b'
    /// the centre's coordinate along the principal (or orthogonal, whichever is larger) direction
    /// [N mm per unit of A' = kappa / 2]: a driven curvature with weight w that meets no contact
    /// stops about 2 G / w short of its target, pulled back by gravity alone.
    double gravity_load() const;

  private:
    PlacedAssembly               patch;
    double                       angle;
    NativeSolveSettings          settings;
    Eigen::VectorXd              q;
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

#include <mpi.h>

namespace nlmech::dim
{
  /// The sampling protocol of section 4.3.3 for one material, per direction theta_i = i pi / n:
  /// phase 1 drives the principal component to +far and -far with the orthogonal one free (the
  /// uniaxial stretch / compression limits, or positive / negative bending); phase 2 holds the
  /// principal component at `levels` values evenly inside those limits and drives the orthogonal
  /// one to +far and -far. Every sample is the nearest feasible state to its target, a point on
  /// the boundary of the feasible set.
  struct SamplingPlan
  {
    unsigned int directions = 12;
    /// Directions of the bending test, when it needs fewer than the cheap in-plane one (0: as
    /// `directions`).
    unsigned int bending_directions = 0;
    unsigned int directions_of(const std::string &test) const
    {
      return test == "bending" && bending_directions > 0 ? bending_directions : directions;
    }
    unsigned int levels         = 3;
    double       far_strain     = 0.5; // |target| of a driven strain component [-]
    double       far_curvature  = 0.5; // |target| of a driven curvature [1/mm]
    unsigned int patch_elements = 19;  // disk patch of the bending tests
    bool         in_plane = true, bending = true;
    /// Only the phase-1 positive samples (uniaxial stretch / positive bending), no boundary: for
    /// validation runs against closed-form limits.
    bool positive_only = false;
    /// Stop after this many new samples (0: no limit), as if the run were killed: for tests of
    /// the checkpoint.
    unsigned int stop_after = 0;
    /// Describes everything the samples depend on (material, contact, plan). It is kept in the
    /// checkpoint directory; a checkpoint written for another description is refused.
    std::string fingerprint;
  };

  enum class SampleKind
  {
    positive, // principal driven to +far (stretch, positive curvature), orthogonal free
    negative, // principal driven to -far
    level_up, // principal held at a level, orthogonal driven to +far
    level_down
  };
  std::string to_string(SampleKind kind);

  struct Sample
  {
    std::string     test; // "in-plane" or "bending"
    unsigned int    direction = 0, level = 0;
    double          theta    = 0;
    SampleKind      kind     = SampleKind::positive;
    double          target_p = 0, target_o = 0;
    TestOutcome     outcome;
    Eigen::Vector3d point = Eigen::Vector3d::Zero(); // Green strain or curvature tensor components
    std::string     key() const;
  };

  /// Whether the sample's driven component (the principal one of a positive or negative sample,
  /// the orthogonal one of a level sample) got within `tolerance` (relative) of its far target:
  /// then the test found no limit in that direction, and the boundary there is the target, not a
  /// limit. The held or free component does not count.
  bool reached_far_target(const Sample &sample, double tolerance = 0.01);

  /// A hash of the code a sample's result depends on (element shapes, contact, the native solve),
  /// made at build time: checkpoints written by other code are recomputed, not reused.
  const char *code_version();

  /// What a (resumed) sampling run did with its checkpoint.
  struct SamplingStatistics
  {
    unsigned int resumed  = 0; // samples read from the checkpoint, verified
    unsigned int computed = 0; // samples solved in this run, on this rank
    unsigned int stale    = 0; // found but written by another code version: recomputed
    unsigned int damaged  = 0; // found but unreadable, edited (checksum) or invalid: recomputed
    /// The first sample that failed (its message), empty when all were solved. Then the returned
    /// samples are those finished (in the checkpoint), and the phases after it were not run.
    std::string failure;
  };

  /// Runs (or resumes) the sampling of one test ("in-plane" or "bending") over the communicator's
  /// ranks: the jobs of a phase are dealt out round-robin, and every finished sample is written at
  /// once (atomically) to `checkpoint_directory`, where a resumed run finds it and skips the job.
  /// Every sample file carries the code version and a checksum over it, its key and the plan's
  /// fingerprint; a sample that fails them (edited by hand, of an older build, a negative gap, a
  /// non-finite value) is recomputed, and a directory with samples but no plan.txt is refused.
  /// `statistics` (optional) counts what was resumed and recomputed. A sample that fails ends the
  /// sampling after its phase: with `statistics`, the finished samples are returned and the failure
  /// is reported there (the caller keeps them as a partial result); without, it throws.
  /// Returns all samples of the test, in job order, on every rank. `progress(done, total)` is
  /// called on each rank after each of its samples.
  std::vector<Sample>
  sample_strain_space(const Pattern &pattern, const std::string &test, const SamplingPlan &plan,
                      const NativeSolveSettings &settings, const std::string &checkpoint_directory,
                      MPI_Comm comm, const std::function<void(unsigned, unsigned, const Sample &)> &progress,
                      SamplingStatistics *statistics = nullptr);

  /// The weights the bending tests drive and hold curvatures with: the settings' ones, raised
  /// together (ratio kept) where gravity could otherwise hold a driven curvature back by more than
  /// about 1 % of the far curvature (2 G / w <= 0.005 far, G the largest BendingTest::gravity_load
  /// over the plan's directions; measured shortfalls are up to 1.5 x 2 G / w). Returns the factor
  /// applied (1: unchanged).
  double raise_bending_weights(const Pattern &pattern, const SamplingPlan &plan,
                               NativeSolveSettings &settings);

  /// Per direction: the uniaxial limits of phase 1 (principal and the orthogonal value reached).
  struct DirectionalLimits
  {
    double theta      = 0;
    double positive_p = 0, positive_o = 0, negative_p = 0, negative_o = 0;
    /// Whether the negative (compression, negative curvature) sample was taken (not with
    /// `Positive only`): without it, the negative figures and the travel c are not reported.
    bool negative_sampled = false;
  };
  std::vector<DirectionalLimits> directional_limits(const std::vector<Sample> &samples,
                                                    unsigned int               directions);

  /// The directional limits of both tests as CSV (`limits.csv`): one row per direction of either
  /// test, sorted by angle; where a test was not sampled at a row's angle (its directions are
  /// fewer, or it did not run: an empty vector) its fields are left empty.
  std::string limits_table(const std::vector<DirectionalLimits> &stretch,
                           const std::vector<DirectionalLimits> &bending);
} // namespace nlmech::dim
