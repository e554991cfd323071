// Tests source/mesh/gmsh_mesh.cc: gmsh .geo meshing with constants and sizes, physical groups by
// name, triangulated surfaces, and the mesh checks (inverted, degenerate, empty, missing group).
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <nlmech/mesh/gmsh_mesh.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace dealii;
using namespace nlmech;

namespace
{
  const std::string source_dir = NLMECH_SOURCE_DIR;

  template <int dim, int spacedim>
  double measure(const Triangulation<dim, spacedim> &tria)
  {
    const MappingFE<dim, spacedim>   mapping(FE_SimplexP<dim, spacedim>(1));
    const FE_SimplexP<dim, spacedim> fe(1);
    FEValues<dim, spacedim>          values(mapping, fe, QGaussSimplex<dim>(1), update_JxW_values);
    double                           total = 0;
    for (const auto &cell : tria.active_cell_iterators())
      {
        values.reinit(cell);
        total += values.JxW(0);
      }
    return total;
  }

  template <typename F>
  std::string error_of(F &&f)
  {
    try
      {
        f();
      }
    catch (const ExceptionBase &e)
      {
        std::ostringstream s;
        e.print_info(s);
        return s.str();
      }
    return "";
  }
} // namespace

TEST(GmshMesh, CantileverVolumeGroupsAndConstants)
{
  MeshOptions options;
  options.file                  = source_dir + "/meshes/cantilever.geo";
  options.characteristic_length = 0.05;
  options.constants             = {{"L", 2.0}, {"W", 0.2}, {"H", 0.1}};
  Triangulation<3> tria;
  const MeshGroups groups = load_gmsh_mesh(options, tria);
  EXPECT_NEAR(measure(tria), 2.0 * 0.2 * 0.1, 1e-12);
  EXPECT_EQ(groups.boundary_ids.size(), 3u);
  EXPECT_EQ(groups.material_ids.count("beam"), 1u);
  // Faces of "clamped" lie on x = 0, faces of "tip" on x = L.
  unsigned int n_clamped = 0, n_tip = 0;
  for (const auto &face : tria.active_face_iterators())
    if (face->at_boundary())
      {
        if (face->boundary_id() == groups.boundary_id("clamped"))
          {
            ++n_clamped;
            EXPECT_NEAR(face->center()[0], 0.0, 1e-12);
          }
        if (face->boundary_id() == groups.boundary_id("tip"))
          {
            ++n_tip;
            EXPECT_NEAR(face->center()[0], 2.0, 1e-12);
          }
      }
  EXPECT_GT(n_clamped, 0u);
  EXPECT_GT(n_tip, 0u);
  // The element size controls the mesh: halving it gives many more cells.
  Triangulation<3> finer;
  options.characteristic_length = 0.025;
  load_gmsh_mesh(options, finer);
  EXPECT_GT(finer.n_active_cells(), 4 * tria.n_active_cells());
}

TEST(GmshMesh, MissingGroupIsAClearError)
{
  MeshOptions       options{source_dir + "/meshes/cantilever.geo", 0.1, {}, ""};
  Triangulation<3>  tria;
  const MeshGroups  groups  = load_gmsh_mesh(options, tria);
  const std::string message = error_of([&] { groups.boundary_id("no-such-group"); });
  EXPECT_NE(message.find("<no-such-group> does not exist"), std::string::npos) << message;
  EXPECT_NE(message.find("clamped, sides, tip"), std::string::npos) << message;
}

TEST(GmshMesh, UnitSquareTriangles)
{
  MeshOptions      options{source_dir + "/meshes/unit_square.geo", 0.1, {}, ""};
  Triangulation<2> tria;
  const MeshGroups groups = load_gmsh_mesh(options, tria);
  EXPECT_NEAR(measure(tria), 1.0, 1e-12);
  EXPECT_EQ(groups.boundary_ids.count("boundary"), 1u);
  for (const auto &cell : tria.active_cell_iterators())
    EXPECT_TRUE(cell->reference_cell() == ReferenceCells::Triangle);
}

TEST(GmshMesh, SphereSurfaceAsTriangulation2In3)
{
  MeshOptions         options{source_dir + "/meshes/sphere_surface.geo", 0.1, {{"R", 2.0}}, ""};
  Triangulation<2, 3> tria;
  load_gmsh_mesh(options, tria);
  const double exact = 4 * M_PI * 4.0;
  // Flat triangles inscribed in the sphere: area below the exact one by O(h^2).
  EXPECT_LT(measure(tria), exact);
  EXPECT_NEAR(measure(tria) / exact, 1.0, 5e-3);
  for (const auto &v : tria.get_vertices())
    EXPECT_NEAR(v.norm(), 2.0, 1e-6);
}

TEST(GmshMesh, InvertedElementIsRejected)
{
  MeshOptions       options{source_dir + "/tests/data/inverted_tet.msh", 0, {}, ""};
  Triangulation<3>  tria;
  const std::string message = error_of([&] { load_gmsh_mesh(options, tria); });
  EXPECT_NE(message.find("inverted element 1"), std::string::npos) << message;
}

TEST(GmshMesh, DegenerateElementIsRejected)
{
  MeshOptions       options{source_dir + "/tests/data/degenerate_tet.msh", 0, {}, ""};
  Triangulation<3>  tria;
  const std::string message = error_of([&] { load_gmsh_mesh(options, tria); });
  EXPECT_NE(message.find("degenerate element 1"), std::string::npos) << message;
}

TEST(GmshMesh, EmptyMeshIsRejected)
{
  MeshOptions       options{source_dir + "/tests/data/surface_only.msh", 0, {}, ""};
  Triangulation<3>  tria;
  const std::string message = error_of([&] { load_gmsh_mesh(options, tria); });
  EXPECT_NE(message.find("has no tetrahedra"), std::string::npos) << message;
}

TEST(GmshMesh, MissingFileIsRejected)
{
  MeshOptions       options{source_dir + "/meshes/does-not-exist.geo", 0.1, {}, ""};
  Triangulation<3>  tria;
  const std::string message = error_of([&] { load_gmsh_mesh(options, tria); });
  EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
}
