// Native-scale contact of rigid interlocking elements: barrier derivatives against finite
// differences for every placement and primitive type, distances against closed forms, and two linked
// tori pulled apart, whose largest centre distance is 2 (R - r) (the inner edges of the two holes touch).
#include <nlmech/dim/element_shape.h>
#include <nlmech/dim/patterns.h>
#include <nlmech/dim/rigid_assembly.h>
#include <nlmech/models/model.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <limits>
#include <random>

using namespace nlmech;
using namespace nlmech::dim;

namespace
{
  /// Largest difference between the analytic gradient and Hessian and central differences,
  /// relative to the largest entry of each.
  std::pair<double, double> derivative_errors(const EnergyTerm &term, const Eigen::VectorXd &q,
                                              const double h)
  {
    const Eigen::Index n = q.size();
    Eigen::VectorXd    g = Eigen::VectorXd::Zero(n);
    term.add_gradient(q, g);
    Triplets t;
    term.add_hessian(q, t);
    Eigen::SparseMatrix<double> Hs(n, n);
    Hs.setFromTriplets(t.begin(), t.end());
    const Eigen::MatrixXd H = Hs;
    Eigen::VectorXd       g_fd(n);
    Eigen::MatrixXd       H_fd(n, n);
    for (Eigen::Index i = 0; i < n; ++i)
      {
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += h, qm[i] -= h;
        g_fd[i]            = (term.value(qp) - term.value(qm)) / (2 * h);
        Eigen::VectorXd gp = Eigen::VectorXd::Zero(n), gm = Eigen::VectorXd::Zero(n);
        term.add_gradient(qp, gp), term.add_gradient(qm, gm);
        H_fd.col(i) = (gp - gm) / (2 * h);
      }
    return {(g - g_fd).lpNorm<Eigen::Infinity>() / g.lpNorm<Eigen::Infinity>(),
            (H - H_fd).lpNorm<Eigen::Infinity>() / H.lpNorm<Eigen::Infinity>()};
  }

  Eigen::VectorXd state(const std::vector<Eigen::Matrix<double, 6, 1>> &bodies,
                        const std::vector<double>                      &params = {})
  {
    Eigen::VectorXd q(6 * bodies.size() + params.size());
    for (std::size_t b = 0; b < bodies.size(); ++b)
      q.segment<6>(6 * b) = bodies[b];
    for (std::size_t j = 0; j < params.size(); ++j)
      q[6 * bodies.size() + j] = params[j];
    return q;
  }
  Eigen::Matrix<double, 6, 1> body(double x, double y, double z, double wx, double wy, double wz)
  {
    Eigen::Matrix<double, 6, 1> b;
    b << x, y, z, wx, wy, wz;
    return b;
  }
} // namespace

TEST(PrimitiveDistance, ClosedFormsOfSegmentsAndTriangles)
{
  // Crossed segments at height 2: line-line type, distance 2.
  const auto ll = segment_segment_type({-1, 0, 0}, {1, 0, 0}, {0, -1, 2}, {0, 1, 2});
  EXPECT_EQ(ll.type, DistanceType::line_line);
  EXPECT_NEAR(std::sqrt(ll.squared_distance), 2.0, 1e-14);
  // Parallel segments offset by 3 and overlapping: the endpoint-segment type, distance 3.
  const auto par = segment_segment_type({0, 0, 0}, {2, 0, 0}, {1, 3, 0}, {4, 3, 0});
  EXPECT_NEAR(std::sqrt(par.squared_distance), 3.0, 1e-14);
  // Collinear, apart by 1: point-point.
  const auto pp = segment_segment_type({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0});
  EXPECT_EQ(pp.type, DistanceType::point_point);
  EXPECT_NEAR(std::sqrt(pp.squared_distance), 1.0, 1e-14);
  // Point above a triangle's interior, beyond an edge, beyond a vertex.
  const Eigen::Vector3d t0(0, 0, 0), t1(2, 0, 0), t2(0, 2, 0);
  EXPECT_EQ(point_triangle_type({0.5, 0.5, 1.5}, t0, t1, t2).type, DistanceType::point_plane);
  EXPECT_NEAR(std::sqrt(point_triangle_type({0.5, 0.5, 1.5}, t0, t1, t2).squared_distance), 1.5, 1e-14);
  EXPECT_EQ(point_triangle_type({1, -1, 0}, t0, t1, t2).type, DistanceType::point_line);
  EXPECT_NEAR(std::sqrt(point_triangle_type({1, -1, 1}, t0, t1, t2).squared_distance), std::sqrt(2.0), 1e-14);
  EXPECT_EQ(point_triangle_type({-1, -1, 0}, t0, t1, t2).type, DistanceType::point_point);
  // A segment through the triangle has distance 0; one passing beside it, the edge distance.
  EXPECT_EQ(segment_triangle_distance({0.5, 0.5, -1}, {0.5, 0.5, 1}, t0, t1, t2), 0.0);
  EXPECT_NEAR(segment_triangle_distance({3, 0, -1}, {3, 0, 1}, t0, t1, t2), 1.0, 1e-14);
}

TEST(PrimitiveDistance, RotationVectorGivesTheRotationMatrix)
{
  const Eigen::Vector3d omega(0.3, -0.7, 1.1);
  const Eigen::Matrix3d R = RigidAssembly::rotation(omega);
  const Eigen::Matrix3d E = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  EXPECT_LT((R - E).norm(), 1e-14);
  // The series branch near zero.
  const Eigen::Vector3d small(1e-3, 2e-3, -3e-3);
  EXPECT_LT((RigidAssembly::rotation(small) -
             Eigen::AngleAxisd(small.norm(), small.normalized()).toRotationMatrix())
                .norm(),
            1e-15);
}

TEST(ContactBarrier, DerivativesOfTwoRingsMatchFiniteDifferences)
{
  // Two linked rings (R = 3, r = 1 mm) pulled close to contact, slightly rotated: line-line and
  // point-line pairs within dhat.
  auto assembly = std::make_shared<RigidAssembly>(std::vector<ElementShape>{torus_ring(3, 1, 32, 1e-6)},
                                                  std::vector<unsigned>{0, 0});
  ContactSettings settings;
  settings.dhat             = 0.2;
  settings.project_hessians = false;
  ContactBarrier barrier(assembly, settings);
  const auto     q =
      state({body(0, 0, 0, 0.01, -0.02, 0.03), body(3.9, 0.05, -0.02, M_PI / 2 + 0.02, 0.01, 0.04)});
  ASSERT_TRUE(barrier.is_valid(q));
  const auto pairs = assembly->contact_pairs(q, settings.dhat);
  ASSERT_GE(pairs.size(), 2u);
  const auto [eg, eh] = derivative_errors(barrier, q, 1e-6);
  std::printf("two rings: %zu pairs, gradient error %.2e, Hessian error %.2e\n", pairs.size(), eg, eh);
  EXPECT_LT(eg, 1e-6);
  EXPECT_LT(eh, 1e-5);
}

TEST(ContactBarrier, OneCollisionSearchPerState)
{
  // Value, gradient and Hessian at one state share one search; a new state searches again; the
  // kept pairs give the same figures as a barrier that searches afresh.
  auto assembly = std::make_shared<RigidAssembly>(std::vector<ElementShape>{torus_ring(3, 1, 32, 1e-6)},
                                                  std::vector<unsigned>{0, 0});
  ContactSettings settings;
  settings.dhat       = 0.2;
  settings.separation = 0.05;
  ContactBarrier barrier(assembly, settings);
  const auto     q =
      state({body(0, 0, 0, 0.01, -0.02, 0.03), body(3.82, 0.05, -0.02, M_PI / 2 + 0.02, 0.01, 0.04)});
  ASSERT_TRUE(barrier.is_valid(q));
  const std::size_t searches_for_validity = barrier.n_collision_searches(); // is_valid: exact gaps
  Eigen::VectorXd   g                     = Eigen::VectorXd::Zero(q.size());
  Triplets          h;
  const double      e = barrier.value(q);
  barrier.add_gradient(q, g);
  barrier.add_hessian(q, h);
  EXPECT_EQ(barrier.n_collision_searches(), searches_for_validity + 1);
  ASSERT_GT(e, 0.0);
  Eigen::VectorXd q2 = q;
  q2[6] += 1e-3;
  barrier.value(q2);
  EXPECT_EQ(barrier.n_collision_searches(), searches_for_validity + 2);
  ContactBarrier  fresh(assembly, settings);
  Eigen::VectorXd g_fresh = Eigen::VectorXd::Zero(q.size());
  fresh.add_gradient(q, g_fresh);
  barrier.add_gradient(q, g.setZero());
  EXPECT_EQ(fresh.value(q), e);
  EXPECT_EQ((g - g_fresh).lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_EQ(barrier.n_collision_searches(), searches_for_validity + 3);
}

TEST(ContactBarrier, DerivativesWithSeparationAndPlatesMatchFiniteDifferences)
{
  // Scale-mail elements: plate faces against plate points (point-plane pairs) and ring tubes, with
  // a print clearance of 0.05 mm.
  auto shape = scale_mail_element(3, 0.6, 0.0, 48, 3.4, 0.6, 1.6, 1e-6);
  auto assembly =
      std::make_shared<RigidAssembly>(std::vector<ElementShape>{shape}, std::vector<unsigned>{0, 0});
  ContactSettings settings;
  settings.dhat             = 0.3;
  settings.separation       = 0.05;
  settings.project_hessians = false;
  ContactBarrier barrier(assembly, settings);
  // Second element stacked above the first: its ring's points just above the first one's plate
  // (plate at 1.6, half-thickness 0.3, tube radius 0.6, clearance 0.05: gaps of about 0.1 mm).
  const auto q = state({body(0, 0, 0, 0.0, 0.0, 0.0), body(0.5, 0.3, 2.65, 0.01, -0.01, 0.2)});
  ASSERT_TRUE(barrier.is_valid(q)) << assembly->smallest_gap(q).gap;
  const auto pairs = assembly->contact_pairs(q, settings.dhat + settings.separation);
  unsigned   plane = 0;
  for (const auto &p : pairs)
    plane += p.type == DistanceType::point_plane;
  ASSERT_GE(plane, 1u);
  const auto [eg, eh] = derivative_errors(barrier, q, 1e-7);
  std::printf("plates: %zu pairs (%u point-plane), gradient error %.2e, Hessian error %.2e\n", pairs.size(),
              plane, eg, eh);
  EXPECT_LT(eg, 1e-6);
  EXPECT_LT(eh, 1e-5);
}

TEST(ContactBarrier, DerivativesThroughPeriodicImagesAndParaboloidMatchFiniteDifferences)
{
  // A one-ring periodic cell whose lattice is so short that a ring nearly touches its own image:
  // the barrier depends on the strain parameters through the image offsets.
  {
    auto assembly = std::make_shared<RigidAssembly>(std::vector<ElementShape>{torus_ring(3, 1, 32, 1e-6)},
                                                    std::vector<unsigned>{0}, Placement::periodic);
    Eigen::Matrix2d Bx, By, Bxy;
    Bx << 1, 0, 0, 0;
    By << 0, 0, 0, 1;
    Bxy << 0, 1, 1, 0;
    assembly->set_lattice({8.1, 0}, {0.3, 9}, {Bx, By, Bxy});
    ContactSettings settings;
    settings.dhat             = 0.3;
    settings.project_hessians = false;
    ContactBarrier barrier(assembly, settings);
    const auto     q = state({body(0, 0, 0, 0.05, 0.02, 0.1)}, {-0.0, 0.01, 0.002});
    ASSERT_TRUE(barrier.is_valid(q));
    ASSERT_GE(assembly->contact_pairs(q, settings.dhat).size(), 1u);
    const auto [eg, eh] = derivative_errors(barrier, q, 1e-7);
    std::printf("periodic: gradient error %.2e, Hessian error %.2e\n", eg, eh);
    EXPECT_LT(eg, 1e-6);
    EXPECT_LT(eh, 1e-5);
  }
  {
    auto assembly = std::make_shared<RigidAssembly>(std::vector<ElementShape>{torus_ring(3, 1, 32, 1e-6)},
                                                    std::vector<unsigned>{0, 0}, Placement::paraboloid);
    ContactSettings settings;
    settings.dhat             = 0.3;
    settings.project_hessians = false;
    ContactBarrier barrier(assembly, settings);
    const auto     q = state({body(-0.5, 0.2, 0, 0.05, 0.02, 0.1), body(7.6, 0.3, 0, 0.02, -0.03, 0.1)},
                             {0.01, -0.02, 0.005});
    ASSERT_TRUE(barrier.is_valid(q));
    ASSERT_GE(assembly->contact_pairs(q, settings.dhat).size(), 1u);
    const auto [eg, eh] = derivative_errors(barrier, q, 1e-7);
    std::printf("paraboloid: gradient error %.2e, Hessian error %.2e\n", eg, eh);
    EXPECT_LT(eg, 1e-6);
    EXPECT_LT(eh, 1e-5);
    // Gravity on the paraboloid acts on the curvatures too.
    CentreForces gravity(assembly, {Eigen::Vector3d(0, 0, -0.01), Eigen::Vector3d(0, 0, -0.01)});
    const auto [gg, gh] = derivative_errors(gravity, q, 1e-6);
    EXPECT_LT(gg, 1e-8);
    EXPECT_LT(gh, 1e-6);
  }
}

TEST(ContactBarrier, ProjectedHessianIsPositiveSemiDefinite)
{
  auto assembly = std::make_shared<RigidAssembly>(std::vector<ElementShape>{torus_ring(3, 1, 32, 1e-6)},
                                                  std::vector<unsigned>{0, 0});
  ContactSettings settings;
  settings.dhat = 0.2;
  ContactBarrier barrier(assembly, settings);
  const auto     q =
      state({body(0, 0, 0, 0.01, -0.02, 0.03), body(3.9, 0.05, -0.02, M_PI / 2 + 0.02, 0.01, 0.04)});
  Triplets t;
  barrier.add_hessian(q, t);
  Eigen::SparseMatrix<double> H(12, 12);
  H.setFromTriplets(t.begin(), t.end());
  const Eigen::VectorXd lambda =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(H)).eigenvalues();
  EXPECT_GE(lambda.minCoeff(), -1e-10 * lambda.maxCoeff());
}

TEST(LinkedTori, LargestCentreDistanceIsTwiceTheHoleRadius)
{
  // Ring A fixed in the xy plane, ring B in the xz plane through A's hole, pulled along x. At the
  // largest distance the inner edges of the two holes touch: |x_B - x_A| = 2 (R - r).
  const double R = 3, r = 1;
  auto assembly = std::make_shared<RigidAssembly>(std::vector<ElementShape>{torus_ring(R, r, 64, 1.24e-6)},
                                                  std::vector<unsigned>{0, 0});
  ContactSettings settings;
  settings.dhat  = 1e-3;
  settings.kappa = 1e-2;
  auto  barrier  = std::make_shared<ContactBarrier>(assembly, settings);
  Model model(assembly->n_unknowns());
  model.add_term(barrier);
  model.add_term(std::make_shared<CentreForces>(
      assembly, std::vector<Eigen::Vector3d>{Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0, 0)}));
  for (unsigned k = 0; k < 6; ++k)
    model.fix(k, 0.0);
  Eigen::VectorXd q = state({body(0, 0, 0, 0, 0, 0), body(R, 0, 0, M_PI / 2, 0, 0)});
  ASSERT_TRUE(model.is_valid(q));
  NewtonSettings newton;
  newton.max_iterations = 200;
  newton.step_tolerance = 1e-10;
  const auto   result   = minimize_with_newton(model, q, newton);
  const double distance = (assembly->centre(q, 1) - assembly->centre(q, 0)).norm();
  const double expected = 2 * (R - r);
  std::printf("linked tori: distance %.6f mm, expected %.6f (%.3f %%), %u Newton iterations, gap %.2e mm\n",
              distance, expected, 100 * (distance / expected - 1), result.iterations,
              assembly->smallest_gap(q).gap);
  EXPECT_NEAR(distance, expected, 0.005 * expected);
  EXPECT_GT(assembly->smallest_gap(q).gap, 0.0);
}

TEST(MeshElement, ATriangulatedTorusHasTheTorusVolumeExtentAndCentre)
{
  // meshes/dim-torus.geo (gmsh, OpenCASCADE torus R = 3, r = 1) as a closed triangulated surface:
  // the enclosed volume tends to 2 pi^2 R r^2 as the mesh is refined (the vertices lie on the torus,
  // so the polyhedron is inside it by about the chord sagitta), the extent is R + r, the centre of
  // mass is the origin.
  const double R = 3, r = 1, exact = 2 * M_PI * M_PI * R * r * r;
  double       last_error = 1;
  for (const double h : {0.8, 0.4})
    {
      const ElementShape s =
          triangle_mesh_element(std::string(NLMECH_SOURCE_DIR) + "/meshes/dim-torus.geo", 0.0, 1.0, h);
      const double error = std::abs(s.mass / exact - 1);
      std::printf("mesh torus h = %.1f: %zu triangles, volume %.4f (exact %.4f, %.2f %% low), extent %.4f\n",
                  h, s.triangles.size(), s.mass, exact, 100 * error, s.bounding_radius());
      EXPECT_LT(s.mass, exact);
      EXPECT_LT(error, 2 * h * h / (8 * r) / r + 0.01); // about twice the relative sagitta
      EXPECT_LT(error, last_error);                     // converges
      EXPECT_NEAR(s.bounding_radius(), R + r, 0.01);
      // Centred: the extremes are symmetric about the origin (x, y: R + r; z: r).
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
      for (const auto &p : s.points)
        lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      EXPECT_LT((hi + lo).lpNorm<Eigen::Infinity>(), 0.02);
      EXPECT_NEAR(hi.z(), r, 0.02);
      last_error = error;
    }
  // An open surface without a skin has no volume: rejected with an explanation.
  EXPECT_THROW(
      triangle_mesh_element(std::string(NLMECH_SOURCE_DIR) + "/meshes/unit_square.geo", 0.0, 1.0, 0.5),
      std::exception);
}

TEST(MeshElement, SphereTreeSearchFindsWhatTheAllPairsSearchFinds)
{
  // Two triangulated tori (skin 0.02 mm) in random placements near contact: the smallest gap and
  // the primitive pairs within reach from the sphere-tree search against the all-pairs reference
  // (every edge-edge and edge-face pair for the gap, edge-edge and vertex-face pairs for the list).
  const ElementShape s =
      triangle_mesh_element(std::string(NLMECH_SOURCE_DIR) + "/meshes/dim-torus.geo", 0.02, 1e-6, 0.8);
  const RigidAssembly                    assembly({s}, {0, 0});
  std::mt19937                           rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  unsigned                               with_pairs = 0, apart = 0;
  for (int trial = 0; trial < 8; ++trial)
    {
      const double    reach = 0.15;
      Eigen::VectorXd q =
          state({body(0, 0, 0, 0, 0, 0), body(4.0 + 0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng),
                                              M_PI / 2 + 0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng))});
      const auto [brute, close] = assembly.all_pairs_gap(q, 0, 1, {{0, 0}}, reach);
      const double tree         = assembly.exact_gap(q, 0, 1, {{0, 0}});
      const auto   pairs        = assembly.contact_pairs(q, reach);
      std::printf(
          "placement %d: smallest gap %.6e (all pairs %.6e), %zu pairs within reach (all pairs %zu)\n", trial,
          tree, brute, pairs.size(), close);
      EXPECT_NEAR(tree, brute, 1e-12);
      EXPECT_EQ(pairs.size(), close);
      with_pairs += close > 0, apart += brute > 0;
    }
  EXPECT_GE(with_pairs, 4u); // the placements do come within reach
  EXPECT_GE(apart, 1u);      // and some are intersection-free
}

TEST(MeshElement, LinkedTriangulatedToriSeparateToTwiceTheHoleRadius)
{
  // Two linked tori from meshes/dim-torus.geo (gmsh surface, h = 0.5 mm, skin radius s = 0.05 mm),
  // ring B pulled along the axis with only its x free (as the free-range test below): the largest
  // centre distance is 2 (R - r) - 2 s (each skin adds s to the tube and takes it from the hole),
  // plus at most the chord sagittas of the inscribed polyhedra at the two touching surfaces (the
  // facets lie inside the torus: h^2 / 8 r across the tube, h^2 / 8 (R - r) along the hole).
  const double       R = 3, r = 1, h = 0.5, skin = 0.05;
  const ElementShape s =
      triangle_mesh_element(std::string(NLMECH_SOURCE_DIR) + "/meshes/dim-torus.geo", skin, 1.24e-6, h);
  auto assembly = std::make_shared<RigidAssembly>(std::vector<ElementShape>{s}, std::vector<unsigned>{0, 0});
  ContactSettings settings;
  settings.dhat  = 1e-3;
  settings.kappa = 1e-2;
  Model model(assembly->n_unknowns());
  model.add_term(std::make_shared<ContactBarrier>(assembly, settings));
  model.add_term(std::make_shared<CentreForces>(
      assembly, std::vector<Eigen::Vector3d>{Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0, 0)}));
  Eigen::VectorXd q = state({body(0, 0, 0, 0, 0, 0), body(R, 0, 0, M_PI / 2, 0, 0)});
  for (unsigned k = 0; k < 12; ++k)
    if (k != 6)
      model.fix(k, q[k]);
  ASSERT_TRUE(model.is_valid(q));
  // Every accepted state is intersection-free (exact gaps between the swept triangles).
  double         smallest = std::numeric_limits<double>::infinity();
  NewtonSettings newton;
  newton.max_iterations = 200;
  newton.step_tolerance = 1e-10;
  newton.on_accepted    = [&](const Eigen::VectorXd &x) {
    smallest = std::min(smallest, assembly->smallest_gap(x).gap);
  };
  const auto   started  = std::chrono::steady_clock::now();
  const auto   result   = minimize_with_newton(model, q, newton);
  const double seconds  = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double distance = (assembly->centre(q, 1) - assembly->centre(q, 0)).norm();
  const double expected = 2 * (R - r) - 2 * skin, sagittas = h * h / (8 * r) + h * h / (8 * (R - r));
  std::printf(
      "linked mesh tori (%zu triangles each): distance %.5f mm, expected %.5f (+ up to %.4f), %u Newton "
      "iterations, %.2f s, smallest gap on the way %.2e mm\n",
      s.triangles.size(), distance, expected, sagittas, result.iterations, seconds, smallest);
  EXPECT_GT(distance, expected - 1e-3);
  EXPECT_LT(distance, expected + sagittas + 1e-3);
  EXPECT_GT(smallest, 0.0);
  EXPECT_GT(assembly->smallest_gap(q).gap, 0.0);
}

TEST(LinkedTori, TightAndImpossibleLinksAreRejectedAndTheFreeRangeClosesAtRIsTwoR)
{
  // R < 2 r: the tube cannot pass through the hole. R = 2 r: locked tight (zero free range).
  EXPECT_THROW(linked_ring_pair(1.9, 1, 32, 1e-6), std::exception);
  EXPECT_THROW(linked_ring_pair(2.0, 1, 32, 1e-6), std::exception);
  // Just above R = 2 r the pair is valid, and its free range of centre distance along the axis with
  // the rings held perpendicular, [2 r, 2 (R - r)], shrinks to zero as R -> 2 r: pushing and pulling
  // ring B (only its x free) stop at both ends.
  for (const double R : {2.4, 2.1})
    {
      const double r      = 1;
      const auto   placed = linked_ring_pair(R, r, 128, 1e-6);
      ASSERT_GT(placed.assembly->smallest_gap(placed.q).gap, 0);
      std::array<double, 2> ends{};
      for (int side = 0; side < 2; ++side)
        {
          ContactSettings settings;
          settings.dhat  = 1e-3;
          settings.kappa = 1e-2;
          Model model(placed.assembly->n_unknowns());
          model.add_term(std::make_shared<ContactBarrier>(placed.assembly, settings));
          model.add_term(std::make_shared<CentreForces>(
              placed.assembly,
              std::vector<Eigen::Vector3d>{Eigen::Vector3d::Zero(),
                                           Eigen::Vector3d(side == 0 ? 1e-3 : -1e-3, 0, 0)}));
          for (unsigned k = 0; k < 12; ++k)
            if (k != 6)
              model.fix(k, placed.q[k]);
          Eigen::VectorXd q = placed.q;
          NewtonSettings  newton;
          newton.max_iterations = 200;
          newton.step_tolerance = 1e-10;
          minimize_with_newton(model, q, newton);
          ends[side] = q[6];
        }
      std::printf("R = %.1f r: centre distance from %.4f to %.4f mm (closed form %.4f to %.4f)\n", R, ends[1],
                  ends[0], 2 * r, 2 * (R - r));
      EXPECT_NEAR(ends[0], 2 * (R - r), 0.005 * 2 * (R - r));
      EXPECT_NEAR(ends[1], 2 * r, 0.005 * 2 * r);
    }
}
