// Strain limits and their projection: the directional stretch against the analytic value, the SOCP
// projection against the Gauss-Seidel baseline (it must be feasible and never farther away), convex
// limits only, infeasible pins, and the energy behaviour of the time-stepping schemes.
#include <nlmech/models/cloth/strain_limits.h>
#include <nlmech/solvers/socp/strain_projection.h>
#include <nlmech/solvers/time/cloth_simulation.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

using namespace nlmech;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  Eigen::VectorXd positions(const RawSimplexMesh<3> &mesh)
  {
    Eigen::VectorXd x(3 * mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int d = 0; d < 3; ++d)
        x[3 * v + d] = mesh.vertices[v][d];
    return x;
  }
  const std::array<double, 3> warp = {{1, 0, 0}}, weft = {{0, 0, 1}};
} // namespace

TEST(StrainLimits, DirectionalStretchOfAUniformStretchIsAnalytic)
{
  // x -> (s x, y, z): |F d(alpha)| = sqrt(s^2 cos^2 + sin^2); with limit 1 everywhere the largest
  // violation is at the direction closest to alpha = 0.
  const auto         mesh   = make_sheet_mesh(0.5, 4);
  const unsigned int m      = 8;
  const auto         limits = make_strain_limits(mesh, warp, weft, m, [](double) { return 1.0; });
  EXPECT_EQ(limits.size(), mesh.cells.size() * m);
  Eigen::VectorXd x = positions(mesh);
  const double    s = 1.3;
  for (Eigen::Index v = 0; v < x.size() / 3; ++v)
    x[3 * v] *= s;
  double expected = 0;
  for (unsigned int j = 0; j < m; ++j)
    {
      const double a = -pi / 2 + (j + 0.5) * pi / m;
      expected =
          std::max(expected, std::sqrt(s * s * std::cos(a) * std::cos(a) + std::sin(a) * std::sin(a)) - 1);
    }
  EXPECT_NEAR(max_violation(limits, x), expected, 1e-13);
  EXPECT_NEAR(max_violation(limits, positions(mesh)), 0.0, 1e-13);
}

TEST(StrainLimits, CompressionBoundsAreRejected)
{
  const auto mesh = make_sheet_mesh(0.5, 2);
  EXPECT_THROW(make_strain_limits(mesh, warp, weft, 4, [](double a) { return 1.05 - 0.1 * std::cos(a); }),
               std::exception);
}

TEST(StrainLimits, ALimitThatDipsBelowOneBetweenTheSamplesIsRejected)
{
  // 1.01 - 0.05 cos 8 alpha is 1.06 at the four sampled directions (8 alpha = +-180, +-540 deg) and
  // 0.96 between them: a compression bound there, which only a check beyond the samples finds.
  const auto mesh  = make_sheet_mesh(0.5, 2);
  const auto limit = [](double a) { return 1.01 - 0.05 * std::cos(8 * a); };
  for (const double a : {-67.5, -22.5, 22.5, 67.5})
    EXPECT_NEAR(limit(a * pi / 180), 1.06, 1e-12);
  EXPECT_THROW(make_strain_limits(mesh, warp, weft, 4, limit), std::exception);
  EXPECT_THROW(check_limit_curve(limit), std::exception);
  EXPECT_NO_THROW(check_limit_curve([](double a) { return 1.06 - 0.05 * std::cos(8 * a); }));
}

TEST(StrainLimits, CurveExcessOfAUniaxialStretchIsAnalytic)
{
  // x -> (s x, y, c z) with the limit 1.01 everywhere: the largest stretch is s along alpha = 0,
  // so the excess is (s - 1.01) / 0.01, and the stretch per direction is sqrt(s^2 cos^2 + c^2 sin^2).
  const auto      mesh   = make_sheet_mesh(0.5, 3);
  const auto      limits = make_strain_limits(mesh, warp, weft, 4, [](double) { return 1.01; });
  Eigen::VectorXd x      = positions(mesh);
  const double    s = 1.05, c = 0.97;
  for (Eigen::Index v = 0; v < x.size() / 3; ++v)
    x[3 * v] *= s, x[3 * v + 2] *= c;
  EXPECT_NEAR(max_curve_excess(limits, x), (s - 1.01) / 0.01, 1e-9);
  const auto over = curve_excesses(limits, x, 0.1);
  ASSERT_EQ(over.size(), mesh.cells.size());
  for (const auto &e : over)
    EXPECT_NEAR(std::remainder(e.alpha, pi), 0.0, 1e-6);
  const auto reached = largest_stretch_per_direction(limits, x);
  for (std::size_t k = 0; k < reached.size(); ++k)
    {
      const double a = limits.grid_angle[k];
      EXPECT_NEAR(reached[k], std::hypot(s * std::cos(a), c * std::sin(a)), 1e-12);
    }
  EXPECT_LT(max_curve_excess(limits, positions(mesh)), 0.0);
}

TEST(StrainLimits, TheProjectionHoldsTheCurveBetweenTheSamples)
{
  // The case of the issue: stretched along x with lateral contraction, |F d| <= 1.01 at +-22.5 deg
  // allows up to 1.01 / cos 22.5 deg = 1.093 along x. Sampled rows alone (tolerance 0) stop near
  // that; with the curve held (tolerance 0.1 of the 1 % strain) no direction passes 1.011.
  const auto    mesh = make_sheet_mesh(0.5, 8);
  ShellMaterial material;
  material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
  material.poissons_ratio = 0.41;
  const ShellModel shell  = make_shell_model(mesh, material);
  Eigen::VectorXd  x_hat  = shell.rest_positions;
  for (Eigen::Index v = 0; v < x_hat.size() / 3; ++v)
    x_hat[3 * v] *= 1.15, x_hat[3 * v + 2] *= 0.85;
  const std::map<std::size_t, double> fixed; // nothing pinned: the projection of a free sheet
  for (const double tolerance : {0.0, 0.1})
    {
      const auto limits = make_strain_limits(
          mesh, warp, weft, 4, [](double) { return 1.01; }, tolerance);
      StrainLimitProjector   projector(limits, shell.model.lumped_mass(), fixed);
      Eigen::VectorXd        x;
      const ProjectionResult r = projector.project(x_hat, x);
      ASSERT_EQ(r.status, ConicStatus::solved) << to_string(r.status);
      const double excess  = max_curve_excess(limits, x);
      double       along_x = 0;
      for (const double v : largest_stretch_per_direction(limits, x))
        along_x = std::max(along_x, v);
      std::printf("curve tolerance %.1f: %zu cuts, largest stretch %.5f, excess %.3f of the strain, %u "
                  "iterations in %u rounds\n",
                  tolerance, r.cuts_added, along_x, excess, r.iterations, r.rounds);
      if (tolerance == 0)
        {
          EXPECT_EQ(r.cuts_added, 0u);
          EXPECT_GT(along_x, 1.03); // the samples alone let the sheet stretch far beyond 1 % (1.039)
          EXPECT_GT(excess, 1.0);
        }
      else
        {
          EXPECT_GT(r.cuts_added, 0u);
          EXPECT_LE(excess, 0.1 + 1e-6);
          EXPECT_NEAR(r.curve_excess, excess, 1e-9);
          EXPECT_LE(along_x, 1.011 + 1e-8);
          EXPECT_LT(max_violation(projector.current_limits(), x), 1e-8);
          // A second, nearby projection reuses the cuts: none or few new ones.
          Eigen::VectorXd        x2;
          const ProjectionResult r2 = projector.project(x_hat * (1 + 1e-4), x2);
          ASSERT_EQ(r2.status, ConicStatus::solved);
          EXPECT_LE(r2.curve_excess, 0.1 + 1e-6);
          EXPECT_LT(r2.cuts_added, r.cuts_added);
        }
    }
}

TEST(StrainLimits, PinsWithinTheSamplesButBeyondTheCurveAreInfeasible)
{
  // Two corners pinned 5 % farther apart along x: the four sampled directions allow it (up to
  // 9.3 %), the 1 % curve does not.
  const auto    mesh = make_sheet_mesh(0.5, 6);
  ShellMaterial material;
  material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
  material.poissons_ratio             = 0.41;
  const ShellModel              shell = make_shell_model(mesh, material);
  std::map<std::size_t, double> fixed;
  for (const unsigned int p : {0u, 6u})
    for (unsigned int d = 0; d < 3; ++d)
      fixed[3 * p + d] = shell.rest_positions[3 * p + d] * (d == 0 ? 1.05 : 1.0);
  for (const double tolerance : {0.0, 0.1})
    {
      const auto limits = make_strain_limits(
          mesh, warp, weft, 4, [](double) { return 1.01; }, tolerance);
      StrainLimitProjector projector(limits, shell.model.lumped_mass(), fixed);
      Eigen::VectorXd      x;
      const auto           r = projector.project(shell.rest_positions, x);
      EXPECT_EQ(r.status, tolerance == 0 ? ConicStatus::solved : ConicStatus::primal_infeasible)
          << "tolerance " << tolerance << ": " << to_string(r.status);
    }
}

TEST(StrainLimits, ProjectionIsFeasibleAndNoFartherThanGaussSeidel)
{
  const auto mesh = make_sheet_mesh(0.5, 10);
  for (const double limit : {1.01, 1.1})
    {
      // The sampled rows only (curve tolerance 0): screening and starts are compared on one problem.
      const auto limits = make_strain_limits(
          mesh, warp, weft, 4, [&](double) { return limit; }, 0.0);
      ShellMaterial material;
      material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
      material.poissons_ratio             = 0.41;
      const ShellModel              shell = make_shell_model(mesh, material);
      std::map<std::size_t, double> fixed;
      for (const unsigned int p : {0u, 10u})
        for (unsigned int d = 0; d < 3; ++d)
          fixed[3 * p + d] = shell.rest_positions[3 * p + d];
      // A candidate: the sheet sagging and stretched by a random smooth field.
      std::mt19937                     rng(5);
      std::normal_distribution<double> normal(0, 0.01);
      Eigen::VectorXd                  x_hat = shell.rest_positions;
      for (Eigen::Index v = 0; v < x_hat.size() / 3; ++v)
        {
          const double X = shell.rest_positions[3 * v], Z = shell.rest_positions[3 * v + 2];
          x_hat[3 * v] *= 1.08;
          x_hat[3 * v + 1] -= 0.2 * Z * Z + 0.05 * std::sin(6 * X);
          x_hat[3 * v + 2] *= 1.05;
          for (int d = 0; d < 3; ++d)
            x_hat[3 * v + d] += normal(rng);
        }
      StrainLimitProjector   projector(limits, shell.model.lumped_mass(), fixed);
      Eigen::VectorXd        x;
      const ProjectionResult r = projector.project(x_hat, x);
      ASSERT_EQ(r.status, ConicStatus::solved) << to_string(r.status);
      EXPECT_LT(r.violation, 1e-8) << "limit " << limit;
      for (const auto &f : fixed)
        EXPECT_EQ(x[f.first], f.second);
      Eigen::VectorXd x_gs = x_hat;
      for (const auto &f : fixed)
        x_gs[f.first] = f.second;
      const auto gs =
          gauss_seidel_projection(limits, shell.model.lumped_mass(), fixed, x_gs, 1e-9, 100000, 30);
      ASSERT_TRUE(gs.converged);
      const double d_gs = std::sqrt((x_gs - x_hat).cwiseAbs2().dot(shell.model.lumped_mass()));
      std::printf("limit %.2f: SOCP %u iterations in %u rounds (%zu of %zu limits), %.3f s, distance %.6e; "
                  "Gauss-Seidel %u sweeps, %.3f s, distance %.6e\n",
                  limit, r.iterations, r.rounds, r.cones, limits.size(), r.seconds, r.distance, gs.sweeps,
                  gs.seconds, d_gs);
      EXPECT_LE(r.distance, d_gs * (1 + 1e-9)); // the SOCP point is the closest feasible one
      // Screening is exact: the full problem (screening 0) gives the same point, and solving it
      // again reuses the symbolic analysis.
      StrainLimitProjector full(limits, shell.model.lumped_mass(), fixed, {}, 0.0);
      Eigen::VectorXd      x_full;
      ASSERT_EQ(full.project(x_hat, x_full).status, ConicStatus::solved);
      EXPECT_LT((x_full - x).norm(), 1e-6 * x.norm()) << "limit " << limit;
      full.project(x_hat, x_full);
      EXPECT_EQ(full.solver().n_symbolic_analyses, 1u);
      // The default start (centred, at the candidate) against CVXOPT's start: the same point.
      ConicSettings cvxopt_start;
      cvxopt_start.start_mu = -1;
      StrainLimitProjector classic(limits, shell.model.lumped_mass(), fixed, cvxopt_start, 0.0);
      Eigen::VectorXd      x_classic;
      const auto           rc = classic.project(x_hat, x_classic);
      ASSERT_EQ(rc.status, ConicStatus::solved);
      EXPECT_LT((x_classic - x_full).norm(), 1e-6 * x.norm()) << "limit " << limit;
      std::printf("limit %.2f: centred start %u iterations, CVXOPT's start %u\n", limit, r.iterations,
                  rc.iterations);
    }
}

TEST(StrainLimits, WarmStartsFromTheLastProjectionGiveTheSamePoints)
{
  // A sequence of nearby candidates, as in time stepping: the projector warm-started from its
  // last projection (the default) against a cold one (warm_mu = 0), both screened.
  const auto mesh   = make_sheet_mesh(0.5, 10);
  const auto limits = make_strain_limits(
      mesh, warp, weft, 4, [](double) { return 1.01; }, 0.0);
  ShellMaterial material;
  material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
  material.poissons_ratio             = 0.41;
  const ShellModel              shell = make_shell_model(mesh, material);
  std::map<std::size_t, double> fixed;
  for (const unsigned int p : {0u, 10u})
    for (unsigned int d = 0; d < 3; ++d)
      fixed[3 * p + d] = shell.rest_positions[3 * p + d];
  ConicSettings cold_settings;
  cold_settings.warm_mu = 0;
  StrainLimitProjector warm(limits, shell.model.lumped_mass(), fixed);
  StrainLimitProjector cold(limits, shell.model.lumped_mass(), fixed, cold_settings);
  unsigned int         warm_iterations = 0, cold_iterations = 0;
  for (unsigned int k = 0; k < 6; ++k)
    {
      Eigen::VectorXd x_hat = shell.rest_positions;
      const double    a     = 0.02 + 0.01 * k;
      for (Eigen::Index v = 0; v < x_hat.size() / 3; ++v)
        {
          const double X = shell.rest_positions[3 * v], Z = shell.rest_positions[3 * v + 2];
          x_hat[3 * v] *= 1 + a;
          x_hat[3 * v + 1] -= 4 * a * Z * Z + a * std::sin(6 * X + k);
        }
      Eigen::VectorXd x_warm, x_cold;
      const auto      rw = warm.project(x_hat, x_warm);
      const auto      rc = cold.project(x_hat, x_cold);
      ASSERT_EQ(rw.status, ConicStatus::solved) << "step " << k;
      ASSERT_EQ(rc.status, ConicStatus::solved) << "step " << k;
      EXPECT_LT(rw.violation, 1e-8);
      EXPECT_LT((x_warm - x_cold).norm(), 1e-6 * x_cold.norm()) << "step " << k;
      warm_iterations += rw.iterations, cold_iterations += rc.iterations;
    }
  std::printf("six nearby candidates: %u iterations warm, %u cold\n", warm_iterations, cold_iterations);
}

TEST(StrainLimits, AFeasibleCandidateIsItsOwnProjection)
{
  const auto                    mesh   = make_sheet_mesh(0.5, 6);
  const auto                    limits = make_strain_limits(mesh, warp, weft, 4, [](double) { return 1.01; });
  ShellMaterial                 material;
  const ShellModel              shell = make_shell_model(mesh, material);
  std::map<std::size_t, double> fixed;
  for (unsigned int d = 0; d < 3; ++d)
    fixed[d] = shell.rest_positions[d];
  // Shrunk by 1 % about the pinned corner (at the origin) and stretched by 0.5 % along x:
  // every stretch is below 1.01.
  Eigen::VectorXd x_hat = 0.99 * shell.rest_positions;
  for (Eigen::Index v = 0; v < x_hat.size() / 3; ++v)
    x_hat[3 * v] *= 1.005 / 0.99;
  ASSERT_LT(max_violation(limits, x_hat), 0);
  StrainLimitProjector   projector(limits, shell.model.lumped_mass(), fixed);
  Eigen::VectorXd        x;
  const ProjectionResult r = projector.project(x_hat, x);
  EXPECT_EQ(r.status, ConicStatus::solved);
  EXPECT_EQ(r.iterations, 0u);
  EXPECT_EQ(x, x_hat);
}

TEST(StrainLimits, PinsFartherApartThanTheLimitsAllowAreInfeasible)
{
  const auto                    mesh   = make_sheet_mesh(0.5, 6);
  const auto                    limits = make_strain_limits(mesh, warp, weft, 4, [](double) { return 1.01; });
  ShellMaterial                 material;
  const ShellModel              shell = make_shell_model(mesh, material);
  std::map<std::size_t, double> fixed;
  // Corners 0 and 6 (along x, 0.5 m apart) pinned 0.6 m apart: 20 % > 1 %.
  for (unsigned int d = 0; d < 3; ++d)
    fixed[d] = shell.rest_positions[d], fixed[18 + d] = shell.rest_positions[18 + d];
  fixed[18] = 0.6;
  StrainLimitProjector projector(limits, shell.model.lumped_mass(), fixed);
  Eigen::VectorXd      x;
  const auto           r = projector.project(shell.rest_positions, x);
  EXPECT_EQ(r.status, ConicStatus::primal_infeasible) << to_string(r.status);
}

TEST(ClothSimulation, StepAndReflectLosesLessEnergyThanStepAndProject)
{
  // The swinging sheet (pinned at two corners of one edge, released horizontal), 1 % limits.
  const auto    mesh = make_sheet_mesh(0.5, 8);
  ShellMaterial material;
  material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
  material.poissons_ratio = 0.41;
  const auto limits       = make_strain_limits(mesh, warp, weft, 4, [](double) { return 1.01; });
  double     loss[2];
  int        k = 0;
  for (const ClothScheme scheme : {ClothScheme::sap, ClothScheme::sar})
    {
      ClothSettings settings;
      settings.scheme    = scheme;
      settings.time_step = 1.0 / 60;
      ClothSimulation sim(mesh, material, {0, 8}, limits, settings);
      const double    e0    = sim.energy().total();
      double          worst = -1;
      for (int step = 0; step < 60; ++step)
        worst = std::max(worst, sim.step().violation);
      loss[k++] = e0 - sim.energy().total();
      std::printf("%s: total energy lost over 1 s %.4e J, largest violation %.2e\n",
                  to_string(scheme).c_str(), loss[k - 1], worst);
      EXPECT_LT(worst, 1e-8);
    }
  EXPECT_LT(loss[1], loss[0]);
}

/// A sheet crumpled between its pins (held at 60 % of their distance, vertices pushed together and
/// jittered out of plane), stepped by implicit Euler at ten times the default step: Newton on
/// projected element Hessians must converge in every step. The exact Hessian with a global shift is
/// run beside it for the record (it may need many more iterations or fail; not asserted).
TEST(ClothSimulation, ImplicitStepsOfACrumpledSheetConvergeWithProjectedHessians)
{
  const unsigned n    = 16;
  const auto     mesh = make_sheet_mesh(0.5, n);
  ShellMaterial  material;
  material.thickness = 5e-4, material.density = 200, material.youngs_modulus = 1800,
  material.poissons_ratio                      = 0.41;
  const Eigen::VectorXd                  rest  = positions(mesh);
  Eigen::VectorXd                        start = rest;
  std::mt19937                           random(11);
  std::uniform_real_distribution<double> jitter(-2e-3, 2e-3);
  for (Eigen::Index v = 0; v < start.size() / 3; ++v)
    start[3 * v] *= 0.6, start[3 * v + 1] += jitter(random);
  const std::vector<std::array<double, 3>> offsets = {
      {{start[0] - rest[0], start[1] - rest[1], 0}},
      {{start[3 * n] - rest[3 * n], start[3 * n + 1] - rest[3 * n + 1], 0}}};
  unsigned int iterations[2] = {0, 0};
  for (const bool project : {true, false})
    {
      ClothSettings settings;
      settings.scheme                   = ClothScheme::ie;
      settings.time_step                = 10.0 / 60;
      settings.project_element_hessians = project;
      ClothSimulation sim(mesh, material, {0, n}, {}, settings, {}, offsets);
      sim.set_state(start, Eigen::VectorXd::Zero(start.size()));
      try
        {
          for (int step = 0; step < 6; ++step)
            {
              const ClothStepStatistics st = sim.step();
              iterations[project ? 0 : 1] += st.newton_iterations;
              EXPECT_TRUE(sim.positions().allFinite());
            }
          std::printf("%s Hessians: %u Newton iterations over 6 steps\n", project ? "projected" : "exact",
                      iterations[project ? 0 : 1]);
        }
      catch (const std::exception &e)
        {
          std::printf("%s Hessians failed: %s\n", project ? "projected" : "exact", e.what());
          EXPECT_FALSE(project) << e.what();
        }
    }
}

/// The area barrier of the cloth (crushed triangles): zero at rest and for mild compression, its
/// derivatives against finite differences where triangles are crushed below a tenth of their area,
/// and infinite energy never reached by a finite state.
TEST(ClothSimulation, AreaBarrierIsInactiveAtRestAndHasExactDerivatives)
{
  const unsigned n    = 6;
  const auto     mesh = make_sheet_mesh(0.5, n);
  ClothSettings  settings;
  settings.scheme = ClothScheme::ie;
  ClothSimulation   sim(mesh, ShellMaterial(), {0, n}, {}, settings);
  const EnergyTerm *barrier = nullptr;
  for (const auto &term : sim.shell().model.terms())
    if (term->name() == "area barrier")
      barrier = term.get();
  ASSERT_NE(barrier, nullptr);
  const Eigen::VectorXd rest = positions(mesh);
  EXPECT_EQ(barrier->value(rest), 0.0);
  EXPECT_EQ(barrier->value(0.5 * rest), 0.0); // a quarter of the area: still above 0.1
  // Crush the sheet along x to 5 % and jitter: most triangles keep 3-8 % of their area.
  Eigen::VectorXd                        crushed = rest;
  std::mt19937                           random(3);
  std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
  for (Eigen::Index v = 0; v < crushed.size() / 3; ++v)
    crushed[3 * v] *= 0.05, crushed[3 * v] += jitter(random), crushed[3 * v + 1] += jitter(random);
  EXPECT_GT(barrier->value(crushed), 0.0);
  const DerivativeCheck check = check_derivatives(*barrier, crushed, 1e-8);
  EXPECT_LT(check.gradient_error, 1e-6);
  EXPECT_LT(check.hessian_error, 1e-6);
}
