// Tests source/models/solid/hyperelastic_tet_energy.cc and hyperelastic_model.cc: finite-difference
// checks of both laws, the Taylor-series gradient, the det F step bound, and uniaxial stretch of a
// block against the analytic solution of the neo-Hookean energy.
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/models/solid/hyperelastic_tet_energy.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <deal.II/base/multithread_info.h>

#include <gtest/gtest.h>

#include <random>

using namespace dealii;
using namespace nlmech;

namespace
{
  RawSimplexMesh<3> block_mesh(double h)
  {
    MeshOptions options{std::string(NLMECH_SOURCE_DIR) + "/meshes/block.geo", h, {}, ""};
    return read_simplex_mesh<3>(options, 3);
  }

  Eigen::VectorXd perturbed_positions(const RawSimplexMesh<3> &mesh, double amplitude, unsigned seed)
  {
    std::mt19937                           random(seed);
    std::uniform_real_distribution<double> uniform(-amplitude, amplitude);
    Eigen::VectorXd                        x(3 * mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int i = 0; i < 3; ++i)
        x[3 * v + i] = (1.0 + 0.2 * i) * mesh.vertices[v][i] + uniform(random);
    return x;
  }

  HyperelasticMaterial rubber(HyperelasticLaw law)
  {
    HyperelasticMaterial m;
    m.law            = law;
    m.youngs_modulus = 1e6;
    m.poissons_ratio = 0.45;
    m.density        = 1000;
    return m;
  }
} // namespace

class HyperelasticLaws : public ::testing::TestWithParam<HyperelasticLaw>
{
};

TEST_P(HyperelasticLaws, DerivativesMatchFiniteDifferences)
{
  const RawSimplexMesh<3>   mesh = block_mesh(0.5);
  const HyperelasticTetTerm term(mesh.vertices, mesh.cells, rubber(GetParam()));
  const Eigen::VectorXd     x = perturbed_positions(mesh, 0.02, 3);
  ASSERT_TRUE(term.is_valid(x));
  const DerivativeCheck check = check_derivatives(term, x, 1e-6);
  EXPECT_LT(check.gradient_error, 1e-6);
  EXPECT_LT(check.hessian_error, 1e-6);
}

TEST_P(HyperelasticLaws, StressTangentEqualsNestedAutomaticDifferentiation)
{
  // P and dP/dF of stress_and_tangent against forward AD on energy_density (P) and central
  // differences of P (C); the element Hessian V B^T C B against nested AD over the 12 unknowns.
  const RawSimplexMesh<3>   mesh = block_mesh(0.5);
  const HyperelasticTetTerm term(mesh.vertices, mesh.cells, rubber(GetParam()));
  HyperelasticTetElements   el      = term.elements();
  const Eigen::VectorXd     x       = perturbed_positions(mesh, 0.05, 9);
  double                    worst_P = 0, worst_C = 0, worst_H = 0, scale_P = 0, scale_C = 0, scale_H = 0;
  for (std::size_t e = 0; e < el.n_elements(); e += 7)
    {
      const auto             dofs = el.dofs(e);
      std::array<double, 12> local;
      for (int i = 0; i < 12; ++i)
        local[i] = x[dofs[i]];
      double F[3][3], P[9], C[9][9];
      el.deformation_gradient(local, e, F);
      el.stress_and_tangent(F, P, C);
      using Dual = ForwardGradient<double, 9>;
      Dual G[3][3];
      for (int ab = 0; ab < 9; ++ab)
        G[ab / 3][ab % 3] = Dual(F[ab / 3][ab % 3], ab);
      const Dual W = el.energy_density(G);
      for (int ab = 0; ab < 9; ++ab)
        {
          worst_P        = std::max(worst_P, std::abs(P[ab] - W.dx[ab]));
          scale_P        = std::max(scale_P, std::abs(W.dx[ab]));
          const double h = 1e-6;
          double       Fp[3][3], Fm[3][3], Pp[9], Pm[9], Cp[9][9];
          std::copy(&F[0][0], &F[0][0] + 9, &Fp[0][0]);
          std::copy(&F[0][0], &F[0][0] + 9, &Fm[0][0]);
          Fp[ab / 3][ab % 3] += h, Fm[ab / 3][ab % 3] -= h;
          el.stress_and_tangent(Fp, Pp, Cp);
          el.stress_and_tangent(Fm, Pm, Cp);
          for (int cd = 0; cd < 9; ++cd)
            {
              worst_C = std::max(worst_C, std::abs(C[cd][ab] - (Pp[cd] - Pm[cd]) / (2 * h)));
              scale_C = std::max(scale_C, std::abs(C[cd][ab]));
            }
        }
      Eigen::Matrix<double, 12, 12> H, H_ad;
      el.use_stress_tangent = true;
      ASSERT_TRUE(el.element_hessian(local, e, H));
      using Inner = Sacado::Fad::SFad<double, 12>;
      using Outer = Sacado::Fad::SFad<Inner, 12>;
      std::array<Outer, 12> nested;
      for (int i = 0; i < 12; ++i)
        nested[i] = Outer(12, i, Inner(12, i, local[i]));
      const Outer energy = el.energy(nested, e);
      for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
          H_ad(i, j) = energy.dx(i).dx(j);
      worst_H = std::max(worst_H, (H - H_ad).lpNorm<Eigen::Infinity>());
      scale_H = std::max(scale_H, H_ad.lpNorm<Eigen::Infinity>());
    }
  EXPECT_LT(worst_P, 1e-12 * scale_P);
  EXPECT_LT(worst_C, 1e-6 * scale_C);
  EXPECT_LT(worst_H, 1e-12 * scale_H);
}

TEST_P(HyperelasticLaws, SeriesGradientMatchesDerivativesAlongAPath)
{
  // x(a) = x0 + a x1 + a^2 x2: the Taylor coefficients of grad E(x(a)) of orders 1 and 2 against
  // central differences in a of the gradient (independent of the Taylor arithmetic).
  const RawSimplexMesh<3>   mesh = block_mesh(0.5);
  const HyperelasticTetTerm term(mesh.vertices, mesh.cells, rubber(GetParam()));
  const Eigen::VectorXd     x0          = perturbed_positions(mesh, 0.02, 5);
  const Eigen::VectorXd     x1          = perturbed_positions(mesh, 0.02, 6) * 0.01;
  const Eigen::VectorXd     x2          = perturbed_positions(mesh, 0.02, 7) * 0.01;
  auto                      gradient_at = [&](double a) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x0.size());
    term.add_gradient(x0 + a * x1 + a * a * x2, g);
    return g;
  };
  // By contract the coefficient of order k leaves out path[k], whose part is K path[k].
  const std::vector<Eigen::VectorXd> path = {x0, x1, x2};
  Eigen::SparseMatrix<double>        K(x0.size(), x0.size());
  {
    Triplets t;
    term.add_hessian(x0, t);
    K.setFromTriplets(t.begin(), t.end());
  }
  const double          h = 1e-3, h3 = 1e-2;
  const Eigen::VectorXd d1 = (gradient_at(h) - gradient_at(-h)) / (2 * h);
  const Eigen::VectorXd d2 = (gradient_at(h) - 2 * gradient_at(0) + gradient_at(-h)) / (2 * h * h);
  const Eigen::VectorXd d3 =
      (gradient_at(2 * h3) - 2 * gradient_at(h3) + 2 * gradient_at(-h3) - gradient_at(-2 * h3)) /
      (12 * h3 * h3 * h3);
  Eigen::VectorXd c1 = Eigen::VectorXd::Zero(x0.size()), c2 = c1, c3 = c1;
  term.add_gradient_series_coefficient(path, 1, c1);
  term.add_gradient_series_coefficient(path, 2, c2);
  term.add_gradient_series_coefficient(path, 3, c3);
  EXPECT_LT(c1.norm(), 1e-12 * d1.norm()); // order 1 is all tangent
  EXPECT_LT((K * x1 - d1).norm() / d1.norm(), 1e-6);
  EXPECT_LT((c2 + K * x2 - d2).norm() / d2.norm(), 1e-5);
  EXPECT_LT((c3 - d3).norm() / d3.norm(), 1e-3); // O(h^2) differences of a third derivative
}

TEST_P(HyperelasticLaws, TwoThreadsComputeWhatOneDoes)
{
  // Value, gradient, Hessian, series coefficients and step bounds, bit for bit, with deal.II's
  // task threads limited to one and to two (more elements than one block of the threaded loops).
  const RawSimplexMesh<3>   mesh = block_mesh(0.2);
  const HyperelasticTetTerm term(mesh.vertices, mesh.cells, rubber(GetParam()));
  ASSERT_GT(mesh.cells.size(), 2 * HyperelasticTetTerm::block_size); // three blocks or more
  std::vector<Eigen::VectorXd> path = {perturbed_positions(mesh, 0.02, 31)};
  for (unsigned int j = 1; j <= 6; ++j)
    path.push_back(perturbed_positions(mesh, 0.02, 31 + j) * std::pow(0.05, j));
  struct Results
  {
    double                       value, step, first_inversion;
    Eigen::VectorXd              gradient, hv;
    Triplets                     hessian;
    std::vector<Eigen::VectorXd> series;
  };
  auto evaluate = [&](const unsigned int threads) {
    MultithreadInfo::set_thread_limit(threads);
    EXPECT_EQ(MultithreadInfo::n_threads(), std::min(threads, MultithreadInfo::n_cores()));
    Results r;
    r.value    = term.value(path[0]);
    r.gradient = Eigen::VectorXd::Zero(path[0].size());
    term.add_gradient(path[0], r.gradient);
    r.hv = Eigen::VectorXd::Zero(path[0].size());
    term.add_hessian_vector_product(path[0], path[1], r.hv);
    term.add_hessian(path[0], r.hessian);
    for (unsigned int k = 2; k <= 6; ++k)
      {
        r.series.push_back(Eigen::VectorXd::Zero(path[0].size()));
        term.add_gradient_series_coefficient(path, k, r.series.back());
      }
    r.step            = term.max_safe_step(path[0], 50 * path[1]);
    r.first_inversion = term.first_invalid_along_series(path, 100.0);
    return r;
  };
  const Results one = evaluate(1), two = evaluate(2);
  MultithreadInfo::set_thread_limit(1);
  EXPECT_EQ(one.value, two.value);
  EXPECT_EQ(one.step, two.step);
  EXPECT_EQ(one.first_inversion, two.first_inversion);
  EXPECT_EQ((one.gradient - two.gradient).lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_EQ((one.hv - two.hv).lpNorm<Eigen::Infinity>(), 0.0);
  ASSERT_EQ(one.hessian.size(), two.hessian.size());
  for (std::size_t i = 0; i < one.hessian.size(); ++i)
    ASSERT_TRUE(one.hessian[i].row() == two.hessian[i].row() &&
                one.hessian[i].col() == two.hessian[i].col() &&
                one.hessian[i].value() == two.hessian[i].value());
  for (std::size_t k = 0; k < one.series.size(); ++k)
    EXPECT_EQ((one.series[k] - two.series[k]).lpNorm<Eigen::Infinity>(), 0.0) << "order " << k + 2;
}

TEST_P(HyperelasticLaws, SeriesKernelEqualsSacadoTaylorArithmetic)
{
  // The fast kernel (forward derivatives of W(F) over truncated series) against the generic
  // Sacado::Tay::Taylor path on the element energy in x, for orders 1..8 along a random path.
  const RawSimplexMesh<3>      mesh = block_mesh(0.5);
  const HyperelasticTetTerm    term(mesh.vertices, mesh.cells, rubber(GetParam()));
  std::vector<Eigen::VectorXd> path = {perturbed_positions(mesh, 0.02, 11)};
  for (unsigned int j = 1; j <= 8; ++j)
    path.push_back(perturbed_positions(mesh, 0.02, 11 + j) * std::pow(0.05, j));
  for (unsigned int k = 1; k <= 8; ++k)
    {
      Eigen::VectorXd fast = Eigen::VectorXd::Zero(path[0].size()), generic = fast;
      term.add_gradient_series_coefficient(path, k, fast);
      term.add_gradient_series_coefficient_by_taylor_ad(path, k, generic);
      EXPECT_LT((fast - generic).norm(), 1e-12 * std::max(1.0, generic.norm())) << "order " << k;
    }
}

TEST(NeoHookeanSeries, RecurrencesEqualTaylorArithmetic)
{
  // The auxiliary-variable recurrences (cached, O(k) per order) against the generic Sacado Taylor
  // arithmetic on the energy, and against the truncated-series kernel, orders 1..12 in sequence.
  const RawSimplexMesh<3>      mesh = block_mesh(0.5);
  const HyperelasticTetTerm    term(mesh.vertices, mesh.cells, rubber(HyperelasticLaw::neo_hookean));
  HyperelasticTetElements      kernels = term.elements();
  std::vector<Eigen::VectorXd> path    = {perturbed_positions(mesh, 0.02, 21)};
  for (unsigned int j = 1; j <= 12; ++j)
    path.push_back(perturbed_positions(mesh, 0.02, 21 + j) * std::pow(0.05, j));
  for (unsigned int k = 1; k <= 12; ++k)
    {
      Eigen::VectorXd recurrences = Eigen::VectorXd::Zero(path[0].size()), series = recurrences,
                      taylor = recurrences;
      auto add_kernel        = [&](Eigen::VectorXd &out) {
        kernels.prepare_series(k);
        for (std::size_t e = 0; e < kernels.n_elements(); ++e)
          {
            std::array<double, 12> local{};
            kernels.add_gradient_series_coefficient(path, k, e, local);
            const auto dofs = kernels.dofs(e);
            for (int i = 0; i < 12; ++i)
              out[dofs[i]] += local[i];
          }
      };
      kernels.use_recurrences = true;
      add_kernel(recurrences);
      kernels.use_recurrences = false;
      add_kernel(series);
      term.add_gradient_series_coefficient_by_taylor_ad(path, k, taylor);
      const double scale = std::max(1.0, taylor.norm());
      EXPECT_LT((recurrences - taylor).norm(), 1e-12 * scale) << "order " << k;
      EXPECT_LT((series - taylor).norm(), 1e-12 * scale) << "order " << k;
    }
}

INSTANTIATE_TEST_SUITE_P(BothLaws, HyperelasticLaws,
                         ::testing::Values(HyperelasticLaw::neo_hookean,
                                           HyperelasticLaw::saint_venant_kirchhoff));

TEST(HyperelasticTetTerm, SafeStepStopsAtInversion)
{
  // One tet, moving its apex through the base plane at t = 0.5: det F(t) = 1 - 2t.
  const std::vector<Point<3>>                  rest = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::vector<unsigned int>> tets = {{0, 1, 2, 3}};
  const HyperelasticTetTerm                    term(rest, tets, rubber(HyperelasticLaw::neo_hookean));
  Eigen::VectorXd                              x(12), dx = Eigen::VectorXd::Zero(12);
  for (int v = 0; v < 4; ++v)
    for (int i = 0; i < 3; ++i)
      x[3 * v + i] = rest[v][i];
  dx[11] = -2.0;
  EXPECT_NEAR(term.max_safe_step(x, dx), 0.5, 1e-12);
  EXPECT_NEAR(term.first_inversion_along_series({x, dx}, 1.0), 0.5, 1e-12);
  EXPECT_FALSE(term.is_valid(x + 0.6 * dx));
}

namespace
{
  // Nominal stress components of the neo-Hookean energy for F = diag(l1, l2, l2).
  std::array<double, 2> uniaxial_stress(double l1, double l2, double mu, double kappa)
  {
    const double J = l1 * l2 * l2, Ic = l1 * l1 + 2 * l2 * l2, s = std::pow(J, -2.0 / 3.0);
    return {{mu * s * (l1 - Ic / (3 * l1)) + kappa * (J - 1) * J / l1,
             mu * s * (l2 - Ic / (3 * l2)) + kappa * (J - 1) * J / l2}};
  }

  /// Stretches (l1, l2) with P11 = traction, P22 = 0, by Newton with a difference Jacobian.
  std::array<double, 2> uniaxial_stretches(double traction, double mu, double kappa)
  {
    double l1 = 1, l2 = 1;
    for (int it = 0; it < 100; ++it)
      {
        const auto   r  = uniaxial_stress(l1, l2, mu, kappa);
        const double f0 = r[0] - traction, f1 = r[1], h = 1e-7;
        const auto   a = uniaxial_stress(l1 + h, l2, mu, kappa), b = uniaxial_stress(l1, l2 + h, mu, kappa);
        const double j00 = (a[0] - r[0]) / h, j01 = (b[0] - r[0]) / h, j10 = (a[1] - r[1]) / h,
                     j11 = (b[1] - r[1]) / h, det = j00 * j11 - j01 * j10;
        l1 -= (j11 * f0 - j01 * f1) / det;
        l2 -= (-j10 * f0 + j00 * f1) / det;
      }
    return {{l1, l2}};
  }
} // namespace

TEST(HyperelasticStatics, UniaxialStretchMatchesAnalyticSolution)
{
  const RawSimplexMesh<3>        mesh     = block_mesh(0.35);
  const HyperelasticMaterial     material = rubber(HyperelasticLaw::neo_hookean);
  const double                   traction = 3e5; // Pa on the x = 1 face: about 30 % stretch
  HyperelasticBoundaryConditions conditions;
  conditions.rollers = {{"x0", 0}, {"y0", 1}, {"z0", 2}};
  HyperelasticLoads loads;
  loads.tractions                   = {{"x1", Tensor<1, 3>({traction, 0, 0})}};
  const HyperelasticProblem problem = make_hyperelastic_problem(mesh, material, conditions, loads);
  const auto stretch = uniaxial_stretches(traction, material.shear_modulus(), material.bulk_modulus());
  ASSERT_GT(stretch[0], 1.2);

  auto max_error = [&](const Eigen::VectorXd &x) {
    double worst = 0;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int i = 0; i < 3; ++i)
        worst = std::max(worst, std::abs(x[3 * v + i] - stretch[i == 0 ? 0 : 1] * mesh.vertices[v][i]));
    return worst;
  };
  Eigen::VectorXd newton = problem.rest_positions;
  solve_with_load_stepping(problem.internal, problem.load, newton, 3, 1e-11);
  EXPECT_LT(max_error(newton), 1e-8);

  Eigen::VectorXd anm = problem.rest_positions;
  AnmSettings     settings;
  settings.residual_tolerance = 1e-10;
  const AnmResult result      = AnmSolver(problem.internal, problem.load, settings).solve(anm);
  ASSERT_TRUE(result.completed) << result.stop_reason;
  EXPECT_LT(max_error(anm), 1e-8);
}
