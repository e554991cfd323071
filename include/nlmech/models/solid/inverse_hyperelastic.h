#pragma once
// Inverse rest-shape design (ANM paper, section 4): given the target deformed shape x and the loads
// g, find the rest shape X with r(X) = grad_x E(x; X) = g. The unknowns are the rest positions X;
// at fixed vertices X = x. The internal force is written once as a template on the scalar type of
// X (double, Sacado Fad for the non-symmetric tangent dr/dX, truncated series for the ANM), on the
// same energy density W(F) as the forward problem, F = D_s(x) D_m(X)^-1.

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

  private:
    std::vector<std::array<unsigned int, 4>> tets;
    Eigen::VectorXd                          target;
    HyperelasticTetElements                  density; // for energy_density(F) and the constants
    std::map<std::size_t, double>            fixed_values;
  };
} // namespace nlmech
