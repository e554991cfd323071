#pragma once
// The projection (SOCP paper eq. 5) min 1/2 |x - x_hat|_M^2 subject to every stretch limit of a
// sheet (pinned unknowns fixed), by the interior-point ConicQPSolver with screening and cutting
// planes; a per-constraint Gauss-Seidel projection is the baseline.

#include <nlmech/models/cloth/strain_limits.h>
#include <nlmech/solvers/socp/conic_qp.h>

#include <Eigen/Dense>

#include <limits>
#include <map>
#include <vector>

namespace nlmech
{
  struct ProjectionResult
  {
    ConicStatus  status     = ConicStatus::numerical_error;
    unsigned int iterations = 0; // interior-point iterations, summed over the screening rounds
    unsigned int rounds     = 0; // screening rounds (cone problems solved)
    std::size_t  cones      = 0; // limits in the last cone problem
    std::size_t  cuts_added = 0; // cutting planes added in this projection
    /// Largest excess over the limit curve, relative to the requested strain (<= the curve
    /// tolerance when the projection holds the curve; NaN when not computed).
    double curve_excess = std::numeric_limits<double>::quiet_NaN();
    double seconds = 0, violation = 0, distance = 0; // distance |x - x_hat|_M
  };

  /// The SOCP projection with a solver (and its symbolic analysis) kept across calls.
  ///
  /// Screening (exact): the cone problem holds only the limits that the candidate comes within
  /// `screening` of (|A x_hat| >= screening b) or that were active in the previous projection, and
  /// only the unknowns they touch (the objective is separable: every other unknown stays at
  /// x_hat). After a solve every limit is checked; any that is violated or within 0.1 % of its bound
  /// is added and the problem solved again. A point that meets every limit and solves the reduced
  /// problem solves the full one (the left-out limits have zero multipliers), so the result is the
  /// projection itself. Once a quarter of the limits are in, the full problem is solved instead
  /// (its symbolic analysis is then kept). `screening` = 0 keeps every limit (the full problem,
  /// one round).
  ///
  /// The curve between the samples (cutting planes): after the rows hold, every triangle whose
  /// stretch exceeds b(alpha) by more than curve_tolerance (b - 1) in some direction gets a row in
  /// that direction, and the projection is solved again, until none does (at most
  /// `max_cuts_per_triangle` cuts each, past which the oldest cut of the triangle moves to the new
  /// direction; the cuts are kept for later projections).
  class StrainLimitProjector
  {
  public:
    /// `mass` per unknown (3 per vertex); `fixed` unknowns keep their values in every projection.
    /// The projector keeps its own copy of the limits, to which it adds the cuts.
    StrainLimitProjector(const StrainLimits &limits, const Eigen::VectorXd &mass,
                         const std::map<std::size_t, double> &fixed, ConicSettings settings = {},
                         double screening = 0.98);
    /// x = argmin 1/2 |x - x_hat|_M^2 subject to every limit (x_hat's fixed unknowns are ignored).
    ProjectionResult project(const Eigen::VectorXd &x_hat, Eigen::VectorXd &x);
    /// The cone problem of one projection (for comparisons with other solvers).
    ConicQP problem(const Eigen::VectorXd &x_hat) const;
    /// The cone problem of the limits marked in `include`, on the free unknowns they touch (listed
    /// in `unknowns`); the others are held at x_hat.
    ConicQP problem(const Eigen::VectorXd &x_hat, const std::vector<char> &include,
                    std::vector<std::size_t> &unknowns) const;
    /// Full-length x from the free unknowns.
    Eigen::VectorXd full(const Eigen::VectorXd &free_values) const;

    const ConicQPSolver &solver() const { return cone_solver; }
    /// The limits with the cuts added so far.
    const StrainLimits &current_limits() const { return limits; }

    static constexpr unsigned int max_cuts_per_triangle = 16;

  private:
    /// Adds cuts where the curve is exceeded at x; returns how many.
    std::size_t add_cuts(const Eigen::VectorXd &x, double &excess);

    StrainLimits              limits;
    std::vector<unsigned int> cuts_of_triangle;
    /// Per triangle its cut rows, oldest first: at the cap, the oldest is moved to the new direction.
    std::vector<std::vector<std::size_t>> cut_rows;
    std::vector<std::size_t>              row_order; // rows grouped by triangle (cones on the same columns)
    Eigen::VectorXd                       mass;
    std::map<std::size_t, double>         fixed;
    ConicSettings                         settings;
    std::vector<long>                     free_index;
    std::vector<std::size_t>              free_dofs;
    double                                mass_scale = 1, screening = 0.98;
    std::vector<char>                     previously_active;
    // Warm start (settings.warm_mu > 0): the last projection's correction x - x_hat and its cone
    // multipliers, 4 per limit (zero for limits left out of its cone problem).
    Eigen::VectorXd     previous_correction;
    std::vector<double> previous_z;
    ConicQPSolver       cone_solver;
  };

  struct GaussSeidelResult
  {
    bool         converged = false;
    unsigned int sweeps    = 0;
    double       seconds = 0, violation = 0;
  };

  /// The per-element baseline: sweeps over the limits projecting each violated one exactly (mass
  /// weighted, closed form: A M^-1 A^T is a multiple of I) until the largest relative violation is
  /// below `tolerance` or after `max_sweeps` sweeps or `max_seconds`.
  GaussSeidelResult gauss_seidel_projection(const StrainLimits &limits, const Eigen::VectorXd &mass,
                                            const std::map<std::size_t, double> &fixed, Eigen::VectorXd &x,
                                            double tolerance = 1e-6, unsigned int max_sweeps = 100000,
                                            double max_seconds = 1e300);
} // namespace nlmech
