#pragma once
// Energies times design factors: a whole term times one factor (a layer's Young's modulus relative
// to its initial value) and element energies times one factor each (a modulus per element), with
// the derivative of an element's energy by its own forward AD for the design parameters' dh/dp.
// The factors are shared: changing them changes the Model that holds the term.

#include <nlmech/models/energy_term.h>

#include <memory>
#include <vector>

namespace nlmech
{
  /// inner(x) times *factor.
  class ScaledEnergyTerm : public EnergyTerm
  {
  public:
    ScaledEnergyTerm(std::shared_ptr<const EnergyTerm> inner, std::shared_ptr<double> factor);
    std::string name() const override { return inner->name() + " (scaled)"; }
    bool        partial_over_ranks() const override { return inner->partial_over_ranks(); }
    double      value(const Eigen::VectorXd &x) const override;
    void        add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const override;
    void        add_hessian(const Eigen::VectorXd &x, Triplets &h) const override;
    void        add_projected_hessian(const Eigen::VectorXd &x, Triplets &h) const override;
    void        add_hessian_vector_product(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                           Eigen::VectorXd &out) const override;
    void        add_directional_hessian(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                        Triplets &h) const override;
    bool        is_valid(const Eigen::VectorXd &x) const override { return inner->is_valid(x); }
    double      max_safe_step(const Eigen::VectorXd &x, const Eigen::VectorXd &dx) const override
    {
      return inner->max_safe_step(x, dx);
    }
    const EnergyTerm &unscaled() const { return *inner; }

  private:
    std::shared_ptr<const EnergyTerm> inner;
    std::shared_ptr<double>           factor;
  };

  /// Element energies times one factor per element (shared, changed in place by design).
  template <typename Element>
  struct ScaledElements
  {
    static constexpr std::size_t             n_dofs = Element::n_dofs;
    Element                                  inner;
    std::shared_ptr<std::vector<double>>     factors;
    std::size_t                              n_elements() const { return inner.n_elements(); }
    std::array<std::size_t, Element::n_dofs> dofs(const std::size_t e) const { return inner.dofs(e); }
    template <typename S>
    S energy(const std::array<S, Element::n_dofs> &x, const std::size_t e) const
    {
      return (*factors)[e] * inner.energy(x, e);
    }
  };

  /// out += w dE_e/dx of one element (its own, unscaled energy) by forward AD; with a non-empty v
  /// also out += w_v H_e(x) v (forward over forward). Full-length vectors.
  template <typename Element>
  void add_element_force_derivatives(const Element &element, const std::size_t e, const Eigen::VectorXd &x,
                                     const Eigen::VectorXd &v, const double w, const double w_v,
                                     Eigen::VectorXd &out)
  {
    constexpr std::size_t N = Element::n_dofs;
    using Gradient          = Sacado::Fad::SFad<double, N>;
    using Hessian           = Sacado::Fad::SFad<Gradient, N>;
    const auto dofs         = element.dofs(e);
    const bool hv           = v.size() > 0 && w_v != 0;
    if (!hv)
      {
        std::array<Gradient, N> local;
        for (std::size_t i = 0; i < N; ++i)
          local[i] = Gradient(N, i, x[dofs[i]]);
        const Gradient energy = element.energy(local, e);
        for (std::size_t i = 0; i < N; ++i)
          out[dofs[i]] += w * energy.dx(i);
        return;
      }
    std::array<Hessian, N> local;
    for (std::size_t i = 0; i < N; ++i)
      local[i] = Hessian(N, i, Gradient(N, i, x[dofs[i]]));
    const Hessian energy = element.energy(local, e);
    for (std::size_t i = 0; i < N; ++i)
      {
        double Hv = 0;
        for (std::size_t j = 0; j < N; ++j)
          Hv += energy.dx(i).dx(j) * v[dofs[j]];
        out[dofs[i]] += w * energy.dx(i).val() + w_v * Hv;
      }
  }
} // namespace nlmech
