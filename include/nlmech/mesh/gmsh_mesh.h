#pragma once
// Meshes from gmsh: .geo sources are meshed through the gmsh C++ API with the element size taken
// from the parameter file; .msh files are read through the same API. The elements are checked
// (empty mesh, inverted or degenerate elements) before a deal.II Triangulation is built from them.
// Physical groups become boundary ids (faces) and material ids (cells), addressed by name.

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <map>
#include <string>
#include <vector>

namespace nlmech
{
  struct MeshOptions
  {
    /// A gmsh .geo source or a .msh mesh file.
    std::string file;
    /// Largest element size for .geo sources (length units of the geometry); 0 keeps the file's.
    double characteristic_length = 0;
    /// Values for DefineConstant[] entries of a .geo source (e.g. L, W, H).
    std::map<std::string, double> constants;
    /// The path as the user wrote it (relative to the parameter file), for messages; empty: `file`.
    std::string written;

    /// `<written>` for messages, with the resolved path beside it when the two differ.
    std::string name() const;
  };

  /// The physical groups of a mesh, by name.
  struct MeshGroups
  {
    std::string                         source;
    std::map<std::string, unsigned int> boundary_ids; ///< face groups, dimension dim-1
    std::map<std::string, unsigned int> material_ids; ///< cell groups, dimension dim

    /// The boundary id of a face group; throws a clear error listing the groups if it is missing.
    unsigned int boundary_id(const std::string &name) const;
    unsigned int material_id(const std::string &name) const;
  };

  /// Element data as gmsh delivers it, before any deal.II object is built.
  template <int spacedim>
  struct RawSimplexMesh
  {
    std::vector<dealii::Point<spacedim>>   vertices;
    std::vector<std::vector<unsigned int>> cells;          ///< dim+1 vertex indices each
    std::vector<unsigned int>              cell_material;  ///< material id per cell
    std::vector<std::vector<unsigned int>> boundary_faces; ///< dim vertex indices each
    std::vector<unsigned int>              boundary_face_id;
    MeshGroups                             groups;
  };

  /// Runs gmsh on `options` and returns the linear simplices of dimension `dim`.
  /// Opens the file in gmsh without meshing it (a .geo is parsed, a .msh read): one clear error
  /// naming the file for what gmsh cannot read. For `--validate`.
  void check_mesh_readable(const MeshOptions &options);

  template <int spacedim>
  RawSimplexMesh<spacedim> read_simplex_mesh(const MeshOptions &options, int dim);

  /// Throws a clear error for an empty mesh or an inverted or degenerate element.
  template <int spacedim>
  void check_simplex_mesh(const RawSimplexMesh<spacedim> &mesh, int dim);

  /// read_simplex_mesh + check_simplex_mesh + Triangulation::create_triangulation.
  template <int dim, int spacedim>
  MeshGroups load_gmsh_mesh(const MeshOptions &options, dealii::Triangulation<dim, spacedim> &tria);
} // namespace nlmech
