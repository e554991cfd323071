#pragma once
// Multi-target inverse design (ANM paper, section 5.2): further targets x_t with their loads g_t,
// each given by a target mesh or a displacement of the main target, and one rest shape for all of
// them by the reduced basis of the individual rest shapes' series, checked by forward solves.

#include <deal.II/base/function_parser.h>
#include <deal.II/base/parameter_handler.h>

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/models/solid/inverse_hyperelastic.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/solvers/anm/anm_solver.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace nlmech
{
  class RunContext;

  /// A further target x_t and its loads g_t (subsection `Load case N`, N = 2..max_cases).
  struct LoadCase
  {
    std::string                                                    target_mesh;  // file, or empty
    std::string                                                    displacement; // u(x), or empty
    double                                                         scale = 1;
    std::vector<std::pair<dealii::Point<3>, dealii::Tensor<1, 3>>> point_loads;

    static constexpr unsigned int max_cases = 4;
    static void                   declare_parameters(dealii::ParameterHandler &prm);
    /// The load cases that differ from the main one (each checked), in order.
    static std::vector<LoadCase> parse_parameters(dealii::ParameterHandler &prm);
  };

  /// What the multi-target design needs of the scene.
  struct MultiTargetProblem
  {
    const std::vector<LoadCase> &load_cases;
    const MeshParameters        &mesh;
    const HyperelasticLoads     &loads;
    const HyperelasticMaterial  &material;
    const AnmSettings           &anm;
  };

  /// The vertex positions of a mesh as one vector.
  Eigen::VectorXd target_positions(const RawSimplexMesh<3> &mesh);

  /// u(x) from three muparser expressions separated by `;`, parsed and evaluated once here so that
  /// a bad expression is one clear error.
  std::unique_ptr<dealii::FunctionParser<3>> displacement_function(const std::string &text,
                                                                   const std::string &name);

  /// The target mesh of a load case: same vertices and tetrahedra as the main target, supports
  /// in place (the single rest shape holds them where every target has them).
  RawSimplexMesh<3> load_case_target(const LoadCase &c, const RawSimplexMesh<3> &main,
                                     const MeshParameters            &mesh,
                                     const std::vector<unsigned int> &support_vertices,
                                     const std::string               &name);

  /// One rest shape for the main target and the further load cases; multi_target.csv and figures.
  /// The forward solution of the main case from that rest shape goes to `forward_of_case_1` (the
  /// scene's round trip, not solved twice). Timed as "multi-target: inverse solves" (the further
  /// targets' ANM, every series at its solution, the reduced basis) and "...: forward checks".
  Eigen::VectorXd multi_target_rest_shape(RunContext &context, const MultiTargetProblem &p,
                                          const RawSimplexMesh<3>         &target_mesh,
                                          const InverseHyperelasticSystem &system,
                                          const Eigen::VectorXd &load, const Eigen::VectorXd &rest_for_case_1,
                                          const HyperelasticBoundaryConditions &conditions,
                                          const std::vector<unsigned int>      &support_vertices,
                                          Eigen::VectorXd                      *forward_of_case_1 = nullptr);
} // namespace nlmech
