// Pattern "mesh element" (subsection Material/Mesh element): any element shape from a triangulated
// surface (gmsh .msh or .geo), placed in a periodic cell by lattice vectors and a list of elements.

#include <deal.II/base/utilities.h>

#include <nlmech/base/run_context.h>
#include <nlmech/dim/element_shape.h>
#include <nlmech/scenes/dim/pattern_plugin.h>

#include <cmath>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class MeshElementPattern : public PatternPlugin
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Mesh element");
        prm.declare_entry("Mesh file", "", Patterns::Anything(),
                          "Triangulated surface of the element: gmsh .msh, or a .geo source meshed in 2D "
                          "(relative to this file) [mm].");
        prm.declare_entry("Mesh size", "0", Patterns::Double(0),
                          "Largest triangle edge for a .geo source [mm] (0: the file's own sizes).");
        prm.declare_entry("Skin radius", "0", Patterns::Double(0),
                          "Swept-sphere radius around every triangle [mm] (needed for an open surface).");
        prm.declare_entry("Lattice vector 1", "10, 0", Patterns::List(Patterns::Double(), 2, 2),
                          "t1 of the periodic cell [mm].");
        prm.declare_entry("Lattice vector 2", "0, 10", Patterns::List(Patterns::Double(), 2, 2),
                          "t2 of the periodic cell [mm].");
        prm.declare_entry("Elements", "0, 0, 0, 0, 0, 0", Patterns::Anything(),
                          "The cell's elements, separated by ';': centre x, y, z [mm] and rotation vector "
                          "[deg] each.");
        prm.leave_subsection();
      }

      /// Reads and checks everything here, so a bad file fails before any work.
      explicit MeshElementPattern(ParameterHandler &prm)
      {
        prm.enter_subsection("Mesh element");
        written = prm.get("Mesh file");
        AssertThrow(!written.empty(),
                    ExcMessage("Mesh element: give the 'Mesh file' of the element's surface."));
        file        = resolve_input_path(written, current_parameter_directory());
        skin_radius = prm.get_double("Skin radius"), mesh_size = prm.get_double("Mesh size");
        auto vector2 = [&](const std::string &entry) {
          const auto v = Utilities::string_to_double(Utilities::split_string_list(prm.get(entry)));
          return Eigen::Vector2d(v[0], v[1]);
        };
        t1 = vector2("Lattice vector 1"), t2 = vector2("Lattice vector 2");
        AssertThrow(std::abs(t1.x() * t2.y() - t1.y() * t2.x()) > 1e-9,
                    ExcMessage("Mesh element: the lattice vectors must not be parallel."));
        for (const auto &element : Utilities::split_string_list(prm.get("Elements"), ';'))
          {
            std::vector<double> v;
            try
              {
                v = Utilities::string_to_double(Utilities::split_string_list(element));
              }
            catch (...)
              {
              }
            AssertThrow(v.size() == 6, ExcMessage("Mesh element: every entry of 'Elements' needs six numbers "
                                                  "(x, y, z, rotation vector in degrees): <" +
                                                  element + ">."));
            for (const double x : v)
              AssertThrow(std::isfinite(x), ExcMessage("Mesh element: the entry <" + element +
                                                       "> of 'Elements' has a number that is not finite."));
            centres.emplace_back(v[0], v[1], v[2]);
            rotations.push_back(Eigen::Vector3d(v[3], v[4], v[5]) * dim_units::degree);
          }
        prm.leave_subsection();
      }

      dim::Pattern pattern(const double density) const override
      {
        dim::Pattern p;
        p.name = "mesh element";
        p.shapes.push_back(dim::triangle_mesh_element(file, skin_radius, density, mesh_size, written));
        p.t1 = t1, p.t2 = t2;
        for (std::size_t i = 0; i < centres.size(); ++i)
          {
            p.shape_of.push_back(0);
            p.centres.push_back(centres[i]);
            p.rotations.push_back(rotations[i]);
          }
        p.neighbours = 0; // no centreline: links are not checked
        return p;
      }

    private:
      std::string                  written, file;
      double                       skin_radius = 0, mesh_size = 0;
      Eigen::Vector2d              t1, t2;
      std::vector<Eigen::Vector3d> centres, rotations;
    };
  } // namespace

  NLMECH_REGISTER_PATTERN(mesh_element,
                          PatternInfo{"mesh element",
                                      "any shape from a triangulated surface, placed by the 'Mesh element' "
                                      "subsection",
                                      {&MeshElementPattern::declare_parameters},
                                      [](ParameterHandler &prm) -> std::unique_ptr<PatternPlugin> {
                                        return std::make_unique<MeshElementPattern>(prm);
                                      }})
} // namespace nlmech
