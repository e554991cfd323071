#pragma once
// Helpers shared by the harmonic-balance tests.
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/dynamics/elastic_solids.h>
#include <nlmech/solvers/hbm/harmonic_balance.h>

#include <Eigen/Dense>

#include <algorithm>
#include <string>
#include <vector>

namespace nlmech::testing
{
  /// Largest difference between the Jacobian's columns and central differences of the residual,
  /// relative to the largest Jacobian entry (at least 1).
  inline double jacobian_difference(const HarmonicBalance &hb, const Eigen::VectorXd &z, double omega,
                                    double h)
  {
    const Eigen::MatrixXd J     = Eigen::MatrixXd(hb.jacobian(z, omega));
    double                worst = 0;
    for (Eigen::Index j = 0; j < z.size(); ++j)
      {
        Eigen::VectorXd zp = z, zm = z;
        zp[j] += h, zm[j] -= h;
        const Eigen::VectorXd column = (hb.residual(zp, omega) - hb.residual(zm, omega)) / (2 * h);
        worst                        = std::max(worst, (column - J.col(j)).lpNorm<Eigen::Infinity>());
      }
    return worst / std::max(1.0, J.lpNorm<Eigen::Infinity>());
  }

  /// A gmsh mesh from meshes/, checked.
  inline RawSimplexMesh<3> mesh(const std::string &geo, double size, int dim)
  {
    MeshOptions options;
    options.file                  = std::string(NLMECH_SOURCE_DIR "/meshes/") + geo;
    options.characteristic_length = size;
    RawSimplexMesh<3> m           = read_simplex_mesh<3>(options, dim);
    check_simplex_mesh(m, dim);
    return m;
  }

  /// A soft plane unit square (E = 1e4 Pa, t = 1 cm) whose bottom edge is shaken along x with
  /// `amplitude` and `phase`: a small tower-like strip.
  struct ShakenStrip
  {
    RawSimplexMesh<3>          m;
    SolidModel                 solid;
    std::vector<HarmonicDrive> drives;
  };
  inline ShakenStrip shaken_strip(double amplitude, double phase)
  {
    ShakenStrip s;
    s.m = mesh("unit_square.geo", 0.3, 2);
    SolidMaterial material;
    material.youngs_modulus = 1e4, material.thickness = 0.01;
    s.solid = make_plane_model(s.m, {material});
    for (std::size_t v = 0; v < s.m.vertices.size(); ++v)
      if (s.m.vertices[v][1] < 1e-9)
        for (unsigned int i = 0; i < 2; ++i)
          s.drives.push_back(
              {2 * v + i, i == 0 ? amplitude : 0.0, phase, 0.0, s.solid.rest_positions[2 * v + i], {}, {}});
    return s;
  }
} // namespace nlmech::testing
