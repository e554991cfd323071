#include <deal.II/base/exceptions.h>

#include <nlmech/models/cloth/strain_limits.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    double           since(std::chrono::steady_clock::time_point t0)
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
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

  namespace
  {
    Eigen::Vector3d image(const StrainLimits &limits, std::size_t i, const Eigen::VectorXd &x)
    {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k)
        d += limits.coefficients[i][k] * x.segment<3>(3 * limits.vertices[i][k]);
      return d;
    }
  } // namespace

  double max_violation(const StrainLimits &limits, const Eigen::VectorXd &x)
  {
    double worst = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < limits.size(); ++i)
      worst = std::max(worst, (image(limits, i, x).norm() - limits.bound[i]) / limits.bound[i]);
    return worst;
  }

  StrainLimitProjector::StrainLimitProjector(const StrainLimits &limits, const Eigen::VectorXd &mass,
                                             const std::map<std::size_t, double> &fixed,
                                             ConicSettings settings, const double screening)
      : limits(limits)
      , cuts_of_triangle(limits.triangles.size(), 0)
      , cut_rows(limits.triangles.size())
      , mass(mass)
      , fixed(fixed)
      , settings(settings)
      , screening(screening)
  {
    // The candidate is close to its projection: start there, centred (start_mu = 0 picks this
    // default, chosen on the swinging sheet where 1e-5 to 1e-3 cost within two iterations of it;
    // start_mu < 0 keeps CVXOPT's start).
    if (this->settings.start_mu == 0)
      this->settings.start_mu = 1e-4, this->settings.start_margin = 0.1;
    free_index.assign(std::size_t(mass.size()), -1);
    for (std::size_t i = 0; i < std::size_t(mass.size()); ++i)
      if (!fixed.count(i))
        {
          AssertThrow(mass[Eigen::Index(i)] > 0,
                      dealii::ExcMessage("Projection: a free unknown without mass."));
          free_index[i] = long(free_dofs.size());
          free_dofs.push_back(i);
        }
    mass_scale = 0;
    for (const std::size_t i : free_dofs)
      mass_scale += mass[Eigen::Index(i)];
    mass_scale = free_dofs.empty() ? 1.0 : mass_scale / double(free_dofs.size());
    row_order.resize(this->limits.size());
    for (std::size_t i = 0; i < row_order.size(); ++i)
      row_order[i] = i;
  }

  std::size_t StrainLimitProjector::add_cuts(const Eigen::VectorXd &x, double &excess)
  {
    excess = 0;
    if (!limits.curve || limits.curve_tolerance <= 0 || limits.triangles.empty())
      return 0;
    // Once any triangle exceeds the tolerance, every triangle past half of it gets its cut: the
    // projection that follows moves stretch between neighbours, and the ones close to the
    // tolerance would need a round of their own. Measured on 10 steps of the 40x40 swinging sheet
    // (SAP; projection time against the sampled rows alone): cutting only past the tolerance 6.1x
    // (1 %) and 4.7x (10 %), past half of it 3.8x and 2.9x, past a quarter 3.5x and 2.8x with more
    // rows, every positive excess 4.0x and 4.3x; a cut either side of the worst direction as well
    // gave no gain.
    const auto over = curve_excesses(limits, x, 0.5 * limits.curve_tolerance, &excess);
    if (excess <= limits.curve_tolerance)
      return 0;
    std::size_t added = 0;
    std::size_t moved = 0;
    for (const auto &e : over)
      if (cuts_of_triangle[e.triangle] < max_cuts_per_triangle)
        {
          cut_rows[e.triangle].push_back(limits.size());
          limits.add(e.triangle, e.alpha);
          ++cuts_of_triangle[e.triangle], ++added;
        }
      else
        {
          // At the cap: the oldest cut of the triangle moves to the new direction (its pattern is
          // the same, so the cone problem's structure does not change); its multipliers restart.
          auto             &rows = cut_rows[e.triangle];
          const std::size_t row  = rows.front();
          rows.erase(rows.begin());
          rows.push_back(row);
          limits.move(row, e.alpha);
          previously_active[row] = 0;
          if (!previous_z.empty())
            std::fill(previous_z.begin() + long(4 * row), previous_z.begin() + long(4 * row + 4), 0.0);
          ++moved;
        }
    if (added == 0)
      return moved;
    // Rows grouped by triangle, so that each triangle's cones share their columns in the problem.
    row_order.resize(limits.size());
    for (std::size_t i = 0; i < row_order.size(); ++i)
      row_order[i] = i;
    std::stable_sort(row_order.begin(), row_order.end(),
                     [&](std::size_t a, std::size_t b) { return limits.triangle[a] < limits.triangle[b]; });
    previously_active.resize(limits.size(), 0);
    if (!previous_z.empty())
      previous_z.resize(4 * limits.size(), 0.0);
    return added;
  }

  Eigen::VectorXd StrainLimitProjector::full(const Eigen::VectorXd &free_values) const
  {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(mass.size());
    for (std::size_t k = 0; k < free_dofs.size(); ++k)
      x[Eigen::Index(free_dofs[k])] = free_values[Eigen::Index(k)];
    for (const auto &f : fixed)
      x[Eigen::Index(f.first)] = f.second;
    return x;
  }

  ConicQP StrainLimitProjector::problem(const Eigen::VectorXd &x_hat) const
  {
    std::vector<std::size_t> unknowns;
    return problem(x_hat, std::vector<char>(limits.size(), 1), unknowns);
  }

  ConicQP StrainLimitProjector::problem(const Eigen::VectorXd &x_hat, const std::vector<char> &include,
                                        std::vector<std::size_t> &unknowns) const
  {
    // The free unknowns the included limits touch, numbered in order.
    std::vector<long> local(std::size_t(mass.size()), -1);
    unknowns.clear();
    if (std::size_t(std::count(include.begin(), include.end(), 1)) == limits.size())
      unknowns = free_dofs;
    else
      {
        std::vector<char> touched(std::size_t(mass.size()), 0);
        for (std::size_t i = 0; i < limits.size(); ++i)
          if (include[i])
            for (int k = 0; k < 3; ++k)
              for (int d = 0; d < 3; ++d)
                touched[3 * limits.vertices[i][k] + std::size_t(d)] = 1;
        for (const std::size_t i : free_dofs)
          if (touched[i])
            unknowns.push_back(i);
      }
    for (std::size_t k = 0; k < unknowns.size(); ++k)
      local[unknowns[k]] = long(k);
    const Eigen::Index n = Eigen::Index(unknowns.size());
    ConicQP            p;
    // Objective scaled by the mean mass (keeps the tolerances meaningful for light sheets).
    p.P_diagonal.resize(n), p.q.resize(n);
    for (Eigen::Index k = 0; k < n; ++k)
      {
        p.P_diagonal[k] = mass[Eigen::Index(unknowns[std::size_t(k)])] / mass_scale;
        p.q[k]          = -p.P_diagonal[k] * x_hat[Eigen::Index(unknowns[std::size_t(k)])];
      }
    const std::size_t                   m = std::size_t(std::count(include.begin(), include.end(), 1));
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(m * 9);
    p.h = Eigen::VectorXd::Zero(Eigen::Index(4 * m));
    p.cones.assign(m, 4);
    std::size_t row = 0;
    for (const std::size_t i : row_order)
      {
        if (!include[i])
          continue;
        // s = (b, A x) = h - G x: h = (b, A_fixed x_fixed), G = -(0, A_free).
        p.h[Eigen::Index(row)] = limits.bound[i];
        for (int k = 0; k < 3; ++k)
          for (int d = 0; d < 3; ++d)
            {
              const std::size_t dof = 3 * limits.vertices[i][k] + std::size_t(d);
              const double      c   = limits.coefficients[i][k];
              if (local[dof] >= 0)
                t.emplace_back(Eigen::Index(row + 1 + std::size_t(d)), local[dof], -c);
              else
                p.h[Eigen::Index(row + 1 + std::size_t(d))] += c * fixed.at(dof);
            }
        row += 4;
      }
    p.G.resize(Eigen::Index(4 * m), n);
    p.G.setFromTriplets(t.begin(), t.end());
    p.G.makeCompressed();
    return p;
  }

  ProjectionResult StrainLimitProjector::project(const Eigen::VectorXd &x_hat, Eigen::VectorXd &x)
  {
    const auto       started = std::chrono::steady_clock::now();
    ProjectionResult result;
    x = x_hat;
    for (const auto &f : fixed)
      x[Eigen::Index(f.first)] = f.second;
    // A candidate that meets every limit is its own projection.
    // The limits within 0.1 % of their bound at x, screened in by the next projection.
    auto remember_active = [&]() {
      previously_active.resize(limits.size());
      for (std::size_t i = 0; i < limits.size(); ++i)
        previously_active[i] = image(limits, i, x).norm() >= (1 - 1e-3) * limits.bound[i];
    };
    const double candidate_violation = max_violation(limits, x);
    // A candidate that meets every row but not the curve between them gets its cuts and is solved.
    if (candidate_violation <= 0)
      result.cuts_added = add_cuts(x, result.curve_excess);
    if (candidate_violation <= 0 && result.cuts_added == 0)
      {
        remember_active();
        if (settings.warm_mu > 0)
          previous_correction = x - x_hat, previous_z.assign(4 * limits.size(), 0.0);
        result.status    = ConicStatus::solved;
        result.violation = candidate_violation;
        result.seconds   = since(started);
        return result;
      }
    // The limits in the first cone problem.
    std::vector<char> include(limits.size(), 0);
    if (previously_active.size() != limits.size())
      previously_active.assign(limits.size(), 0);
    for (std::size_t i = 0; i < limits.size(); ++i)
      include[i] =
          screening <= 0 || previously_active[i] || image(limits, i, x).norm() >= screening * limits.bound[i];
    // Once a quarter of the limits are in, all go in: the full problem costs about as much as
    // a reduced one of that size solved twice (a second round to add what the first missed).
    // Measured on 20 steps of the swinging sheet at 10 % limits (all projections, medians of 10):
    // 20x20 0.40 s with the threshold at one half, 0.26-0.28 s at one quarter, 0.31 s always full;
    // 40x40 2.40, 1.40-1.58 and 1.65 s; 60x60 6.7 s at one half, 3.9 s at one quarter. At 1 %
    // nearly every limit is active from the first steps and the threshold makes no difference.
    auto all_if_many = [&]() {
      if (4 * std::size_t(std::count(include.begin(), include.end(), 1)) > limits.size())
        std::fill(include.begin(), include.end(), 1);
    };
    all_if_many();
    result.status = ConicStatus::solved;
    for (unsigned int round = 0; round < 50; ++round)
      {
        if (std::count(include.begin(), include.end(), 1) > 0)
          {
            std::vector<std::size_t> unknowns;
            const ConicQP            p = problem(x_hat, include, unknowns);
            // From the candidate (first round) or the last round's projection, centred; warm from
            // the last projection where there is one: its correction added to the candidate in
            // the first round, its multipliers.
            const bool      warm = settings.warm_mu > 0 && previous_z.size() == 4 * limits.size();
            Eigen::VectorXd x0(Eigen::Index(unknowns.size()));
            for (std::size_t k = 0; k < unknowns.size(); ++k)
              x0[Eigen::Index(k)] =
                  x[Eigen::Index(unknowns[k])] +
                  (warm && round == 0 ? previous_correction[Eigen::Index(unknowns[k])] : 0.0);
            Eigen::VectorXd z0;
            if (warm)
              {
                z0.resize(p.h.size());
                Eigen::Index row = 0;
                for (const std::size_t i : row_order)
                  if (include[i])
                    for (int k = 0; k < 4; ++k)
                      z0[row++] = previous_z[4 * i + std::size_t(k)];
              }
            const ConicResult r = cone_solver.solve(p, settings, settings.start_mu > 0 ? &x0 : nullptr,
                                                    warm && settings.start_mu > 0 ? &z0 : nullptr);
            if (std::getenv("NLMECH_PROJECTION_DEBUG"))
              std::fprintf(stderr, "projection round %u: %zu limits, %zu unknowns, %u iterations, %.3f s\n",
                           round, p.cones.size(), unknowns.size(), r.iterations, r.seconds);
            ++result.rounds;
            result.iterations += r.iterations;
            result.status = r.status;
            result.cones  = p.cones.size();
            if (r.status != ConicStatus::solved && r.status != ConicStatus::almost_solved)
              {
                previous_z.clear();
                break;
              }
            if (settings.warm_mu > 0)
              {
                previous_z.assign(4 * limits.size(), 0.0);
                Eigen::Index row = 0;
                for (const std::size_t i : row_order)
                  if (include[i])
                    for (int k = 0; k < 4; ++k)
                      previous_z[4 * i + std::size_t(k)] = r.z[row++];
              }
            x = x_hat;
            for (const auto &f : fixed)
              x[Eigen::Index(f.first)] = f.second;
            for (std::size_t k = 0; k < unknowns.size(); ++k)
              x[Eigen::Index(unknowns[k])] = r.x[Eigen::Index(k)];
          }
        // Check every limit left out; add the violated and nearly active ones (with the same
        // margin as the first screening, so that few rounds follow); past a quarter, all go in
        // (all_if_many), and the full problem's pattern is analysed once and reused from then on.
        // The projection pushes stretch outwards ring by ring; the limits that share a vertex
        // with a newly added one go in too, so that the rounds do not crawl one ring at a time.
        std::size_t       added = 0;
        std::vector<char> near_vertex(std::size_t(mass.size()) / 3, 0);
        for (std::size_t i = 0; i < limits.size(); ++i)
          if (!include[i] && image(limits, i, x).norm() >= screening * limits.bound[i])
            {
              include[i] = 1, ++added;
              for (const unsigned int v : limits.vertices[i])
                near_vertex[v] = 1;
            }
        if (added == 0)
          {
            // Every row holds: cut where the curve between them is still exceeded, and go again.
            if (result.status != ConicStatus::solved && result.status != ConicStatus::almost_solved)
              break;
            const std::size_t before = limits.size();
            const std::size_t cuts   = add_cuts(x, result.curve_excess);
            if (cuts == 0)
              break;
            result.cuts_added += cuts;
            include.resize(limits.size(), 0);
            for (std::size_t i = 0; i < limits.size(); ++i)
              // The new rows, and cuts moved to a new direction that x now violates.
              if (i >= before || (!include[i] && image(limits, i, x).norm() >= screening * limits.bound[i]))
                {
                  include[i] = 1;
                  for (const unsigned int v : limits.vertices[i])
                    near_vertex[v] = 1;
                }
          }
        for (std::size_t i = 0; i < limits.size(); ++i)
          if (!include[i])
            for (const unsigned int v : limits.vertices[i])
              if (near_vertex[v])
                {
                  include[i] = 1;
                  break;
                }
        all_if_many();
      }
    remember_active();
    if (!previous_z.empty())
      previous_correction = x - x_hat;
    if (result.status == ConicStatus::solved || result.status == ConicStatus::almost_solved)
      {
        result.violation = max_violation(limits, x);
        if (limits.curve && !limits.triangles.empty())
          result.curve_excess = max_curve_excess(limits, x);
        double d2 = 0;
        for (const std::size_t i : free_dofs)
          d2 += mass[Eigen::Index(i)] * std::pow(x[Eigen::Index(i)] - x_hat[Eigen::Index(i)], 2);
        result.distance = std::sqrt(d2);
      }
    result.seconds = since(started);
    return result;
  }

  GaussSeidelResult gauss_seidel_projection(const StrainLimits &limits, const Eigen::VectorXd &mass,
                                            const std::map<std::size_t, double> &fixed, Eigen::VectorXd &x,
                                            const double tolerance, const unsigned int max_sweeps,
                                            const double max_seconds)
  {
    const auto        started = std::chrono::steady_clock::now();
    GaussSeidelResult result;
    // Inverse vertex masses, 0 for pinned vertices.
    std::vector<double> inverse_mass(std::size_t(mass.size()) / 3);
    for (std::size_t v = 0; v < inverse_mass.size(); ++v)
      inverse_mass[v] = fixed.count(3 * v) ? 0.0 : 1.0 / mass[Eigen::Index(3 * v)];
    for (result.sweeps = 0; result.sweeps < max_sweeps; ++result.sweeps)
      {
        double worst = -std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < limits.size(); ++i)
          {
            const Eigen::Vector3d y = image(limits, i, x);
            const double          r = y.norm(), b = limits.bound[i];
            worst = std::max(worst, (r - b) / b);
            if (r <= b)
              continue;
            // min 1/2 |dx|_M^2 s.t. A (x + dx) = y b / r: dx = M^-1 A^T mu, A M^-1 A^T = k I.
            double k = 0;
            for (int j = 0; j < 3; ++j)
              k += std::pow(limits.coefficients[i][j], 2) * inverse_mass[limits.vertices[i][j]];
            if (k <= 0)
              continue; // every vertex pinned
            const Eigen::Vector3d mu = -(1 - b / r) * y / k;
            for (int j = 0; j < 3; ++j)
              x.segment<3>(3 * limits.vertices[i][j]) +=
                  inverse_mass[limits.vertices[i][j]] * limits.coefficients[i][j] * mu;
          }
        result.violation = worst;
        if (worst <= tolerance)
          {
            result.converged = true;
            break;
          }
        if (since(started) > max_seconds)
          break;
      }
    result.violation = max_violation(limits, x);
    result.converged = result.violation <= tolerance;
    result.seconds   = since(started);
    return result;
  }
} // namespace nlmech
