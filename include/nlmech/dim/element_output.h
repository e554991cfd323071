#pragma once
// Surfaces of rigid elements and strain-space boundaries as triangle meshes for VTU output.

#include <nlmech/dim/rigid_assembly.h>
#include <nlmech/dim/strain_space_boundary.h>
#include <nlmech/mesh/gmsh_mesh.h>

#include <string>
#include <vector>

namespace nlmech::dim
{
  /// Tubes around every element's centreline loop (`sides` around) and slabs around its faces, at
  /// state q, for the given images of each body (periodic cells: e.g. the 3 x 3 block around the
  /// cell); `element` receives the body index per triangle.
  RawSimplexMesh<3> element_surfaces(const RigidAssembly &assembly, const Eigen::VectorXd &q,
                                     const std::vector<std::array<int, 2>> &images,
                                     std::vector<double> &element, unsigned int sides = 8);

  /// Writes the surfaces (element index as a cell field) to a VTU file.
  void write_elements_vtu(const RigidAssembly &assembly, const Eigen::VectorXd &q,
                          const std::vector<std::array<int, 2>> &images, const std::string &path);

  /// Writes a strain-space boundary mesh to a VTU file (coordinates are the strain axes).
  void write_boundary_vtu(const StrainSpaceBoundary &boundary, const std::string &path);
} // namespace nlmech::dim
