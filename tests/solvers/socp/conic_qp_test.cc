// The interior-point cone QP solver against independent checks: the KKT conditions, a closed-form
// projection onto one cone, uniqueness from different starting points, infeasibility certificates.
#include <nlmech/solvers/socp/conic_qp.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <random>

using namespace nlmech;

namespace
{
  /// A random feasible problem: n unknowns, m cones of dimension d, strictly feasible at x0.
  ConicQP random_problem(unsigned int n, unsigned int m, unsigned int d, unsigned int seed, bool lp = false)
  {
    std::mt19937                           rng(seed);
    std::normal_distribution<double>       normal;
    std::uniform_real_distribution<double> uniform(0.1, 2.0);
    ConicQP                                p;
    p.P_diagonal = Eigen::VectorXd::NullaryExpr(n, [&]() { return lp ? 0.0 : uniform(rng); });
    p.q          = Eigen::VectorXd::NullaryExpr(n, [&]() { return normal(rng); });
    const Eigen::VectorXd               x0 = Eigen::VectorXd::NullaryExpr(n, [&]() { return normal(rng); });
    std::vector<Eigen::Triplet<double>> t;
    p.h.resize(m * d);
    for (unsigned int i = 0; i < m; ++i)
      {
        // rows i d .. i d + d - 1 touch 3 random columns
        std::vector<unsigned int> cols = {unsigned(rng() % n), unsigned(rng() % n), unsigned(rng() % n)};
        Eigen::VectorXd           Gx0  = Eigen::VectorXd::Zero(d);
        for (unsigned int r = 0; r < d; ++r)
          for (unsigned int c : cols)
            {
              const double v = normal(rng);
              t.emplace_back(i * d + r, c, v);
              Gx0[r] += v * x0[c];
            }
        // h = G x0 + s0 with s0 strictly inside the cone
        Eigen::VectorXd s0    = Eigen::VectorXd::NullaryExpr(d, [&]() { return normal(rng); });
        s0[0]                 = s0.tail(d - 1).norm() + uniform(rng);
        p.h.segment(i * d, d) = Gx0 + s0;
        p.cones.push_back(d);
      }
    p.G.resize(m * d, n);
    p.G.setFromTriplets(t.begin(), t.end());
    p.G.makeCompressed();
    if (lp) // bounded: |x| <= 10 by one more cone
      {
        p.G.conservativeResize(m * d + n + 1, n);
        std::vector<Eigen::Triplet<double>> t2 = t;
        for (unsigned int j = 0; j < n; ++j)
          t2.emplace_back(m * d + 1 + j, j, -1.0);
        p.G.setFromTriplets(t2.begin(), t2.end());
        p.G.makeCompressed();
        p.h.conservativeResize(m * d + n + 1);
        p.h.tail(n + 1).setZero();
        p.h[m * d] = 10 + x0.norm();
        p.cones.push_back(n + 1);
      }
    return p;
  }

  /// Largest violation of the KKT conditions of a returned solution, relative.
  double kkt_error(const ConicQP &p, const ConicResult &r)
  {
    const double stationarity =
        (p.P_diagonal.cwiseProduct(r.x) + p.q + p.G.transpose() * r.z).norm() / std::max(1.0, p.q.norm());
    const double primal = (r.s + p.G * r.x - p.h).norm() / std::max(1.0, p.h.norm());
    double       cone = 0, offset = 0;
    for (const unsigned int d : p.cones)
      {
        const auto s = r.s.segment(offset, d), z = r.z.segment(offset, d);
        cone = std::max({cone, s.tail(d - 1).norm() - s[0], z.tail(d - 1).norm() - z[0]});
        offset += d;
      }
    const double complementarity = std::abs(r.s.dot(r.z)) / std::max(1.0, std::abs(r.objective));
    return std::max({stationarity, primal, cone, complementarity});
  }
} // namespace

TEST(ConicQP, RandomProblemsMeetTheKktConditions)
{
  ConicQPSolver solver;
  for (unsigned int seed = 1; seed <= 20; ++seed)
    {
      const ConicQP     p = random_problem(30, 25, 2 + seed % 4, seed, seed % 5 == 0);
      const ConicResult r = solver.solve(p);
      ASSERT_EQ(r.status, ConicStatus::solved) << "seed " << seed << ": " << to_string(r.status);
      EXPECT_LT(kkt_error(p, r), 1e-8) << "seed " << seed;
      EXPECT_LT(r.iterations, 40u);
    }
}

TEST(ConicQP, ProjectionOntoOneConeIsTheClosedForm)
{
  // min 1/2 |x - a|^2 subject to |x_1| <= x_0: the Euclidean projection onto the cone.
  ConicQPSolver solver;
  const double  cases[][3] = {{1, 3, 0.5}, {-1, 0.3, -0.2}, {0.5, 2, 2}, {2, 0.1, 0.2}};
  for (const auto &a_values : cases)
    {
      const Eigen::Vector3d a(a_values[0], a_values[1], a_values[2]);
      ConicQP               p;
      p.P_diagonal = Eigen::VectorXd::Ones(3);
      p.q          = -a;
      p.G.resize(3, 3);
      p.G.setIdentity();
      p.G *= -1.0;
      p.G.makeCompressed();
      p.h                 = Eigen::VectorXd::Zero(3);
      p.cones             = {3};
      const ConicResult r = solver.solve(p);
      ASSERT_EQ(r.status, ConicStatus::solved);
      // Closed form: inside -> a; in the polar cone -> 0; else ((t + |y|)/2) (1, y/|y|).
      const double    t = a[0], ny = a.tail(2).norm();
      Eigen::Vector3d expected;
      if (ny <= t)
        expected = a;
      else if (ny <= -t)
        expected.setZero();
      else
        expected << 0.5 * (t + ny), 0.5 * (t + ny) * a.tail(2) / ny;
      EXPECT_LT((r.x - expected).norm(), 1e-8) << a.transpose();
    }
  EXPECT_EQ(solver.n_symbolic_analyses, 1u); // same pattern every time
}

TEST(ConicQP, SameSolutionFromDifferentStartingPoints)
{
  const ConicQP p = random_problem(40, 30, 4, 99);
  // Strongly convex (P >= 0.1): |x - x*|^2 <= 2 gap / 0.1, so a tight gap pins x down.
  ConicSettings settings;
  settings.gap_tolerance = settings.feasibility_tolerance = 1e-12;
  ConicQPSolver solver;
  const auto    reference = solver.solve(p, settings);
  ASSERT_TRUE(reference.status == ConicStatus::solved || reference.status == ConicStatus::almost_solved);
  std::mt19937                     rng(3);
  std::normal_distribution<double> normal(0, 10);
  for (int k = 0; k < 5; ++k)
    {
      const Eigen::VectorXd start = Eigen::VectorXd::NullaryExpr(p.q.size(), [&]() { return normal(rng); });
      const auto            r     = solver.solve(p, settings, &start);
      ASSERT_TRUE(r.status == ConicStatus::solved || r.status == ConicStatus::almost_solved);
      EXPECT_LT((r.x - reference.x).norm(), 1e-6 * std::max(1.0, reference.x.norm()));
    }
}

TEST(ConicQP, CentredStartFromAGivenPointFindsTheSameSolution)
{
  // The centred start (s = h - G x lifted into the cones, z = mu s^-1) must reach the solution of
  // CVXOPT's start on every problem, from near and far points, without the start's factorisation.
  std::mt19937                     rng(11);
  std::normal_distribution<double> normal;
  for (unsigned int seed = 1; seed <= 12; ++seed)
    {
      const ConicQP p = random_problem(30, 25, 2 + seed % 4, 100 + seed, seed % 6 == 0);
      ConicQPSolver reference_solver, solver;
      const auto    reference = reference_solver.solve(p);
      ASSERT_EQ(reference.status, ConicStatus::solved);
      EXPECT_EQ(reference_solver.n_factorizations, reference.iterations + 1);
      for (const double distance : {1e-3, 1.0, 10.0})
        for (const double mu : {1e-4, 1e-1})
          {
            const Eigen::VectorXd start =
                reference.x +
                distance * Eigen::VectorXd::NullaryExpr(p.q.size(), [&]() { return normal(rng); });
            ConicSettings settings;
            settings.start_mu         = mu;
            const unsigned int before = solver.n_factorizations;
            const ConicResult  r      = solver.solve(p, settings, &start);
            ASSERT_EQ(r.status, ConicStatus::solved)
                << "seed " << seed << ", distance " << distance << ", mu " << mu;
            EXPECT_LT(kkt_error(p, r), 1e-8) << "seed " << seed;
            EXPECT_LT(std::abs(r.objective - reference.objective),
                      1e-7 * std::max(1.0, std::abs(reference.objective)));
            // No factorisation for the start, and no restart from CVXOPT's point (the fallback)
            // on these problems, except from far away on LP-like ones.
            if (distance < 10 || seed % 6 != 0)
              {
                EXPECT_EQ(solver.n_factorizations - before, r.iterations) << "seed " << seed;
                EXPECT_LT(r.iterations, 50u);
              }
          }
    }
}

TEST(ConicQP, SimplicialAndSupernodalFactorisationsGiveTheSameSolution)
{
  // The normal equations factorised column by column (simplicial, CHOLMOD's choice for small
  // problems) or by supernodes: the same iterates up to round-off, so the same solution.
  for (unsigned int seed = 1; seed <= 4; ++seed)
    {
      const ConicQP              p = random_problem(60, 50, 4, 300 + seed);
      ConicSettings              settings;
      std::array<ConicResult, 3> r;
      std::array<bool, 3>        simplicial{};
      for (int mode = 0; mode < 3; ++mode)
        {
          settings.factorization = mode == 0   ? ConicFactorization::automatic
                                   : mode == 1 ? ConicFactorization::supernodal
                                               : ConicFactorization::simplicial;
          ConicQPSolver solver;
          r[mode]          = solver.solve(p, settings);
          simplicial[mode] = solver.simplicial();
          ASSERT_EQ(r[mode].status, ConicStatus::solved) << "seed " << seed << ", mode " << mode;
          EXPECT_LT(kkt_error(p, r[mode]), 1e-8);
        }
      EXPECT_TRUE(simplicial[0]); // 60 unknowns: far below 40 flops per entry of L
      EXPECT_FALSE(simplicial[1]);
      EXPECT_TRUE(simplicial[2]);
      EXPECT_LT((r[1].x - r[2].x).norm(), 1e-8 * std::max(1.0, r[1].x.norm())) << "seed " << seed;
      EXPECT_EQ(r[1].iterations, r[2].iterations);
    }
}

TEST(ConicQP, InfeasibleProblemsAreDetected)
{
  // |x - 0| <= 1 and |x - 3| <= 1 in 1D (as 2D cones (1, x) and (1, x - 3)).
  ConicQP p;
  p.P_diagonal = Eigen::VectorXd::Ones(1);
  p.q          = Eigen::VectorXd::Zero(1);
  p.G.resize(4, 1);
  p.G.insert(1, 0) = -1;
  p.G.insert(3, 0) = -1;
  p.G.makeCompressed();
  p.h     = (Eigen::VectorXd(4) << 1, 0, 1, -3).finished();
  p.cones = {2, 2};
  ConicQPSolver     solver;
  const ConicResult r = solver.solve(p);
  EXPECT_EQ(r.status, ConicStatus::primal_infeasible) << to_string(r.status);
  // Touching balls (distance 2): feasible, x = 1.
  p.h[3]               = -2;
  const ConicResult r2 = solver.solve(p);
  EXPECT_TRUE(r2.status == ConicStatus::solved || r2.status == ConicStatus::almost_solved)
      << to_string(r2.status);
  EXPECT_NEAR(r2.x[0], 1.0, 1e-4);
}

namespace
{
  /// |x| <= 1 and |x - (2 + g)| <= 1 in 1D (as the 2D cones (1, x) and (1, x - 2 - g)), minimising
  /// x^2 / 2: infeasible by a gap g > 0; for g < 0 the solution is x = 1 + g.
  ConicQP two_intervals(const double g)
  {
    ConicQP p;
    p.P_diagonal = Eigen::VectorXd::Ones(1);
    p.q          = Eigen::VectorXd::Zero(1);
    p.G.resize(4, 1);
    p.G.insert(1, 0) = -1;
    p.G.insert(3, 0) = -1;
    p.G.makeCompressed();
    p.h     = (Eigen::VectorXd(4) << 1, 0, 1, -(2 + g)).finished();
    p.cones = {2, 2};
    return p;
  }
} // namespace

TEST(ConicQP, NearlyInfeasibleProblemsAreCertified)
{
  // Near g = 1e-5 the certificate's h^T z < 0 is of the size of round-off for the direct method,
  // which stalls there (it stopped as "stalled" or "numerical error" after 11-23 iterations at
  // 1e-5 to 1e-7); the embedding then certifies infeasibility. The certificate is checked
  // independently: z in K x K, h^T z = -1, G^T z ~ 0.
  // A certificate with |G^T z| / -h^T z = eps proves that no feasible x has |x| < 1 / eps (from
  // 0 <= s^T z = h^T z - x^T G^T z); at the default eps = 1e-8 it needs |G^T z| / |z| ~ 1e-8 g,
  // which the iterates themselves reach only down to g ~ 1e-5 (rounding); the polished
  // certificate (one more solve with the factorisation at hand) goes further.
  for (const double g : {1e-2, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9})
    for (const ConicMethod method : {ConicMethod::automatic, ConicMethod::embedded})
      {
        const ConicQP p = two_intervals(g);
        ConicQPSolver solver;
        ConicSettings settings;
        settings.method     = method;
        const ConicResult r = solver.solve(p, settings);
        std::printf("gap %.0e, %s: %s after %u iterations%s\n", g,
                    method == ConicMethod::embedded ? "embedded" : "automatic", to_string(r.status).c_str(),
                    r.iterations, r.embedded ? " (by the embedding)" : "");
        EXPECT_EQ(r.status, ConicStatus::primal_infeasible) << "gap " << g << ": " << to_string(r.status);
        if (r.status != ConicStatus::primal_infeasible)
          continue;
        // h^T z in rounding: |h| |z| / |h^T z| ~ 1 / g.
        EXPECT_NEAR(p.h.dot(r.z), -1.0, 1e-14 / g) << "gap " << g;
        EXPECT_LE((p.G.transpose() * r.z).norm(), settings.infeasibility_tolerance * (1 + 1e-6))
            << "gap " << g;
        for (int i = 0; i < 2; ++i)
          EXPECT_GE(r.z[2 * i] - std::abs(r.z[2 * i + 1]), 0.0) << "gap " << g;
        EXPECT_LE(r.iterations, 60u) << "gap " << g;
      }
}

TEST(ConicQP, NearlyInfeasibleLargerProblemsAreCertified)
{
  // The two intervals on one unknown of a random feasible problem (40 unknowns, 30 cones of
  // dimension 4, x_0 in other cones too): infeasible by g, certified the same way down to 1e-5.
  // At 1e-7 two of the three are certified; in the third the embedding's iterates reach the cone
  // boundary in rounding (after 25 steps, |G^T z| / -h^T z ~ 1e-2) and the run ends "numerical
  // error": named, not certified.
  for (const double g : {1e-3, 1e-5, 1e-7})
    for (unsigned int seed = 1; seed <= 3; ++seed)
      {
        ConicQP                             p   = random_problem(40, 30, 4, 500 + seed);
        const ConicQP                       two = two_intervals(g);
        std::vector<Eigen::Triplet<double>> t;
        for (int c = 0; c < p.G.outerSize(); ++c)
          for (Eigen::SparseMatrix<double>::InnerIterator it(p.G, c); it; ++it)
            t.emplace_back(it.row(), it.col(), it.value());
        const Eigen::Index rows = p.G.rows();
        t.emplace_back(rows + 1, 0, -1.0);
        t.emplace_back(rows + 3, 0, -1.0);
        p.G.resize(rows + 4, p.G.cols());
        p.G.setFromTriplets(t.begin(), t.end());
        p.G.makeCompressed();
        p.h.conservativeResize(rows + 4);
        p.h.tail(4) = two.h;
        p.cones.push_back(2), p.cones.push_back(2);
        ConicQPSolver     solver;
        const ConicResult r = solver.solve(p);
        std::printf("random problem %u with a gap %.0e: %s after %u iterations%s\n", seed, g,
                    to_string(r.status).c_str(), r.iterations, r.embedded ? " (by the embedding)" : "");
        if (g < 1e-6)
          {
            EXPECT_TRUE(r.status == ConicStatus::primal_infeasible || r.status == ConicStatus::stalled ||
                        r.status == ConicStatus::numerical_error)
                << to_string(r.status);
            EXPECT_LT(r.iterations, 100u);
            continue;
          }
        ASSERT_EQ(r.status, ConicStatus::primal_infeasible) << "gap " << g << ", seed " << seed;
        EXPECT_LE((p.G.transpose() * r.z).norm(), 1e-8 * (1 + 1e-6));
        EXPECT_NEAR(p.h.dot(r.z), -1.0, 1e-6);
        for (std::size_t i = 0, o = 0; i < p.cones.size(); o += p.cones[i], ++i)
          EXPECT_GE(r.z[Eigen::Index(o)] - r.z.segment(Eigen::Index(o) + 1, p.cones[i] - 1).norm(), 0.0);
      }
}

TEST(ConicQP, NearlyInfeasibleFeasibleProblemsAreSolved)
{
  // The other side: overlapping by |g|, the solution x = 1 + g, by both methods.
  for (const double g : {-1e-2, -1e-4, -1e-6, -1e-8})
    for (const ConicMethod method : {ConicMethod::automatic, ConicMethod::embedded})
      {
        const ConicQP p = two_intervals(g);
        ConicQPSolver solver;
        ConicSettings settings;
        settings.method     = method;
        const ConicResult r = solver.solve(p, settings);
        std::printf("overlap %.0e, %s: %s after %u iterations, x - (1 + g) = %.2e\n", -g,
                    method == ConicMethod::embedded ? "embedded" : "automatic", to_string(r.status).c_str(),
                    r.iterations, r.x[0] - (1 + g));
        ASSERT_TRUE(r.status == ConicStatus::solved || r.status == ConicStatus::almost_solved)
            << "overlap " << -g << ": " << to_string(r.status);
        // The solution sits where two cones meet at a point of width |g|: x to a fraction of it.
        EXPECT_NEAR(r.x[0], 1 + g, std::max(1e-2 * std::abs(g), 1e-9)) << "overlap " << -g;
      }
}

TEST(ConicQP, EmbeddingSolvesWhatTheDirectMethodSolves)
{
  // Random feasible problems (QPs and LPs) by the embedding alone: the same solution as the
  // direct method, a tight KKT residual.
  for (unsigned int seed = 1; seed <= 8; ++seed)
    for (const bool lp : {false, true})
      {
        const ConicQP p = random_problem(30, 25, seed % 2 ? 3 : 5, 300 + seed, lp);
        ConicSettings direct, embedded;
        direct.method = ConicMethod::direct, embedded.method = ConicMethod::embedded;
        ConicQPSolver     solver;
        const ConicResult a = solver.solve(p, direct), b = solver.solve(p, embedded);
        ASSERT_EQ(a.status, ConicStatus::solved) << "seed " << seed;
        ASSERT_EQ(b.status, ConicStatus::solved) << "seed " << seed << ": " << to_string(b.status);
        EXPECT_TRUE(b.embedded);
        EXPECT_LT(kkt_error(p, b), 1e-8) << "seed " << seed;
        EXPECT_NEAR(a.objective, b.objective, 1e-7 * std::max(1.0, std::abs(a.objective))) << "seed " << seed;
        if (!lp) // strictly convex: x to the square root of the gap tolerance (|dx|^2 ~ gap / P_min)
          {
            EXPECT_LT((a.x - b.x).norm(), 1e-4 * std::max(1.0, a.x.norm())) << "seed " << seed;
          }
      }
}

TEST(ConicQP, UnboundedProblemsAreCertified)
{
  // Minimise -x1 + x2^2 / 2 over x1 >= |x2 - 1| (the cone (x1, x2 - 1)): unbounded along x1, with
  // the certificate x = (1, 0) (P x = 0, -G x = (1, 0) in K, q^T x = -1).
  ConicQP p;
  p.P_diagonal = (Eigen::VectorXd(2) << 0, 1).finished();
  p.q          = (Eigen::VectorXd(2) << -1, 0).finished();
  p.G.resize(2, 2);
  p.G.insert(0, 0) = -1;
  p.G.insert(1, 1) = -1;
  p.G.makeCompressed();
  p.h     = (Eigen::VectorXd(2) << 0, -1).finished();
  p.cones = {2};
  ConicQPSolver     solver;
  const ConicResult r = solver.solve(p);
  ASSERT_EQ(r.status, ConicStatus::dual_infeasible) << to_string(r.status);
  EXPECT_TRUE(r.embedded);
  EXPECT_NEAR(p.q.dot(r.x), -1.0, 1e-12);
  EXPECT_LT((p.P_diagonal.cwiseProduct(r.x)).norm(), 1e-8);
  const Eigen::VectorXd minus_Gx = -(p.G * r.x);
  EXPECT_GE(minus_Gx[0] - std::abs(minus_Gx[1]), -1e-8);
}

TEST(ConicQP, BadlyScaledProblemsAreSolvedToATightKktResidual)
{
  // Cones whose rows are scaled over twelve orders of magnitude (G rows and h times 1e-6 .. 1e6:
  // the same feasible set) and unknowns in units six orders apart (x = D y): the same problem in
  // bad units must still end solved, to a tight KKT residual, at tight tolerances.
  for (unsigned int seed = 1; seed <= 6; ++seed)
    {
      ConicQP                                p = random_problem(40, 30, 4, 100 + seed);
      std::mt19937                           rng(seed);
      std::uniform_real_distribution<double> exponent(-6, 6), p_exponent(-3, 3);
      Eigen::VectorXd                        row_scale(p.h.size());
      for (std::size_t i = 0, o = 0; i < p.cones.size(); o += p.cones[i], ++i)
        row_scale.segment(Eigen::Index(o), p.cones[i]).setConstant(std::pow(10.0, exponent(rng)));
      p.G = row_scale.asDiagonal() * p.G;
      p.h = row_scale.cwiseProduct(p.h);
      // Unknowns in units six orders of magnitude apart: x = D y.
      Eigen::VectorXd column_scale(p.q.size());
      for (Eigen::Index j = 0; j < column_scale.size(); ++j)
        column_scale[j] = std::pow(10.0, p_exponent(rng));
      p.G          = p.G * column_scale.asDiagonal();
      p.P_diagonal = p.P_diagonal.cwiseProduct(column_scale.cwiseAbs2());
      p.q          = p.q.cwiseProduct(column_scale);
      ConicSettings tight;
      tight.gap_tolerance = tight.feasibility_tolerance = 1e-10;
      ConicQPSolver     solver;
      const ConicResult r = solver.solve(p, tight);
      std::printf("badly scaled seed %u: %s in %u iterations, KKT %.2e gap %.1e\n", seed,
                  to_string(r.status).c_str(), r.iterations, kkt_error(p, r), r.gap);
      EXPECT_EQ(r.status, ConicStatus::solved) << "seed " << seed << ": " << to_string(r.status);
      EXPECT_LT(kkt_error(p, r), 1e-9) << "seed " << seed;
    }
}

namespace
{
  /// The projection step of strain limiting on a chain: min sum_i m_i/2 |x_i - y_i|^2 subject to
  /// |x_{i+1} - x_i| <= L for every edge, with y stretched 30 % past the limits and masses spread
  /// over `orders` orders of magnitude (very light and very heavy vertices side by side): most
  /// cones active, multipliers and NT scalings over many orders.
  ConicQP chain_projection(unsigned int n_vertices, double orders, unsigned int seed)
  {
    std::mt19937                           rng(seed);
    std::uniform_real_distribution<double> exponent(-orders / 2, orders / 2), noise(-0.2, 0.2);
    const double                           L = 1;
    ConicQP                                p;
    const Eigen::Index                     n = 2 * Eigen::Index(n_vertices);
    p.P_diagonal.resize(n);
    p.q.resize(n);
    for (unsigned int i = 0; i < n_vertices; ++i)
      {
        const double m    = std::pow(10.0, exponent(rng));
        const double y[2] = {1.3 * L * i, noise(rng)};
        for (unsigned int k = 0; k < 2; ++k)
          p.P_diagonal[2 * i + k] = m, p.q[2 * i + k] = -m * y[k];
      }
    std::vector<Eigen::Triplet<double>> t;
    const unsigned int                  edges = n_vertices - 1;
    p.h                                       = Eigen::VectorXd::Zero(3 * edges);
    for (unsigned int e = 0; e < edges; ++e)
      {
        p.h[3 * e] = L; // s = (L, x_{e+1} - x_e) = h - G x
        for (unsigned int k = 0; k < 2; ++k)
          {
            t.emplace_back(3 * e + 1 + k, 2 * (e + 1) + k, -1.0);
            t.emplace_back(3 * e + 1 + k, 2 * e + k, 1.0);
          }
        p.cones.push_back(3);
      }
    p.G.resize(3 * edges, n);
    p.G.setFromTriplets(t.begin(), t.end());
    p.G.makeCompressed();
    return p;
  }
} // namespace

TEST(ConicQP, ProjectionWithMassesOverManyOrdersIsSolvedToATightKktResidual)
{
  // Masses over 10 orders of magnitude (the light and heavy vertices of a strain-limiting
  // projection side by side): the normal matrix P + G^T W^-2 G spans them on top of the NT scalings,
  // and the result must still meet tight tolerances. (Measured: with masses over 14-20 orders and
  // tolerances of 1e-12-1e-13 some seeds end `almost solved` or `numerical error`, with or without
  // the one step of iterative refinement in the normal-equation solves; at 10 orders and 1e-11
  // every seed is solved either way.)
  for (unsigned int seed = 1; seed <= 6; ++seed)
    {
      const ConicQP p = chain_projection(200, 10, seed);
      ConicSettings tight;
      tight.gap_tolerance = tight.feasibility_tolerance = 1e-11;
      ConicQPSolver     solver;
      const ConicResult r = solver.solve(p, tight);
      std::printf("chain projection seed %u: %s in %u iterations, KKT %.2e\n", seed,
                  to_string(r.status).c_str(), r.iterations, kkt_error(p, r));
      EXPECT_EQ(r.status, ConicStatus::solved) << "seed " << seed << ": " << to_string(r.status);
      EXPECT_LT(kkt_error(p, r), 1e-9) << "seed " << seed;
    }
}
