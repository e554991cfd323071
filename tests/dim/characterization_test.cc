// Macroscopic tests on native-scale models: strain measures, a rigid rotation gives zero strain,
// and the periodic ring chain stops at its closed-form stretch limit 2 (R - r) / spacing - 1.
#include <nlmech/dim/characterization.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace nlmech;
using namespace nlmech::dim;

TEST(StrainMeasures, RigidRotationOfACellGivesZeroStrain)
{
  const Pattern            pattern = threefold_pattern({}, 1.24e-6);
  const Eigen::Rotation2Dd Q(0.7);
  // Lattice vectors of the rotated, unstretched cell and of a stretched then rotated one.
  EXPECT_LT(
      green_strain(cell_deformation_gradient(Q * pattern.t1, Q * pattern.t2, pattern.t1, pattern.t2)).norm(),
      1e-15);
  const double          theta = 0.4, ep = 0.03, eo = -0.02;
  const Eigen::Vector2d dp(std::cos(theta), std::sin(theta)), dn(-std::sin(theta), std::cos(theta));
  const Eigen::Matrix2d U = Eigen::Matrix2d::Identity() + ep * dp * dp.transpose() + eo * dn * dn.transpose();
  const Eigen::Matrix2d F =
      cell_deformation_gradient(Q * (U * pattern.t1), Q * (U * pattern.t2), pattern.t1, pattern.t2);
  EXPECT_LT((green_strain(F) - green_strain(theta, ep, eo)).norm(), 1e-15);
  // Principal Green strains 1/2 ((1 + eps)^2 - 1).
  const Eigen::Vector3d E = green_strain(0.0, ep, eo);
  EXPECT_NEAR(E[0], 0.5 * (std::pow(1 + ep, 2) - 1), 1e-15);
  EXPECT_NEAR(E[1], 0.5 * (std::pow(1 + eo, 2) - 1), 1e-15);
  EXPECT_NEAR(E[2], 0.0, 1e-15);

  // The contact energy of a patch moved rigidly (rotation about an arbitrary axis plus a shift)
  // is unchanged.
  const auto      patch = finite_patch(pattern, 7, PatchShape::hexagon);
  ContactSettings contact;
  contact.dhat = 0.5;
  ContactBarrier        barrier(patch.assembly, contact);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::VectorXd       moved = patch.q;
  for (unsigned b = 0; b < patch.assembly->n_bodies(); ++b)
    {
      moved.segment<3>(6 * b) = R * patch.q.segment<3>(6 * b) + Eigen::Vector3d(1, -2, 0.5);
      const Eigen::AngleAxisd composed(R * RigidAssembly::rotation(patch.q.segment<3>(6 * b + 3)));
      moved.segment<3>(6 * b + 3) = composed.angle() * composed.axis();
    }
  const double e0 = barrier.value(patch.q), e1 = barrier.value(moved);
  ASSERT_GT(e0, 0);
  EXPECT_NEAR(e1, e0, 1e-10 * e0);
}

TEST(InPlaneTest, RingChainStopsAtItsClosedFormStretchLimit)
{
  // Link distance at the limit: 2 (R - r) for circles; the polygons' inner edges lie inside the
  // circles by up to the sagitta R (1 - cos(pi / N)), so the polygon chain stops between
  // 2 (R cos(pi / N) - r) and 2 (R - r). With N = 256 that is within 0.5 % of the strain.
  const double R = 4, r = 1, spacing = 5.5;
  for (const unsigned N : {64u, 256u})
    {
      const Pattern       chain = ring_chain_pattern(R, r, spacing, N, 12, 1.24e-6);
      NativeSolveSettings settings;
      settings.contact.dhat  = 1e-3;
      settings.contact.kappa = 1e-2;
      InPlaneTest  test(chain, 0.0, settings);
      const auto   out      = test.solve(1.0, 1e-2, 0.0, 0.0);
      const double expected = 2 * (R - r) / spacing - 1;
      const double link     = (1 + out.principal) * spacing;
      std::printf(
          "ring chain, N = %u: eps_p %.6f (expected %.6f, %.3f %%), link distance %.5f mm, %u iterations, "
          "%.2f s, gap %.2e mm\n",
          N, out.principal, expected, 100 * (out.principal / expected - 1), link, out.iterations, out.seconds,
          out.smallest_gap);
      EXPECT_LE(link, 2 * (R - r));
      EXPECT_GE(link, 2 * (R * std::cos(M_PI / N) - r) - settings.contact.dhat);
      if (N == 256)
        {
          EXPECT_NEAR(out.principal, expected, 0.005 * expected);
        }
      EXPECT_GT(out.smallest_gap, 0);
    }
}

TEST(InPlaneTest, NoAcceptedStateNorAnyStateBetweenThemIntersects)
{
  // A 4-in-1 cell driven far into compression: large steps, many contacts. Every state Newton
  // accepts, and 20 states on the straight path between consecutive ones, must keep every surface
  // gap positive (exact distances).
  const Pattern         pattern = four_in_one_pattern({}, 1.24e-6);
  const Eigen::Vector2d dp(1, 0), dn(0, 1);
  auto                  cell = periodic_cell(pattern, {dp * dp.transpose(), dn * dn.transpose()});
  ContactSettings       contact;
  contact.dhat  = 0.01;
  contact.kappa = 0.01;
  Model model(cell.assembly->n_unknowns());
  model.add_term(std::make_shared<ContactBarrier>(cell.assembly, contact));
  model.add_term(std::make_shared<ParameterTarget>(
      cell.assembly->parameter_index(0), std::vector<double>{-0.9, 0.0}, std::vector<double>{0.01, 0.0}));
  for (unsigned k = 0; k < 3; ++k)
    model.fix(k, cell.q[k]);
  std::vector<Eigen::VectorXd> states{cell.q};
  NewtonSettings               newton;
  newton.max_iterations = 600;
  newton.step_tolerance = 1e-9;
  newton.on_accepted    = [&](const Eigen::VectorXd &x) { states.push_back(x); };
  DiagonalShift::Settings shift;
  shift.metric      = cell.assembly->motion_metric(cell.q);
  Eigen::VectorXd q = cell.q;
  NewtonSolver(newton, std::make_shared<DiagonalShift>(shift)).minimize(model, q);
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < states.size(); ++k)
    for (int j = 0; j <= 20; ++j)
      smallest = std::min(
          smallest, cell.assembly->smallest_gap(states[k] + j / 20.0 * (states[k + 1] - states[k]), 1.0).gap);
  std::printf("4-in-1 compression: %zu accepted states, eps_p %.4f, smallest gap on the path %.3e mm\n",
              states.size() - 1, q[cell.assembly->parameter_index(0)], smallest);
  EXPECT_GT(states.size(), 5u);
  EXPECT_GT(smallest, 0.0);
}

TEST(BendingTest, GravityHoldsAWeakDriveBackByAboutTwoGOverWAndTheRaisedWeightsDoNot)
{
  // A 7-element threefold patch bent to 0.05 /mm (well inside its limit of about 0.2 /mm, so no
  // contact stops it): what holds the curvature back is gravity alone, sum m g x^2 = G per unit
  // of A' = kappa / 2, against the drive w (A' - A'_target), a shortfall of about 2 G / w.
  Pattern             pattern = threefold_pattern({}, 1.24e-6);
  NativeSolveSettings settings;
  settings.contact.dhat = 0.01, settings.contact.kappa = 0.01, settings.max_iterations = 3000;
  const double target = 0.05;
  double       load   = 0;
  {
    BendingTest  test(pattern, 7, 0.0, settings);
    const double w         = 0.01; // the scene's default target weight
    load                   = test.gravity_load();
    const auto   o         = test.solve(target, w, 0, 0);
    const double shortfall = target - o.principal, predicted = 2 * load / w;
    std::printf("w %.3f: kappa %.5f, shortfall %.5f, 2 G / w %.5f\n", w, o.principal, shortfall, predicted);
    EXPECT_GT(shortfall, 0.7 * predicted);
    EXPECT_LT(shortfall, 2.0 * predicted);
  }
  SamplingPlan plan;
  plan.directions = 2, plan.patch_elements = 7, plan.far_curvature = 0.5;
  NativeSolveSettings raised = settings;
  raised.target_weight = 0.01, raised.hold_weight = 1;
  const double factor = raise_bending_weights(pattern, plan, raised);
  EXPECT_GT(factor, 1.0);
  EXPECT_NEAR(raised.hold_weight / raised.target_weight, 100.0, 1e-9);
  EXPECT_GE(raised.target_weight, 2 * load / (0.005 * plan.far_curvature) * (1 - 1e-12));
  BendingTest  test(pattern, 7, 0.0, settings);
  const auto   o         = test.solve(target, raised.target_weight, 0, 0);
  const double shortfall = target - o.principal;
  std::printf("raised w %.4f (x%.2f): kappa %.5f, shortfall %.5f\n", raised.target_weight, factor,
              o.principal, shortfall);
  EXPECT_LT(std::abs(shortfall), 0.01 * plan.far_curvature);
}

TEST(Sampling, OnlyTheDrivenComponentDecidesWhetherASampleReachedItsFarTarget)
{
  // The knot's bending samples of 2026-12-03: every driven curvature got to 0.5 /mm, with the free
  // orthogonal one anywhere; the summary used to count none of them.
  Sample s;
  s.kind = SampleKind::positive, s.target_p = 0.5, s.target_o = 0;
  s.outcome.principal = 0.500002, s.outcome.orthogonal = -0.056;
  EXPECT_TRUE(reached_far_target(s));
  s.outcome.principal = 0.4960; // held back 0.8 %, by gravity say: still no limit found
  EXPECT_TRUE(reached_far_target(s));
  s.outcome.principal = 0.1168; // the threefold chainmail's limit
  EXPECT_FALSE(reached_far_target(s));
  s.kind = SampleKind::negative, s.target_p = -0.5, s.outcome.principal = -0.4999;
  EXPECT_TRUE(reached_far_target(s));
  s.outcome.principal = 0.4999; // the wrong side
  EXPECT_FALSE(reached_far_target(s));
  // A level sample drives the orthogonal component; the held principal one does not count.
  s.kind = SampleKind::level_down, s.target_p = 0.02, s.target_o = -0.5;
  s.outcome.principal = 0.02, s.outcome.orthogonal = -0.3;
  EXPECT_FALSE(reached_far_target(s));
  s.outcome.orthogonal = -0.50008;
  EXPECT_TRUE(reached_far_target(s));
}

TEST(Sampling, LimitsTableReportsOnlyWhatWasSampled)
{
  // `Positive only`: the stretch limits were sampled, compression was not, so neither it nor the
  // range of travel c (which needs both) may be reported as a number (it once read 0 and c).
  std::vector<DirectionalLimits> stretch(2);
  stretch[0].positive_p = 0.09, stretch[1].positive_p = 0.05;
  std::istringstream table(limits_table(stretch, {}));
  std::string        header, row;
  std::getline(table, header);
  std::getline(table, row);
  EXPECT_EQ(row, "0,0.09,0,,,,,,,");
}

TEST(Sampling, LimitsTableHasARowPerDirectionOfEitherTestAndLeavesTheOthersFieldsEmpty)
{
  // Six in-plane directions (every 30 deg), four bending ones (every 45 deg): rows at 0, 30, 45,
  // 60, 90, 120, 135, 150 deg.
  std::vector<DirectionalLimits> stretch(6), bending(4);
  for (unsigned d = 0; d < 6; ++d)
    stretch[d].positive_p = 0.01 * (d + 1), stretch[d].negative_p = -0.01, stretch[d].negative_sampled = true;
  for (unsigned d = 0; d < 4; ++d)
    bending[d].positive_p = 0.1 * (d + 1), bending[d].negative_p = -0.1, bending[d].negative_sampled = true;
  std::istringstream       table(limits_table(stretch, bending));
  std::vector<std::string> lines;
  for (std::string line; std::getline(table, line);)
    lines.push_back(line);
  ASSERT_EQ(lines.size(), 9u);
  EXPECT_EQ(lines[0].substr(0, 22), "theta_deg,eps_stretch,");
  const auto fields = [](const std::string &line) {
    std::vector<std::string> f;
    std::string              item;
    std::istringstream       in(line);
    while (std::getline(in, item, ','))
      f.push_back(item);
    if (!line.empty() && line.back() == ',')
      f.push_back("");
    return f;
  };
  const std::vector<std::string> angle{"0", "30", "45", "60", "90", "120", "135", "150"};
  const std::vector<bool>        in_plane{true, true, false, true, true, true, false, true};
  const std::vector<bool>        bent{true, false, true, false, true, false, true, false};
  for (unsigned r = 0; r < 8; ++r)
    {
      const auto f = fields(lines[r + 1]);
      ASSERT_EQ(f.size(), 10u) << lines[r + 1];
      EXPECT_EQ(f[0], angle[r]);
      EXPECT_EQ(f[1].empty(), !in_plane[r]) << lines[r + 1];
      EXPECT_EQ(f[6].empty(), !bent[r]) << lines[r + 1];
    }
  // The values land in their rows: 60 deg is the third stretch direction, 135 the fourth bending.
  EXPECT_DOUBLE_EQ(std::stod(fields(lines[4])[1]), 0.03);
  EXPECT_DOUBLE_EQ(std::stod(fields(lines[7])[6]), 0.4);
  // c of eq. 4.4.1 at 0 deg: (0.01 + 0.01) / (1 - 0.01).
  EXPECT_NEAR(std::stod(fields(lines[1])[5]), 0.02 / 0.99, 1e-9);
  // One test alone: its fields only, the other's empty everywhere.
  std::istringstream alone(limits_table(stretch, {}));
  std::string        line;
  std::getline(alone, line);
  unsigned rows = 0;
  while (std::getline(alone, line))
    {
      ++rows;
      EXPECT_TRUE(fields(line)[6].empty());
    }
  EXPECT_EQ(rows, 6u);
}
