#pragma once
// The two small interfaces that carry the physics. An EnergyTerm gives the value, gradient and
// Hessian of its energy on a flat vector of unknowns, plus the hooks barrier contact needs (is a
// state valid, how far can a step go). ElementEnergyTerm writes an element's energy once, as a
// template on the scalar type, and derives gradient and Hessian by forward AD (Trilinos Sacado).

#include <nlmech/base/rank_sharing.h>
#include <nlmech/base/threads.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>
#include <Sacado.hpp>
#include <Sacado_Tay_Taylor.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace nlmech
{
  using Triplets = std::vector<Eigen::Triplet<double>>;

  /// Replaces a symmetric matrix by its nearest positive semi-definite one in the Frobenius norm
  /// (eigenvalues below zero set to zero); unchanged when it already is.
  template <int N>
  void project_to_positive_semidefinite(Eigen::Matrix<double, N, N> &block)
  {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(0.5 * (block + block.transpose()));
    if (eig.eigenvalues().minCoeff() >= 0)
      return;
    block =
        eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
  }

  class EnergyTerm
  {
  public:
    virtual ~EnergyTerm()            = default;
    virtual std::string name() const = 0;

    /// Whether value, gradient, Hessian, Hessian products and series are this rank's part only
    /// (its block of the elements, inside a ShareElementsOverRanks scope); the Model sums such
    /// parts over the ranks. Hessian triplets keep the whole pattern (zeros elsewhere), so that
    /// every rank assembles the same sparsity and the sum is one all-reduce of the values.
    virtual bool partial_over_ranks() const { return false; }

    virtual double value(const Eigen::VectorXd &x) const = 0;
    /// g += dE/dx
    virtual void add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const = 0;
    /// H += d2E/dx2, as (row, column, value) triplets (duplicates are summed).
    virtual void add_hessian(const Eigen::VectorXd &x, Triplets &h) const = 0;
    /// H += the Hessian with every element's block projected to positive semi-definite (negative
    /// eigenvalues clamped to zero, as IPC and PolyFEM do), so that a sum of such terms plus a mass
    /// term is positive definite without a global shift. Default: the Hessian itself (terms that are
    /// convex, or not sums of small element blocks).
    virtual void add_projected_hessian(const Eigen::VectorXd &x, Triplets &h) const { add_hessian(x, h); }

    /// out += H(x) v (default: through the Hessian).
    virtual void add_hessian_vector_product(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                            Eigen::VectorXd &out) const;
    /// Triplets of d(H(x) v)/dx, the third derivative contracted with v (default: central
    /// differences of the Hessian; element terms use forward AD). Needed by stiffness-proportional
    /// damping D_beta K(x) x' in dynamics.
    virtual void add_directional_hessian(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                         Triplets &h) const;

    /// Whether add_gradient_series_coefficient is available (needed by the ANM).
    virtual bool has_series() const { return false; }
    /// Adds coefficient k of the Taylor series of the gradient along the path
    /// x(a) = sum_{j<k} a^j path[j] (the k-th coefficient of x taken as zero) to `out`. With a path
    /// that is exact up to order k-1, this is the ANM's right-hand side f_nl of order k.
    virtual void add_gradient_series_coefficient(const std::vector<Eigen::VectorXd> &path, unsigned int k,
                                                 Eigen::VectorXd &out) const;

    /// False where the energy is undefined (inverted element, interpenetration).
    virtual bool is_valid(const Eigen::VectorXd &) const { return true; }
    /// Largest alpha in (0, 1] such that x + t dx stays valid for all t in [0, alpha).
    virtual double max_safe_step(const Eigen::VectorXd &, const Eigen::VectorXd &) const { return 1.0; }
    /// Smallest a in (0, a_max] where the truncated series x(a) = sum_k a^k path[k] leaves the
    /// valid states (an element inverts), or a_max: the ANM's step bound.
    virtual double first_invalid_along_series(const std::vector<Eigen::VectorXd> &, double a_max) const
    {
      return a_max;
    }
  };

  /// Whether an element type brings its own ANM series kernel
  /// add_gradient_series_coefficient(path, k, e, local) (local: the element's N-vector, in its
  /// own dof numbering) and prepare_series() (called once, on one thread, before the loop).
  template <typename Element, typename = void>
  struct has_series_kernel : std::false_type
  {
  };
  template <typename Element>
  struct has_series_kernel<
      Element, std::void_t<decltype(std::declval<const Element &>().add_gradient_series_coefficient(
                   std::declval<const std::vector<Eigen::VectorXd> &>(), 0u, std::size_t(0),
                   std::declval<std::array<double, Element::n_dofs> &>()))>> : std::true_type
  {
  };

  /// Whether an element type brings its own Hessian kernel element_hessian(x_local, e, H), which
  /// may decline (return false) and leave the element to nested AD.
  template <typename Element, typename = void>
  struct has_hessian_kernel : std::false_type
  {
  };
  template <typename Element>
  struct has_hessian_kernel<Element,
                            std::void_t<decltype(std::declval<const Element &>().element_hessian(
                                std::declval<const std::array<double, Element::n_dofs> &>(), std::size_t(0),
                                std::declval<Eigen::Matrix<double, Element::n_dofs, Element::n_dofs> &>()))>>
      : std::true_type
  {
  };

  /// An energy that is a sum over elements, each depending on N unknowns. `Element` provides
  ///   static constexpr std::size_t n_dofs = N;
  ///   std::size_t n_elements() const;
  ///   std::array<std::size_t, N> dofs(std::size_t e) const;
  ///   template <typename S> S energy(const std::array<S, N> &x, std::size_t e) const;
  template <typename Element>
  class ElementEnergyTerm : public EnergyTerm
  {
  public:
    static constexpr std::size_t N = Element::n_dofs;
    using Gradient                 = Sacado::Fad::SFad<double, N>;
    using Hessian                  = Sacado::Fad::SFad<Gradient, N>;
    /// Forward AD over truncated Taylor series: the gradient along a polynomial path.
    using SeriesGradient = Sacado::Fad::SFad<Sacado::Tay::Taylor<double>, N>;

    ElementEnergyTerm(std::string term_name, Element element)
        : term_name(std::move(term_name))
        , element(std::move(element))
    {
    }

    std::string    name() const override { return term_name; }
    const Element &elements() const { return element; }
    bool           partial_over_ranks() const override { return element_sharing_ranks() > 1; }

    double value(const Eigen::VectorXd &x) const override
    {
      // Element values first (on threads), then summed in element order: the same total for
      // every thread count.
      const auto          owned = owned_elements(element.n_elements());
      std::vector<double> values(owned.second - owned.first);
      for_each_block(values.size(), block_size, [&](const std::size_t begin, const std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
          values[i] = element.energy(gather<double>(x, owned.first + i), owned.first + i);
      });
      double total = 0;
      for (const double v : values)
        total += v;
      return total;
    }

    void add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const override
    {
      add_element_vectors(g, [&](const std::size_t e, std::array<double, N> &out) {
        const auto              dofs = element.dofs(e);
        std::array<Gradient, N> local;
        for (std::size_t i = 0; i < N; ++i)
          local[i] = Gradient(N, i, x[dofs[i]]);
        const Gradient energy = element.energy(local, e);
        for (std::size_t i = 0; i < N; ++i)
          out[i] = energy.dx(i);
      });
    }

    void add_hessian(const Eigen::VectorXd &x, Triplets &h) const override { element_hessians(x, h, false); }
    void add_projected_hessian(const Eigen::VectorXd &x, Triplets &h) const override
    {
      element_hessians(x, h, true);
    }

    /// H(x) v from the gradient of the directional derivative phi = dE(x + eps v)/deps (cost ~2N).
    void add_hessian_vector_product(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                    Eigen::VectorXd &out) const override
    {
      using Direction = Sacado::Fad::SFad<double, 1>;
      using Outer     = Sacado::Fad::SFad<Direction, N>;
      add_element_vectors(out, [&](const std::size_t e, std::array<double, N> &local_out) {
        const auto           dofs = element.dofs(e);
        std::array<Outer, N> local;
        for (std::size_t i = 0; i < N; ++i)
          {
            Direction xi(1, 0, x[dofs[i]]);
            xi.fastAccessDx(0) = v[dofs[i]];
            local[i]           = Outer(N, i, xi);
          }
        const Outer energy = element.energy(local, e);
        for (std::size_t i = 0; i < N; ++i)
          local_out[i] = energy.dx(i).dx(0);
      });
    }

    /// d(H(x) v)/dx as the Hessian of phi = dE(x + eps v)/deps, by nested forward AD.
    void add_directional_hessian(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                 Triplets &h) const override
    {
      using Direction  = Sacado::Fad::SFad<double, 1>;
      using Inner      = Sacado::Fad::SFad<Direction, N>;
      using Outer      = Sacado::Fad::SFad<Inner, N>;
      const auto owned = owned_elements(element.n_elements());
      for (std::size_t e = 0; e < element.n_elements(); ++e)
        {
          const auto dofs   = element.dofs(e);
          bool       moving = false;
          for (std::size_t i = 0; i < N; ++i)
            moving = moving || v[dofs[i]] != 0;
          if (!moving)
            continue;
          if (e < owned.first || e >= owned.second)
            {
              // Another rank's element: its pattern, not its values (the same on every rank).
              for (std::size_t i = 0; i < N; ++i)
                for (std::size_t j = 0; j < N; ++j)
                  h.emplace_back(dofs[i], dofs[j], 0.0);
              continue;
            }
          std::array<Outer, N> local;
          for (std::size_t i = 0; i < N; ++i)
            {
              Direction xi(1, 0, x[dofs[i]]);
              xi.fastAccessDx(0) = v[dofs[i]];
              local[i]           = Outer(N, i, Inner(N, i, xi));
            }
          const Outer energy = element.energy(local, e);
          for (std::size_t i = 0; i < N; ++i)
            for (std::size_t j = 0; j < N; ++j)
              h.emplace_back(dofs[i], dofs[j], energy.dx(i).dx(j).dx(0));
        }
    }

    bool has_series() const override { return true; }

    void add_gradient_series_coefficient(const std::vector<Eigen::VectorXd> &path, const unsigned int k,
                                         Eigen::VectorXd &out) const override
    {
      if constexpr (has_series_kernel<Element>::value)
        {
          element.prepare_series(k);
          add_element_vectors(out, [&](const std::size_t e, std::array<double, N> &local) {
            element.add_gradient_series_coefficient(path, k, e, local);
          });
        }
      else
        add_gradient_series_coefficient_by_taylor_ad(path, k, out);
    }

    /// The generic path: forward AD over Sacado::Tay::Taylor on the element energy in x. Works
    /// for every element; element kernels are checked against it.
    void add_gradient_series_coefficient_by_taylor_ad(const std::vector<Eigen::VectorXd> &path,
                                                      const unsigned int k, Eigen::VectorXd &out) const
    {
      add_element_vectors(out, [&](const std::size_t e, std::array<double, N> &local_out) {
        const auto                    dofs = element.dofs(e);
        std::array<SeriesGradient, N> local;
        for (std::size_t i = 0; i < N; ++i)
          {
            Sacado::Tay::Taylor<double> xi(static_cast<int>(k));
            for (unsigned int j = 0; j < k && j < path.size(); ++j)
              xi.fastAccessCoeff(j) = path[j][dofs[i]];
            local[i] = SeriesGradient(N, i, xi);
          }
        const SeriesGradient energy = element.energy(local, e);
        for (std::size_t i = 0; i < N; ++i)
          local_out[i] = energy.dx(i).coeff(k);
      });
    }

    /// Element energies' local Hessian, for tests and hand-tuned kernels to compare against.
    std::array<double, N * N> local_hessian(const Eigen::VectorXd &x, std::size_t e) const
    {
      const auto             dofs = element.dofs(e);
      std::array<Hessian, N> local;
      for (std::size_t i = 0; i < N; ++i)
        local[i] = Hessian(N, i, Gradient(N, i, x[dofs[i]]));
      const Hessian             energy = element.energy(local, e);
      std::array<double, N * N> out;
      for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < N; ++j)
          out[i * N + j] = energy.dx(i).dx(j);
      return out;
    }

    /// Elements per block of the threaded loops (a block is one task).
    static constexpr std::size_t block_size = 256;

  private:
    /// Every element's N x N Hessian by forward-over-forward AD, on deal.II's threads (each
    /// element writes its own N^2 triplets); with `project`, each block with a negative eigenvalue
    /// is replaced by V max(Lambda, 0) V^T.
    void element_hessians(const Eigen::VectorXd &x, Triplets &h, const bool project) const
    {
      const std::size_t n_elem = element.n_elements(), first = h.size();
      const auto        owned = owned_elements(n_elem);
      h.resize(first + n_elem * N * N);
      for_each_block(n_elem, block_size / 2, [&](const std::size_t begin, const std::size_t end) {
        for (std::size_t e = begin; e < end; ++e)
          {
            const auto                  dofs = element.dofs(e);
            Eigen::Matrix<double, N, N> block;
            if (e < owned.first || e >= owned.second)
              {
                // Another rank's element: its pattern, not its values.
                for (std::size_t i = 0; i < N; ++i)
                  for (std::size_t j = 0; j < N; ++j)
                    h[first + e * N * N + i * N + j] =
                        Eigen::Triplet<double>(int(dofs[i]), int(dofs[j]), 0.0);
                continue;
              }
            bool done = false;
            if constexpr (has_hessian_kernel<Element>::value)
              done = element.element_hessian(gather<double>(x, e), e, block);
            if (!done)
              {
                std::array<Hessian, N> local;
                for (std::size_t i = 0; i < N; ++i)
                  local[i] = Hessian(N, i, Gradient(N, i, x[dofs[i]]));
                const Hessian energy = element.energy(local, e);
                for (std::size_t i = 0; i < N; ++i)
                  for (std::size_t j = 0; j < N; ++j)
                    block(i, j) = energy.dx(i).dx(j);
              }
            if (project)
              project_to_positive_semidefinite(block);
            for (std::size_t i = 0; i < N; ++i)
              for (std::size_t j = 0; j < N; ++j)
                h[first + e * N * N + i * N + j] =
                    Eigen::Triplet<double>(int(dofs[i]), int(dofs[j]), block(i, j));
          }
      });
    }

    /// out += the element vectors local(e, v) of this rank's elements, bit for bit what one
    /// thread computes.
    template <typename Local>
    void add_element_vectors(Eigen::VectorXd &out, const Local &local) const
    {
      const auto owned = owned_elements(element.n_elements());
      nlmech::add_element_vectors<N>(
          owned.first, owned.second, block_size, [&](const std::size_t e) { return element.dofs(e); }, local,
          out);
    }

    template <typename S>
    std::array<S, N> gather(const Eigen::VectorXd &x, std::size_t e) const
    {
      const auto       dofs = element.dofs(e);
      std::array<S, N> local;
      for (std::size_t i = 0; i < N; ++i)
        local[i] = x[dofs[i]];
      return local;
    }

    std::string term_name;
    Element     element;
  };

  /// External potential -f . x of constant nodal forces (gravity on lumped masses, point loads).
  class ConstantForceTerm : public EnergyTerm
  {
  public:
    ConstantForceTerm(std::string term_name, Eigen::VectorXd force);
    std::string name() const override { return term_name; }
    double      value(const Eigen::VectorXd &x) const override;
    void        add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const override;
    void        add_hessian(const Eigen::VectorXd &, Triplets &) const override {}
    bool        has_series() const override { return true; }
    /// The gradient is constant: every coefficient of order k >= 1 is zero.
    void add_gradient_series_coefficient(const std::vector<Eigen::VectorXd> &, unsigned int,
                                         Eigen::VectorXd &) const override
    {
    }

  private:
    std::string     term_name;
    Eigen::VectorXd force;
  };
} // namespace nlmech
