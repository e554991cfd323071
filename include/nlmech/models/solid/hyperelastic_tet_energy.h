#pragma once
// Hyperelastic linear tetrahedra as element energies written once on the scalar type, so the same
// code gives values (double), forces and tangents (Sacado Fad) and truncated Taylor series for the
// Asymptotic Numerical Method (Fad over Sacado::Tay::Taylor). Unknowns: deformed vertex positions,
// 3 per vertex (x, y, z interleaved). F = D_s D_m^-1 is constant per element.
//  - compressible neo-Hookean (ANM paper eq. 3): W = mu/2 (J^(-2/3) I_c - 3) + kappa/2 (J - 1)^2
//  - St.Venant-Kirchhoff: W = mu E:E + lambda/2 tr(E)^2, E = (F^T F - I)/2

#include <nlmech/base/series_cache.h>
#include <nlmech/base/truncated_series.h>
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/elastic_constants.h>
#include <nlmech/models/energy_term.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace nlmech
{
  enum class HyperelasticLaw
  {
    neo_hookean,
    saint_venant_kirchhoff
  };

  struct HyperelasticMaterial
  {
    HyperelasticLaw law            = HyperelasticLaw::neo_hookean;
    double          youngs_modulus = 1; // Pa
    double          poissons_ratio = 0; // -
    double          density        = 0; // kg/m^3

    double shear_modulus() const { return nlmech::shear_modulus(youngs_modulus, poissons_ratio); }
    double bulk_modulus() const { return nlmech::bulk_modulus(youngs_modulus, poissons_ratio); }
    double lame_lambda() const { return nlmech::lame_lambda(youngs_modulus, poissons_ratio); }
    /// Throws a clear error for E <= 0 or nu outside (-1, 0.5).
    void check() const;
  };

  struct HyperelasticTetElements
  {
    static constexpr std::size_t n_dofs = 12;

    /// `rest` are the rest positions the elements are built on.
    HyperelasticTetElements(const std::vector<dealii::Point<3>>          &rest,
                            const std::vector<std::vector<unsigned int>> &tets,
                            const HyperelasticMaterial                   &material);

    std::size_t                 n_elements() const { return tets.size(); }
    std::array<std::size_t, 12> dofs(std::size_t e) const;

    /// Deformation gradient F = D_s D_m^-1 of element e from its 4 deformed vertex positions.
    template <typename S>
    void deformation_gradient(const std::array<S, 12> &x, std::size_t e, S (&F)[3][3]) const
    {
      const auto &Dinv = rest_shape_inverse[e];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          {
            F[i][j] = 0.0;
            for (int a = 0; a < 3; ++a)
              F[i][j] += (x[3 * (a + 1) + i] - x[i]) * Dinv[a][j];
          }
    }

    template <typename S>
    static S determinant(const S (&F)[3][3])
    {
      return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
             F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
             F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
    }

    /// Strain energy density W(F) [J/m^3], written once for every scalar type.
    template <typename S>
    S energy_density(const S (&F)[3][3]) const
    {
      using std::pow;
      if (law == HyperelasticLaw::neo_hookean)
        {
          const S J  = determinant(F);
          S       Ic = 0.0;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              Ic += F[i][j] * F[i][j];
          return 0.5 * mu * (pow(J, -2.0 / 3.0) * Ic - 3.0) + 0.5 * kappa * (J - 1.0) * (J - 1.0);
        }
      S E[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          {
            E[i][j] = (i == j ? -0.5 : 0.0);
            for (int k = 0; k < 3; ++k)
              E[i][j] += 0.5 * F[k][i] * F[k][j];
          }
      S EE = 0.0, trace = E[0][0] + E[1][1] + E[2][2];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          EE += E[i][j] * E[i][j];
      return mu * EE + 0.5 * lambda * trace * trace;
    }

    template <typename S>
    S energy(const std::array<S, 12> &x, std::size_t e) const
    {
      S F[3][3];
      deformation_gradient(x, e, F);
      return volume[e] * energy_density(F);
    }

    /// Fast ANM kernel: coefficient k of the element's force series along sum_{j<k} a^j path[j],
    /// from forward derivatives of energy_density over truncated series in F (9 inputs instead
    /// of 12, no allocation). Added into the element's force vector `out` (its 12 dofs).
    /// Safe to call for different elements on different threads after prepare_series(k).
    void add_gradient_series_coefficient(const std::vector<Eigen::VectorXd> &path, unsigned int k,
                                         std::size_t e, std::array<double, 12> &out) const;
    /// Sizes the per-element cache of the recurrences for coefficient k (once per k, before the
    /// loop over the elements; not thread-safe itself).
    void prepare_series(unsigned int k) const;

    /// The neo-Hookean ANM kernel by auxiliary-variable recurrences (ANM paper section 4.2.2 and
    /// appendix A, here on cof F, J, I_c, s = J^(-2/3), u = s I_c / J): every coefficient is linear
    /// in the newest one, so with the lower orders cached per element one order costs O(k) instead
    /// of O(k^2). Valid while called with k = 2, 3, ... on one path; anything else restarts the cache.
    void add_neo_hookean_series_by_recurrences(const std::vector<Eigen::VectorXd> &path, unsigned int k,
                                               std::size_t e, std::array<double, 12> &out) const;
    /// Adds the nodal forces V P grad(phi) of element e for a (series coefficient of the) first
    /// Piola stress P to its force vector `out`.
    void add_nodal_forces(const double (&P)[3][3], std::size_t e, std::array<double, 12> &out) const;
    /// Use the recurrences for neo-Hookean (default); false forces the truncated-series kernel.
    bool use_recurrences = true;

    /// The first Piola stress P = dW/dF and its derivative C = d2W/dF2 (row-major 3x3 pairs:
    /// C[3i+j][3k+l] = dP_ij/dF_kl) at F: in closed form for neo-Hookean, by forward AD over
    /// energy_density in the 9 entries of F for St.Venant-Kirchhoff.
    void stress_and_tangent(const double (&F)[3][3], double (&P)[9], double (&C)[9][9]) const;
    /// The element Hessian H = V B^T C B (B = dF/dx, constant per element) from the stress
    /// tangent: the same matrix as nested AD over the 12 unknowns, at a fraction of the cost.
    /// Returns false (H untouched) when use_stress_tangent is off.
    bool element_hessian(const std::array<double, 12> &x, std::size_t e,
                         Eigen::Matrix<double, 12, 12> &H) const;
    /// Use the W(F)-level tangent for Hessians (default); false forces nested AD over x.
    bool use_stress_tangent = true;

    HyperelasticLaw                                   law;
    double                                            mu, kappa, lambda;
    std::vector<std::array<unsigned int, 4>>          tets;
    std::vector<std::array<std::array<double, 3>, 3>> rest_shape_inverse; // D_m^-1
    std::vector<double>                               volume;             // rest volume

  private:
    static constexpr int cached_series = 9 + 9 + 4; // F, cof F, J, I_c, s = J^(-2/3), u = s I_c / J
    mutable SeriesCache  cache;
  };

  extern template class ElementEnergyTerm<HyperelasticTetElements>;

  /// The hyperelastic energy term, with the validity hooks: a state is valid when every element
  /// has det F > 0, and a step may go at most to the first root of det F(x + t dx) in any element.
  class HyperelasticTetTerm : public ElementEnergyTerm<HyperelasticTetElements>
  {
  public:
    HyperelasticTetTerm(const std::vector<dealii::Point<3>>          &rest,
                        const std::vector<std::vector<unsigned int>> &tets,
                        const HyperelasticMaterial                   &material);

    bool   is_valid(const Eigen::VectorXd &x) const override;
    double max_safe_step(const Eigen::VectorXd &x, const Eigen::VectorXd &dx) const override;
    /// Smallest a in (0, a_max] where det F of some element vanishes along the truncated series
    /// x(a) = sum_k a^k path[k] (det F(a) expanded by Taylor arithmetic), or a_max if none.
    double first_inversion_along_series(const std::vector<Eigen::VectorXd> &path, double a_max) const;
    double first_invalid_along_series(const std::vector<Eigen::VectorXd> &path, double a_max) const override
    {
      return first_inversion_along_series(path, a_max);
    }
    /// Smallest det F over the elements.
    double min_jacobian(const Eigen::VectorXd &x) const;
  };

  /// Smallest t in (0, t_max] where the polynomial sum_k c[k] t^k (positive at 0) reaches zero:
  /// sampled at `samples` points, then bisected; t_max if it stays positive.
  double first_nonpositive_point(const std::vector<double> &c, double t_max, int samples = 32);

  /// Smallest root t in (0, t_max] of the cubic c0 + c1 t + c2 t^2 + c3 t^3, or t_max if none.
  double first_positive_root_of_cubic(const std::array<double, 4> &c, double t_max);
} // namespace nlmech
