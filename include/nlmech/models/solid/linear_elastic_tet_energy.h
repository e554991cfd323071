#pragma once
// Linear-elastic tetrahedra as an element energy written once on the scalar type:
// W = mu eps:eps + lambda/2 tr(eps)^2 with eps = sym(grad u), integrated exactly on a linear tet.
// The unknowns are the vertex displacements, 3 per vertex (x, y, z interleaved).

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/energy_term.h>
#include <nlmech/models/model.h>
#include <nlmech/models/solid/linear_elasticity.h>

#include <array>
#include <vector>

namespace nlmech
{
  struct LinearElasticTetElements
  {
    static constexpr std::size_t n_dofs = 12;

    LinearElasticTetElements(const std::vector<dealii::Point<3>>          &vertices,
                             const std::vector<std::vector<unsigned int>> &tets,
                             const IsotropicMaterial                      &material);

    std::size_t                 n_elements() const { return tets.size(); }
    std::array<std::size_t, 12> dofs(std::size_t e) const;

    template <typename S>
    S energy(const std::array<S, 12> &u, std::size_t e) const
    {
      const auto &dphi = shape_gradients[e]; // dphi_a / dX_j, a = vertex, j = direction
      S           grad[3][3];                // du_i / dX_j
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          {
            grad[i][j] = 0.0;
            for (int a = 0; a < 4; ++a)
              grad[i][j] += u[3 * a + i] * dphi[a][j];
          }
      S trace   = grad[0][0] + grad[1][1] + grad[2][2];
      S eps_eps = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          {
            const S eps_ij = 0.5 * (grad[i][j] + grad[j][i]);
            eps_eps += eps_ij * eps_ij;
          }
      return volume[e] * (mu * eps_eps + 0.5 * lambda * trace * trace);
    }

    std::vector<std::array<unsigned int, 4>>          tets;
    std::vector<std::array<std::array<double, 3>, 4>> shape_gradients;
    std::vector<double>                               volume;
    double                                            lambda, mu;
  };

  using LinearElasticTetTerm = ElementEnergyTerm<LinearElasticTetElements>;
  extern template class ElementEnergyTerm<LinearElasticTetElements>;

  /// A Model of linear-elastic tetrahedra from a gmsh mesh: the elastic term, lumped masses, the
  /// weight rho g as a constant force term, and zero displacement on the named face groups.
  Model make_linear_elastic_tet_model(const RawSimplexMesh<3> &mesh, const IsotropicMaterial &material,
                                      const dealii::Tensor<1, 3>     &gravity,
                                      const std::vector<std::string> &clamped_groups);
} // namespace nlmech
