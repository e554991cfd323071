#pragma once
// Parameter subsections shared by the linear-elastic statics scenes. One struct per subsection,
// each with declare_parameters / parse_parameters; every doc string states units.

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>

#include <nlmech/base/parse.h>
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/solid/hyperelastic_tet_energy.h>
#include <nlmech/models/solid/linear_elasticity.h>

#include <string>
#include <vector>

namespace nlmech
{
  /// subsection Mesh
  struct MeshParameters
  {
    std::string                   file;    // resolved path
    std::string                   written; // as written in the parameter file
    double                        element_size = 0;
    std::map<std::string, double> constants;

    static void declare_parameters(dealii::ParameterHandler &prm, const std::string &default_file,
                                   double default_size);
    void        parse_parameters(dealii::ParameterHandler &prm);
    MeshOptions options(double size) const;
    /// A clear error when the mesh file is missing or gmsh cannot read it, naming the path as
    /// written and as resolved (for validate(): a .geo is parsed, not meshed).
    void check_exists() const;
  };

  /// subsection Mesh study
  struct MeshStudyParameters
  {
    std::vector<double> element_sizes; // empty: one run at the Mesh element size
    bool                write_fields               = true;
    bool                write_vertex_displacements = false;

    static void declare_parameters(dealii::ParameterHandler &prm, const std::string &default_sizes);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// The sizes to run: the study's, or the single Mesh element size.
    std::vector<double> sizes(double single_size) const;
  };

  /// subsection Material
  struct MaterialParameters
  {
    IsotropicMaterial material;

    static void declare_parameters(dealii::ParameterHandler &prm, double E, double nu, double rho);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

  /// subsection Material of the hyperelastic scenes
  struct HyperelasticMaterialParameters
  {
    HyperelasticMaterial material;

    static void declare_parameters(dealii::ParameterHandler &prm, double E, double nu, double rho);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

  /// subsection Discretization
  struct DiscretizationParameters
  {
    unsigned int degree = 1;

    static void declare_parameters(dealii::ParameterHandler &prm, unsigned int default_degree);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

  /// subsection Linear solver
  struct LinearSolverParameters
  {
    LinearSolverSettings settings;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

} // namespace nlmech
