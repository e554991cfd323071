// Structures "solid" (St.Venant-Kirchhoff tetrahedra on a gmsh volume mesh) and "plane"
// (plane-stress St.Venant-Kirchhoff triangles on a gmsh mesh in z = 0), with per-layer materials
// from subsection Solid.

#include <deal.II/base/exceptions.h>

#include <nlmech/models/dynamics/elastic_solids.h>
#include <nlmech/scenes/hbm/mesh_structure.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// subsection Solid
    struct SolidSettings
    {
      std::vector<SolidMaterial> materials; // one per layer
      unsigned int               layer_axis = 2;

      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Solid");
        prm.declare_entry("Young's modulus", "1e6", Patterns::Anything(),
                          "One value, or one per layer (comma-separated, from the low end of the layer axis "
                          "up) [Pa].");
        prm.declare_entry("Poisson's ratio", "0.3", Patterns::Double(-1, 0.5), "[-].");
        prm.declare_entry("Density", "1000", Patterns::Double(0), "[kg/m^3].");
        prm.declare_entry("Thickness", "0.01", Patterns::Double(0), "plane: out-of-plane thickness [m].");
        prm.declare_entry("Layer axis", "z", Patterns::Selection("x|y|z"),
                          "Layers are equal slabs of the mesh's extent along this axis [-].");
        prm.leave_subsection();
      }

      void parse_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Solid");
        for (const double E : parse_number_list(prm.get("Young's modulus"), "Young's modulus"))
          {
            SolidMaterial m;
            m.youngs_modulus = E, m.poissons_ratio = prm.get_double("Poisson's ratio");
            m.density = prm.get_double("Density"), m.thickness = prm.get_double("Thickness");
            m.check();
            materials.push_back(m);
          }
        AssertThrow(!materials.empty(), ExcMessage("Solid: Young's modulus needs at least one value."));
        layer_axis = prm.get("Layer axis") == "x" ? 0 : prm.get("Layer axis") == "y" ? 1 : 2;
        prm.leave_subsection();
      }
    };

    class SolidStructure : public MeshStructure
    {
    public:
      SolidStructure(ParameterHandler &prm, const bool plane)
          : MeshStructure(prm, plane ? "plane" : "solid", plane ? 2 : 3)
          , plane(plane)
      {
        solid.parse_parameters(prm);
      }

    protected:
      MeshModel make_model(const RawSimplexMesh<3> &mesh) const override
      {
        const auto layers = cell_layers(mesh, solid.layer_axis, solid.materials.size());
        SolidModel made   = plane ? make_plane_model(mesh, solid.materials, layers)
                                  : make_tet_solid_model(mesh, solid.materials, layers);
        MeshModel  m;
        m.model = std::move(made.model), m.rest = made.rest_positions, m.dofs_per_vertex = made.dim;
        m.material_layers = unsigned(solid.materials.size());
        // Design: the tet model has one term per layer with cells; the plane one a modulus per element.
        std::vector<std::size_t> cells(solid.materials.size(), 0);
        for (const unsigned int l : layers)
          ++cells[l];
        long term = 0;
        for (std::size_t l = 0; l < solid.materials.size(); ++l)
          m.layer_terms.emplace_back(plane || cells[l] == 0 ? -1 : term++, solid.materials[l].youngs_modulus);
        if (plane)
          for (const unsigned int l : layers)
            m.element_moduli.push_back(solid.materials[l].youngs_modulus);
        return m;
      }

    private:
      bool          plane;
      SolidSettings solid;
    };
  } // namespace

  NLMECH_REGISTER_STRUCTURE(solid,
                            StructureInfo{"solid",
                                          "St.Venant-Kirchhoff tetrahedra on a gmsh volume mesh (subsection "
                                          "Solid, per-layer materials)",
                                          {&MeshStructureSettings::declare_parameters,
                                           &SolidSettings::declare_parameters},
                                          [](ParameterHandler &prm) -> std::unique_ptr<StructurePlugin> {
                                            return std::make_unique<SolidStructure>(prm, false);
                                          }})
  NLMECH_REGISTER_STRUCTURE(
      plane, StructureInfo{"plane",
                           "plane-stress St.Venant-Kirchhoff triangles on a gmsh mesh in z = 0 "
                           "(subsection Solid)",
                           {&MeshStructureSettings::declare_parameters, &SolidSettings::declare_parameters},
                           [](ParameterHandler &prm) -> std::unique_ptr<StructurePlugin> {
                             return std::make_unique<SolidStructure>(prm, true);
                           }})
} // namespace nlmech
