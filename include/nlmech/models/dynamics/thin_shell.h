#pragma once
// Thin shells on triangle surface meshes (thesis appendix 2.A.5): constant-strain triangles with a
// St.Venant-Kirchhoff membrane (plane stress) plus discrete hinge bending (Grinspun et al. 2003).
// Unknowns: 3 positions per vertex.
//
// Membrane, per triangle: F = D_s D_m^-1 (3x2) from the rest triangle in its own 2D frame,
// E = (F^T F - I) / 2, W = A t (mu E:E + lambda_ps / 2 tr(E)^2), lambda_ps = 2 lambda mu / (lambda + 2 mu).
// Bending, per interior edge e with dihedral angle theta (signed angle between the two normals):
// W = k_b (theta - theta_rest)^2 3 |e_rest|^2 / A_e, A_e the two rest triangles' area, and
// k_b = D / 6 with D = E t^3 / (12 (1 - nu^2)): for a flat sheet rolled to a cylinder this gives the
// plate energy D / 2 kappa^2 per area on equilateral lattices as they are refined (tested: the
// ratio is 0.946, 0.973, 0.986 at 10, 20, 40 triangles per side) and within about 5 % on gmsh's unstructured
// meshes. (Face normals of chords of a cylinder differ by more than the centroid distance times the
// curvature: a naive estimate gives D / 4.)

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/energy_term.h>
#include <nlmech/models/model.h>

#include <array>
#include <cmath>
#include <vector>

namespace nlmech
{
  struct ShellMaterial
  {
    double youngs_modulus = 1e6;  // Pa
    double poissons_ratio = 0.3;  // -
    double density        = 1000; // kg/m^3
    double thickness      = 1e-3; // m
  };

  struct MembraneElements
  {
    static constexpr std::size_t             n_dofs = 9;
    std::vector<std::array<unsigned int, 3>> triangles;
    std::vector<std::array<double, 4>>       dm_inverse; // row-major 2x2
    std::vector<double>                      area;
    double                                   mu = 0, lambda = 0, thickness = 0;

    std::size_t                n_elements() const { return triangles.size(); }
    std::array<std::size_t, 9> dofs(std::size_t e) const
    {
      std::array<std::size_t, 9> d;
      for (int v = 0; v < 3; ++v)
        for (int i = 0; i < 3; ++i)
          d[3 * v + i] = 3 * triangles[e][v] + i;
      return d;
    }
    template <typename S>
    S energy(const std::array<S, 9> &x, std::size_t e) const
    {
      const auto &B = dm_inverse[e];
      S           F[3][2];
      for (int i = 0; i < 3; ++i)
        {
          const S d1 = x[3 + i] - x[i], d2 = x[6 + i] - x[i];
          F[i][0] = d1 * B[0] + d2 * B[2];
          F[i][1] = d1 * B[1] + d2 * B[3];
        }
      S C[2][2];
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          C[a][b] = F[0][a] * F[0][b] + F[1][a] * F[1][b] + F[2][a] * F[2][b];
      const S E00 = 0.5 * (C[0][0] - 1.0), E11 = 0.5 * (C[1][1] - 1.0), E01 = 0.5 * C[0][1];
      const S trace = E00 + E11;
      return area[e] * thickness *
             (mu * (E00 * E00 + E11 * E11 + 2.0 * E01 * E01) + 0.5 * lambda * trace * trace);
    }
  };

  struct HingeElements
  {
    static constexpr std::size_t             n_dofs = 12;
    std::vector<std::array<unsigned int, 4>> hinges;             // edge (0, 1), opposite vertices 2 and 3
    std::vector<double>                      rest_angle, weight; // weight = k_b 3 |e|^2 / A_e

    std::size_t                 n_elements() const { return hinges.size(); }
    std::array<std::size_t, 12> dofs(std::size_t e) const
    {
      std::array<std::size_t, 12> d;
      for (int v = 0; v < 4; ++v)
        for (int i = 0; i < 3; ++i)
          d[3 * v + i] = 3 * hinges[e][v] + i;
      return d;
    }
    template <typename S>
    static S dihedral_angle(const std::array<S, 12> &x)
    {
      using std::atan;
      using std::sqrt;
      S e[3], a[3], b[3];
      for (int i = 0; i < 3; ++i)
        e[i] = x[3 + i] - x[i], a[i] = x[6 + i] - x[i], b[i] = x[9 + i] - x[i];
      // n1 = e x a, n2 = b x e
      const S n1[3]    = {e[1] * a[2] - e[2] * a[1], e[2] * a[0] - e[0] * a[2], e[0] * a[1] - e[1] * a[0]};
      const S n2[3]    = {b[1] * e[2] - b[2] * e[1], b[2] * e[0] - b[0] * e[2], b[0] * e[1] - b[1] * e[0]};
      const S cross[3] = {n1[1] * n2[2] - n1[2] * n2[1], n1[2] * n2[0] - n1[0] * n2[2],
                          n1[0] * n2[1] - n1[1] * n2[0]};
      const S length   = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
      const S sine     = (cross[0] * e[0] + cross[1] * e[1] + cross[2] * e[2]) / length;
      const S cosine   = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
      const S norms    = sqrt((n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]) *
                              (n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]));
      // atan2(sine, cosine) by the half-angle formula (Sacado's Taylor atan2 does not compile here).
      return 2.0 * atan(sine / (norms + cosine));
    }
    template <typename S>
    S energy(const std::array<S, 12> &x, std::size_t e) const
    {
      const S d = dihedral_angle(x) - rest_angle[e];
      return weight[e] * d * d;
    }
  };

  struct ShellModel
  {
    Model                                                model{0};
    Eigen::VectorXd                                      rest_positions;
    std::shared_ptr<ElementEnergyTerm<MembraneElements>> membrane;
    std::shared_ptr<ElementEnergyTerm<HingeElements>>    bending;
  };

  /// The shell Model of a triangle mesh in 3D (from read_simplex_mesh<3>(..., 2)), with lumped
  /// masses rho t A / 3 per vertex. Throws for degenerate triangles or edges shared by more than two
  /// triangles.
  ShellModel make_shell_model(const RawSimplexMesh<3> &mesh, const ShellMaterial &material);

  // Instantiated once, in thin_shell.cc (not again in every file that uses the terms).
  extern template class ElementEnergyTerm<MembraneElements>;
  extern template class ElementEnergyTerm<HingeElements>;
} // namespace nlmech
