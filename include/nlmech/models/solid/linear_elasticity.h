#pragma once
// Small-strain isotropic linear elasticity on simplex meshes (tetrahedra in 3D, triangles in 2D,
// plane strain), assembled with deal.II finite elements into Trilinos distributed matrices.
// K u = f with K from sigma = lambda tr(eps) I + 2 mu eps (lecture: Hooke's law in Voigt form),
// body force density (gravity = rho g), surface tractions and Dirichlet data by boundary id.

#include <deal.II/base/function.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <map>
#include <memory>
#include <string>

namespace nlmech
{
  struct IsotropicMaterial
  {
    double youngs_modulus = 1; // Pa
    double poissons_ratio = 0; // -
    double density        = 0; // kg/m^3

    double lame_lambda() const;
    double shear_modulus() const;
    /// Throws a clear error for E <= 0 or nu outside (-1, 0.5).
    void check() const;
  };

  struct LinearSolverSettings
  {
    std::string  method             = "direct"; // "direct" or "cg-amg"
    std::string  direct_solver      = "mumps";  // Amesos solver: "mumps" or "klu"
    double       relative_tolerance = 1e-10;
    unsigned int max_iterations     = 5000;
  };

  struct LinearSolveStatistics
  {
    unsigned int iterations        = 0; // 1 for a direct solve
    double       setup_seconds     = 0; // factorisation or AMG set-up
    double       solve_seconds     = 0; // total, including set-up
    double       relative_residual = 0;
  };

  template <int dim>
  class LinearElasticity
  {
  public:
    LinearElasticity(const dealii::parallel::shared::Triangulation<dim> &tria,
                     const IsotropicMaterial &material, unsigned int degree);

    /// Prescribes all displacement components on a boundary id (nullptr: clamped, u = 0).
    void add_dirichlet(unsigned int boundary_id, const dealii::Function<dim> *displacement = nullptr);
    /// Constant traction (Pa) on a boundary id.
    void add_traction(unsigned int boundary_id, const dealii::Tensor<1, dim> &traction);
    /// Body force per unit volume (N/m^3), added to rho * gravity.
    void set_body_force(const dealii::Function<dim> *force_density);
    void set_gravity(const dealii::Tensor<1, dim> &gravity);

    void                  setup();
    void                  assemble();
    LinearSolveStatistics solve(const LinearSolverSettings &settings);

    dealii::types::global_dof_index n_dofs() const { return dof_handler.n_dofs(); }
    /// Mean displacement component over the faces with a boundary id.
    double boundary_mean_displacement(unsigned int boundary_id, unsigned int component) const;
    /// Area (3D) or length (2D) of the faces with a boundary id.
    double boundary_measure(unsigned int boundary_id) const;
    /// L2 norm of u_h - u over the domain.
    double l2_error(const dealii::Function<dim> &exact) const;
    /// Largest |u_h - u| at the mesh vertices.
    double max_vertex_error(const dealii::Function<dim> &exact) const;
    /// Largest displacement magnitude at the vertices.
    double max_displacement() const;

    /// Vertex positions and displacements, one row (x, u) per mesh vertex in vertex order, gathered
    /// on rank 0 (empty elsewhere). Identical ordering serially and under MPI.
    std::vector<std::pair<dealii::Point<dim>, dealii::Tensor<1, dim>>> vertex_displacements() const;

    /// Writes this rank's VTU piece, and (rank 0) the .pvtu record; returns the .pvtu file name.
    std::string write_vtu(const std::string &directory, const std::string &basename) const;

    const dealii::TrilinosWrappers::MPI::Vector  &solution() const { return ghosted_solution; }
    const dealii::DoFHandler<dim>                &dofs() const { return dof_handler; }
    const dealii::TrilinosWrappers::SparseMatrix &stiffness() const { return matrix; }

  private:
    MPI_Comm                                            comm;
    const dealii::parallel::shared::Triangulation<dim> &tria;
    IsotropicMaterial                                   material;
    unsigned int                                        degree;
    dealii::FESystem<dim>                               fe;
    dealii::MappingFE<dim>                              mapping;
    dealii::DoFHandler<dim>                             dof_handler;
    dealii::IndexSet                                    locally_owned, locally_relevant;
    dealii::AffineConstraints<double>                   constraints;
    dealii::TrilinosWrappers::SparseMatrix              matrix;
    dealii::TrilinosWrappers::MPI::Vector               rhs, ghosted_solution;

    std::map<unsigned int, const dealii::Function<dim> *> dirichlet;
    std::map<unsigned int, dealii::Tensor<1, dim>>        tractions;
    const dealii::Function<dim>                          *body_force = nullptr;
    dealii::Tensor<1, dim>                                gravity;
  };
} // namespace nlmech
