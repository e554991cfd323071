// Our strain-limiting projection alone, for profiling (perf) and for timing changes to the solver:
// the swinging sheet (as in strain_limiting_benchmark: SAP, h = 1/60 s, 4 directions) is run once
// and its candidates stored; then the projections of the whole sequence are repeated `repeats`
// times with a fresh projector each time (so every repeat sees the same warm starts), and the
// median time of every late candidate's projection (the last `late` steps) is printed with its
// iterations, rounds and cones, next to Gauss-Seidel on the same candidate; last, the median time
// of all the projections of a repeat.
//
// usage: projection_profile [n = 10] [limit = 1.01] [steps = 10] [late = 3] [repeats = 20]
#include <nlmech/solvers/time/cloth_simulation.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

using namespace nlmech;

int main(int argc, char **argv)
{
  const unsigned int n       = argc > 1 ? unsigned(std::stoi(argv[1])) : 10;
  const double       limit   = argc > 2 ? std::stod(argv[2]) : 1.01;
  const unsigned int steps   = argc > 3 ? unsigned(std::stoi(argv[3])) : 10;
  const unsigned int late    = argc > 4 ? unsigned(std::stoi(argv[4])) : 3;
  const unsigned int repeats = argc > 5 ? unsigned(std::stoi(argv[5])) : 20;

  ShellMaterial material;
  material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
  material.poissons_ratio = 0.41;
  const auto mesh         = make_sheet_mesh(0.5, n);
  // The sampled rows only (curve tolerance 0): the problem Gauss-Seidel solves too.
  const auto limits = make_strain_limits(
      mesh, {{1, 0, 0}}, {{0, 0, 1}}, 4, [&](double) { return limit; }, 0.0);
  ClothSettings settings;
  settings.scheme    = ClothScheme::sap;
  settings.time_step = 1.0 / 60;
  ClothSimulation              sim(mesh, material, {0, n}, limits, settings);
  std::vector<Eigen::VectorXd> candidates;
  {
    StrainLimitProjector projector(limits, sim.mass(), sim.fixed());
    for (unsigned int s = 0; s < steps; ++s)
      {
        ClothStepStatistics   st;
        const Eigen::VectorXd x0 = sim.positions(), v0 = sim.velocities();
        candidates.push_back(sim.implicit_euler(x0, v0, settings.time_step, st));
        Eigen::VectorXd x;
        projector.project(candidates.back(), x);
        sim.set_state(x, (x - x0) / settings.time_step);
      }
  }
  std::vector<std::vector<double>> seconds(steps);
  std::vector<double>              totals; // all steps of a repeat
  std::vector<ProjectionResult>    last(steps);
  for (unsigned int r = 0; r < repeats; ++r)
    {
      StrainLimitProjector projector(limits, sim.mass(), sim.fixed());
      double               total = 0;
      for (unsigned int s = 0; s < steps; ++s)
        {
          Eigen::VectorXd x;
          last[s] = projector.project(candidates[s], x);
          seconds[s].push_back(last[s].seconds);
          total += last[s].seconds;
        }
      totals.push_back(total);
    }
  std::printf(
      "| step | ours (median of %u) | iterations | rounds | cones | Gauss-Seidel | sweeps | GS/ours |\n",
      repeats);
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (unsigned int s = steps - std::min(late, steps); s < steps; ++s)
    {
      std::sort(seconds[s].begin(), seconds[s].end());
      const double    ours = seconds[s][seconds[s].size() / 2];
      Eigen::VectorXd x_gs = candidates[s];
      for (const auto &f : sim.fixed())
        x_gs[Eigen::Index(f.first)] = f.second;
      const auto g = gauss_seidel_projection(limits, sim.mass(), sim.fixed(), x_gs, 1e-6, 100000, 60);
      std::printf("| %u | %.3f ms | %u | %u | %zu | %.3f ms%s | %u | %.1f |\n", s + 1, 1e3 * ours,
                  last[s].iterations, last[s].rounds, last[s].cones, 1e3 * g.seconds, g.converged ? "" : "*",
                  g.sweeps, g.seconds / ours);
    }
  std::sort(totals.begin(), totals.end());
  std::printf("all %u projections: %.3f ms (median of %u)\n", steps, 1e3 * totals[totals.size() / 2],
              repeats);
  return 0;
}
