#pragma once
// A hyperelastic statics problem on a gmsh tetrahedral mesh as a Model (unknowns: deformed vertex
// positions) plus the load vector g: weight (lumped), nominal surface tractions (per reference
// area, consistent nodal forces) and point loads. Clamped groups fix all components at the rest
// position; roller groups fix one component.

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/model.h>
#include <nlmech/models/solid/hyperelastic_tet_energy.h>

#include <memory>
#include <string>
#include <vector>

namespace nlmech
{
  struct HyperelasticBoundaryConditions
  {
    std::vector<std::string>                          clamped;
    std::vector<std::pair<std::string, unsigned int>> rollers; // group, fixed component (0, 1, 2)
  };

  struct HyperelasticLoads
  {
    dealii::Tensor<1, 3>                                           gravity;     // m/s^2
    std::vector<std::pair<std::string, dealii::Tensor<1, 3>>>      tractions;   // Pa, per reference area
    std::vector<std::pair<dealii::Point<3>, dealii::Tensor<1, 3>>> point_loads; // N, at the nearest vertex
  };

  struct HyperelasticProblem
  {
    Model                                internal{0};
    Eigen::VectorXd                      load;
    Eigen::VectorXd                      rest_positions;
    std::shared_ptr<HyperelasticTetTerm> elastic;
  };

  HyperelasticProblem make_hyperelastic_problem(const RawSimplexMesh<3>              &mesh,
                                                const HyperelasticMaterial           &material,
                                                const HyperelasticBoundaryConditions &conditions,
                                                const HyperelasticLoads              &loads);

  /// The resultant of a nodal load vector (x, y, z per vertex): the vector sum of its nodal forces,
  /// e.g. the weight of the body for gravity (the Euclidean norm of the vector is not a force).
  Eigen::Vector3d resultant_force(const Eigen::VectorXd &nodal_loads);
} // namespace nlmech
