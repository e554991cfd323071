// Thesis Table 3.1 / SOCP paper Table 1 on this machine, in one run: per time step of the swinging
// sheet (0.5 m, pinned at two corners, the paper's material), the unconstrained implicit Euler step
// (IE), our interior-point SOCP projection, general nonlinear programming with Ipopt (same objective,
// constraints |A x|^2 <= b^2, exact Hessians) and per-element Gauss-Seidel (stop at 1e-6 violation
// or 1e5 sweeps), all on the same candidate positions, for 1 % and 10 % isotropic limits.
// Medians over the steps; the baselines run on the last steps' candidates (where the swing is under
// way and many limits are active), and their ratios to ours are to our median on those same
// candidates ("ours, late candidates"); "*" marks a method that did not converge on some step, "-" one that
// failed. Also the distance of each result from the candidate (the SOCP one is the true projection)
// and the fitted growth of our projection's cost with the number of unknowns.
//
// Our solver runs three times on every candidate: with its default start (warm from the last step's
// projection: its correction and multipliers), without the warm start (centred at the candidate,
// the column "ours, no warm start") and from CVXOPT's starting point ("ours, CVXOPT start"); the
// same solver otherwise.
//
// usage: strain_limiting_benchmark [steps] [baseline_steps] [max resolution] [--no-ipopt]
// [--only-1|--only-10]
//                                  [--mesh N] (only the N x N row)
//        strain_limiting_benchmark --curve-cost [steps] [mesh N]
//   what holding the limit curve between the samples costs: the swinging sheet by SAP with the
//   sampled rows only (curve tolerance 0) and with the curve held to 0.1 of the strain, side by side
//   (projection time per step, iterations, cuts, the largest excess over the curve).
#include <nlmech/solvers/time/cloth_simulation.h>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <tuple>
#include <vector>

using namespace nlmech;

namespace
{
  double median(std::vector<double> v)
  {
    if (v.empty())
      return std::nan("");
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  }

  /// The projection as a nonlinear program for Ipopt: min 1/2 sum P_i (x_i - x_hat_i)^2 subject to
  /// |h_y - G_y x|^2 <= h_t^2 per cone (rows of G for t are zero in the strain-limit problems).
  class ProjectionNlp : public Ipopt::TNLP
  {
    struct Entry
    {
      int    row, col;
      double value;
    };
    struct Cone
    {
      Eigen::Index       first_row = 0;
      int                dimension = 0;
      std::vector<Entry> entries;
      std::vector<int>   columns;
    };

  public:
    explicit ProjectionNlp(const ConicQP &p)
        : p(p)
    {
      const Eigen::SparseMatrix<double, Eigen::RowMajor> Gr(p.G);
      Eigen::Index                                       row = 0;
      for (const unsigned int d : p.cones)
        {
          Cone c;
          c.first_row = row;
          for (unsigned int r = 1; r < d; ++r)
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Gr, row + r); it; ++it)
              c.entries.push_back({int(r - 1), int(it.col()), it.value()});
          for (const auto &e : c.entries)
            if (std::find(c.columns.begin(), c.columns.end(), e.col) == c.columns.end())
              c.columns.push_back(e.col);
          std::sort(c.columns.begin(), c.columns.end());
          c.dimension = int(d - 1);
          cones.push_back(c);
          row += d;
        }
    }
    Eigen::VectorXd solution;
    bool            succeeded = false;
    int             status    = 0;

    bool get_nlp_info(Ipopt::Index &n, Ipopt::Index &m, Ipopt::Index &nnz_jac, Ipopt::Index &nnz_h,
                      IndexStyleEnum &style) override
    {
      n = Ipopt::Index(p.q.size()), m = Ipopt::Index(cones.size());
      nnz_jac = 0, nnz_h = n;
      for (const auto &c : cones)
        {
          nnz_jac += Ipopt::Index(c.columns.size());
          nnz_h += Ipopt::Index(c.columns.size() * (c.columns.size() + 1) / 2);
        }
      style = C_STYLE;
      return true;
    }
    bool get_bounds_info(Ipopt::Index n, Ipopt::Number *xl, Ipopt::Number *xu, Ipopt::Index m,
                         Ipopt::Number *gl, Ipopt::Number *gu) override
    {
      for (Ipopt::Index i = 0; i < n; ++i)
        xl[i] = -1e19, xu[i] = 1e19;
      for (Ipopt::Index k = 0; k < m; ++k)
        gl[k] = -1e19, gu[k] = std::pow(p.h[cones[std::size_t(k)].first_row], 2);
      return true;
    }
    bool get_starting_point(Ipopt::Index n, bool, Ipopt::Number *x, bool, Ipopt::Number *, Ipopt::Number *,
                            Ipopt::Index, bool, Ipopt::Number *) override
    {
      for (Ipopt::Index i = 0; i < n; ++i)
        x[i] = -p.q[i] / p.P_diagonal[i]; // the candidate itself
      return true;
    }
    bool eval_f(Ipopt::Index n, const Ipopt::Number *x, bool, Ipopt::Number &f) override
    {
      f = 0;
      for (Ipopt::Index i = 0; i < n; ++i)
        f += 0.5 * p.P_diagonal[i] * x[i] * x[i] + p.q[i] * x[i];
      return true;
    }
    bool eval_grad_f(Ipopt::Index n, const Ipopt::Number *x, bool, Ipopt::Number *g) override
    {
      for (Ipopt::Index i = 0; i < n; ++i)
        g[i] = p.P_diagonal[i] * x[i] + p.q[i];
      return true;
    }
    Eigen::Vector3d image(const Cone &c, const Ipopt::Number *x) const
    {
      Eigen::Vector3d y = Eigen::Vector3d::Zero();
      for (int r = 0; r < c.dimension; ++r)
        y[r] = p.h[c.first_row + 1 + r];
      for (const auto &e : c.entries)
        y[e.row] -= e.value * x[e.col];
      return y;
    }
    bool eval_g(Ipopt::Index, const Ipopt::Number *x, bool, Ipopt::Index m, Ipopt::Number *g) override
    {
      for (Ipopt::Index k = 0; k < m; ++k)
        g[k] = image(cones[std::size_t(k)], x).squaredNorm();
      return true;
    }
    bool eval_jac_g(Ipopt::Index, const Ipopt::Number *x, bool, Ipopt::Index m, Ipopt::Index,
                    Ipopt::Index *rows, Ipopt::Index *cols, Ipopt::Number *values) override
    {
      Ipopt::Index k = 0;
      for (Ipopt::Index c = 0; c < m; ++c)
        {
          const Cone &cone = cones[std::size_t(c)];
          if (values == nullptr)
            {
              for (const int col : cone.columns)
                rows[k] = c, cols[k++] = col;
              continue;
            }
          const Eigen::Vector3d y  = image(cone, x);
          const Ipopt::Index    k0 = k;
          for (std::size_t j = 0; j < cone.columns.size(); ++j)
            values[k++] = 0;
          for (const auto &e : cone.entries) // d|y|^2/dx = -2 G_y^T y
            values[k0 + (std::lower_bound(cone.columns.begin(), cone.columns.end(), e.col) -
                         cone.columns.begin())] -= 2 * e.value * y[e.row];
        }
      return true;
    }
    bool eval_h(Ipopt::Index n, const Ipopt::Number *, bool, Ipopt::Number sigma, Ipopt::Index m,
                const Ipopt::Number *lambda, bool, Ipopt::Index, Ipopt::Index *rows, Ipopt::Index *cols,
                Ipopt::Number *values) override
    {
      Ipopt::Index k = 0;
      for (Ipopt::Index i = 0; i < n; ++i)
        {
          if (values == nullptr)
            rows[k] = i, cols[k] = i;
          else
            values[k] = sigma * p.P_diagonal[i];
          ++k;
        }
      for (Ipopt::Index c = 0; c < m; ++c)
        {
          const Cone  &cone = cones[std::size_t(c)];
          const size_t nc   = cone.columns.size();
          if (values == nullptr)
            {
              for (std::size_t a = 0; a < nc; ++a)
                for (std::size_t b = 0; b <= a; ++b)
                  rows[k] = cone.columns[a], cols[k++] = cone.columns[b];
              continue;
            }
          // 2 lambda G_y^T G_y on the cone's columns.
          Eigen::MatrixXd Gy = Eigen::MatrixXd::Zero(cone.dimension, Eigen::Index(nc));
          for (const auto &e : cone.entries)
            Gy(e.row, std::lower_bound(cone.columns.begin(), cone.columns.end(), e.col) -
                          cone.columns.begin()) = e.value;
          const Eigen::MatrixXd H = 2 * lambda[c] * Gy.transpose() * Gy;
          for (std::size_t a = 0; a < nc; ++a)
            for (std::size_t b = 0; b <= a; ++b)
              values[k++] = H(Eigen::Index(a), Eigen::Index(b));
        }
      return true;
    }
    void finalize_solution(Ipopt::SolverReturn s, Ipopt::Index n, const Ipopt::Number *x,
                           const Ipopt::Number *, const Ipopt::Number *, Ipopt::Index, const Ipopt::Number *,
                           const Ipopt::Number *, Ipopt::Number, const Ipopt::IpoptData *,
                           Ipopt::IpoptCalculatedQuantities *) override
    {
      solution  = Eigen::Map<const Eigen::VectorXd>(x, n);
      status    = int(s);
      succeeded = s == Ipopt::SUCCESS || s == Ipopt::STOP_AT_ACCEPTABLE_POINT;
    }

  private:
    const ConicQP    &p;
    std::vector<Cone> cones;
  };

  struct Column
  {
    std::vector<double> seconds;
    bool                not_converged = false, failed = false;
    std::string         text() const
    {
      if (failed && seconds.empty())
        return "-";
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.3f s%s", median(seconds), not_converged ? "*" : "");
      return buffer;
    }
  };
} // namespace

namespace
{
  int curve_cost(const unsigned int steps, const unsigned int n)
  {
    ShellMaterial material;
    material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
    material.poissons_ratio = 0.41;
    const auto mesh         = make_sheet_mesh(0.5, n);
    std::printf("Swinging sheet %ux%u, SAP, h = 1/60 s, %u steps, 4 sampled directions; medians over the "
                "steps that projected\n",
                n, n, steps);
    std::printf("| limit | curve tolerance | projection per step | total projection | iterations per step | "
                "cuts | rows at the end | largest excess over the curve | largest stretch | time / "
                "tolerance 0 |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for (const double limit : {1.01, 1.10})
      {
        double base = 0;
        for (const double tolerance : {0.0, 0.1})
          {
            const auto limits = make_strain_limits(
                mesh, {{1, 0, 0}}, {{0, 0, 1}}, 4, [&](double) { return limit; }, tolerance);
            ClothSettings settings;
            settings.scheme    = ClothScheme::sap;
            settings.time_step = 1.0 / 60;
            ClothSimulation     sim(mesh, material, {0, n}, limits, settings);
            std::vector<double> seconds, iterations;
            double              total = 0, excess = -1e300, stretch = 0;
            std::size_t         cuts = 0;
            for (unsigned int s = 0; s < steps; ++s)
              {
                const ClothStepStatistics st = sim.step();
                total += st.projection_seconds, cuts += st.cuts;
                if (st.projection_iterations > 0)
                  seconds.push_back(st.projection_seconds), iterations.push_back(st.projection_iterations);
                excess = std::max(excess, max_curve_excess(limits, sim.positions()));
                for (const double v : largest_stretch_per_direction(limits, sim.positions()))
                  stretch = std::max(stretch, v);
              }
            if (tolerance == 0)
              base = total;
            std::printf("| %.0f%% | %.1f | %.4f s | %.3f s | %.0f | %zu | %zu | %.3f | %.5f | %.2f |\n",
                        (limit - 1) * 100, tolerance, median(seconds), total, median(iterations), cuts,
                        sim.current_limits().size(), excess, stretch, total / base);
            std::fflush(stdout);
          }
      }
    return 0;
  }
} // namespace

int main(int argc, char **argv)
{
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args[0] == "--curve-cost")
    return curve_cost(args.size() > 1 ? unsigned(std::stoi(args[1])) : 20,
                      args.size() > 2 ? unsigned(std::stoi(args[2])) : 60);
  const bool ipopt = std::find(args.begin(), args.end(), "--no-ipopt") == args.end();
  args.erase(std::remove(args.begin(), args.end(), "--no-ipopt"), args.end());
  std::vector<double> limit_values = {1.01, 1.10};
  for (const double l : {1.01, 1.10})
    if (std::find(args.begin(), args.end(), "--only-" + std::to_string(int(std::lround((l - 1) * 100)))) !=
        args.end())
      limit_values = {l};
  args.erase(std::remove_if(args.begin(), args.end(),
                            [](const std::string &a) { return a.rfind("--only-", 0) == 0; }),
             args.end());
  unsigned int only_mesh = 0;
  for (std::size_t k = 0; k + 1 < args.size(); ++k)
    if (args[k] == "--mesh")
      {
        only_mesh = unsigned(std::stoi(args[k + 1]));
        args.erase(args.begin() + long(k), args.begin() + long(k) + 2);
        break;
      }
  const unsigned int steps          = args.size() > 0 ? unsigned(std::stoi(args[0])) : 20;
  const unsigned int baseline_steps = args.size() > 1 ? unsigned(std::stoi(args[1])) : 3;
  const unsigned int max_resolution = args.size() > 2 ? unsigned(std::stoi(args[2])) : 120;
  const double       gs_time_cap    = 60; // s per Gauss-Seidel solve (marked * when hit)

  ShellMaterial material;
  material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
  material.poissons_ratio = 0.41;
  std::printf(
      "Swinging sheet, SAP, h = 1/60 s; medians over %u steps (baselines: the last %u steps' candidates)\n",
      steps, baseline_steps);
  std::printf(
      "| limit | mesh | unknowns | limits | IE | ours | iterations | ours, no warm start | iterations | "
      "ours, CVXOPT start | iterations | ours, late candidates | Ipopt | Gauss-Seidel | ours/IE | "
      "no warm start/ours | CVXOPT start/ours | Ipopt/ours | GS/ours | distance Ipopt/ours | distance "
      "GS/ours |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const double limit : limit_values)
    {
      std::vector<std::pair<double, double>> growth, growth_late; // (unknowns, our median)
      for (const unsigned int n : {10u, 20u, 40u, 60u, 120u})
        {
          if (n > max_resolution || (only_mesh > 0 && n != only_mesh))
            continue;
          const bool baselines = n <= 60;
          const auto mesh      = make_sheet_mesh(0.5, n);
          // The sampled rows only (curve tolerance 0): the problem the baselines solve too.
          const auto limits = make_strain_limits(
              mesh, {{1, 0, 0}}, {{0, 0, 1}}, 4, [&](double) { return limit; }, 0.0);
          ClothSettings settings;
          settings.scheme    = ClothScheme::sap;
          settings.time_step = 1.0 / 60;
          ClothSimulation      sim(mesh, material, {0, n}, limits, settings);
          StrainLimitProjector projector(limits, sim.mass(), sim.fixed());
          ConicSettings        cvxopt_start;
          cvxopt_start.start_mu = -1;
          StrainLimitProjector classic(limits, sim.mass(), sim.fixed(), cvxopt_start);
          ConicSettings        no_warm_start;
          no_warm_start.warm_mu = 0;
          StrainLimitProjector cold(limits, sim.mass(), sim.fixed(), no_warm_start);
          Column               ie, ours, ours_cold, ours_classic, ip, gs;
          std::vector<double>  ours_same; // ours on the late candidates (the baselines' inputs)
          std::vector<double>  iterations, iterations_cold, iterations_classic, ratio_ip, ratio_gs;
          for (unsigned int s = 0; s < steps; ++s)
            {
              ClothStepStatistics   st;
              const Eigen::VectorXd x0 = sim.positions(), v0 = sim.velocities();
              const Eigen::VectorXd x_hat = sim.implicit_euler(x0, v0, settings.time_step, st);
              ie.seconds.push_back(st.newton_seconds);
              Eigen::VectorXd        x;
              const ProjectionResult r = projector.project(x_hat, x);
              ours.seconds.push_back(r.seconds);
              iterations.push_back(r.iterations);
              if (r.status != ConicStatus::solved)
                ours.not_converged = true;
              for (auto [variant, column, its] : {std::tuple(&classic, &ours_classic, &iterations_classic),
                                                  std::tuple(&cold, &ours_cold, &iterations_cold)})
                {
                  Eigen::VectorXd        xc;
                  const ProjectionResult rc = variant->project(x_hat, xc);
                  column->seconds.push_back(rc.seconds);
                  its->push_back(rc.iterations);
                  if (rc.status != ConicStatus::solved)
                    column->not_converged = true;
                }
              // The baselines on the last steps' candidates, where the swing is under way and many
              // limits are active (the first candidates from rest barely violate any).
              const bool late = s + baseline_steps >= steps && r.distance > 1e-12;
              if (late)
                ours_same.push_back(r.seconds);
              if (baselines && late)
                {
                  // Gauss-Seidel from the candidate.
                  Eigen::VectorXd x_gs = x_hat;
                  for (const auto &f : sim.fixed())
                    x_gs[Eigen::Index(f.first)] = f.second;
                  const auto g = gauss_seidel_projection(limits, sim.mass(), sim.fixed(), x_gs, 1e-6, 100000,
                                                         gs_time_cap);
                  gs.seconds.push_back(g.seconds);
                  gs.not_converged = gs.not_converged || !g.converged;
                  ratio_gs.push_back(std::sqrt((x_gs - x_hat).cwiseAbs2().dot(sim.mass())) / r.distance);
                  if (ipopt)
                    {
                      const ConicQP                            problem = projector.problem(x_hat);
                      Ipopt::SmartPtr<ProjectionNlp>           nlp     = new ProjectionNlp(problem);
                      Ipopt::SmartPtr<Ipopt::IpoptApplication> app     = IpoptApplicationFactory();
                      app->Options()->SetIntegerValue("print_level", 0);
                      app->Options()->SetStringValue("sb", "yes");
                      app->Options()->SetNumericValue("max_cpu_time", 60);
                      const auto t0 = std::chrono::steady_clock::now();
                      bool       ok = app->Initialize() == Ipopt::Solve_Succeeded;
                      ok            = ok && (app->OptimizeTNLP(nlp), true);
                      ip.seconds.push_back(
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
                      if (!nlp->succeeded || nlp->solution.size() == 0)
                        (nlp->solution.size() == 0 ? ip.failed : ip.not_converged) = true;
                      else
                        {
                          const Eigen::VectorXd xi = projector.full(nlp->solution);
                          ratio_ip.push_back(std::sqrt((xi - x_hat).cwiseAbs2().dot(sim.mass())) /
                                             r.distance);
                        }
                    }
                }
              sim.set_state(x, (x - x0) / settings.time_step); // continue the swing (SAP)
            }
          const double ours_median = median(ours.seconds);
          growth.emplace_back(double(3 * mesh.vertices.size()), ours_median);
          char r_ip[32] = "", r_gs[32] = "", d_ip[32] = "", d_gs[32] = "", r_classic[32] = "",
               r_cold[32]          = "";
          const double same_median = median(ours_same);
          if (!ours_same.empty())
            growth_late.emplace_back(double(3 * mesh.vertices.size()), same_median);
          std::snprintf(r_classic, sizeof r_classic, "%.2f", median(ours_classic.seconds) / ours_median);
          std::snprintf(r_cold, sizeof r_cold, "%.2f", median(ours_cold.seconds) / ours_median);
          if (!ip.seconds.empty())
            std::snprintf(r_ip, sizeof r_ip, "%.1f", median(ip.seconds) / same_median);
          if (!gs.seconds.empty())
            std::snprintf(r_gs, sizeof r_gs, "%.1f", median(gs.seconds) / same_median);
          if (!ratio_ip.empty())
            std::snprintf(d_ip, sizeof d_ip, "%.4f", median(ratio_ip));
          if (!ratio_gs.empty())
            std::snprintf(d_gs, sizeof d_gs, "%.4f", median(ratio_gs));
          std::printf("| %.0f%% | %ux%u | %zu | %zu | %.3f s | %s | %.0f | %s | %.0f | %s | %.0f | %.4f s | "
                      "%s | %s | %.2f | %s | %s | %s | %s | %s | %s |\n",
                      (limit - 1) * 100, n, n, 3 * mesh.vertices.size(), limits.size(), median(ie.seconds),
                      ours.text().c_str(), median(iterations), ours_cold.text().c_str(),
                      median(iterations_cold), ours_classic.text().c_str(), median(iterations_classic),
                      same_median, baselines && ipopt ? ip.text().c_str() : "",
                      baselines ? gs.text().c_str() : "", ours_median / median(ie.seconds), r_cold, r_classic,
                      r_ip, r_gs, d_ip, d_gs);
          std::fflush(stdout);
        }
      // Least-squares slope of log(time) against log(unknowns).
      auto slope = [](const std::vector<std::pair<double, double>> &points) {
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        for (const auto &g : points)
          {
            const double lx = std::log(g.first), ly = std::log(g.second);
            sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
          }
        const double k = double(points.size());
        return (k * sxy - sx * sy) / (k * sxx - sx * sx);
      };
      if (growth.size() >= 2)
        std::printf("\nlimit %.0f%%: our projection's cost grows like n^%.2f in the unknowns over all steps, "
                    "n^%.2f over the late candidates (fit over %zu meshes)\n\n",
                    (limit - 1) * 100, slope(growth),
                    growth_late.size() >= 2 ? slope(growth_late) : std::nan(""), growth.size());
    }
  return 0;
}
