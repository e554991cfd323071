#include <deal.II/base/exceptions.h>

#include <nlmech/models/cloth/strain_limits.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
  } // namespace

  RawSimplexMesh<3> make_sheet_mesh(const double size, const unsigned int n)
  {
    AssertThrow(n >= 1 && size > 0, dealii::ExcMessage("Sheet: needs a positive size and n >= 1."));
    RawSimplexMesh<3> mesh;
    for (unsigned int j = 0; j <= n; ++j)
      for (unsigned int i = 0; i <= n; ++i)
        mesh.vertices.emplace_back(size * i / n, 0.0, size * j / n);
    auto v = [&](unsigned int i, unsigned int j) { return j * (n + 1) + i; };
    for (unsigned int j = 0; j < n; ++j)
      for (unsigned int i = 0; i < n; ++i)
        {
          if ((i + j) % 2 == 0)
            {
              mesh.cells.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
              mesh.cells.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
            }
          else
            {
              mesh.cells.push_back({v(i, j), v(i + 1, j), v(i, j + 1)});
              mesh.cells.push_back({v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
            }
          mesh.cell_material.push_back(0), mesh.cell_material.push_back(0);
        }
    return mesh;
  }

  void check_limit_curve(const std::function<double(double)> &limit, const unsigned int grid)
  {
    for (unsigned int k = 0; k < grid; ++k)
      {
        const double alpha = -pi / 2 + k * pi / grid, b = limit(alpha);
        char         where[96];
        std::snprintf(where, sizeof where, "%.2f degrees (alpha = %.6g rad)", alpha * 180 / pi, alpha);
        AssertThrow(std::isfinite(b), dealii::ExcMessage("Strain limits: the limit at " + std::string(where) +
                                                         " is not finite."));
        AssertThrow(b >= 1,
                    dealii::ExcMessage(
                        "Strain limits: the stretch limit " + std::to_string(b) + " at " + where +
                        " is below 1 (checked on " + std::to_string(grid) +
                        " directions, not only the sampled ones). That bounds compression, |F d| >= b, "
                        "whose feasible set is not convex (the outside of an ellipsoid), so the "
                        "projection would lose its unique solution. Limits must be stretches b >= 1."));
      }
  }

  void StrainLimits::add(const unsigned int t, const double alpha)
  {
    const Eigen::Vector2d c = dm_inverse[t] * Eigen::Vector2d(std::cos(alpha), std::sin(alpha));
    vertices.push_back(triangles[t]);
    coefficients.push_back({{-(c[0] + c[1]), c[0], c[1]}});
    bound.push_back(curve(alpha));
    angle.push_back(alpha);
    triangle.push_back(t);
  }

  void StrainLimits::move(const std::size_t row, const double alpha)
  {
    const Eigen::Vector2d c = dm_inverse[triangle[row]] * Eigen::Vector2d(std::cos(alpha), std::sin(alpha));
    coefficients[row]       = {{-(c[0] + c[1]), c[0], c[1]}};
    bound[row]              = curve(alpha);
    angle[row]              = alpha;
  }

  StrainLimits make_strain_limits(const RawSimplexMesh<3> &mesh, const std::array<double, 3> &warp,
                                  const std::array<double, 3> &weft, const unsigned int directions,
                                  const std::function<double(double)> &limit, const double curve_tolerance,
                                  const unsigned int grid)
  {
    AssertThrow(directions >= 1, dealii::ExcMessage("Strain limits: at least one direction per triangle."));
    AssertThrow(curve_tolerance >= 0 && grid >= 8,
                dealii::ExcMessage("Strain limits: the curve tolerance must not be negative."));
    check_limit_curve(limit, std::max(grid, 3600u));
    StrainLimits limits;
    limits.curve           = limit;
    limits.curve_tolerance = curve_tolerance;
    limits.smallest_bound  = std::numeric_limits<double>::infinity();
    for (unsigned int k = 0; k < grid; ++k)
      {
        limits.grid_angle.push_back(-pi / 2 + k * pi / grid);
        limits.grid_bound.push_back(limit(limits.grid_angle.back()));
        limits.smallest_bound = std::min(limits.smallest_bound, limits.grid_bound.back());
      }
    std::vector<double> alpha(directions);
    for (unsigned int j = 0; j < directions; ++j)
      alpha[j] = -pi / 2 + (j + 0.5) * pi / directions;
    for (const auto &cell : mesh.cells)
      {
        // Material coordinates of the rest triangle and D_m = [X_1 - X_0, X_2 - X_0].
        double X[3][2];
        for (int k = 0; k < 3; ++k)
          {
            const auto &p = mesh.vertices[cell[k]];
            X[k][0]       = p[0] * warp[0] + p[1] * warp[1] + p[2] * warp[2];
            X[k][1]       = p[0] * weft[0] + p[1] * weft[1] + p[2] * weft[2];
          }
        Eigen::Matrix2d Dm;
        Dm << X[1][0] - X[0][0], X[2][0] - X[0][0], X[1][1] - X[0][1], X[2][1] - X[0][1];
        AssertThrow(std::abs(Dm.determinant()) > 1e-14 * Dm.squaredNorm(),
                    dealii::ExcMessage("Strain limits: a degenerate rest triangle in the material frame."));
        limits.triangles.push_back({{cell[0], cell[1], cell[2]}});
        limits.dm_inverse.push_back(Dm.inverse());
        for (unsigned int j = 0; j < directions; ++j)
          limits.add(unsigned(limits.triangles.size() - 1), alpha[j]);
      }
    limits.sampled = limits.size();
    return limits;
  }

  namespace
  {
    /// C = F^T F of a triangle at x (F = [x_1 - x_0, x_2 - x_0] D_m^-1, 3 x 2).
    Eigen::Matrix2d right_cauchy_green(const StrainLimits &limits, const std::size_t t,
                                       const Eigen::VectorXd &x)
    {
      const auto                 &v = limits.triangles[t];
      Eigen::Matrix<double, 3, 2> E;
      E.col(0)                            = x.segment<3>(3 * v[1]) - x.segment<3>(3 * v[0]);
      E.col(1)                            = x.segment<3>(3 * v[2]) - x.segment<3>(3 * v[0]);
      const Eigen::Matrix<double, 3, 2> F = E * limits.dm_inverse[t];
      return F.transpose() * F;
    }

    double stretch(const Eigen::Matrix2d &C, const double alpha)
    {
      const double c = std::cos(alpha), s = std::sin(alpha);
      return std::sqrt(std::max(0.0, C(0, 0) * c * c + 2 * C(0, 1) * c * s + C(1, 1) * s * s));
    }

    /// The requested strain b - 1, floored so that a limit of exactly 1 keeps a finite tolerance.
    double strain_scale(const double b)
    {
      return std::max(b - 1, 1e-4);
    }

    /// The largest singular value of F (square root of C's largest eigenvalue).
    double largest_stretch(const Eigen::Matrix2d &C)
    {
      const double mean = 0.5 * (C(0, 0) + C(1, 1)), half = 0.5 * (C(0, 0) - C(1, 1));
      return std::sqrt(std::max(0.0, mean + std::sqrt(half * half + C(0, 1) * C(0, 1))));
    }
  } // namespace

  std::vector<CurveExcess> curve_excesses(const StrainLimits &limits, const Eigen::VectorXd &x,
                                          const double tolerance, double *worst)
  {
    std::vector<CurveExcess> out;
    double                   largest = -std::numeric_limits<double>::infinity();
    const std::size_t        n       = limits.grid_angle.size();
    AssertThrow(n > 0 && limits.curve, dealii::ExcMessage("Strain limits: no limit curve to check."));
    const double b_min = limits.smallest_bound, s_min = strain_scale(b_min);
    for (std::size_t t = 0; t < limits.triangles.size(); ++t)
      {
        const Eigen::Matrix2d C     = right_cauchy_green(limits, t, x);
        const double          sigma = largest_stretch(C);
        // For |F d| >= 1 the excess (|F d| - b) / (b - 1) falls as b grows, so it is at most
        // (sigma - b_min) / (b_min - 1); for |F d| < 1 it is below -1. Skip the triangles that can
        // neither exceed the tolerance nor (when the largest excess is asked for) beat it.
        const double bound = std::max((sigma - b_min) / s_min, -1.0);
        if (bound <= (worst ? std::min(tolerance, largest) : tolerance))
          continue;
        auto        excess = [&](double a, double b) { return (stretch(C, a) - b) / strain_scale(b); };
        std::size_t best   = 0;
        double      top    = -std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < n; ++k)
          {
            const double e = excess(limits.grid_angle[k], limits.grid_bound[k]);
            if (e > top)
              top = e, best = k;
          }
        // Golden-section refinement between the neighbouring grid directions.
        const double h  = pi / double(n);
        double       lo = limits.grid_angle[best] - h, hi = limits.grid_angle[best] + h;
        const double g  = 0.5 * (std::sqrt(5.0) - 1);
        double       a1 = hi - g * (hi - lo), a2 = lo + g * (hi - lo);
        double       e1 = excess(a1, limits.curve(a1)), e2 = excess(a2, limits.curve(a2));
        for (int it = 0; it < 30 && hi - lo > 1e-9; ++it)
          if (e1 > e2)
            hi = a2, a2 = a1, e2 = e1, a1 = hi - g * (hi - lo), e1 = excess(a1, limits.curve(a1));
          else
            lo = a1, a1 = a2, e1 = e2, a2 = lo + g * (hi - lo), e2 = excess(a2, limits.curve(a2));
        double alpha = e1 > e2 ? a1 : a2, e = std::max(e1, e2);
        if (top > e)
          alpha = limits.grid_angle[best], e = top;
        // Directions are defined modulo pi.
        alpha   = std::remainder(alpha, pi);
        largest = std::max(largest, e);
        if (e > tolerance)
          out.push_back({unsigned(t), alpha, e, stretch(C, alpha)});
      }
    if (worst)
      *worst = largest;
    return out;
  }

  double max_curve_excess(const StrainLimits &limits, const Eigen::VectorXd &x)
  {
    double worst = 0;
    curve_excesses(limits, x, std::numeric_limits<double>::infinity(), &worst);
    return worst;
  }

  std::vector<double> largest_stretch_per_direction(const StrainLimits &limits, const Eigen::VectorXd &x)
  {
    std::vector<double> out(limits.grid_angle.size(), 0.0);
    std::vector<double> c(out.size()), s(out.size());
    for (std::size_t k = 0; k < out.size(); ++k)
      c[k] = std::cos(limits.grid_angle[k]), s[k] = std::sin(limits.grid_angle[k]);
    for (std::size_t t = 0; t < limits.triangles.size(); ++t)
      {
        const Eigen::Matrix2d C = right_cauchy_green(limits, t, x);
        for (std::size_t k = 0; k < out.size(); ++k)
          out[k] =
              std::max(out[k], C(0, 0) * c[k] * c[k] + 2 * C(0, 1) * c[k] * s[k] + C(1, 1) * s[k] * s[k]);
      }
    for (auto &v : out)
      v = std::sqrt(std::max(0.0, v));
    return out;
  }

  Eigen::Vector3d stretch_image(const StrainLimits &limits, const std::size_t i, const Eigen::VectorXd &x)
  {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      d += limits.coefficients[i][k] * x.segment<3>(3 * limits.vertices[i][k]);
    return d;
  }

  double max_violation(const StrainLimits &limits, const Eigen::VectorXd &x)
  {
    double worst = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < limits.size(); ++i)
      worst = std::max(worst, (stretch_image(limits, i, x).norm() - limits.bound[i]) / limits.bound[i]);
    return worst;
  }
} // namespace nlmech
