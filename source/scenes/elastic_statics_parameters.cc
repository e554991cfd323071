#include <nlmech/scenes/elastic_statics_parameters.h>

#include <deal.II/base/utilities.h>

#include <nlmech/base/run_context.h>

#include <cmath>
#include <filesystem>

namespace nlmech
{
  using namespace dealii;

  void MeshParameters::declare_parameters(ParameterHandler &prm, const std::string &default_file,
                                          const double default_size)
  {
    prm.enter_subsection("Mesh");
    prm.declare_entry("Mesh file", default_file, Patterns::FileName(),
                      "gmsh .geo source or .msh mesh; a relative path is relative to this parameter file.");
    prm.declare_entry("Element size", std::to_string(default_size), Patterns::Double(0),
                      "Largest element edge for .geo sources [m]; 0 keeps the sizes set in the file.");
    prm.declare_entry("Geometry constants", "", Patterns::Anything(),
                      "Values for the DefineConstant[] entries of a .geo source, as `name = value, ...` "
                      "[length units of the geometry].");
    prm.leave_subsection();
  }

  void MeshParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    written      = prm.get("Mesh file");
    file         = resolve_input_path(written, current_parameter_directory());
    element_size = prm.get_double("Element size");
    constants.clear();
    for (const auto &item : Utilities::split_string_list(prm.get("Geometry constants"), ','))
      {
        if (item.empty())
          continue;
        const auto pair = Utilities::split_string_list(item, '=');
        AssertThrow(pair.size() == 2 && !pair[0].empty(),
                    ExcMessage("Geometry constants must read `name = value, ...`; <" + item + "> does not."));
        constants[pair[0]] = parse_number_list(pair[1], "Geometry constants").at(0);
      }
    prm.leave_subsection();
  }

  MeshOptions MeshParameters::options(const double size) const
  {
    MeshOptions o;
    o.file                  = file;
    o.written               = written;
    o.characteristic_length = size;
    o.constants             = constants;
    return o;
  }

  void MeshParameters::check_exists() const
  {
    AssertThrow(std::filesystem::is_regular_file(file),
                ExcMessage("The mesh file " + options(0).name() + " does not exist."));
    check_mesh_readable(options(element_size));
  }

  void MeshStudyParameters::declare_parameters(ParameterHandler &prm, const std::string &default_sizes)
  {
    prm.enter_subsection("Mesh study");
    prm.declare_entry("Element sizes", default_sizes, Patterns::Anything(),
                      "Comma-separated element sizes [m], one solve each, coarse to fine; empty runs the "
                      "single Mesh/Element size.");
    prm.declare_entry("Write fields", "true", Patterns::Bool(),
                      "Write VTU/PVD displacement and stress fields for every mesh of the study.");
    prm.declare_entry(
        "Write vertex displacements", "false", Patterns::Bool(),
        "Write vertex_displacements.csv (x, y[, z] [m], u_x, u_y[, u_z] [m] per mesh vertex) for the "
        "finest mesh; used to compare runs, e.g. serial against MPI.");
    prm.leave_subsection();
  }

  void MeshStudyParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh study");
    element_sizes = parse_number_list(prm.get("Element sizes"), "Element sizes");
    for (double h : element_sizes)
      AssertThrow(h > 0, ExcMessage("Every mesh-study element size must be positive."));
    write_fields               = prm.get_bool("Write fields");
    write_vertex_displacements = prm.get_bool("Write vertex displacements");
    prm.leave_subsection();
  }

  std::vector<double> MeshStudyParameters::sizes(const double single_size) const
  {
    return element_sizes.empty() ? std::vector<double>{single_size} : element_sizes;
  }

  void MaterialParameters::declare_parameters(ParameterHandler &prm, const double E, const double nu,
                                              const double rho)
  {
    prm.enter_subsection("Material");
    prm.declare_entry("Young's modulus", std::to_string(E), Patterns::Double(),
                      "Young's modulus E [Pa]; must be positive.");
    prm.declare_entry("Poisson's ratio", std::to_string(nu), Patterns::Double(),
                      "Poisson's ratio nu [-]; must lie in (-1, 0.5).");
    prm.declare_entry("Density", std::to_string(rho), Patterns::Double(), "Mass density rho [kg/m^3].");
    prm.leave_subsection();
  }

  void MaterialParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    material.youngs_modulus = prm.get_double("Young's modulus");
    material.poissons_ratio = prm.get_double("Poisson's ratio");
    material.density        = prm.get_double("Density");
    prm.leave_subsection();
    material.check();
  }

  void HyperelasticMaterialParameters::declare_parameters(ParameterHandler &prm, const double E,
                                                          const double nu, const double rho)
  {
    prm.enter_subsection("Material");
    prm.declare_entry("Law", "neo-Hookean", Patterns::Selection("neo-Hookean|St.Venant-Kirchhoff"),
                      "neo-Hookean: W = mu/2 (J^(-2/3) I_c - 3) + kappa/2 (J - 1)^2; St.Venant-Kirchhoff: "
                      "W = mu E:E + lambda/2 tr(E)^2.");
    prm.declare_entry("Young's modulus", std::to_string(E), Patterns::Double(),
                      "Young's modulus E [Pa]; positive.");
    prm.declare_entry("Poisson's ratio", std::to_string(nu), Patterns::Double(),
                      "Poisson's ratio nu [-]; in (-1, 0.5).");
    prm.declare_entry("Density", std::to_string(rho), Patterns::Double(0), "Mass density rho [kg/m^3].");
    prm.leave_subsection();
  }

  void HyperelasticMaterialParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    material.law            = prm.get("Law") == "neo-Hookean" ? HyperelasticLaw::neo_hookean
                                                              : HyperelasticLaw::saint_venant_kirchhoff;
    material.youngs_modulus = prm.get_double("Young's modulus");
    material.poissons_ratio = prm.get_double("Poisson's ratio");
    material.density        = prm.get_double("Density");
    prm.leave_subsection();
    material.check();
  }

  void DiscretizationParameters::declare_parameters(ParameterHandler &prm, const unsigned int default_degree)
  {
    prm.enter_subsection("Discretization");
    prm.declare_entry("Polynomial degree", std::to_string(default_degree), Patterns::Integer(1, 2),
                      "Degree of the simplex Lagrange elements: 1 (linear) or 2 (quadratic) [-].");
    prm.leave_subsection();
  }

  void DiscretizationParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Discretization");
    degree = prm.get_integer("Polynomial degree");
    prm.leave_subsection();
  }

  void LinearSolverParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    prm.declare_entry(
        "Method", "direct", Patterns::Selection("direct|cg-amg"),
        "direct: sparse LU through Trilinos Amesos; cg-amg: conjugate gradients preconditioned by "
        "Trilinos ML algebraic multigrid.");
    prm.declare_entry("Direct solver", "mumps", Patterns::Selection("mumps|klu"),
                      "Amesos back end for Method = direct: mumps (multifrontal, parallel) or klu (serial).");
    prm.declare_entry("Relative tolerance", "1e-10", Patterns::Double(0),
                      "CG stopping tolerance on the residual relative to the load vector norm [-].");
    prm.declare_entry("Max iterations", "5000", Patterns::Integer(1), "CG iteration limit [-].");
    prm.leave_subsection();
  }

  void LinearSolverParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    settings.method             = prm.get("Method");
    settings.direct_solver      = prm.get("Direct solver");
    settings.relative_tolerance = prm.get_double("Relative tolerance");
    settings.max_iterations     = prm.get_integer("Max iterations");
    prm.leave_subsection();
    AssertThrow(settings.relative_tolerance > 0 && settings.relative_tolerance < 1,
                ExcMessage("The linear solver's relative tolerance must lie in (0, 1)."));
  }
} // namespace nlmech
