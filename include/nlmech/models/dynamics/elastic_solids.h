#pragma once
// St.Venant-Kirchhoff solids for dynamics (thesis appendix 2.A.5): linear tetrahedra in 3D and
// plane-stress constant-strain triangles in 2D, with material parameters per cell group (layers,
// per-element stiffness for design) and lumped masses. Unknowns: `dim` positions per vertex.
//
// Plane triangle: F = D_s D_m^-1 (2x2), E = (F^T F - I) / 2,
// W = A t (mu E:E + lambda_ps / 2 tr(E)^2) with the plane-stress lambda_ps = 2 lambda mu / (lambda + 2 mu).
// Tetrahedron: W = V (mu E:E + lambda / 2 tr(E)^2) (HyperelasticTetTerm with the StVK law).

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/energy_term.h>
#include <nlmech/models/model.h>

#include <array>
#include <vector>

namespace nlmech
{
  struct SolidMaterial
  {
    double youngs_modulus = 1e6;  // Pa
    double poissons_ratio = 0.3;  // -
    double density        = 1000; // kg/m^3
    double thickness      = 1;    // m, plane elements only
    /// Throws a clear error for non-positive E, density, thickness or nu outside (-1, 0.5).
    void check() const;
  };

  struct PlaneTriangleElements
  {
    static constexpr std::size_t             n_dofs = 6;
    std::vector<std::array<unsigned int, 3>> triangles;
    std::vector<std::array<double, 4>>       dm_inverse; // row-major 2x2
    /// Per element: area times thickness, mu and the plane-stress lambda.
    std::vector<double> measure, mu, lambda;

    std::size_t                n_elements() const { return triangles.size(); }
    std::array<std::size_t, 6> dofs(std::size_t e) const
    {
      std::array<std::size_t, 6> d;
      for (int v = 0; v < 3; ++v)
        for (int i = 0; i < 2; ++i)
          d[2 * v + i] = 2 * triangles[e][v] + i;
      return d;
    }
    template <typename S>
    S energy(const std::array<S, 6> &x, std::size_t e) const
    {
      const auto &B = dm_inverse[e];
      S           F[2][2];
      for (int i = 0; i < 2; ++i)
        {
          const S d1 = x[2 + i] - x[i], d2 = x[4 + i] - x[i];
          F[i][0] = d1 * B[0] + d2 * B[2];
          F[i][1] = d1 * B[1] + d2 * B[3];
        }
      const S E00   = 0.5 * (F[0][0] * F[0][0] + F[1][0] * F[1][0] - 1.0);
      const S E11   = 0.5 * (F[0][1] * F[0][1] + F[1][1] * F[1][1] - 1.0);
      const S E01   = 0.5 * (F[0][0] * F[0][1] + F[1][0] * F[1][1]);
      const S trace = E00 + E11;
      return measure[e] *
             (mu[e] * (E00 * E00 + E11 * E11 + 2.0 * E01 * E01) + 0.5 * lambda[e] * trace * trace);
    }
    /// Signed area of element e at positions x (negative: inverted).
    double signed_area(const Eigen::VectorXd &x, std::size_t e) const;
  };

  /// The plane term with the validity hooks: no triangle may invert.
  class PlaneTriangleTerm : public ElementEnergyTerm<PlaneTriangleElements>
  {
  public:
    using ElementEnergyTerm<PlaneTriangleElements>::ElementEnergyTerm;
    bool   is_valid(const Eigen::VectorXd &x) const override;
    double max_safe_step(const Eigen::VectorXd &x, const Eigen::VectorXd &dx) const override;
  };

  struct SolidModel
  {
    Model           model{0};
    Eigen::VectorXd rest_positions;
    unsigned int    dim = 3; // unknowns per vertex
  };

  /// Plane-stress St.Venant-Kirchhoff triangles on a planar mesh (z ignored; 2 unknowns per
  /// vertex). `cell_material[c]` indexes `materials` (empty: materials[0] everywhere).
  SolidModel make_plane_model(const RawSimplexMesh<3> &mesh, const std::vector<SolidMaterial> &materials,
                              const std::vector<unsigned int> &cell_material = {});

  /// St.Venant-Kirchhoff tetrahedra (3 unknowns per vertex), one energy term per material.
  SolidModel make_tet_solid_model(const RawSimplexMesh<3> &mesh, const std::vector<SolidMaterial> &materials,
                                  const std::vector<unsigned int> &cell_material = {});

  /// Layer index of every cell: its centroid's position along `axis` (0, 1, 2) cut into `n_layers`
  /// equal slabs between the mesh's extremes.
  std::vector<unsigned int> cell_layers(const RawSimplexMesh<3> &mesh, unsigned int axis,
                                        unsigned int n_layers);

  // Instantiated once, in elastic_solids.cc (not again in every file that uses the terms).
  extern template class ElementEnergyTerm<PlaneTriangleElements>;
} // namespace nlmech
