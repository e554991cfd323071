#pragma once
// What the continuation solvers need of a problem R(q, lambda) = r(q) - lambda g = 0 on the free
// unknowns: the internal force r, its tangent dr/dq (symmetric for energies, not for inverse
// design), the Taylor coefficients of r along a polynomial path, and validity hooks. The forward
// problem adapts a Model (r = grad E); inverse rest-shape design implements it directly.

#include <nlmech/models/model.h>

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

  /// Forward statics: r = grad E of a Model; validity and the series step bound from its terms.
  class ModelEquilibrium : public EquilibriumSystem
  {
  public:
    explicit ModelEquilibrium(const Model &model)
        : model(model)
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
      return model.first_invalid_along_series(path, a_max);
    }

  private:
    const Model &model;
  };
  /// r(q) - g_known: continuing from a solution under g_known towards another load g_new is the
  /// ANM on this system with the load g_new - g_known (a load-direction change from a known
  /// solution, paper section 5.1). Tangent, series of order >= 1 and validity are those of `base`.
  class LoadShiftedSystem : public EquilibriumSystem
  {
  public:
    LoadShiftedSystem(const EquilibriumSystem &base, const Eigen::VectorXd &known_load)
        : base(base)
        , known_load(known_load)
    {
    }
    std::size_t                          n_unknowns() const override { return base.n_unknowns(); }
    const std::map<std::size_t, double> &fixed() const override { return base.fixed(); }
    Eigen::VectorXd                      internal_force(const Eigen::VectorXd &q) const override
    {
      return base.internal_force(q) - known_load;
    }
    Eigen::SparseMatrix<double> tangent(const Eigen::VectorXd &q) const override { return base.tangent(q); }
    bool                        symmetric_tangent() const override { return base.symmetric_tangent(); }
    Eigen::VectorXd             internal_force_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                                  unsigned int                        k) const override
    {
      Eigen::VectorXd c = base.internal_force_series_coefficient(path, k);
      if (k == 0)
        c -= known_load;
      return c;
    }
    bool   is_valid(const Eigen::VectorXd &q) const override { return base.is_valid(q); }
    double max_safe_step(const Eigen::VectorXd &q, const Eigen::VectorXd &dq) const override
    {
      return base.max_safe_step(q, dq);
    }
    double first_invalid_along_series(const std::vector<Eigen::VectorXd> &path, double a_max) const override
    {
      return base.first_invalid_along_series(path, a_max);
    }

  private:
    const EquilibriumSystem &base;
    Eigen::VectorXd          known_load;
  };
} // namespace nlmech
