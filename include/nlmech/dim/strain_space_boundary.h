#pragma once
// Strain-space boundaries (thesis section 4.3.3): a closed, watertight triangle mesh through the
// boundary samples of a material's feasible set of in-plane strains (E_xx, E_yy, E_xy) or
// curvatures (kappa_xx, kappa_yy, kappa_xy).
//
// The feasible set is assumed star-shaped about the rest state (the thesis' assumption, section
// 4.5.1). The samples are scaled per axis, projected radially onto the unit sphere about the rest
// state, and triangulated there by their convex hull (CGAL convex_hull_3: on a sphere this is the
// spherical Delaunay triangulation); the triangles are then mapped back to the samples. The mesh is
// therefore closed and two-manifold by construction; `check` confirms it (CGAL), counts triangles
// whose orientation flips in the map (the set was not star-shaped there) and tests that the rest
// state lies inside (CGAL Side_of_triangle_mesh).
//
// File format (".ssb", plain text, read by `read_boundary`):
//   # comment lines
//   nlmech-strain-space-boundary 1
//   kind stretch|bending
//   axes E_xx E_yy E_xy              (or kappa_xx kappa_yy kappa_xy, curvatures in 1/mm)
//   rest <x> <y> <z>                 (a point inside: the rest state)
//   vertices <n>
//   <x> <y> <z>                      (n lines)
//   triangles <m>
//   <i> <j> <k>                      (m lines, 0-based, counter-clockwise seen from outside)

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace nlmech::dim
{
  struct StrainSpaceBoundary
  {
    std::string                          kind = "stretch";
    std::array<std::string, 3>           axes{{"E_xx", "E_yy", "E_xy"}};
    Eigen::Vector3d                      rest = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d>         vertices;
    std::vector<std::array<unsigned, 3>> triangles;
  };

  struct BoundaryCheck
  {
    bool        closed        = false; // every edge shared by exactly two triangles (CGAL is_closed)
    bool        contains_rest = false;
    unsigned    flipped       = 0; // triangles facing the rest state (not star-shaped there)
    double      volume        = 0;
    std::size_t vertices = 0, triangles = 0;
  };

  /// Triangulates boundary samples about `rest`; axes are scaled by `scale` (per axis) before the
  /// radial projection, so that the triangulation does not depend on the units. Samples within
  /// 1e-9 (scaled) of the rest state or in a direction already taken are dropped.
  StrainSpaceBoundary star_shaped_boundary(const std::vector<Eigen::Vector3d> &samples,
                                           const Eigen::Vector3d &rest, const Eigen::Vector3d &scale);

  BoundaryCheck check(const StrainSpaceBoundary &boundary);

  /// Signed distance of a point to the boundary (positive outside), by CGAL's AABB tree.
  double signed_distance(const StrainSpaceBoundary &boundary, const Eigen::Vector3d &point);

  void                write_boundary(const std::string &path, const StrainSpaceBoundary &boundary,
                                     const std::string &comment);
  StrainSpaceBoundary read_boundary(const std::string &path);
} // namespace nlmech::dim
