// Tests source/models/solid/inverse_hyperelastic.cc: the inverse internal force against the forward
// energy gradient, its non-symmetric tangent and series against finite differences, and the
// inverse-then-forward round trip by ANM and by Newton.
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/models/solid/inverse_hyperelastic.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/linear/sparse_factorization.h>
#include <nlmech/solvers/relaxation/levenberg_marquardt.h>

#include <gtest/gtest.h>

#include <memory>
#include <random>

using namespace dealii;
using namespace nlmech;

namespace
{
  const std::string source_dir = NLMECH_SOURCE_DIR;

  HyperelasticMaterial silicone(double E = 1e5)
  {
    HyperelasticMaterial m;
    m.youngs_modulus = E;
    m.poissons_ratio = 0.45;
    m.density        = 1100;
    return m;
  }

  Eigen::VectorXd positions(const RawSimplexMesh<3> &mesh)
  {
    Eigen::VectorXd x(3 * mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int i = 0; i < 3; ++i)
        x[3 * v + i] = mesh.vertices[v][i];
    return x;
  }

  std::vector<unsigned int> vertices_of(const RawSimplexMesh<3> &mesh, const std::string &group)
  {
    std::vector<unsigned int> out;
    const unsigned int        id = mesh.groups.boundary_id(group);
    for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f)
      if (mesh.boundary_face_id[f] == id)
        out.insert(out.end(), mesh.boundary_faces[f].begin(), mesh.boundary_faces[f].end());
    return out;
  }
} // namespace

TEST(InverseHyperelastic, ForceEqualsForwardGradientAndTangentMatchesDifferences)
{
  MeshOptions                            options{source_dir + "/meshes/block.geo", 0.5, {}, ""};
  const RawSimplexMesh<3>                mesh   = read_simplex_mesh<3>(options, 3);
  const Eigen::VectorXd                  target = positions(mesh);
  std::mt19937                           random(1);
  std::uniform_real_distribution<double> uniform(-0.03, 0.03);
  Eigen::VectorXd                        rest = target;
  for (auto &v : rest)
    v += uniform(random);
  const InverseHyperelasticSystem system(mesh, target, silicone(), vertices_of(mesh, "x0"));

  // Forward: the gradient in x of the energy built on rest shape `rest`, evaluated at the target.
  std::vector<Point<3>> rest_points(mesh.vertices.size());
  for (std::size_t v = 0; v < rest_points.size(); ++v)
    rest_points[v] = Point<3>(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
  const HyperelasticTetTerm forward(rest_points, mesh.cells, silicone());
  Eigen::VectorXd           g = Eigen::VectorXd::Zero(target.size());
  forward.add_gradient(target, g);
  const Eigen::VectorXd r = system.internal_force(rest);
  EXPECT_LT((r - g).norm(), 1e-10 * g.norm());

  // Non-symmetric tangent dr/dX against central differences.
  const Eigen::MatrixXd K     = Eigen::MatrixXd(system.tangent(rest));
  double                worst = 0;
  const double          h     = 1e-7;
  for (int j = 0; j < rest.size(); ++j)
    {
      Eigen::VectorXd p = rest, m = rest;
      p[j] += h, m[j] -= h;
      worst = std::max(worst, ((system.internal_force(p) - system.internal_force(m)) / (2 * h) - K.col(j))
                                  .lpNorm<Eigen::Infinity>());
    }
  EXPECT_LT(worst, 1e-5 * K.lpNorm<Eigen::Infinity>());
  EXPECT_GT((K - K.transpose()).lpNorm<Eigen::Infinity>(), 1e-3 * K.lpNorm<Eigen::Infinity>());
  // The stress-tangent kernel against nested AD over element_force.
  InverseHyperelasticSystem by_ad(mesh, target, silicone(), vertices_of(mesh, "x0"));
  by_ad.use_stress_tangent = false;
  EXPECT_LT((K - Eigen::MatrixXd(by_ad.tangent(rest))).lpNorm<Eigen::Infinity>(),
            1e-12 * K.lpNorm<Eigen::Infinity>());

  // Series: coefficient 2 along X(a) = X0 + a X1 (+ K X2) against second differences.
  Eigen::VectorXd X1 = Eigen::VectorXd::Zero(rest.size());
  for (auto &v : X1)
    v = uniform(random);
  const double          a = 1e-3;
  const Eigen::VectorXd d2 =
      (system.internal_force(rest + a * X1) - 2 * r + system.internal_force(rest - a * X1)) / (2 * a * a);
  const Eigen::VectorXd c2 = system.internal_force_series_coefficient({rest, X1}, 2);
  EXPECT_LT((c2 - d2).norm(), 1e-5 * d2.norm());
}

TEST(InverseHyperelastic, SeriesByRecurrencesEqualsTruncatedSeries)
{
  // The O(k) recurrence kernel (D_m, adj D_m, det D_m, F = D_s adj / det, then the neo-Hookean
  // recurrences) against element_force on truncated series, orders 2..14 in sequence on one path
  // and again from order 2 on a second path (the cache must restart).
  MeshOptions                            options{source_dir + "/meshes/block.geo", 0.5, {}, ""};
  const RawSimplexMesh<3>                mesh   = read_simplex_mesh<3>(options, 3);
  const Eigen::VectorXd                  target = positions(mesh);
  std::mt19937                           random(3);
  std::uniform_real_distribution<double> uniform(-0.03, 0.03);
  InverseHyperelasticSystem              system(mesh, target, silicone(), vertices_of(mesh, "x0"));
  for (const int pass : {0, 1})
    {
      std::vector<Eigen::VectorXd> path(15, target);
      for (std::size_t j = 0; j < path.size(); ++j)
        for (auto &v : path[j])
          v = (j == 0 ? v : 0.0) + uniform(random) * std::pow(0.3, j) * (pass + 1);
      std::vector<Eigen::VectorXd> known(path.begin(), path.begin() + 2); // grows as the ANM's does
      for (unsigned int k = 2; k <= 14; known.push_back(path[k]), ++k)
        {
          system.use_recurrences            = true;
          const Eigen::VectorXd recurrences = system.internal_force_series_coefficient(known, k);
          system.use_recurrences            = false;
          const Eigen::VectorXd generic     = system.internal_force_series_coefficient(known, k);
          EXPECT_LT((recurrences - generic).norm(), 1e-12 * std::max(1.0, generic.norm()))
              << "pass " << pass << ", order " << k << ", |generic| " << generic.norm();
        }
    }
}

class RoundTrip : public ::testing::TestWithParam<double>
{
};

TEST_P(RoundTrip, ReproducesTheTarget)
{
  // The target: a straight soft bar. Its rest shape must sag upwards so that gravity pulls it
  // straight (paper Fig. 5). Forward from the computed rest shape must give back the target.
  MeshOptions options{
      source_dir + "/meshes/cantilever.geo", 0.015, {{"L", 0.3}, {"W", 0.03}, {"H", 0.03}}, ""};
  const RawSimplexMesh<3> mesh   = read_simplex_mesh<3>(options, 3);
  const Eigen::VectorXd   target = positions(mesh);
  HyperelasticLoads       loads;
  loads.gravity = Tensor<1, 3>({0, 0, -9.81});
  HyperelasticBoundaryConditions conditions;
  conditions.clamped = {"clamped"};
  const HyperelasticProblem forward_on_target =
      make_hyperelastic_problem(mesh, silicone(GetParam()), conditions, loads);
  const Eigen::VectorXd g = forward_on_target.load; // lumped weight of the target shape

  const InverseHyperelasticSystem system(mesh, target, silicone(GetParam()), vertices_of(mesh, "clamped"));
  Eigen::VectorXd                 rest = target;
  AnmSettings                     settings;
  settings.residual_tolerance = 1e-10;
  const AnmResult result      = AnmSolver(system, g, settings).solve(rest);
  ASSERT_TRUE(result.completed) << result.stop_reason;
  EXPECT_GT((rest - target).lpNorm<Eigen::Infinity>(), 1e-3); // a different rest shape

  // Forward from the computed rest shape, under the same nodal loads.
  RawSimplexMesh<3> rest_mesh = mesh;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    rest_mesh.vertices[v] = Point<3>(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
  HyperelasticLoads   no_gravity;
  HyperelasticProblem forward =
      make_hyperelastic_problem(rest_mesh, silicone(GetParam()), conditions, no_gravity);
  forward.load = g;
  {
    // The target must be a stable equilibrium of the computed rest shape (Hessian positive definite).
    SparseFactorization factorization;
    factorization.factorize(FreeDofMap(forward.internal).restrict(forward.internal.hessian(target)));
    EXPECT_TRUE(factorization.positive_definite());
  }
  Eigen::VectorXd x     = forward.rest_positions;
  const AnmResult check = AnmSolver(forward.internal, forward.load, settings).solve(x);
  ASSERT_TRUE(check.completed) << check.stop_reason;
  const double diagonal = std::sqrt(0.3 * 0.3 + 2 * 0.03 * 0.03);
  EXPECT_LT((x - target).lpNorm<Eigen::Infinity>() / diagonal, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(StiffAndSoft, RoundTrip, ::testing::Values(1e7, 1e6));

TEST(InverseHyperelastic, TooSoftBarHasAnUnstableTarget)
{
  // At E = 0.1 MPa the bar that should hang straight needs a rest shape curled into a hook (0.4 m
  // from the target); the straight target is then an unstable equilibrium of it (like an inverted
  // pendulum), so a fabricated part would not stay there. The system must say so.
  MeshOptions options{
      source_dir + "/meshes/cantilever.geo", 0.015, {{"L", 0.3}, {"W", 0.03}, {"H", 0.03}}, ""};
  const RawSimplexMesh<3> mesh   = read_simplex_mesh<3>(options, 3);
  const Eigen::VectorXd   target = positions(mesh);
  HyperelasticLoads       loads;
  loads.gravity = Tensor<1, 3>({0, 0, -9.81});
  HyperelasticBoundaryConditions conditions;
  conditions.clamped                = {"clamped"};
  const Eigen::VectorXd           g = make_hyperelastic_problem(mesh, silicone(1e5), conditions, loads).load;
  const InverseHyperelasticSystem system(mesh, target, silicone(1e5), vertices_of(mesh, "clamped"));
  Eigen::VectorXd                 rest = target;
  ASSERT_TRUE(AnmSolver(system, g, AnmSettings()).solve(rest).completed);
  EXPECT_GT((rest - target).lpNorm<Eigen::Infinity>(), 0.3);
  RawSimplexMesh<3> rest_mesh = mesh;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    rest_mesh.vertices[v] = Point<3>(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
  const HyperelasticProblem forward = make_hyperelastic_problem(rest_mesh, silicone(1e5), conditions, {});
  SparseFactorization       factorization;
  factorization.factorize(FreeDofMap(forward.internal).restrict(forward.internal.hessian(target)));
  EXPECT_FALSE(factorization.positive_definite());
}

namespace
{
  /// A stiffer bar (E = 1 MPa), moderately nonlinear, where Newton with line search converges with
  /// load stepping, and its ANM rest shape.
  class StiffBar : public ::testing::Test
  {
  protected:
    void SetUp() override
    {
      MeshOptions options{
          source_dir + "/meshes/cantilever.geo", 0.015, {{"L", 0.3}, {"W", 0.03}, {"H", 0.03}}, ""};
      mesh                          = read_simplex_mesh<3>(options, 3);
      HyperelasticMaterial material = silicone();
      material.youngs_modulus       = 1e7;
      HyperelasticLoads loads;
      loads.gravity = Tensor<1, 3>({0, 0, -9.81});
      HyperelasticBoundaryConditions conditions;
      conditions.clamped = {"clamped"};
      g                  = make_hyperelastic_problem(mesh, material, conditions, loads).load;
      x                  = positions(mesh);
      system = std::make_unique<InverseHyperelasticSystem>(mesh, x, material, vertices_of(mesh, "clamped"));
      rest   = x;
      AnmSettings settings;
      settings.residual_tolerance = 1e-10;
      ASSERT_TRUE(AnmSolver(*system, g, settings).solve(rest).completed);
    }

    RawSimplexMesh<3>                          mesh;
    Eigen::VectorXd                            g, x, rest;
    std::unique_ptr<InverseHyperelasticSystem> system;
  };
} // namespace

TEST_F(StiffBar, AnmAgreesWithNewton)
{
  // Both solvers must find the same rest shape.
  Eigen::VectorXd newton = x;
  solve_equilibrium_with_newton(*system, g, newton, 10, 1e-10);
  EXPECT_GT((rest - x).lpNorm<Eigen::Infinity>(), 5e-3);
  EXPECT_LT((newton - rest).lpNorm<Eigen::Infinity>(), 1e-8 * (rest - x).lpNorm<Eigen::Infinity>());
}

TEST_F(StiffBar, LevenbergMarquardtByCeresFindsTheAnmRestShape)
{
  // The paper's baseline (Ceres' Levenberg-Marquardt on |r(X) - g|^2 from X = x): the same rest
  // shape as the ANM, to the residual tolerance (1e-9: the normal equations square the tangent's
  // condition number, and LM stagnates near 2e-10 here).
  Eigen::VectorXd            lm = x;
  LevenbergMarquardtSettings lms;
  lms.relative_tolerance           = 1e-9;
  const LevenbergMarquardtResult r = solve_with_levenberg_marquardt(*system, g, lm, lms);
  std::printf("Levenberg-Marquardt (Ceres): %u iterations, %u linear solves, residual %.2g, %.2f s\n",
              r.iterations, r.factorizations, r.residual, r.seconds);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.residual, 1e-9);
  EXPECT_GT(r.iterations, 0u);
  EXPECT_LT((lm - rest).lpNorm<Eigen::Infinity>(), 1e-7 * (rest - x).lpNorm<Eigen::Infinity>());
  for (const auto &f : system->fixed()) // the supports stay where they are
    EXPECT_EQ(lm[f.first], f.second);
}

namespace
{
  /// The bar of prm/inverse-bar.prm at 15 mm (0.3 m x 0.03 m x 0.03 m, clamped at x = 0) as the
  /// target, under its weight: load, target positions and the inverse system.
  struct BarUnderItsWeight
  {
    explicit BarUnderItsWeight(const HyperelasticMaterial &material)
        : material(material)
    {
      MeshOptions options{
          source_dir + "/meshes/cantilever.geo", 0.015, {{"L", 0.3}, {"W", 0.03}, {"H", 0.03}}, ""};
      mesh = read_simplex_mesh<3>(options, 3);
      HyperelasticLoads loads;
      loads.gravity      = Tensor<1, 3>({0, 0, -9.81});
      conditions.clamped = {"clamped"};
      g                  = make_hyperelastic_problem(mesh, material, conditions, loads).load;
      x                  = positions(mesh);
      system = std::make_unique<InverseHyperelasticSystem>(mesh, x, material, vertices_of(mesh, "clamped"));
    }
    HyperelasticMaterial                       material;
    RawSimplexMesh<3>                          mesh;
    HyperelasticBoundaryConditions             conditions;
    Eigen::VectorXd                            g, x;
    std::unique_ptr<InverseHyperelasticSystem> system;
  };
} // namespace

TEST(InverseHyperelastic, AdaptiveLoadStepsTakeNewtonWhereOneStepFails)
{
  // The soft bar of prm/inverse-bar.prm (E = 1 MPa, tip sag ~0.15 m): the inverse residual is so
  // nonlinear along a rest-shape bend (per-element rotations leave the force unchanged to first
  // order, not to second) that Newton from X = x stalls at the first increment of 1/20 unless the
  // increment shrinks. Adaptive steps from one step of 1 must reach the ANM rest shape.
  const BarUnderItsWeight          bar(silicone(1e6));
  const Eigen::VectorXd           &g = bar.g, &x = bar.x;
  const InverseHyperelasticSystem &system = *bar.system;
  Eigen::VectorXd                  rest   = x;
  AnmSettings                      settings;
  settings.residual_tolerance = 1e-10;
  ASSERT_TRUE(AnmSolver(system, g, settings).solve(rest).completed);

  NewtonSettings newton;
  newton.max_iterations              = 15;
  Eigen::VectorXd          by_newton = x;
  const LoadSteppingResult r         = solve_equilibrium_with_newton(system, g, by_newton, 1, 1e-10, newton);
  std::printf("adaptive Newton: %u load steps, %u rejected, smallest increment %g, %u iterations\n",
              r.load_steps, r.rejected_steps, r.smallest_increment, r.iterations);
  EXPECT_GT(r.rejected_steps, 0u); // one step of 1 is too much
  EXPECT_LT(r.smallest_increment, 1.0);
  EXPECT_GT((rest - x).lpNorm<Eigen::Infinity>(), 0.05);
  EXPECT_LT((by_newton - rest).lpNorm<Eigen::Infinity>(), 1e-7 * (rest - x).lpNorm<Eigen::Infinity>());
}

TEST(InverseHyperelastic, MultiTargetRestShapeByReducedBasis)
{
  // Paper section 5.2 on two load cases of one target (the bar straight under g and under 1.5 g):
  // individual rest shapes, the reduced-basis least-squares rest shape, and the forward results.
  const BarUnderItsWeight          bar(silicone(1e6));
  const RawSimplexMesh<3>         &mesh     = bar.mesh;
  const HyperelasticMaterial      &material = bar.material;
  const Eigen::VectorXd           &g = bar.g, &x = bar.x;
  const InverseHyperelasticSystem &system     = *bar.system;
  const auto                      &conditions = bar.conditions;
  AnmSettings                      settings;
  settings.residual_tolerance = 1e-10;
  std::vector<AnmSeries>       series;
  std::vector<Eigen::VectorXd> individual;
  for (const double scale : {1.0, 1.5})
    {
      const Eigen::VectorXd load = scale * g;
      const AnmSolver       solver(system, load, settings);
      Eigen::VectorXd       rest = x;
      ASSERT_TRUE(solver.solve(rest).completed);
      individual.push_back(rest);
      series.push_back(solver.series_at(rest, 1.0));
    }
  const Eigen::VectorXd combined = reduced_basis_rest_shape(series);
  EXPECT_LT((combined - 0.5 * (individual[0] + individual[1])).norm(), 1e-8 * combined.norm());

  // Forward from the combined rest shape: each case misses its target, by less than the distance
  // between the two individual rest shapes.
  RawSimplexMesh<3> rest_mesh = mesh;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    rest_mesh.vertices[v] = Point<3>(combined[3 * v], combined[3 * v + 1], combined[3 * v + 2]);
  HyperelasticProblem forward = make_hyperelastic_problem(rest_mesh, material, conditions, {});
  const double        spread  = (individual[0] - individual[1]).lpNorm<Eigen::Infinity>();
  for (const double scale : {1.0, 1.5})
    {
      forward.load      = scale * g;
      Eigen::VectorXd y = forward.rest_positions;
      ASSERT_TRUE(AnmSolver(forward.internal, forward.load, settings).solve(y).completed);
      const double miss = (y - x).lpNorm<Eigen::Infinity>();
      EXPECT_GT(miss, 1e-6);
      EXPECT_LT(miss, spread);
    }
}
