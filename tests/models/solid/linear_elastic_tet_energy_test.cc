// Tests source/models/solid/linear_elastic_tet_energy.cc and the energy-term machinery:
// finite-difference checks of gradient and Hessian, the AD element Hessian against deal.II's
// finite-element stiffness, and Newton on the Model against the deal.II/Trilinos solve.
#include <deal.II/distributed/shared_tria.h>

#include <nlmech/models/solid/linear_elastic_tet_energy.h>
#include <nlmech/models/solid/linear_elasticity.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <gtest/gtest.h>

#include <random>

using namespace dealii;
using namespace nlmech;

namespace
{
  const IsotropicMaterial steel{2e11, 0.3, 7800};

  RawSimplexMesh<3> cantilever_mesh(double h)
  {
    MeshOptions options{std::string(NLMECH_SOURCE_DIR) + "/meshes/cantilever.geo", h, {}, ""};
    return read_simplex_mesh<3>(options, 3);
  }
} // namespace

TEST(LinearElasticTetEnergy, DerivativesMatchFiniteDifferences)
{
  const RawSimplexMesh<3>    mesh = cantilever_mesh(0.1);
  const IsotropicMaterial    soft{1e3, 0.3, 1};
  const LinearElasticTetTerm term("elastic", LinearElasticTetElements(mesh.vertices, mesh.cells, soft));
  std::mt19937               random(7);
  std::uniform_real_distribution<double> uniform(-0.01, 0.01);
  Eigen::VectorXd                        x(3 * mesh.vertices.size());
  for (auto &v : x)
    v = uniform(random);
  const DerivativeCheck check = check_derivatives(term, x, 1e-6);
  EXPECT_LT(check.gradient_error, 1e-7);
  // The energy is quadratic: central differences of the gradient are exact up to round-off.
  EXPECT_LT(check.hessian_error, 1e-7);
}

TEST(LinearElasticTetEnergy, GravityTermDerivatives)
{
  Eigen::VectorXd         force = Eigen::VectorXd::LinSpaced(9, -1.0, 2.0);
  const ConstantForceTerm term("gravity", force);
  Eigen::VectorXd         x     = Eigen::VectorXd::LinSpaced(9, 0.3, 0.7);
  const DerivativeCheck   check = check_derivatives(term, x);
  EXPECT_LT(check.gradient_error, 1e-8);
  EXPECT_LT(check.hessian_error, 1e-12);
}

TEST(LinearElasticTetEnergy, ElementHessianEqualsDealIIStiffness)
{
  // One distorted tetrahedron: AD Hessian of the energy vs deal.II's P1 stiffness matrix.
  const std::vector<Point<3>> vertices = {{0.1, 0, 0}, {1.2, 0.1, 0}, {0.2, 0.9, 0.1}, {0.3, 0.2, 1.1}};
  const std::vector<std::vector<unsigned int>> cells = {{0, 1, 2, 3}};
  const LinearElasticTetTerm term("elastic", LinearElasticTetElements(vertices, cells, steel));
  const auto                 ad = term.local_hessian(Eigen::VectorXd::Zero(12), 0);

  parallel::shared::Triangulation<3> tria(MPI_COMM_SELF);
  std::vector<CellData<3>>           cell_data(1);
  cell_data[0].vertices = cells[0];
  tria.create_triangulation(vertices, cell_data, SubCellData());
  LinearElasticity<3> problem(tria, steel, 1);
  problem.setup();
  problem.assemble();
  const auto                          &fe   = problem.dofs().get_fe();
  const auto                           cell = problem.dofs().begin_active();
  std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
  cell->get_dof_indices(dofs);
  double largest = 0, worst = 0;
  for (unsigned int k = 0; k < 12; ++k)
    for (unsigned int l = 0; l < 12; ++l)
      {
        const auto   ck = fe.system_to_component_index(k), cl = fe.system_to_component_index(l);
        const double dealii_entry = problem.stiffness().el(dofs[k], dofs[l]);
        const double ad_entry     = ad[(3 * ck.second + ck.first) * 12 + 3 * cl.second + cl.first];
        largest                   = std::max(largest, std::abs(dealii_entry));
        worst                     = std::max(worst, std::abs(dealii_entry - ad_entry));
      }
  EXPECT_LT(worst / largest, 1e-12);
}

TEST(NewtonSolver, ModelMatchesDealIIOnGravityCantilever)
{
  // The same P1 problem two independent ways: AD energy terms + Newton/CHOLMOD on the Model, and
  // deal.II FE assembly + Trilinos/MUMPS. Lumped and consistent gravity loads coincide for P1 tets.
  const double            h    = 0.05;
  const RawSimplexMesh<3> mesh = cantilever_mesh(h);
  const Tensor<1, 3>      gravity({0, 0, -9.81});
  const Model             model  = make_linear_elastic_tet_model(mesh, steel, gravity, {"clamped"});
  Eigen::VectorXd         x      = Eigen::VectorXd::Zero(model.n_unknowns());
  const NewtonResult      result = minimize_with_newton(model, x);
  // A quadratic energy: one full Newton step solves it (a second may refine round-off).
  EXPECT_LE(result.iterations, 2u);
  EXPECT_EQ(result.factorizations, result.iterations);

  parallel::shared::Triangulation<3> tria(MPI_COMM_SELF);
  MeshOptions         options{std::string(NLMECH_SOURCE_DIR) + "/meshes/cantilever.geo", h, {}, ""};
  const MeshGroups    groups = load_gmsh_mesh(options, tria);
  LinearElasticity<3> problem(tria, steel, 1);
  problem.add_dirichlet(groups.boundary_id("clamped"));
  problem.set_gravity(gravity);
  problem.setup();
  problem.assemble();
  problem.solve(LinearSolverSettings());
  const auto rows = problem.vertex_displacements();
  ASSERT_EQ(rows.size(), mesh.vertices.size());
  double largest = 0, worst = 0;
  for (std::size_t v = 0; v < rows.size(); ++v)
    {
      EXPECT_LT(rows[v].first.distance(mesh.vertices[v]), 1e-14);
      for (int d = 0; d < 3; ++d)
        {
          largest = std::max(largest, std::abs(rows[v].second[d]));
          worst   = std::max(worst, std::abs(rows[v].second[d] - x[3 * v + d]));
        }
    }
  EXPECT_GT(largest, 1e-7);
  EXPECT_LT(worst / largest, 1e-8);
}

TEST(NewtonSolver, DivergenceIsReportedClearly)
{
  // A term with no minimum (linear in x, no stiffness): Newton cannot converge.
  Model           model(2);
  Eigen::VectorXd force(2);
  force << 1.0, 0.0;
  model.add_term(std::make_shared<ConstantForceTerm>("push", force));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  try
    {
      minimize_with_newton(model, x);
      FAIL() << "expected an exception";
    }
  catch (const ExceptionBase &e)
    {
      std::ostringstream s;
      e.print_info(s);
      EXPECT_TRUE(s.str().find("Newton") != std::string::npos) << s.str();
    }
}
