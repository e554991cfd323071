#pragma once
// What the continuation solvers need of a problem R(q, lambda) = r(q) - lambda g = 0 on the free
// unknowns: the internal force r, its tangent dr/dq (symmetric for energies, not for inverse
// design), the Taylor coefficients of r along a polynomial path, and validity hooks. The forward
// problem adapts a Model (r = grad E); inverse rest-shape design implements it directly.

#include <nlmech/models/model.h>
#include <nlmech/models/solid/hyperelastic_tet_energy.h>

#include <map>
#include <vector>

namespace nlmech
{
  class EquilibriumSystem
  {
  public:
    virtual ~EquilibriumSystem()                                                                = default;
    virtual std::size_t                          n_unknowns() const                             = 0;
    virtual const std::map<std::size_t, double> &fixed() const                                  = 0;
    virtual Eigen::VectorXd                      internal_force(const Eigen::VectorXd &q) const = 0;
    virtual Eigen::SparseMatrix<double>          tangent(const Eigen::VectorXd &q) const        = 0;
    virtual bool                                 symmetric_tangent() const                      = 0;
    /// Coefficient k of r(sum_{j<k} a^j path[j]) (path[k] left out), full length.
    virtual Eigen::VectorXd internal_force_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                              unsigned int k) const = 0;
    virtual bool            is_valid(const Eigen::VectorXd &) const { return true; }
    virtual double max_safe_step(const Eigen::VectorXd &, const Eigen::VectorXd &) const { return 1.0; }
    /// Smallest a in (0, a_max] where the truncated series path becomes invalid, or a_max.
    virtual double first_invalid_along_series(const std::vector<Eigen::VectorXd> &, double a_max) const
    {
      return a_max;
    }
  };

  /// Forward statics: r = grad E of a Model; validity from an optional hyperelastic term.
  class ModelEquilibrium : public EquilibriumSystem
  {
  public:
    ModelEquilibrium(const Model &model, const HyperelasticTetTerm *inversion_guard = nullptr)
        : model(model)
        , guard(inversion_guard)
    {
    }
    std::size_t                          n_unknowns() const override { return model.n_unknowns(); }
    const std::map<std::size_t, double> &fixed() const override { return model.fixed(); }
    Eigen::VectorXd internal_force(const Eigen::VectorXd &q) const override { return model.gradient(q); }
    Eigen::SparseMatrix<double> tangent(const Eigen::VectorXd &q) const override { return model.hessian(q); }
    bool                        symmetric_tangent() const override { return true; }
    Eigen::VectorXd             internal_force_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                                  unsigned int                        k) const override
    {
      return model.gradient_series_coefficient(path, k);
    }
    bool   is_valid(const Eigen::VectorXd &q) const override { return model.is_valid(q); }
    double max_safe_step(const Eigen::VectorXd &q, const Eigen::VectorXd &dq) const override
    {
      return model.max_safe_step(q, dq);
    }
    double first_invalid_along_series(const std::vector<Eigen::VectorXd> &path, double a_max) const override
    {
      return guard ? guard->first_inversion_along_series(path, a_max) : a_max;
    }

  private:
    const Model               &model;
    const HyperelasticTetTerm *guard;
  };
} // namespace nlmech
