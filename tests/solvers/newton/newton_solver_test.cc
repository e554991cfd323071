// Newton with diagonal shifts on an indefinite energy: it must reach a true minimum (gradient
// zero, Hessian positive definite, checked densely) and, because the shift search starts from the
// last shift that worked, pay for the search about once rather than in every indefinite iteration.
#include <nlmech/solvers/newton/newton_solver.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cstdio>

using namespace nlmech;

namespace
{
  /// sum_i (x_i^2 - 1)^2 + k/2 sum_i (x_i - x_{i+1})^2: a chain of double wells, indefinite near 0.
  class DoubleWellChain : public EnergyTerm
  {
  public:
    explicit DoubleWellChain(double k)
        : k(k)
    {
    }
    std::string name() const override { return "double-well chain"; }
    double      value(const Eigen::VectorXd &x) const override
    {
      double e = 0;
      for (Eigen::Index i = 0; i < x.size(); ++i)
        e += std::pow(x[i] * x[i] - 1, 2) + (i + 1 < x.size() ? 0.5 * k * std::pow(x[i] - x[i + 1], 2) : 0.0);
      return e;
    }
    void add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const override
    {
      for (Eigen::Index i = 0; i < x.size(); ++i)
        {
          g[i] += 4 * x[i] * (x[i] * x[i] - 1);
          if (i + 1 < x.size())
            g[i] += k * (x[i] - x[i + 1]), g[i + 1] -= k * (x[i] - x[i + 1]);
        }
    }
    void add_hessian(const Eigen::VectorXd &x, Triplets &h) const override
    {
      for (Eigen::Index i = 0; i < x.size(); ++i)
        {
          h.emplace_back(i, i, 12 * x[i] * x[i] - 4);
          if (i + 1 < x.size())
            {
              h.emplace_back(i, i, k), h.emplace_back(i + 1, i + 1, k);
              h.emplace_back(i, i + 1, -k), h.emplace_back(i + 1, i, -k);
            }
        }
    }

  private:
    double k;
  };
} // namespace

TEST(Newton, IndefiniteEnergyReachesAMinimumWithFewShiftSearches)
{
  const Eigen::Index n = 200;
  Model              model(n);
  auto               term = std::make_shared<DoubleWellChain>(0.5);
  model.add_term(term);
  const DerivativeCheck check = check_derivatives(*term, Eigen::VectorXd::LinSpaced(n, -0.3, 0.4));
  EXPECT_LT(check.gradient_error, 1e-7);
  EXPECT_LT(check.hessian_error, 1e-7);
  // Start near the top of the wells (Hessian diagonal about -4): indefinite for several iterations.
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i)
    x[i] = 0.05 * std::sin(0.37 * double(i)) + 0.01;
  NewtonSettings settings;
  settings.max_iterations = 100;
  const NewtonResult r    = minimize_with_newton(model, x, settings);
  std::printf("%u iterations, %u factorisations, gradient %.3e\n", r.iterations, r.factorizations,
              r.gradient_norm);
  const Eigen::VectorXd g = model.gradient(x);
  EXPECT_LT(g.norm(), 1e-9);
  const Eigen::MatrixXd H = Eigen::MatrixXd(model.hessian(x));
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues().minCoeff(), 0.0);
  // Every x_i in a well (|x_i| near 1), energy below the start's.
  EXPECT_GT(x.cwiseAbs().minCoeff(), 0.5);
  // Without the memory each indefinite iteration climbs the shift ladder from 1e-8 of the
  // diagonal (about ten factorisations); with it, only the first one does.
  EXPECT_LE(r.factorizations, 2 * r.iterations + 12);
}
