#include <nlmech/models/model.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>

namespace nlmech
{
  ConstantForceTerm::ConstantForceTerm(std::string term_name, Eigen::VectorXd force)
      : term_name(std::move(term_name))
      , force(std::move(force))
  {
  }

  double ConstantForceTerm::value(const Eigen::VectorXd &x) const
  {
    return -force.dot(x);
  }

  void ConstantForceTerm::add_gradient(const Eigen::VectorXd &, Eigen::VectorXd &g) const
  {
    g -= force;
  }

  Model::Model(const std::size_t n_unknowns)
      : n(n_unknowns)
      , mass(Eigen::VectorXd::Zero(n_unknowns))
  {
  }

  void Model::add_term(std::shared_ptr<const EnergyTerm> term)
  {
    energy_terms.push_back(std::move(term));
  }

  void Model::fix(const std::size_t i, const double value)
  {
    AssertThrow(i < n, dealii::ExcIndexRange(i, 0, n));
    fixed_values[i] = value;
  }

  double Model::energy(const Eigen::VectorXd &x) const
  {
    double e = 0;
    for (const auto &t : energy_terms)
      e += t->value(x);
    return e;
  }

  Eigen::VectorXd Model::gradient(const Eigen::VectorXd &x) const
  {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    for (const auto &t : energy_terms)
      t->add_gradient(x, g);
    return g;
  }

  Eigen::SparseMatrix<double> Model::hessian(const Eigen::VectorXd &x) const
  {
    Triplets triplets;
    for (const auto &t : energy_terms)
      t->add_hessian(x, triplets);
    Eigen::SparseMatrix<double> h(n, n);
    h.setFromTriplets(triplets.begin(), triplets.end());
    return h;
  }

  bool Model::is_valid(const Eigen::VectorXd &x) const
  {
    return std::all_of(energy_terms.begin(), energy_terms.end(),
                       [&](const auto &t) { return t->is_valid(x); });
  }

  double Model::max_safe_step(const Eigen::VectorXd &x, const Eigen::VectorXd &dx) const
  {
    double alpha = 1;
    for (const auto &t : energy_terms)
      alpha = std::min(alpha, t->max_safe_step(x, dx));
    return alpha;
  }

  DerivativeCheck check_derivatives(const EnergyTerm &term, const Eigen::VectorXd &x, const double h)
  {
    const std::size_t n    = x.size();
    const double      step = h * std::max(1.0, x.lpNorm<Eigen::Infinity>());
    Eigen::VectorXd   g    = Eigen::VectorXd::Zero(n);
    term.add_gradient(x, g);
    Triplets triplets;
    term.add_hessian(x, triplets);
    Eigen::SparseMatrix<double> hessian(n, n);
    hessian.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::MatrixXd H = Eigen::MatrixXd(hessian);

    DerivativeCheck result;
    const double    g_scale = std::max(1.0, g.lpNorm<Eigen::Infinity>());
    const double    h_scale = std::max(1.0, H.lpNorm<Eigen::Infinity>());
    Eigen::VectorXd xp = x, xm = x;
    for (std::size_t i = 0; i < n; ++i)
      {
        xp[i]                 = x[i] + step;
        xm[i]                 = x[i] - step;
        const double fd       = (term.value(xp) - term.value(xm)) / (2 * step);
        result.gradient_error = std::max(result.gradient_error, std::abs(fd - g[i]) / g_scale);
        Eigen::VectorXd gp = Eigen::VectorXd::Zero(n), gm = Eigen::VectorXd::Zero(n);
        term.add_gradient(xp, gp);
        term.add_gradient(xm, gm);
        const Eigen::VectorXd column = (gp - gm) / (2 * step);
        result.hessian_error =
            std::max(result.hessian_error, (column - H.col(i)).lpNorm<Eigen::Infinity>() / h_scale);
        xp[i] = xm[i] = x[i];
      }
    return result;
  }
} // namespace nlmech
