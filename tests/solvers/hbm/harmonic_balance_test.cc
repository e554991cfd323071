// Harmonic balance against independent references: finite differences of the residual, the dense
// DFT, the exact Duffing backbone (complete elliptic integral), the linear steady state, Newmark.
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/dynamics/spring_network.h>
#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>

#include "hbm_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace nlmech;
using nlmech::testing::jacobian_difference;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  Model duffing(double m, double k, double k3)
  {
    return make_duffing_model(m, k, k3);
  }

  /// A mass between two pre-stretched geometric springs in the plane (anchors at x = -+1).
  Model two_spring_mass()
  {
    return make_two_spring_mass_model(0.3, 2.0, 0.5, 1.0, 0.8);
  }

  Eigen::VectorXd random_coefficients(const HarmonicBalance &hb, double size, unsigned int seed)
  {
    std::srand(seed);
    return size * Eigen::VectorXd::Random(hb.n_unknowns());
  }
} // namespace

TEST(HarmonicBalance, JacobianAndFrequencyDerivativeMatchFiniteDifferences)
{
  const Model             model = two_spring_mass();
  HarmonicBalanceSettings settings;
  settings.n_harmonics        = 3;
  settings.rayleigh_mass      = 0.2;
  settings.rayleigh_stiffness = 0.01;
  const HarmonicBalance hb(model, settings, {{3, 0.4, 0.3}}, {{2, 0.05, 0.1, 50.0, 0.0, {}, {}}});
  Eigen::VectorXd       z     = random_coefficients(hb, 0.1, 1);
  const double          omega = 1.7;
  EXPECT_LT(jacobian_difference(hb, z, omega, 1e-6), 1e-6);
  const Eigen::VectorXd dw = (hb.residual(z, omega + 1e-6) - hb.residual(z, omega - 1e-6)) / 2e-6;
  EXPECT_LT((dw - hb.d_residual_d_omega(z, omega)).lpNorm<Eigen::Infinity>(),
            1e-6 * std::max(1.0, dw.norm()));
}

TEST(HarmonicBalance, FftEqualsDenseDft)
{
  const Model             model = two_spring_mass();
  HarmonicBalanceSettings fft, dense;
  fft.n_harmonics = dense.n_harmonics = 4;
  fft.n_samples = dense.n_samples = 15; // not a power of two
  dense.use_fft                   = false;
  const HarmonicBalance a(model, fft, {{3, 0.4, 0.3}}), b(model, dense, {{3, 0.4, 0.3}});
  const Eigen::VectorXd z = random_coefficients(a, 0.1, 2);
  EXPECT_LT((a.residual(z, 2.0) - b.residual(z, 2.0)).lpNorm<Eigen::Infinity>(), 1e-13);
  EXPECT_LT(
      (Eigen::MatrixXd(a.jacobian(z, 2.0)) - Eigen::MatrixXd(b.jacobian(z, 2.0))).lpNorm<Eigen::Infinity>(),
      1e-12);
}

TEST(HarmonicBalance, RejectsTooFewTimeSamplesAndNoHarmonics)
{
  const Model             model = duffing(1, 1, 1);
  HarmonicBalanceSettings settings;
  settings.n_harmonics = 5;
  settings.n_samples   = 10; // < 2 * 5 + 1
  EXPECT_THROW(HarmonicBalance(model, settings), std::exception);
  settings.n_harmonics = 0;
  settings.n_samples   = 0;
  EXPECT_THROW(HarmonicBalance(model, settings), std::exception);
}

/// Undamped, unforced Duffing x'' + x + x^3 = 0: the frequency of the free oscillation with c_1
/// held (phase fixed by s_k = 0), against w = pi sqrt(1 + A^2) / (2 K(m)), m = A^2 / (2 (1 + A^2)).
double backbone_error(unsigned int H, double c1)
{
  const Model             model = duffing(1, 1, 1);
  HarmonicBalanceSettings settings;
  settings.n_harmonics = H;
  const HarmonicBalance hb(model, settings);
  // Unknowns: c_0, c_2..c_H and w (s_k = 0 by symmetry, c_1 held); equations: the c-rows.
  Eigen::VectorXd z               = Eigen::VectorXd::Zero(hb.n_unknowns());
  z[2]                            = c1;
  double                    omega = std::sqrt(1 + 0.75 * c1 * c1);
  std::vector<Eigen::Index> rows = {0}, cols = {0};
  for (unsigned int k = 1; k <= H; ++k)
    {
      rows.push_back(2 * k);
      if (k > 1)
        cols.push_back(2 * k);
    }
  for (int it = 0; it < 30; ++it)
    {
      const Eigen::VectorXd h  = hb.residual(z, omega);
      const Eigen::MatrixXd J  = Eigen::MatrixXd(hb.jacobian(z, omega));
      const Eigen::VectorXd hw = hb.d_residual_d_omega(z, omega);
      Eigen::MatrixXd       A(rows.size(), rows.size());
      Eigen::VectorXd       r(rows.size());
      for (std::size_t i = 0; i < rows.size(); ++i)
        {
          r[i] = h[rows[i]];
          for (std::size_t j = 0; j < cols.size(); ++j)
            A(i, j) = J(rows[i], cols[j]);
          A(i, cols.size()) = hw[rows[i]];
        }
      const Eigen::VectorXd d = A.fullPivLu().solve(-r);
      for (std::size_t j = 0; j < cols.size(); ++j)
        z[cols[j]] += d[j];
      omega += d[cols.size()];
      if (d.norm() < 1e-15)
        break;
    }
  double amplitude = z[0];
  for (unsigned int k = 1; k <= H; ++k)
    amplitude += z[2 * k];
  const double m     = amplitude * amplitude / (2 * (1 + amplitude * amplitude));
  const double exact = pi * std::sqrt(1 + amplitude * amplitude) / (2 * std::comp_ellint_1(std::sqrt(m)));
  return std::abs(omega - exact) / exact;
}

TEST(HarmonicBalance, DuffingBackboneConvergesToTheEllipticIntegralFrequency)
{
  const double e1 = backbone_error(1, 1.0), e3 = backbone_error(3, 1.0), e5 = backbone_error(5, 1.0),
               e7 = backbone_error(7, 1.0);
  std::printf("backbone relative error at amplitude ~1: N_H=1 %.3g, 3 %.3g, 5 %.3g, 7 %.3g\n", e1, e3, e5,
              e7);
  EXPECT_LT(e3, e1);
  EXPECT_LT(e5, e3);
  EXPECT_LT(e7, e5);
  EXPECT_LT(e5, 1e-5);
  EXPECT_LT(e7, 1e-7);
}

TEST(HarmonicBalance, SmallForcingMatchesTheLinearSteadyState)
{
  const double            m = 1.0, k = 4.0, c = 0.1, F = 1e-6;
  const Model             model = duffing(m, k, 10.0);
  HarmonicBalanceSettings settings;
  settings.n_harmonics   = 3;
  settings.rayleigh_mass = c / m;
  const HarmonicBalance hb(model, settings, {{1, F, 0.0}});
  for (const double omega : {0.5, 1.9, 2.0, 3.0})
    {
      Eigen::VectorXd z = Eigen::VectorXd::Zero(hb.n_unknowns());
      ASSERT_TRUE(solve_periodic_state(hb, z, omega).converged);
      const auto   sc     = hb.coefficient(z, 0, 1);
      const double linear = F / std::hypot(k - m * omega * omega, c * omega);
      EXPECT_NEAR(std::hypot(sc.first, sc.second), linear, 1e-6 * linear) << "w = " << omega;
    }
}

TEST(HarmonicBalance, ForcedDuffingAgreesWithNewmarkAndHasTwoFolds)
{
  const Model             model = duffing(1.0, 1.0, 1.0);
  HarmonicBalanceSettings settings;
  settings.n_harmonics   = 7;
  settings.rayleigh_mass = 0.1;
  const HarmonicBalance hb(model, settings, {{1, 0.5, 0.0}});
  // Off the hysteresis band: one periodic state; Newmark from rest must reach it.
  const double    omega = 0.6;
  Eigen::VectorXd z     = Eigen::VectorXd::Zero(hb.n_unknowns());
  ASSERT_TRUE(solve_periodic_state(hb, z, omega).converged);
  NewmarkSettings ns;
  ns.steps_per_period = 2048;
  ns.period_tolerance = 1e-9;
  const NewmarkResult nm =
      newmark_steady_state(hb, omega, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), ns);
  ASSERT_TRUE(nm.converged);
  // Compare over the last period, aligned at t = 0 of a period.
  std::vector<double> t(ns.steps_per_period);
  for (unsigned int i = 0; i < t.size(); ++i)
    t[i] = 2 * pi / omega * i / t.size();
  const Eigen::MatrixXd x_hbm = hb.positions_at(z, omega, t);
  const double          size  = hb.half_range(z, omega, 1);
  const double          error = (x_hbm.row(1) - nm.last_period.row(1)).lpNorm<Eigen::Infinity>() / size;
  std::printf("forced Duffing at w = %.2f: HBM vs Newmark %.3g relative (%u periods)\n", omega, error,
              nm.periods);
  EXPECT_LT(error, 1e-4);

  ContinuationSettings cs;
  cs.omega_start = 0.5, cs.omega_end = 2.5, cs.tracked_dofs = {1}, cs.max_step = 0.05;
  const FrequencyResponse frc = trace_frequency_response(hb, Eigen::VectorXd::Zero(hb.n_unknowns()), cs);
  ASSERT_TRUE(frc.completed) << frc.stop_reason;
  unsigned int folds = 0, unstable = 0;
  for (const auto &p : frc.points)
    folds += p.fold, unstable += p.stable == 0;
  EXPECT_EQ(folds, 2u);
  EXPECT_GT(unstable, 0u);
  ASSERT_EQ(frc.peaks.size(), 1u);
  std::printf("forced Duffing: %zu points, 2 folds, %u unstable, peak at w = %.4f\n", frc.points.size(),
              unstable, frc.peaks[0].omega);
}

TEST(HarmonicBalance, ShellJacobianWithPrescribedDriveMatchesFiniteDifferences)
{
  MeshOptions options;
  options.file                  = NLMECH_SOURCE_DIR "/meshes/unit_square.geo";
  options.characteristic_length = 0.5;
  const RawSimplexMesh<3> mesh  = read_simplex_mesh<3>(options, 2);
  ShellMaterial           material;
  material.thickness            = 0.01;
  const ShellModel        shell = make_shell_model(mesh, material);
  HarmonicBalanceSettings settings;
  settings.n_harmonics        = 2;
  settings.rayleigh_mass      = 0.3;
  settings.rayleigh_stiffness = 0.001;
  std::vector<HarmonicDrive> drives;
  for (unsigned int v = 0; v < 3; ++v)
    for (unsigned int i = 0; i < 3; ++i)
      drives.push_back({3 * v + i, i == 2 ? 0.01 : 0.0, 0.2, 0.0, shell.rest_positions[3 * v + i], {}, {}});
  const HarmonicBalance hb(shell.model, settings, {}, drives);
  std::srand(7);
  Eigen::VectorXd z = hb.static_coefficients(shell.rest_positions);
  z += 0.01 * Eigen::VectorXd::Random(z.size());
  const double omega = 3.0;
  EXPECT_LT(jacobian_difference(hb, z, omega, 1e-7), 1e-6); // relative to |J|_inf (> 1 here)
  const Eigen::VectorXd dw = (hb.residual(z, omega + 1e-6) - hb.residual(z, omega - 1e-6)) / 2e-6;
  EXPECT_LT((dw - hb.d_residual_d_omega(z, omega)).lpNorm<Eigen::Infinity>(),
            1e-6 * std::max(1.0, dw.norm()));
  Eigen::VectorXd z0 = hb.static_coefficients(shell.rest_positions);
  const auto      r  = solve_with_excitation_ramp(hb, z0, omega);
  EXPECT_TRUE(r.converged) << r.message << " residual " << r.residual << " iterations " << r.iterations;
}

TEST(HarmonicBalance, AdaptiveHarmonicsMeetTheirThresholdAgainstAManyHarmonicReference)
{
  // The forced Duffing oscillator at 0.6 rad/s, where the third and fifth superharmonics matter:
  // the thesis's strategy (raise N_H until the trajectory changes by less than 1e-3 of its size)
  // must stop with a trajectory that is within a few 1e-3 of an N_H = 25 solution.
  const Model             model = duffing(1, 1, 1);
  HarmonicBalanceSettings settings;
  settings.rayleigh_mass                  = 0.1;
  const std::vector<HarmonicForce> forces = {{1, 0.5, 0.0}};
  const Eigen::VectorXd            rest   = Eigen::VectorXd::Zero(2);
  const HarmonicsChoice choice = choose_harmonics(model, settings, forces, {}, rest, 0.6, 1e-3, 1, 21, 2);
  ASSERT_TRUE(choice.converged);
  EXPECT_GE(choice.n_harmonics, 3u);
  for (const auto &c : choice.changes)
    std::cout << "N_H " << c.first << ": trajectory change " << c.second << std::endl;
  settings.n_harmonics = choice.n_harmonics;
  const HarmonicBalance chosen(model, settings, forces);
  settings.n_harmonics = 25;
  const HarmonicBalance reference(model, settings, forces);
  Eigen::VectorXd       z = reference.static_coefficients(rest);
  z.head(choice.z.size()) = choice.z;
  ASSERT_TRUE(solve_periodic_state(reference, z, 0.6).converged);
  std::vector<double> t(200);
  for (std::size_t j = 0; j < t.size(); ++j)
    t[j] = 2 * pi / 0.6 * double(j) / double(t.size());
  const Eigen::MatrixXd a = chosen.positions_at(choice.z, 0.6, t), b = reference.positions_at(z, 0.6, t);
  const double          size = b.row(1).maxCoeff() - b.row(1).minCoeff();
  EXPECT_LT((a.row(1) - b.row(1)).lpNorm<Eigen::Infinity>() / size, 3e-3);
}

TEST(HarmonicBalance, ShellErrorAgainstNewmarkFallsWithTheNumberOfHarmonics)
{
  // Thesis Fig. 2.3 on the fork shell of prm/fork-shell.prm (coarse mesh), driven 0.5 mm at its
  // handle, off resonance: the HBM trajectory of a tine tip against Newmark run to the periodic
  // steady state (1024 steps per period, started from the N_H = 7 state) for N_H = 1, 3, 5.
  MeshOptions options;
  options.file                  = NLMECH_SOURCE_DIR "/meshes/fork.geo";
  options.characteristic_length = 0.025;
  const RawSimplexMesh<3> mesh  = read_simplex_mesh<3>(options, 2);
  ShellMaterial           material;
  material.youngs_modulus = 1e7, material.poissons_ratio = 0.4, material.density = 1100;
  const ShellModel   shell  = make_shell_model(mesh, material);
  const unsigned int handle = mesh.groups.material_ids.at("handle");
  std::vector<bool>  driven(mesh.vertices.size(), false);
  for (std::size_t c = 0; c < mesh.cells.size(); ++c)
    if (mesh.cell_material[c] == handle)
      for (const unsigned int v : mesh.cells[c])
        driven[v] = true;
  std::vector<HarmonicDrive> drives;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (driven[v])
      for (unsigned int i = 0; i < 3; ++i)
        drives.push_back({3 * v + i, i == 2 ? 5e-4 : 0.0, 0.0, 0.0, shell.rest_positions[3 * v + i], {}, {}});
  std::size_t            tip = 0; // the vertex nearest to the upper tine's tip
  const dealii::Point<3> target(0.16, 0.0275, 0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (mesh.vertices[v].distance(target) < mesh.vertices[tip].distance(target))
      tip = v;
  const double            omega = 6.0; // above the first resonance (3.7 rad/s), below the second
  HarmonicBalanceSettings settings;
  settings.rayleigh_mass = 1;
  auto solve             = [&](unsigned int H) {
    settings.n_harmonics = H;
    auto hb = std::make_unique<HarmonicBalance>(shell.model, settings, std::vector<HarmonicForce>{}, drives);
    Eigen::VectorXd z = hb->static_coefficients(shell.rest_positions);
    EXPECT_TRUE(solve_with_excitation_ramp(*hb, z, omega).converged);
    return std::make_pair(std::move(hb), z);
  };
  const auto [reference_hb, reference_z] = solve(7);
  NewmarkSettings newmark;
  newmark.steps_per_period = 1024;
  newmark.period_tolerance = 1e-7;
  const NewmarkResult nm =
      newmark_steady_state(*reference_hb, omega, reference_hb->positions_at(reference_z, omega, {0.0}).col(0),
                           reference_hb->velocities_at(reference_z, omega, {0.0}).col(0), newmark);
  ASSERT_TRUE(nm.converged);
  std::vector<double> t(newmark.steps_per_period);
  for (std::size_t j = 0; j < t.size(); ++j)
    t[j] = 2 * pi / omega * double(j) / double(t.size());
  const double size =
      0.5 * (nm.last_period.row(3 * tip + 2).maxCoeff() - nm.last_period.row(3 * tip + 2).minCoeff());
  std::vector<double> errors;
  for (const unsigned int H : {1u, 3u, 5u})
    {
      const auto [hb, z]      = solve(H);
      const Eigen::MatrixXd x = hb->positions_at(z, omega, t);
      double                e = 0;
      for (unsigned int i = 0; i < 3; ++i)
        e = std::max(e, (x.row(3 * tip + i) - nm.last_period.row(3 * tip + i)).lpNorm<Eigen::Infinity>());
      errors.push_back(e / size);
      std::cout << "fork shell at " << omega << " rad/s, N_H = " << H << ": HBM vs Newmark " << e / size
                << " of the tip's half range" << std::endl;
    }
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LE(errors[2], errors[1] * 1.01);
  EXPECT_LT(errors[2], 1e-3);
}

TEST(HarmonicBalance, HillExponentsOfALinearOscillatorAreExact)
{
  // m x'' + (alpha m + beta k) x' + k x = f cos(w t): with zeta w_0 = (alpha + beta k / m) / 2 the
  // exponents are -zeta w_0 +- i sqrt(k/m - (zeta w_0)^2) (mod i w).
  const double            m = 1.0, k = 4.0, beta = 0.02, omega = 1.3;
  const double            alpha = 0.2 + beta * k / m; // the same total damping as before
  const Model             model = duffing(m, k, 0.0);
  HarmonicBalanceSettings settings;
  settings.n_harmonics        = 4;
  settings.rayleigh_mass      = 0.2;
  settings.rayleigh_stiffness = beta;
  const HarmonicBalance hb(model, settings, {{1, 0.5, 0.0}});
  Eigen::VectorXd       z = Eigen::VectorXd::Zero(hb.n_unknowns());
  ASSERT_TRUE(solve_periodic_state(hb, z, omega).converged);
  const HillResult h = hill_stability(hb, z, omega);
  ASSERT_TRUE(h.determined);
  EXPECT_TRUE(h.stable);
  const double damped = std::sqrt(k / m - alpha * alpha / 4);
  // The exponent's copy in the strip |Im| <= w / 2: damped frequency folded by multiples of w.
  const double folded = damped - omega * std::round(damped / omega);
  ASSERT_EQ(h.exponents.size(), 2u);
  for (const auto &lambda : h.exponents)
    {
      EXPECT_NEAR(lambda.real(), -alpha / 2, 1e-10);
      EXPECT_NEAR(std::abs(lambda.imag()), std::abs(folded), 1e-10);
    }
  EXPECT_NEAR(h.max_multiplier, std::exp(-alpha / 2 * 2 * pi / omega), 1e-10);
}

TEST(HarmonicBalance, HillAgreesWithFloquetOnTheForcedDuffingCurve)
{
  const Model             model = duffing(1.0, 1.0, 1.0);
  HarmonicBalanceSettings settings;
  settings.n_harmonics   = 7;
  settings.rayleigh_mass = 0.1;
  const HarmonicBalance hb(model, settings, {{1, 0.5, 0.0}});
  ContinuationSettings  cs;
  cs.omega_start = 0.5, cs.omega_end = 2.5, cs.tracked_dofs = {1}, cs.max_step = 0.05;
  cs.stability                 = StabilityMethod::floquet;
  const FrequencyResponse frc  = trace_frequency_response(hb, Eigen::VectorXd::Zero(hb.n_unknowns()), cs);
  cs.stability                 = StabilityMethod::hill;
  const FrequencyResponse hill = trace_frequency_response(hb, Eigen::VectorXd::Zero(hb.n_unknowns()), cs);
  ASSERT_TRUE(frc.completed && hill.completed);
  ASSERT_EQ(frc.points.size(), hill.points.size());
  double       worst            = 0;
  unsigned int unstable_floquet = 0, unstable_hill = 0, compared = 0;
  for (std::size_t i = 0; i < frc.points.size(); ++i)
    {
      const ResponsePoint &f = frc.points[i], &h = hill.points[i];
      ASSERT_NEAR(f.omega, h.omega, 1e-12);
      unstable_floquet += f.stable == 0, unstable_hill += h.stable == 0;
      if (h.stable < 0)
        continue; // exactly at a fold
      ++compared;
      worst = std::max(worst, std::abs(h.max_multiplier - f.max_multiplier) / f.max_multiplier);
      if (std::abs(f.max_multiplier - 1) > 1e-4)
        {
          EXPECT_EQ(f.stable, h.stable)
              << "at w = " << f.omega << ": |mu| " << f.max_multiplier << " vs " << h.max_multiplier;
        }
    }
  std::printf("forced Duffing, Hill vs Floquet: %u of %zu points compared, largest multiplier difference "
              "%.2g, unstable points %u (Floquet) %u (Hill)\n",
              compared, frc.points.size(), worst, unstable_floquet, unstable_hill);
  EXPECT_GT(compared + 2, frc.points.size());
  EXPECT_LT(worst, 1e-5);
  EXPECT_GT(unstable_hill, 0u);
  EXPECT_LE(std::abs(int(unstable_hill) - int(unstable_floquet)), 1);
}

TEST(HarmonicBalance, HillAgreesWithFloquetOnAStripWithStiffnessDamping)
{
  // A shaken plane strip (50 free unknowns), large motion, D_beta > 0 so that Hill's Delta_1
  // carries the per-sample velocity tangents too. Hill's exponents converge with N_H like the
  // solution does: at 6 rad/s the largest multiplier differs from Floquet's by 7e-3 at N_H = 5,
  // 1.3e-5 at 9 and 8e-8 at 13 (the N_H = 5 solution itself is 0.7 % off there).
  const auto              s = nlmech::testing::shaken_strip(0.05, 0.0);
  HarmonicBalanceSettings settings;
  settings.n_harmonics        = 9;
  settings.rayleigh_mass      = 0.5;
  settings.rayleigh_stiffness = 0.002;
  const HarmonicBalance hb(s.solid.model, settings, {}, s.drives);
  for (const double omega : {3.0, 6.0})
    {
      Eigen::VectorXd z = hb.static_coefficients(s.solid.rest_positions);
      ASSERT_TRUE(solve_with_excitation_ramp(hb, z, omega).converged);
      const FloquetResult f = floquet_stability(hb, z, omega, 1000);
      const HillResult    h = hill_stability(hb, z, omega);
      std::printf("strip at w = %.1f (%zu free): |mu| Floquet %.8f, Hill %.8f, %zu exponents, Krylov %u\n",
                  omega, hb.n_free(), f.max_multiplier, h.max_multiplier, h.exponents.size(),
                  h.krylov_dimension);
      ASSERT_TRUE(h.determined);
      EXPECT_LT(h.krylov_dimension,
                2 * hb.n_unknowns()); // ARPACK's restarted Arnoldi, not the dense fallback
      EXPECT_EQ(f.stable, h.stable);
      EXPECT_NEAR(h.max_multiplier, f.max_multiplier, 1e-4 * f.max_multiplier);
      EXPECT_FALSE(h.exponents.empty());
    }
}

namespace
{
  /// The forced Duffing curve near a point y0 = (z0, w0) in the natural parameterisation by one
  /// harmonic coefficient z_k = c: Newton on [h(z, w); z_k - c] = 0 with the dense Jacobian, to
  /// round-off. Independent of the continuation: it only needs a start near the curve.
  struct NaturalCurve
  {
    const HarmonicBalance &hb;
    Eigen::Index           k;
    Eigen::VectorXd        z;
    double                 w;

    bool solve(double c)
    {
      z[k] = c;
      for (int it = 0; it < 40; ++it)
        {
          const Eigen::VectorXd h = hb.residual(z, w);
          if (h.lpNorm<Eigen::Infinity>() < 1e-14)
            return true;
          const Eigen::Index n   = z.size();
          Eigen::MatrixXd    G   = Eigen::MatrixXd::Zero(n + 1, n + 1);
          G.topLeftCorner(n, n)  = Eigen::MatrixXd(hb.jacobian(z, w));
          G.topRightCorner(n, 1) = hb.d_residual_d_omega(z, w);
          G(n, k)                = 1;
          Eigen::VectorXd rhs(n + 1);
          rhs.head(n) = -h, rhs[n] = 0;
          const Eigen::VectorXd d = G.partialPivLu().solve(rhs);
          z += d.head(n), w += d[n];
        }
      return hb.residual(z, w).lpNorm<Eigen::Infinity>() < 1e-12;
    }
  };

  /// The largest value of f(c) on [a, b] by golden-section search to round-off in c.
  template <typename F>
  double golden_maximum(F f, double a, double b)
  {
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    double       c = b - g * (b - a), d = a + g * (b - a), fc = f(c), fd = f(d);
    for (int it = 0; it < 200 && std::abs(b - a) > 1e-15 * (std::abs(a) + std::abs(b)); ++it)
      if (fc > fd)
        b = d, d = c, fd = fc, c = b - g * (b - a), fc = f(c);
      else
        a = c, c = d, fc = fd, d = a + g * (b - a), fd = f(d);
    return 0.5 * (a + b);
  }
} // namespace

TEST(HarmonicBalance, DuffingPeakAndFoldsAreExactOnTheCurve)
{
  // The resonance peak (dA/ds = 0) and the two folds (dw/ds = 0) of the forced Duffing curve,
  // located by the continuation's extended systems, against an independent tight reference: the
  // curve in its natural parameterisation by the first cosine coefficient near each point, solved
  // to round-off, and the maximum of A (peak) or of +-w (folds) over that coefficient by
  // golden-section search. Before this, the peak sat 1.5e-4 low (A by a 256-sample quadrature of
  // |v|) and the fold mark on the curve point before the turn.
  const Model             model = duffing(1.0, 1.0, 1.0);
  HarmonicBalanceSettings settings;
  settings.n_harmonics   = 7;
  settings.rayleigh_mass = 0.1;
  const HarmonicBalance hb(model, settings, {{1, 0.5, 0.0}});
  ContinuationSettings  cs;
  cs.omega_start = 0.5, cs.omega_end = 2.5, cs.tracked_dofs = {1}, cs.max_step = 0.05;
  cs.stability                = StabilityMethod::none;
  const FrequencyResponse frc = trace_frequency_response(hb, Eigen::VectorXd::Zero(hb.n_unknowns()), cs);
  ASSERT_TRUE(frc.completed) << frc.stop_reason;
  ASSERT_EQ(frc.peaks.size(), 1u);
  ASSERT_EQ(frc.folds.size(), 2u);
  const std::vector<std::size_t> tracked = {1};
  // The amplitude of one coordinate is exactly its total variation: 2 (max - min) for a motion
  // with one maximum and one minimum per period; check against a fine quadrature-free sampling.
  {
    const Eigen::VectorXd &z  = frc.peaks[0].z;
    const double           hr = hb.half_range(z, frc.peaks[0].omega, 1);
    std::vector<double>    t(200000);
    for (std::size_t j = 0; j < t.size(); ++j)
      t[j] = 2 * pi / frc.peaks[0].omega * double(j) / double(t.size());
    const Eigen::MatrixXd x = hb.positions_at(z, frc.peaks[0].omega, t);
    EXPECT_NEAR(hr, 0.5 * (x.row(1).maxCoeff() - x.row(1).minCoeff()), 1e-9 * hr);
    EXPECT_NEAR(hb.amplitude(z, frc.peaks[0].omega, tracked), 4 * hr, 1e-12 * hr);
  }
  const Eigen::Index k = Eigen::Index(2 * hb.n_free()); // c_1 of the mass
  auto reference       = [&](const Eigen::VectorXd &z0, double w0, int what, double &w_ref, double &a_ref) {
    NaturalCurve curve{hb, k, z0, w0};
    auto         f = [&](double c) {
      EXPECT_TRUE(curve.solve(c));
      return what == 0 ? hb.amplitude(curve.z, curve.w, tracked) : what * curve.w;
    };
    const double c0 = z0[k], span = 0.02 * std::abs(z0[k]) + 1e-3;
    const double c = golden_maximum(f, c0 - span, c0 + span);
    f(c);
    w_ref = curve.w, a_ref = hb.amplitude(curve.z, curve.w, tracked);
  };
  double w_ref = 0, a_ref = 0;
  reference(frc.peaks[0].z, frc.peaks[0].omega, 0, w_ref, a_ref);
  std::printf("Duffing peak: w = %.12f (reference %.12f), A = %.12f (reference %.12f)\n", frc.peaks[0].omega,
              w_ref, frc.peaks[0].amplitude, a_ref);
  EXPECT_NEAR(frc.peaks[0].amplitude, a_ref, 1e-10 * a_ref);
  EXPECT_NEAR(frc.peaks[0].omega, w_ref, 1e-7 * w_ref);
  // The upper fold is a maximum of w along the curve, the lower one a minimum.
  for (std::size_t f = 0; f < 2; ++f)
    {
      const TurningPoint &t = frc.folds[f];
      reference(t.z, t.omega, f == 0 ? 1 : -1, w_ref, a_ref);
      std::printf("Duffing fold %zu: w = %.12f (reference %.12f), A = %.10f (reference %.10f)\n", f, t.omega,
                  w_ref, t.amplitude, a_ref);
      EXPECT_NEAR(t.omega, w_ref, 1e-10 * w_ref);
      EXPECT_NEAR(t.amplitude, a_ref, 1e-5 * a_ref); // A along the curve is steep at a fold
    }
  // Each fold is a point of the curve of its own, between points on either side of its turn.
  unsigned int marked = 0;
  for (std::size_t i = 0; i < frc.points.size(); ++i)
    if (frc.points[i].fold)
      {
        ++marked;
        ASSERT_TRUE(i > 0 && i + 1 < frc.points.size());
        EXPECT_NE(frc.points[i - 1].d_omega_ds > 0, frc.points[i + 1].d_omega_ds > 0);
        EXPECT_NEAR(frc.points[i].omega, frc.folds[marked - 1].omega, 0);
      }
  EXPECT_EQ(marked, 2u);
}
