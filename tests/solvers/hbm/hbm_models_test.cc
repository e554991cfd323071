// The dynamics models added for harmonic balance (plane triangles, tetrahedral solids with layers,
// compliant mechanisms, rotation drives) and the linear modal reference, against independent
// references: finite differences, closed-form energies, the exact rotation, a direct complex solve
// of the linearised equations, and HBM itself at small amplitude.
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/dynamics/elastic_solids.h>
#include <nlmech/models/dynamics/mechanism.h>
#include <nlmech/solvers/hbm/linear_modal.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>

#include "hbm_test_helpers.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>

using namespace nlmech;
using nlmech::testing::jacobian_difference;
using nlmech::testing::mesh;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  /// Three-link leg hanging from a driven hip, two springs (the scene's prm/three-link.prm).
  MechanismDescription leg()
  {
    MechanismDescription d;
    d.joints         = {{{0, 0}}, {{-0.12, 0}}, {{0.03, -0.12}}, {{-0.02, -0.24}}, {{0.06, -0.27}}};
    d.masses         = {0.01, 0.01, 0.03, 0.02, 0.01};
    d.links          = {{{0, 1}}, {{0, 2}}, {{2, 3}}, {{3, 4}}};
    d.rigid_angles   = {{{2, 3, 4}}};
    d.springs        = {{0, 2, 1.0, 0.0, 0.5, 0.1, 70.2, 0.146}, {1, 3, 0.5, 0.0, 0.5, 0.0, 16.0, 0.088}};
    d.link_stiffness = 1e4, d.angle_stiffness = 10;
    return d;
  }
} // namespace

TEST(DynamicsModels, PlaneTrianglesMatchTheStVKEnergyAndFiniteDifferences)
{
  const RawSimplexMesh<3> m = mesh("unit_square.geo", 0.4, 2);
  SolidMaterial           material;
  material.youngs_modulus = 3e5, material.poissons_ratio = 0.3, material.thickness = 0.02;
  const SolidModel solid = make_plane_model(m, {material});
  // Uniform stretch F = diag(a, b): W = A t (mu (E11^2 + E22^2) + lambda_ps / 2 (E11 + E22)^2).
  const double    a = 1.1, b = 0.95;
  Eigen::VectorXd x = solid.rest_positions;
  for (Eigen::Index v = 0; v < x.size() / 2; ++v)
    x[2 * v] *= a, x[2 * v + 1] *= b;
  const double E = material.youngs_modulus, nu = material.poissons_ratio;
  const double mu = E / (2 * (1 + nu)), lambda_ps = E * nu / (1 - nu * nu);
  const double E11 = 0.5 * (a * a - 1), E22 = 0.5 * (b * b - 1);
  const double exact =
      material.thickness * (mu * (E11 * E11 + E22 * E22) + 0.5 * lambda_ps * std::pow(E11 + E22, 2));
  EXPECT_NEAR(solid.model.energy(x), exact, 1e-12 * exact);
  std::srand(3);
  const Eigen::VectorXd y     = solid.rest_positions + 0.02 * Eigen::VectorXd::Random(x.size());
  const auto            check = check_derivatives(*solid.model.terms()[0], y);
  EXPECT_LT(check.gradient_error, 1e-7);
  EXPECT_LT(check.hessian_error, 1e-7);
  EXPECT_NEAR(solid.model.lumped_mass().sum(), 2 * material.density * material.thickness, 1e-12);
  // An inverting step is cut at the inversion.
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(x.size());
  for (Eigen::Index v = 0; v < x.size() / 2; ++v)
    dx[2 * v] = -2 * solid.rest_positions[2 * v];
  const double step = solid.model.max_safe_step(solid.rest_positions, dx);
  EXPECT_NEAR(step, 0.5, 1e-9);
}

TEST(DynamicsModels, LayeredTetSolidHasItsLayersAndExactDerivatives)
{
  const RawSimplexMesh<3>    m      = mesh("t_solid.geo", 0.03, 3);
  const auto                 layers = cell_layers(m, 2, 3);
  std::vector<SolidMaterial> materials(3);
  for (unsigned int l = 0; l < 3; ++l)
    materials[l].youngs_modulus = 1e5 * (l + 1);
  const SolidModel solid = make_tet_solid_model(m, materials, layers);
  EXPECT_EQ(solid.model.terms().size(), 3u);
  // A rigid rotation costs nothing (St.Venant-Kirchhoff is frame invariant).
  Eigen::VectorXd x = solid.rest_positions;
  const double    c = std::cos(0.7), s = std::sin(0.7);
  for (Eigen::Index v = 0; v < x.size() / 3; ++v)
    {
      const double px = x[3 * v], pz = x[3 * v + 2];
      x[3 * v] = c * px + s * pz, x[3 * v + 2] = -s * px + c * pz;
    }
  EXPECT_LT(std::abs(solid.model.energy(x)), 1e-14);
  std::srand(5);
  const Eigen::VectorXd y = solid.rest_positions + 0.002 * Eigen::VectorXd::Random(x.size());
  for (const auto &term : solid.model.terms())
    {
      const auto check = check_derivatives(*term, y);
      EXPECT_LT(check.gradient_error, 1e-6) << term->name();
      EXPECT_LT(check.hessian_error, 1e-6) << term->name();
    }
}

TEST(DynamicsModels, MechanismDerivativesAndRigidMotion)
{
  const MechanismDescription d    = leg();
  const MechanismModel       mech = make_mechanism_model(d);
  std::srand(11);
  const Eigen::VectorXd y = mech.rest_positions + 0.01 * Eigen::VectorXd::Random(mech.rest_positions.size());
  for (const auto &term : mech.model.terms())
    {
      const auto check = check_derivatives(*term, y, 1e-7);
      EXPECT_LT(check.gradient_error, 1e-6) << term->name();
      EXPECT_LT(check.hessian_error, 1e-6) << term->name();
    }
  // Rigid motion of the whole mechanism: links, joints and springs keep their energy (gravity aside).
  Eigen::VectorXd x = mech.rest_positions;
  const double    c = std::cos(1.1), s = std::sin(1.1);
  for (Eigen::Index j = 0; j < x.size() / 2; ++j)
    {
      const double px = x[2 * j], py = x[2 * j + 1];
      x[2 * j] = c * px - s * py + 0.3, x[2 * j + 1] = s * px + c * py - 0.2;
    }
  double elastic_rest = 0, elastic_moved = 0;
  for (const auto &term : mech.model.terms())
    if (term->name() != "gravity")
      elastic_rest += term->value(mech.rest_positions), elastic_moved += term->value(x);
  EXPECT_NEAR(elastic_moved, elastic_rest, 1e-12 * (1 + elastic_rest));
  const auto violation = mechanism_constraint_violation(d, x);
  EXPECT_LT(violation[0], 1e-14);
  EXPECT_LT(violation[1], 1e-14);
  MechanismDescription bad = d;
  bad.links.push_back({{1, 1}});
  EXPECT_THROW(make_mechanism_model(bad), std::exception);
}

TEST(HarmonicBalanceDrives, RotationDriveReproducesTheExactRotation)
{
  const std::vector<std::array<double, 3>>      points = {{{0.1, -0.02, 0.3}}, {{-0.05, 0.04, 0.2}}};
  const std::vector<std::array<std::size_t, 3>> dofs   = {{{0, 1, 2}}, {{3, 4, 5}}};
  const std::array<double, 3>                   axis = {{0.2, 1, 0.1}}, center = {{0, 0, 0.25}};
  const double                                  phi0 = 0.4;
  const auto            drives                       = rotation_drives(points, dofs, axis, center, phi0, 12);
  const double          n                            = std::sqrt(0.04 + 1 + 0.01);
  const Eigen::Vector3d a(axis[0] / n, axis[1] / n, axis[2] / n);
  double                worst = 0;
  for (double theta : {0.0, 0.3, 1.7, 4.0})
    {
      const double phi = phi0 * std::cos(theta);
      for (std::size_t p = 0; p < points.size(); ++p)
        {
          const Eigen::Vector3d r(points[p][0] - center[0], points[p][1] - center[1],
                                  points[p][2] - center[2]);
          const Eigen::Vector3d exact = Eigen::Vector3d(center[0], center[1], center[2]) +
                                        Eigen::AngleAxisd(phi, a).toRotationMatrix() * r;
          for (int i = 0; i < 3; ++i)
            worst = std::max(worst,
                             std::abs(drives[3 * p + i].center + drives[3 * p + i].motion(theta) - exact[i]));
        }
    }
  EXPECT_LT(worst, 1e-14);
  // Velocity: derivative of the motion.
  const double w = 2.5, theta = 0.9, h = 1e-6;
  const double fd = (drives[1].motion(theta + h) - drives[1].motion(theta - h)) / (2 * h) * w;
  EXPECT_NEAR(drives[1].velocity(theta, w), fd, 1e-8);
}

TEST(HarmonicBalanceDrives, SolidWithRotationDriveJacobianMatchesFiniteDifferences)
{
  const RawSimplexMesh<3> m = mesh("t_solid.geo", 0.04, 3);
  SolidMaterial           material;
  material.youngs_modulus                       = 1e5;
  const SolidModel                        solid = make_tet_solid_model(m, {material});
  std::vector<std::array<double, 3>>      top;
  std::vector<std::array<std::size_t, 3>> dofs;
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    if (m.vertices[v][2] > 0.12 - 1e-9)
      top.push_back({{m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]}}),
          dofs.push_back({{3 * v, 3 * v + 1, 3 * v + 2}});
  ASSERT_GE(top.size(), 3u);
  HarmonicBalanceSettings settings;
  settings.n_harmonics        = 2;
  settings.rayleigh_mass      = 0.5;
  settings.rayleigh_stiffness = 0.002;
  const HarmonicBalance hb(solid.model, settings, {},
                           rotation_drives(top, dofs, {{0, 1, 0}}, {{0, 0, 0.12}}, 0.1, 2));
  std::srand(9);
  Eigen::VectorXd z = hb.static_coefficients(solid.rest_positions);
  z += 1e-3 * Eigen::VectorXd::Random(z.size());
  EXPECT_LT(jacobian_difference(hb, z, 10.0, 1e-8), 1e-6);
  const Eigen::VectorXd dw = (hb.residual(z, 10.0 + 1e-5) - hb.residual(z, 10.0 - 1e-5)) / 2e-5;
  EXPECT_LT((dw - hb.d_residual_d_omega(z, 10.0)).lpNorm<Eigen::Infinity>(), 1e-6 * std::max(1.0, dw.norm()));
}

TEST(LinearModalAnalysis, ModalSuperpositionEqualsTheDirectComplexSolve)
{
  // A plane tower-like strip: the modal response with all modes against (K - w^2 M + i w D) U = F
  // solved directly, with a prescribed drive and a force with a phase.
  const auto  strip  = nlmech::testing::shaken_strip(1e-3, 0.3);
  const auto &m      = strip.m;
  const auto &solid  = strip.solid;
  const auto &drives = strip.drives;
  std::size_t top    = 0;
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    if (m.vertices[v][1] > m.vertices[top][1] + 1e-12 ||
        (m.vertices[v][1] > m.vertices[top][1] - 1e-12 && m.vertices[v][0] > m.vertices[top][0]))
      top = v;
  HarmonicBalanceSettings settings;
  settings.n_harmonics        = 3;
  settings.rayleigh_mass      = 0.4;
  settings.rayleigh_stiffness = 0.003;
  const HarmonicBalance             hb(solid.model, settings, {{2 * top + 1, 2e-4, 1.0}}, drives);
  const LinearModes                 modes  = linear_modes(hb, solid.rest_positions);
  const std::size_t                 n      = hb.n_free();
  const Eigen::SparseMatrix<double> K_full = solid.model.hessian(solid.rest_positions);
  for (const double omega : {3.0, modes.frequencies[0], 25.0})
    {
      const Eigen::VectorXcd U = linear_modal_response(hb, modes, omega);
      // Direct: A U = F with A = K - w^2 M + i w (alpha M + beta K) on the free unknowns.
      Eigen::MatrixXcd A(n, n);
      Eigen::VectorXcd F = Eigen::VectorXcd::Zero(n);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
          {
            const double k  = K_full.coeff(hb.free()[i], hb.free()[j]);
            const double mm = i == j ? hb.free_mass()[i] : 0.0;
            A(i, j)         = std::complex<double>(k - omega * omega * mm, omega * (0.4 * mm + 0.003 * k));
          }
      for (std::size_t i = 0; i < n; ++i)
        {
          if (hb.free()[i] == 2 * top + 1)
            F[i] += std::polar(2e-4, 1.0);
          for (const auto &d : drives)
            F[i] -= std::complex<double>(1, omega * 0.003) * K_full.coeff(hb.free()[i], d.dof) *
                    std::polar(d.amplitude, d.phase);
        }
      const Eigen::VectorXcd direct = A.partialPivLu().solve(F);
      EXPECT_LT((U - direct).norm(), 1e-9 * direct.norm()) << "omega " << omega;
    }
}

TEST(LinearModalAnalysis, HarmonicBalanceAtSmallAmplitudeMatchesIt)
{
  // The tower-like strip again, driven at 1e-7 of its size: the first harmonic of HBM is the
  // linear response to ~1e-7 relative, at, below and above the first resonance.
  const auto              strip  = nlmech::testing::shaken_strip(1e-7, 0.0);
  const auto             &solid  = strip.solid;
  const auto             &drives = strip.drives;
  HarmonicBalanceSettings settings;
  settings.n_harmonics   = 3;
  settings.rayleigh_mass = 0.4;
  const HarmonicBalance hb(solid.model, settings, {}, drives);
  const LinearModes     modes = linear_modes(hb, solid.rest_positions);
  const std::size_t     n     = hb.n_free();
  for (const double omega : {0.5 * modes.frequencies[0], modes.frequencies[0], 1.5 * modes.frequencies[0]})
    {
      Eigen::VectorXd z = hb.static_coefficients(solid.rest_positions);
      ASSERT_TRUE(solve_periodic_state(hb, z, omega).converged);
      const Eigen::VectorXcd U = linear_modal_response(hb, modes, omega);
      // u = Re(U e^{i theta}) = Re U cos - Im U sin: c_1 = Re U, s_1 = -Im U.
      double diff = 0;
      for (std::size_t i = 0; i < n; ++i)
        diff = std::max(diff, std::abs(std::complex<double>(z[2 * n + i], -z[n + i]) - U[i]));
      EXPECT_LT(diff, 1e-6 * U.cwiseAbs().maxCoeff()) << "omega " << omega;
    }
}
