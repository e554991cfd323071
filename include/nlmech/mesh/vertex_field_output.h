#pragma once
// VTU output of per-vertex vector fields on a gmsh simplex mesh (rest configuration), through a
// deal.II Triangulation and DataOut, written atomically. Used by the Model-based solvers, whose
// unknowns live on the mesh vertices.

#include <nlmech/mesh/gmsh_mesh.h>

#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace nlmech
{
  /// `fields`: (name, vector with 3 values per vertex). Also writes the cell-wise `cell_fields`.
  /// Tetrahedral meshes and triangle surface meshes in 3D (a Triangulation<2, 3>).
  void write_vertex_fields_vtu(const RawSimplexMesh<3>                                    &mesh,
                               const std::vector<std::pair<std::string, Eigen::VectorXd>> &fields,
                               const std::vector<std::pair<std::string, Eigen::VectorXd>> &cell_fields,
                               const std::string                                          &path);

  /// A time series: `basename-NNNN.vtu` per frame in `directory` and `basename.pvd` listing them.
  void
  write_vertex_fields_pvd(const RawSimplexMesh<3> &mesh, const std::string &directory,
                          const std::string &basename, const std::vector<double> &times,
                          const std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> &frames);
} // namespace nlmech

namespace nlmech
{
  /// vertex_displacements.csv: x, y, z [m], u_x, u_y, u_z [m] per vertex (the format of the linear
  /// scenes, read by tests/mpi/compare_serial_mpi.py).
  void write_vertex_displacements_csv(const RawSimplexMesh<3> &mesh, const Eigen::VectorXd &displacement,
                                      const std::string &path);
} // namespace nlmech
