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
// The projection onto these cones is in solvers/socp/strain_projection.h.

#include <nlmech/mesh/gmsh_mesh.h>

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
  /// F d of row i at x: A_i x.
  Eigen::Vector3d stretch_image(const StrainLimits &limits, std::size_t i, const Eigen::VectorXd &x);

} // namespace nlmech
