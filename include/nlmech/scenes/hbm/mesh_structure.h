#pragma once
// The structures on a gmsh mesh (shell, solid, plane): clamped and driven groups, a translation or
// rotation drive, point forces and the tracked vertex, shared by their plugins, which add the
// Model built on the mesh.

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/scenes/hbm/structure.h>

#include <string>
#include <vector>

namespace nlmech
{
  /// subsection Mesh and the mesh entries of subsection Structure.
  struct MeshStructureSettings
  {
    MeshParameters           mesh;
    std::vector<std::string> clamped_groups, driven_groups;
    bool                     rotation_drive = false;
    dealii::Tensor<1, 3>     rotation_axis, rotation_center;
    double                   rotation_amplitude = 0, drive_stiffness_factor = 0;
    dealii::Point<3>         tracked_point;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

  /// A Model on a mesh with its rest positions and unknowns per vertex.
  struct MeshModel
  {
    Model                                model{0};
    Eigen::VectorXd                      rest;
    unsigned int                         dofs_per_vertex = 3;
    unsigned int                         material_layers = 1;
    std::vector<std::pair<long, double>> layer_terms;    // PeriodicStructure::layer_terms
    std::vector<double>                  element_moduli; // PeriodicStructure::element_moduli
  };

  class MeshStructure : public StructurePlugin
  {
  public:
    MeshStructure(dealii::ParameterHandler &prm, std::string kind, int cell_dim);
    void              validate() const override;
    PeriodicStructure build(RunContext &context, const HarmonicBalanceSettings &settings,
                            const ExcitationSettings &excitation) override;
    /// period.pvd: the displacement of every vertex at every frame.
    void write_period(RunContext &context, const PeriodicStructure &structure,
                      const std::vector<double> &times, const Eigen::MatrixXd &x) const override;

  protected:
    virtual MeshModel make_model(const RawSimplexMesh<3> &mesh) const = 0;

  private:
    std::string           kind;
    int                   cell_dim;
    MeshStructureSettings settings;
    RawSimplexMesh<3>     mesh;
    unsigned int          dofs_per_vertex = 3;
  };
} // namespace nlmech
