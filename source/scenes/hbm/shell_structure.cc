// Structure "shell": a thin shell (CST St.Venant-Kirchhoff membrane + hinge bending) on the gmsh
// surface mesh of subsection Mesh, its material in subsection Shell.

#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/scenes/hbm/mesh_structure.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// subsection Shell
    struct ShellSettings
    {
      ShellMaterial material;

      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Shell");
        prm.declare_entry("Young's modulus", "1e7", Patterns::Double(0), "[Pa].");
        prm.declare_entry("Poisson's ratio", "0.4", Patterns::Double(-1, 0.5), "[-].");
        prm.declare_entry("Density", "1100", Patterns::Double(0), "[kg/m^3].");
        prm.declare_entry("Thickness", "0.001", Patterns::Double(0), "[m].");
        prm.leave_subsection();
      }

      void parse_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Shell");
        material.youngs_modulus = prm.get_double("Young's modulus");
        material.poissons_ratio = prm.get_double("Poisson's ratio");
        material.density        = prm.get_double("Density");
        material.thickness      = prm.get_double("Thickness");
        prm.leave_subsection();
      }
    };

    class ShellStructure : public MeshStructure
    {
    public:
      explicit ShellStructure(ParameterHandler &prm)
          : MeshStructure(prm, "shell", 2)
      {
        shell.parse_parameters(prm);
      }

    protected:
      MeshModel make_model(const RawSimplexMesh<3> &mesh) const override
      {
        ShellModel made = make_shell_model(mesh, shell.material);
        MeshModel  m;
        m.model = std::move(made.model), m.rest = made.rest_positions, m.dofs_per_vertex = 3;
        return m;
      }

    private:
      ShellSettings shell;
    };
  } // namespace

  NLMECH_REGISTER_STRUCTURE(
      shell, StructureInfo{"shell",
                           "a thin shell (CST St.Venant-Kirchhoff membrane + hinge bending) on "
                           "the gmsh surface mesh of subsection Mesh (subsection Shell)",
                           {&MeshStructureSettings::declare_parameters, &ShellSettings::declare_parameters},
                           [](ParameterHandler &prm) -> std::unique_ptr<StructurePlugin> {
                             return std::make_unique<ShellStructure>(prm);
                           }})
} // namespace nlmech
