#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/socp/strain_projection.h>

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
        previously_active[i] = stretch_image(limits, i, x).norm() >= (1 - 1e-3) * limits.bound[i];
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
      include[i] = screening <= 0 || previously_active[i] ||
                   stretch_image(limits, i, x).norm() >= screening * limits.bound[i];
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
          if (!include[i] && stretch_image(limits, i, x).norm() >= screening * limits.bound[i])
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
              if (i >= before ||
                  (!include[i] && stretch_image(limits, i, x).norm() >= screening * limits.bound[i]))
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
            const Eigen::Vector3d y = stretch_image(limits, i, x);
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
