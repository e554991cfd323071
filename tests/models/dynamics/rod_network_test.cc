// Discrete elastic rods and rod networks against finite differences, rigid motions, and the
// Euler-Bernoulli and Saint-Venant torsion frequencies of a clamped-free wire; a rod split by a
// junction must vibrate like the unsplit rod.
#include <nlmech/models/dynamics/rod_network.h>
#include <nlmech/solvers/hbm/linear_modal.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace nlmech;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  /// Lowest eigenfrequencies of a straight wire along x of length L, clamped at x = 0 (first two
  /// vertices and the first edge's angle held), split into `pieces` rods joined by junctions.
  Eigen::VectorXd cantilever_frequencies(unsigned int segments, unsigned int pieces, RodMaterial material,
                                         double L)
  {
    std::vector<std::vector<std::array<double, 3>>> lines;
    for (unsigned int p = 0; p < pieces; ++p)
      lines.push_back({{{L * p / pieces, 0, 0}}, {{L * (p + 1) / pieces, 0, 0}}});
    RodNetworkDescription d = rods_from_polylines(lines, segments / pieces, 1e-9);
    d.material              = material;
    RodNetwork net          = make_rod_network(d);
    // clamp: the vertices at x = 0 and x = h, and the first edge's angle
    for (std::size_t v = 0; v < d.vertices.size(); ++v)
      if (d.vertices[v][0] < 1.5 * L / segments)
        for (int i = 0; i < 3; ++i)
          net.model.fix(3 * v + i, d.vertices[v][i]);
    for (std::size_t e = 0; e < net.edges.size(); ++e)
      if (d.vertices[net.edges[e][0]][0] < 1e-12 || d.vertices[net.edges[e][1]][0] < 1e-12)
        net.model.fix(net.theta_offset + e, 0.0);
    HarmonicBalanceSettings settings;
    settings.n_harmonics = 1;
    const HarmonicBalance hb(net.model, settings);
    return linear_modes(hb, net.rest_positions).frequencies;
  }
} // namespace

TEST(RodNetwork, DerivativesMatchFiniteDifferences)
{
  // A planar "Y" of three rods meeting at a junction, plus a closed loop.
  std::vector<std::vector<std::array<double, 3>>> lines = {
      {{{0, 0, 0}}, {{0.1, 0.02, 0}}},
      {{{0.1, 0.02, 0}}, {{0.2, 0.06, 0}}},
      {{{0.1, 0.02, 0}}, {{0.15, -0.05, 0}}},
      {{{0.3, 0, 0}}, {{0.35, 0.05, 0}}, {{0.4, 0, 0}}, {{0.35, -0.05, 0}}, {{0.3, 0, 0}}}};
  RodNetworkDescription d   = rods_from_polylines(lines, 4, 1e-9);
  const RodNetwork      net = make_rod_network(d);
  EXPECT_EQ(net.junction_vertices.size(), 1u);
  std::srand(2);
  Eigen::VectorXd x = net.rest_positions;
  x.head(3 * d.vertices.size()) += 0.003 * Eigen::VectorXd::Random(3 * d.vertices.size());
  x.tail(x.size() - 3 * d.vertices.size()) += 0.2 * Eigen::VectorXd::Random(x.size() - 3 * d.vertices.size());
  for (const auto &term : net.model.terms())
    {
      const auto check = check_derivatives(*term, x, 1e-7);
      EXPECT_LT(check.gradient_error, 1e-6) << term->name();
      EXPECT_LT(check.hessian_error, 1e-5) << term->name();
    }
  // At rest every energy vanishes, and after a rigid turn about z (parallel transport in the
  // plane is that turn) with the junction turned alike.
  EXPECT_LT(net.model.energy(net.rest_positions), 1e-20);
  Eigen::VectorXd y   = net.rest_positions;
  const double    phi = 0.8, c = std::cos(phi), s = std::sin(phi);
  for (std::size_t v = 0; v < d.vertices.size(); ++v)
    {
      const double px = y[3 * v], py = y[3 * v + 1];
      y[3 * v] = c * px - s * py + 0.1, y[3 * v + 1] = s * px + c * py - 0.3, y[3 * v + 2] += 0.05;
    }
  y[net.rotation_offset + 2] = std::tan(phi / 2); // Gibbs vector of the turn
  EXPECT_LT(net.model.energy(y), 1e-14);
}

TEST(RodNetwork, CantileverMatchesBeamAndTorsionTheory)
{
  RodMaterial  m; // aluminium wire, d = 1.1 mm
  const double L = 0.2, r = m.radius;
  const double A = pi * r * r, I = pi * std::pow(r, 4) / 4,
               G = m.youngs_modulus / (2 * (1 + m.poissons_ratio));
  const double bending =
      1.875104068711961 * 1.875104068711961 * std::sqrt(m.youngs_modulus * I / (m.density * A)) / (L * L);
  const double          torsion = pi / 2 / L * std::sqrt(G / m.density); // sqrt(G J / (rho J)) / L
  const Eigen::VectorXd w       = cantilever_frequencies(80, 1, m, L);
  // Holding the first two vertices clamps the rod half an edge in: L_eff = L - h / 2.
  const double h = L / 80, clamp = std::pow(L / (L - h / 2), 2);
  // The two bending directions are degenerate; the first torsion mode is far higher.
  EXPECT_NEAR(w[0] / (bending * clamp), 1.0, 2e-3);
  EXPECT_NEAR(w[1] / (bending * clamp), 1.0, 2e-3);
  std::cout << "bending: " << w[0] / (bending * clamp) << " of Euler-Bernoulli (L_eff)" << std::endl;
  bool found = false;
  for (Eigen::Index k = 0; k < w.size(); ++k)
    if (std::abs(w[k] / torsion - 1) < 0.02)
      found = true, std::cout << "torsion: " << w[k] / torsion << " of Saint-Venant" << std::endl;
  EXPECT_TRUE(found) << "no torsion mode near " << torsion << " rad/s";
  // Split into four rods joined by junctions: the same spectrum (low modes) to 1e-3.
  const Eigen::VectorXd split = cantilever_frequencies(80, 4, m, L);
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(split[k] / w[k], 1.0, 1e-3) << "mode " << k;
}
