#pragma once
// A tetrahedral mesh written back as a gmsh 2.2 ASCII file (what gmsh and nlmech read again), at
// given vertex positions, with the physical groups, boundary faces and cell materials it came with.

#include <nlmech/mesh/gmsh_mesh.h>

#include <Eigen/Dense>

#include <string>

namespace nlmech
{
  /// The mesh with vertex v at X[3 v .. 3 v + 2].
  std::string simplex_mesh_msh(const RawSimplexMesh<3> &mesh, const Eigen::VectorXd &X);
} // namespace nlmech
