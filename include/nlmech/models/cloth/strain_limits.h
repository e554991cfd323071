#pragma once
// Direction-dependent stretch limits on triangle sheets (the SOCP paper, eqs. 1-5 and appendix A;
// thesis ch. 3). For a rest triangle with material coordinates X_k (2D, in the sheet's warp/weft
// frame) and deformed positions x_k, the deformation gradient F = [x_1 - x_0, x_2 - x_0] D_m^-1 is
// linear in x, and so is the deformed image of a material direction d(alpha) = (cos alpha, sin alpha):
//
//   F d = c_0 x_0 + c_1 x_1 + c_2 x_2,   (c_1, c_2) = D_m^-1 d,  c_0 = -(c_1 + c_2),
//
// i.e. F d = A x with A = [c_0 I, c_1 I, c_2 I]. A limit b(alpha) >= 1 on the stretch |F d| is the
// second-order cone |A x| <= b. Limits below 1 bound compression, which is not convex: rejected.
//
// The projection (eq. 5) min 1/2 |x - x_hat|_M^2 over all cones (pinned unknowns fixed) goes to
// the interior-point ConicQPSolver; a per-constraint Gauss-Seidel projection is the baseline.

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/solvers/socp/conic_qp.h>

#include <Eigen/Dense>

#include <array>
#include <functional>
#include <limits>
#include <map>
#include <vector>

namespace nlmech
{
  /// A square sheet of side `size` [m] in the xz-plane (y up), corner at the origin, n x n quads
  /// each cut into two triangles along alternating diagonals. Material axes: warp along x, weft
  /// along z. Vertex (i, j) (i along x, j along z) has index j (n + 1) + i.
  RawSimplexMesh<3> make_sheet_mesh(double size, unsigned int n);

  /// One stretch limit per (triangle, direction): |c_0 x_a + c_1 x_b + c_2 x_c| <= bound. The rows
  /// sample the limit curve b(alpha); `curve` and the triangles' D_m^-1 let the curve itself be
  /// checked between the samples and further rows (cutting planes) be added where it is exceeded.
  struct StrainLimits
  {
    std::vector<std::array<unsigned int, 3>> vertices;
    std::vector<std::array<double, 3>>       coefficients;
    std::vector<double>                      bound;
    std::vector<double>                      angle;    // alpha [rad], in the material frame
    std::vector<unsigned int>                triangle; // the row's triangle
    std::size_t                              size() const { return bound.size(); }

    /// Per triangle: its vertices and D_m^-1 (material frame).
    std::vector<std::array<unsigned int, 3>> triangles;
    std::vector<Eigen::Matrix2d>             dm_inverse;
    /// The limit curve b(alpha) the rows sample.
    std::function<double(double)> curve;
    /// The curve is held to this fraction of the requested strain b(alpha) - 1 between the samples
    /// (cutting planes in StrainLimitProjector); 0: the sampled rows only.
    double curve_tolerance = 0.1;
    /// b on a fine grid alpha_k = -pi/2 + k pi / n (k < n) and its smallest value.
    std::vector<double> grid_angle, grid_bound;
    double              smallest_bound = 1;
    /// Rows made from the sampled directions; rows after them are cuts.
    std::size_t sampled = 0;

    /// Appends a row |F d(alpha)| <= b(alpha) for `triangle`.
    void add(unsigned int triangle, double alpha);
    /// Moves row `row` (of the same triangle) to direction alpha.
    void move(std::size_t row, double alpha);
  };

  /// Samples the polar limit curve b(alpha) at `directions` angles alpha_j = -pi/2 + (j + 1/2)
  /// pi / directions in every triangle. Material coordinates: the rest positions' components along
  /// `warp` and `weft` (unit vectors in the sheet's plane). Throws for b < 1 (compression bounds are
  /// not convex) or a non-finite b anywhere on a grid of `grid` directions, not only at the samples.
  StrainLimits make_strain_limits(const RawSimplexMesh<3> &mesh, const std::array<double, 3> &warp,
                                  const std::array<double, 3> &weft, unsigned int directions,
                                  const std::function<double(double)> &limit, double curve_tolerance = 0.1,
                                  unsigned int grid = 360);

  /// Checks b(alpha) >= 1 and finite on `grid` directions over [-pi/2, pi/2); throws naming the first
  /// direction where it is not.
  void check_limit_curve(const std::function<double(double)> &limit, unsigned int grid = 3600);

  /// Where a triangle's stretch exceeds the curve: its direction of largest excess and the excess
  /// (|F d| - b) / (b - 1), relative to the requested strain.
  struct CurveExcess
  {
    unsigned int triangle = 0;
    double       alpha = 0, excess = 0, stretch = 0;
  };
  /// Every triangle whose excess somewhere exceeds `tolerance` (>= 0), with its worst direction
  /// (grid search refined by golden section). `worst` (optional) receives the largest excess of
  /// any triangle, also when it is below the tolerance (-infinity when no triangle reaches its
  /// smallest limit).
  std::vector<CurveExcess> curve_excesses(const StrainLimits &limits, const Eigen::VectorXd &x,
                                          double tolerance, double *worst = nullptr);
  /// The largest excess over all triangles and directions (<= 0 inside the curve).
  double max_curve_excess(const StrainLimits &limits, const Eigen::VectorXd &x);
  /// Per direction of the fine grid (limits.grid_angle): the largest stretch |F d| of any triangle.
  std::vector<double> largest_stretch_per_direction(const StrainLimits &limits, const Eigen::VectorXd &x);

  /// Largest relative violation max_i (|A_i x| - b_i) / b_i (<= 0 when every limit holds).
  double max_violation(const StrainLimits &limits, const Eigen::VectorXd &x);

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
