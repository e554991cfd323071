#include <nlmech/models/model.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>

namespace nlmech
{
  void EnergyTerm::add_gradient_series_coefficient(const std::vector<Eigen::VectorXd> &, unsigned int,
                                                   Eigen::VectorXd &) const
  {
    AssertThrow(false, dealii::ExcMessage("The energy term <" + name() +
                                          "> provides no Taylor series; the ANM cannot use it."));
  }

  void EnergyTerm::add_hessian_vector_product(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                              Eigen::VectorXd &out) const
  {
    Triplets t;
    add_hessian(x, t);
    for (const auto &e : t)
      out[e.row()] += e.value() * v[e.col()];
  }

  void EnergyTerm::add_directional_hessian(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                           Triplets &h) const
  {
    const double vmax = v.lpNorm<Eigen::Infinity>();
    if (vmax == 0)
      return;
    const double eps = 1e-6 * std::max(1.0, x.lpNorm<Eigen::Infinity>()) / vmax;
    Triplets     plus, minus;
    add_hessian(x + eps * v, plus);
    add_hessian(x - eps * v, minus);
    for (const auto &e : plus)
      h.emplace_back(e.row(), e.col(), e.value() / (2 * eps));
    for (const auto &e : minus)
      h.emplace_back(e.row(), e.col(), -e.value() / (2 * eps));
  }

  namespace
  {
    /// The sum of every term's contribution to one vector: the terms that give this rank's part
    /// first, summed over the sharing ranks, then the whole ones.
    template <typename Add>
    Eigen::VectorXd summed_vector(const std::vector<std::shared_ptr<const EnergyTerm>> &terms,
                                  const std::size_t n, const Add &add)
    {
      Eigen::VectorXd out     = Eigen::VectorXd::Zero(n);
      bool            partial = false;
      for (const auto &t : terms)
        if (t->partial_over_ranks())
          add(*t, out), partial = true;
      if (partial)
        sum_over_sharing_ranks(out.data(), out.size());
      for (const auto &t : terms)
        if (!t->partial_over_ranks())
          add(*t, out);
      return out;
    }
  } // namespace

  Eigen::VectorXd Model::hessian_vector_product(const Eigen::VectorXd &x, const Eigen::VectorXd &v) const
  {
    return summed_vector(energy_terms, n, [&](const EnergyTerm &t, Eigen::VectorXd &out) {
      t.add_hessian_vector_product(x, v, out);
    });
  }

  Eigen::SparseMatrix<double> Model::directional_hessian(const Eigen::VectorXd &x,
                                                         const Eigen::VectorXd &v) const
  {
    Triplets partial, whole;
    for (const auto &t : energy_terms)
      t->add_directional_hessian(x, v, t->partial_over_ranks() ? partial : whole);
    // The partial triplets have the same pattern on every rank (zeros for others' elements).
    Eigen::SparseMatrix<double> h(n, n), w(n, n);
    h.setFromTriplets(partial.begin(), partial.end());
    sum_over_sharing_ranks(h.valuePtr(), h.nonZeros());
    w.setFromTriplets(whole.begin(), whole.end());
    h += w;
    return h;
  }

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
    double partial = 0, whole = 0;
    for (const auto &t : energy_terms)
      (t->partial_over_ranks() ? partial : whole) += t->value(x);
    return sum_over_sharing_ranks(partial) + whole;
  }

  Eigen::VectorXd Model::gradient(const Eigen::VectorXd &x) const
  {
    return summed_vector(energy_terms, n,
                         [&](const EnergyTerm &t, Eigen::VectorXd &out) { t.add_gradient(x, out); });
  }

  Eigen::SparseMatrix<double> Model::hessian(const Eigen::VectorXd &x, const bool projected) const
  {
    const TripletAssemblyPool::Handle hessian_assembly = hessian_assemblies->acquire();
    Triplets                         &triplets         = hessian_assembly->buffer();
    triplets.clear();
    // The partial terms' triplets have the same pattern on every rank: their matrix is summed
    // over the ranks value by value; the whole terms' are added after.
    Triplets whole;
    bool     partial = false;
    for (const auto &t : energy_terms)
      {
        Triplets &into = t->partial_over_ranks() ? (partial = true, triplets) : whole;
        projected ? t->add_projected_hessian(x, into) : t->add_hessian(x, into);
      }
    if (!partial)
      return hessian_assembly->assemble(n, whole);
    Eigen::SparseMatrix<double> h = hessian_assembly->assemble(n, triplets);
    sum_over_sharing_ranks(h.valuePtr(), h.nonZeros());
    if (!whole.empty())
      {
        Eigen::SparseMatrix<double> w(n, n);
        w.setFromTriplets(whole.begin(), whole.end());
        h += w;
      }
    return h;
  }

  Eigen::SparseMatrix<double> Model::projected_hessian(const Eigen::VectorXd &x) const
  {
    return hessian(x, true);
  }

  Eigen::VectorXd Model::gradient_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                     const unsigned int                  k) const
  {
    return summed_vector(energy_terms, n, [&](const EnergyTerm &t, Eigen::VectorXd &out) {
      t.add_gradient_series_coefficient(path, k, out);
    });
  }

  bool Model::has_series() const
  {
    return std::all_of(energy_terms.begin(), energy_terms.end(),
                       [](const auto &t) { return t->has_series(); });
  }

  FreeDofMap::FreeDofMap(const Model &model)
      : n(model.n_unknowns())
      , index(model.n_unknowns(), -1)
  {
    for (std::size_t i = 0; i < n; ++i)
      if (!model.is_fixed(i))
        {
          index[i] = free.size();
          free.push_back(i);
        }
  }

  FreeDofMap::FreeDofMap(const std::size_t n_unknowns, const std::map<std::size_t, double> &fixed)
      : n(n_unknowns)
      , index(n_unknowns, -1)
  {
    for (std::size_t i = 0; i < n; ++i)
      if (fixed.count(i) == 0)
        {
          index[i] = free.size();
          free.push_back(i);
        }
  }

  Eigen::VectorXd FreeDofMap::restrict(const Eigen::VectorXd &full) const
  {
    Eigen::VectorXd out(free.size());
    for (std::size_t k = 0; k < free.size(); ++k)
      out[k] = full[free[k]];
    return out;
  }

  Eigen::VectorXd FreeDofMap::expand(const Eigen::VectorXd &free_values) const
  {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < free.size(); ++k)
      out[free[k]] = free_values[k];
    return out;
  }

  Eigen::SparseMatrix<double> FreeDofMap::restrict(const Eigen::SparseMatrix<double> &full) const
  {
    Triplets triplets;
    triplets.reserve(full.nonZeros() + free.size());
    // Explicit diagonal entries keep the pattern fixed when a solver adds a diagonal shift.
    for (std::size_t k = 0; k < free.size(); ++k)
      triplets.emplace_back(k, k, 0.0);
    for (int col = 0; col < full.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(full, col); it; ++it)
        if (index[it.row()] >= 0 && index[it.col()] >= 0)
          triplets.emplace_back(index[it.row()], index[it.col()], it.value());
    Eigen::SparseMatrix<double> out(free.size(), free.size());
    out.setFromTriplets(triplets.begin(), triplets.end());
    out.makeCompressed();
    return out;
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

  double Model::first_invalid_along_series(const std::vector<Eigen::VectorXd> &path, const double a_max) const
  {
    double a = a_max;
    for (const auto &t : energy_terms)
      a = std::min(a, t->first_invalid_along_series(path, a_max));
    return a;
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
