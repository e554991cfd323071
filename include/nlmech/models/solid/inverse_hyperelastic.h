#pragma once
// Inverse rest-shape design (ANM paper, section 4): given the target deformed shape x and the loads
// g, find the rest shape X with r(X) = grad_x E(x; X) = g. The unknowns are the rest positions X;
// at fixed vertices X = x. The internal force is written once as a template on the scalar type of
// X (double, Sacado Fad for the non-symmetric tangent dr/dX, truncated series for the ANM), on the
// same energy density W(F) as the forward problem, F = D_s(x) D_m(X)^-1.

#include <nlmech/base/series_cache.h>
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/equilibrium_system.h>
#include <nlmech/models/solid/hyperelastic_tet_energy.h>

#include <map>
#include <vector>

namespace nlmech
{
  class InverseHyperelasticSystem : public EquilibriumSystem
  {
  public:
    /// `target`: the deformed shape x (3 per vertex). `fixed_vertices`: vertices whose rest position
    /// is their target position (supports). Throws if the target has an inverted element.
    InverseHyperelasticSystem(const RawSimplexMesh<3> &mesh, const Eigen::VectorXd &target,
                              const HyperelasticMaterial      &material,
                              const std::vector<unsigned int> &fixed_vertices);

    std::size_t                          n_unknowns() const override { return target.size(); }
    const std::map<std::size_t, double> &fixed() const override { return fixed_values; }
    Eigen::VectorXd                      internal_force(const Eigen::VectorXd &X) const override;
    Eigen::SparseMatrix<double>          tangent(const Eigen::VectorXd &X) const override;
    bool                                 symmetric_tangent() const override { return false; }
    Eigen::VectorXd internal_force_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                      unsigned int                        k) const override;
    /// Valid while every rest element keeps a positive volume.
    bool   is_valid(const Eigen::VectorXd &X) const override;
    double first_invalid_along_series(const std::vector<Eigen::VectorXd> &path, double a_max) const override;

    /// Element force of element e for rest positions X (scalar type S), target positions fixed.
    template <typename S>
    void element_force(std::size_t e, const std::array<S, 12> &X, std::array<S, 12> &force) const;

    /// Coefficient k of the element force series of element e by auxiliary-variable recurrences
    /// (neo-Hookean only): D_m(X) and its adjugate A are polynomial in the path, det D_m too,
    /// F = D_s A / det D_m by the division recurrence, then the forward kernel's recurrences in F;
    /// the force is A P^T / 6. O(k) per order with the lower orders cached per element; valid
    /// while called with k = 2, 3, ... on one path (anything else restarts the cache), after
    /// prepare_series(k).
    void add_force_series_by_recurrences(const std::vector<Eigen::VectorXd> &path, unsigned int k,
                                         std::size_t e, std::array<double, 12> &force) const;
    void prepare_series(unsigned int k) const;
    /// The generic kernel: element_force on truncated series, O(k^2) per order (any law).
    void add_force_series_by_truncated_series(const std::vector<Eigen::VectorXd> &path, unsigned int k,
                                              std::size_t e, std::array<double, 12> &force) const;
    /// Use the recurrences for neo-Hookean (default); false forces the generic kernel.
    bool use_recurrences = true;
    /// The element tangent dr/dX from the stress tangent dP/dF (HyperelasticTetElements::
    /// stress_and_tangent) and first derivatives of adj D_m and F in X (default); false: nested AD
    /// over element_force.
    bool use_stress_tangent = true;
    /// The 12 x 12 tangent of element e (row: force entry, column: rest coordinate).
    void element_tangent(std::size_t e, const std::array<double, 12> &X,
                         Eigen::Matrix<double, 12, 12> &K) const;

    static constexpr std::size_t block_size = 256; // elements per task of the threaded loops

  private:
    std::array<std::size_t, 12>  dofs(std::size_t e) const;
    static constexpr std::size_t cached_series =
        9 + 9 + 1 + 9 + 9 + 4 + 9; // D_m, A, det, F, cof F, J, I_c, s, u, P
    mutable SeriesCache cache;

    std::vector<std::array<unsigned int, 4>> tets;
    Eigen::VectorXd                          target;
    HyperelasticTetElements                  density; // for energy_density(F) and the constants
    std::map<std::size_t, double>            fixed_values;
  };
} // namespace nlmech
