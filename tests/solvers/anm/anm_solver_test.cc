// Tests source/solvers/anm/anm_solver.cc: the series solves the equilibrium to order n, ANM and
// Newton agree on a large-deflection cantilever, loads beyond a limit point stop cleanly.
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <gtest/gtest.h>

using namespace dealii;
using namespace nlmech;

namespace
{
  HyperelasticProblem soft_cantilever(double gravity, HyperelasticLaw law = HyperelasticLaw::neo_hookean)
  {
    MeshOptions             options{std::string(NLMECH_SOURCE_DIR) + "/meshes/cantilever.geo", 0.05, {}, ""};
    const RawSimplexMesh<3> mesh = read_simplex_mesh<3>(options, 3);
    HyperelasticMaterial    material;
    material.law            = law;
    material.youngs_modulus = 1e5; // Pa: a soft silicone beam that sags visibly under its weight
    material.poissons_ratio = 0.4;
    material.density        = 1100;
    HyperelasticBoundaryConditions conditions;
    conditions.clamped = {"clamped"};
    HyperelasticLoads loads;
    loads.gravity = Tensor<1, 3>({0, 0, -gravity});
    return make_hyperelastic_problem(mesh, material, conditions, loads);
  }
} // namespace

TEST(AnmSolver, AgreesWithNewtonOnLargeDeflection)
{
  const HyperelasticProblem problem = soft_cantilever(9.81);
  Eigen::VectorXd           anm     = problem.rest_positions;
  AnmSettings               settings;
  settings.residual_tolerance = 1e-10;
  const AnmResult result      = AnmSolver(problem.internal, problem.load, settings).solve(anm);
  ASSERT_TRUE(result.completed) << result.stop_reason;
  std::cout << "ANM: " << result.steps.size() << " steps, " << result.factorizations << " factorizations, "
            << result.back_substitutions << " back-substitutions; series " << result.series_seconds
            << " s, factorization " << result.factorization_seconds << " s, solves " << result.solve_seconds
            << " s, total " << result.total_seconds << " s" << std::endl;
  for (const auto &s : result.steps)
    std::cout << "  step: lambda " << s.lambda_begin << " -> " << s.lambda_end << ", a = " << s.step_length
              << " (radius " << s.series_radius << (s.limited_by_inversion ? ", inversion bound" : "")
              << "), corrections " << s.corrections << ", residual " << s.residual << std::endl;
  Eigen::VectorXd          newton = problem.rest_positions;
  const LoadSteppingResult baseline =
      solve_with_load_stepping(problem.internal, problem.load, newton, 10, 1e-10);
  std::cout << "Newton, 10 load steps: " << baseline.iterations << " iterations, " << baseline.factorizations
            << " factorizations, " << baseline.seconds << " s" << std::endl;
  const double deflection = (anm - problem.rest_positions).lpNorm<Eigen::Infinity>();
  EXPECT_GT(deflection, 0.1); // large deformation: more than 10 % of the length
  EXPECT_LT((anm - newton).lpNorm<Eigen::Infinity>() / deflection, 1e-8);
  EXPECT_GE(result.steps.size(), 1u);
}

TEST(AnmSolver, LimitPointOfStVenantKirchhoffCompression)
{
  // Uniaxial compression of a St.Venant-Kirchhoff block: the nominal stress E a (a^2 - 1) / 2 has
  // its extreme -E / (3 sqrt 3) at a = 1/sqrt 3. A dead load twice as large has no equilibrium: the
  // ANM must pass the limit point, report it at that load, and stop without reaching lambda = 1.
  MeshOptions             options{std::string(NLMECH_SOURCE_DIR) + "/meshes/block.geo", 0.5, {}, ""};
  const RawSimplexMesh<3> mesh = read_simplex_mesh<3>(options, 3);
  HyperelasticMaterial    material;
  material.law            = HyperelasticLaw::saint_venant_kirchhoff;
  material.youngs_modulus = 1e6;
  material.poissons_ratio = 0.3;
  HyperelasticBoundaryConditions conditions;
  conditions.rollers      = {{"x0", 0}, {"y0", 1}, {"z0", 2}};
  const double      limit = material.youngs_modulus / (3 * std::sqrt(3.0));
  HyperelasticLoads loads;
  loads.tractions                   = {{"x1", Tensor<1, 3>({-2 * limit, 0, 0})}};
  const HyperelasticProblem problem = make_hyperelastic_problem(mesh, material, conditions, loads);
  Eigen::VectorXd           x       = problem.rest_positions;
  const AnmResult           result  = AnmSolver(problem.internal, problem.load, AnmSettings()).solve(x);
  EXPECT_FALSE(result.completed);
  EXPECT_NE(result.stop_reason.find("limit point"), std::string::npos) << result.stop_reason;
  EXPECT_NEAR(result.extreme_lambda * 2 * limit / limit, 1.0, 1e-4);
  EXPECT_TRUE(x.allFinite());
}

TEST(AnmSolver, LoadScaleChangeFromTheSeriesAtTheSolution)
{
  // Paper section 5.1: with the series at the solution (x, 1), another load scale is a polynomial
  // root and a series evaluation. Compare with fresh ANM solves to that scale.
  const HyperelasticProblem problem = soft_cantilever(9.81);
  Eigen::VectorXd           x       = problem.rest_positions;
  AnmSettings               settings;
  settings.residual_tolerance = 1e-10;
  const AnmSolver solver(problem.internal, problem.load, settings);
  ASSERT_TRUE(solver.solve(x).completed);
  const AnmSeries series = solver.series_at(x, 1.0);
  EXPECT_LT((series.state(0) - x).norm(), 1e-14 * x.norm());
  const FreeDofMap free(problem.internal);
  for (const double scale : {0.97, 1.03})
    {
      const double a = series.parameter_for(scale);
      ASSERT_TRUE(std::isfinite(a)) << "scale " << scale << " outside the radius " << series.radius;
      EXPECT_NEAR(series.load_factor(a), scale, 1e-12);
      const Eigen::VectorXd quick = series.state(a);
      Eigen::VectorXd       fresh = problem.rest_positions;
      ASSERT_TRUE(solver.solve(fresh, 0.0, scale).completed);
      const double deflection = (fresh - problem.rest_positions).lpNorm<Eigen::Infinity>();
      EXPECT_LT((quick - fresh).lpNorm<Eigen::Infinity>() / deflection, 1e-5) << "scale " << scale;
      const Eigen::VectorXd residual =
          free.restrict(problem.internal.gradient(quick)) - scale * free.restrict(problem.load);
      EXPECT_LT(residual.norm() / free.restrict(problem.load).norm(), 1e-4) << "scale " << scale;
    }
}

TEST(AnmSolver, LoadDirectionChangeFromAKnownSolution)
{
  // From the solution under gravity along -z, continue to gravity along -z plus a sideways pull
  // (a new load direction) with the ANM on the load-shifted system; compare with a fresh solve.
  const HyperelasticProblem problem = soft_cantilever(9.81);
  AnmSettings               settings;
  settings.residual_tolerance = 1e-10;
  Eigen::VectorXd x           = problem.rest_positions;
  ASSERT_TRUE(AnmSolver(problem.internal, problem.load, settings).solve(x).completed);

  Eigen::VectorXd new_load = problem.load;
  for (Eigen::Index i = 1; i < new_load.size(); i += 3)
    new_load[i] = 0.5 * problem.load[i + 1]; // y component: half the weight, sideways
  const ModelEquilibrium  forward(problem.internal);
  const LoadShiftedSystem shifted(forward, problem.load);
  ASSERT_TRUE(AnmSolver(shifted, new_load - problem.load, settings).solve(x).completed);

  Eigen::VectorXd fresh = problem.rest_positions;
  ASSERT_TRUE(AnmSolver(problem.internal, new_load, settings).solve(fresh).completed);
  const double deflection = (fresh - problem.rest_positions).lpNorm<Eigen::Infinity>();
  EXPECT_LT((x - fresh).lpNorm<Eigen::Infinity>() / deflection, 1e-8);
}

TEST(AnmSolver, PadeApproximantsLengthenSteps)
{
  // The same branch with and without Pade approximants: same answer, longer steps with them.
  const HyperelasticProblem problem = soft_cantilever(9.81 * 3);
  AnmSettings               settings;
  settings.residual_tolerance = 1e-10;
  Eigen::VectorXd plain       = problem.rest_positions;
  const AnmResult without     = AnmSolver(problem.internal, problem.load, settings).solve(plain);
  settings.pade               = true;
  Eigen::VectorXd pade        = problem.rest_positions;
  const AnmResult with        = AnmSolver(problem.internal, problem.load, settings).solve(pade);
  ASSERT_TRUE(without.completed) << without.stop_reason;
  ASSERT_TRUE(with.completed) << with.stop_reason;
  const double deflection = (plain - problem.rest_positions).lpNorm<Eigen::Infinity>();
  EXPECT_LT((pade - plain).lpNorm<Eigen::Infinity>() / deflection, 1e-8);
  double reach_series = 0, reach_pade = 0;
  for (const auto &s : with.steps)
    {
      reach_series += s.series_radius / with.steps.size();
      reach_pade += std::max(s.pade_radius, s.series_radius) / with.steps.size();
    }
  std::cout << "steps without Pade: " << without.steps.size() << ", with: " << with.steps.size()
            << "; mean series radius " << reach_series << ", mean Pade radius " << reach_pade << std::endl;
  EXPECT_LE(with.steps.size(), without.steps.size());
  EXPECT_GT(reach_pade, reach_series);
}
