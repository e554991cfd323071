#include <nlmech/models/elastic_constants.h>
#include <nlmech/models/solid/linear_elasticity.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <nlmech/base/atomic_output.h>

#include <filesystem>

namespace nlmech
{
  using namespace dealii;

  double IsotropicMaterial::lame_lambda() const
  {
    return nlmech::lame_lambda(youngs_modulus, poissons_ratio);
  }

  double IsotropicMaterial::shear_modulus() const
  {
    return nlmech::shear_modulus(youngs_modulus, poissons_ratio);
  }

  void IsotropicMaterial::check() const
  {
    AssertThrow(youngs_modulus > 0, ExcMessage("Young's modulus must be positive; it is " +
                                               std::to_string(youngs_modulus) + " Pa."));
    AssertThrow(poissons_ratio < 0.5,
                ExcMessage("Poisson's ratio must be below 0.5 (0.5 is an incompressible material, which a "
                           "displacement-only formulation cannot represent); it is " +
                           std::to_string(poissons_ratio) + "."));
    AssertThrow(poissons_ratio > -1, ExcMessage("Poisson's ratio must be above -1; it is " +
                                                std::to_string(poissons_ratio) + "."));
    AssertThrow(density >= 0, ExcMessage("The density must not be negative."));
  }

  template <int dim>
  LinearElasticity<dim>::LinearElasticity(const parallel::shared::Triangulation<dim> &tria,
                                          const IsotropicMaterial &material, const unsigned int degree)
      : comm(tria.get_communicator())
      , tria(tria)
      , material(material)
      , degree(degree)
      , fe(FE_SimplexP<dim>(degree), dim)
      , mapping(FE_SimplexP<dim>(1))
      , dof_handler(tria)
  {
    material.check();
    AssertThrow(degree == 1 || degree == 2, ExcMessage("The polynomial degree must be 1 or 2."));
  }

  template <int dim>
  void LinearElasticity<dim>::add_dirichlet(const unsigned int boundary_id, const Function<dim> *displacement)
  {
    dirichlet[boundary_id] = displacement;
  }

  template <int dim>
  void LinearElasticity<dim>::add_traction(const unsigned int boundary_id, const Tensor<1, dim> &traction)
  {
    tractions[boundary_id] += traction;
  }

  template <int dim>
  void LinearElasticity<dim>::set_body_force(const Function<dim> *force_density)
  {
    body_force = force_density;
  }

  template <int dim>
  void LinearElasticity<dim>::set_gravity(const Tensor<1, dim> &g)
  {
    gravity = g;
  }

  template <int dim>
  void LinearElasticity<dim>::setup()
  {
    dof_handler.distribute_dofs(fe);
    locally_owned = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant);

    constraints.clear();
    constraints.reinit(locally_relevant);
    const Functions::ZeroFunction<dim> zero(dim);
    for (const auto &d : dirichlet)
      VectorTools::interpolate_boundary_values(
          mapping, dof_handler, d.first, d.second ? *d.second : static_cast<const Function<dim> &>(zero),
          constraints);
    constraints.close();

    DynamicSparsityPattern dsp(locally_relevant);
    DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
    SparsityTools::distribute_sparsity_pattern(dsp, locally_owned, comm, locally_relevant);
    matrix.reinit(locally_owned, locally_owned, dsp, comm);
    rhs.reinit(locally_owned, comm);
    ghosted_solution.reinit(locally_owned, locally_relevant, comm);
  }

  template <int dim>
  void LinearElasticity<dim>::assemble()
  {
    matrix = 0;
    rhs    = 0;
    const QGaussSimplex<dim>     quadrature(degree + 1);
    const QGaussSimplex<dim - 1> face_quadrature(degree + 1);
    FEValues<dim>                fe_values(mapping, fe, quadrature,
                                           update_values | update_gradients | update_quadrature_points | update_JxW_values);
    FEFaceValues<dim> fe_face_values(mapping, fe, face_quadrature, update_values | update_JxW_values);

    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   cell_matrix(n, n);
    Vector<double>                       cell_rhs(n);
    std::vector<types::global_dof_index> dof_indices(n);
    const FEValuesExtractors::Vector     u(0);
    const double                         lambda = material.lame_lambda(), mu = material.shear_modulus();
    std::vector<SymmetricTensor<2, dim>> eps(n);
    std::vector<double>                  div(n);
    std::vector<Tensor<1, dim>>          phi(n);
    Vector<double>                       force_value(dim);

    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          cell_matrix = 0;
          cell_rhs    = 0;
          for (const unsigned int q : fe_values.quadrature_point_indices())
            {
              for (unsigned int i = 0; i < n; ++i)
                {
                  eps[i] = fe_values[u].symmetric_gradient(i, q);
                  div[i] = trace(eps[i]);
                  phi[i] = fe_values[u].value(i, q);
                }
              Tensor<1, dim> f = material.density * gravity;
              if (body_force)
                {
                  body_force->vector_value(fe_values.quadrature_point(q), force_value);
                  for (unsigned int d = 0; d < dim; ++d)
                    f[d] += force_value[d];
                }
              const double JxW = fe_values.JxW(q);
              for (unsigned int i = 0; i < n; ++i)
                {
                  for (unsigned int j = 0; j <= i; ++j)
                    cell_matrix(i, j) += (lambda * div[i] * div[j] + 2 * mu * (eps[i] * eps[j])) * JxW;
                  cell_rhs(i) += phi[i] * f * JxW;
                }
            }
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = i + 1; j < n; ++j)
              cell_matrix(i, j) = cell_matrix(j, i);

          if (!tractions.empty())
            for (const unsigned int face : cell->face_indices())
              if (cell->face(face)->at_boundary())
                {
                  const auto t = tractions.find(cell->face(face)->boundary_id());
                  if (t == tractions.end())
                    continue;
                  fe_face_values.reinit(cell, face);
                  for (const unsigned int q : fe_face_values.quadrature_point_indices())
                    for (unsigned int i = 0; i < n; ++i)
                      cell_rhs(i) += fe_face_values[u].value(i, q) * t->second * fe_face_values.JxW(q);
                }

          cell->get_dof_indices(dof_indices);
          constraints.distribute_local_to_global(cell_matrix, cell_rhs, dof_indices, matrix, rhs);
        }
    matrix.compress(VectorOperation::add);
    rhs.compress(VectorOperation::add);
  }

  template <int dim>
  LinearSolveStatistics LinearElasticity<dim>::solve(const LinearSolverSettings &settings)
  {
    LinearSolveStatistics         stats;
    TrilinosWrappers::MPI::Vector solution(locally_owned, comm);
    Timer                         timer(comm, true);
    const double                  rhs_norm = rhs.l2_norm();
    if (settings.method == "direct")
      {
        AssertThrow(settings.direct_solver == "mumps" || settings.direct_solver == "klu",
                    ExcMessage("Unknown direct solver <" + settings.direct_solver + ">."));
        SolverControl                                  control(1, 0);
        TrilinosWrappers::SolverDirect::AdditionalData data(
            false, settings.direct_solver == "mumps" ? "Amesos_Mumps" : "Amesos_Klu");
        TrilinosWrappers::SolverDirect solver(control, data);
        solver.initialize(matrix);
        stats.setup_seconds = timer.wall_time();
        solver.solve(solution, rhs);
        stats.iterations = 1;
      }
    else if (settings.method == "cg-amg")
      {
        TrilinosWrappers::PreconditionAMG                 amg;
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        data.elliptic              = true;
        data.higher_order_elements = degree > 1;
        data.smoother_sweeps       = 2;
        data.aggregation_threshold = 0.02;
        DoFTools::extract_constant_modes(dof_handler, ComponentMask(dim, true), data.constant_modes);
        amg.initialize(matrix, data);
        stats.setup_seconds = timer.wall_time();
        SolverControl control(settings.max_iterations, settings.relative_tolerance * rhs_norm);
        SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
        try
          {
            cg.solve(matrix, solution, rhs, amg);
          }
        catch (const SolverControl::NoConvergence &e)
          {
            AssertThrow(false, ExcMessage("CG + AMG did not converge in " + std::to_string(e.last_step) +
                                          " iterations (residual " + std::to_string(e.last_residual) +
                                          "). Raise `Max iterations` or use `Method = direct`."));
          }
        stats.iterations = control.last_step();
      }
    else
      AssertThrow(false, ExcMessage("Unknown linear solver method <" + settings.method + ">."));
    stats.solve_seconds = timer.wall_time();

    TrilinosWrappers::MPI::Vector residual(locally_owned, comm);
    matrix.vmult(residual, solution);
    residual -= rhs;
    stats.relative_residual = rhs_norm > 0 ? residual.l2_norm() / rhs_norm : residual.l2_norm();
    constraints.distribute(solution);
    ghosted_solution = solution;
    AssertThrow(std::isfinite(solution.l2_norm()),
                ExcMessage("The linear solve produced NaN or inf: the system is singular. Check that the "
                           "boundary conditions prevent rigid-body motion."));
    return stats;
  }

  template <int dim>
  double LinearElasticity<dim>::boundary_measure(const unsigned int boundary_id) const
  {
    const QGaussSimplex<dim - 1> face_quadrature(degree + 1);
    FEFaceValues<dim>            fe_face_values(mapping, fe, face_quadrature, update_JxW_values);
    double                       measure = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int face : cell->face_indices())
          if (cell->face(face)->at_boundary() && cell->face(face)->boundary_id() == boundary_id)
            {
              fe_face_values.reinit(cell, face);
              for (const unsigned int q : fe_face_values.quadrature_point_indices())
                measure += fe_face_values.JxW(q);
            }
    return Utilities::MPI::sum(measure, comm);
  }

  template <int dim>
  double LinearElasticity<dim>::boundary_mean_displacement(const unsigned int boundary_id,
                                                           const unsigned int component) const
  {
    const QGaussSimplex<dim - 1> face_quadrature(degree + 1);
    FEFaceValues<dim> fe_face_values(mapping, fe, face_quadrature, update_values | update_JxW_values);
    std::vector<Vector<double>> values(face_quadrature.size(), Vector<double>(dim));
    double                      integral = 0, measure = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int face : cell->face_indices())
          if (cell->face(face)->at_boundary() && cell->face(face)->boundary_id() == boundary_id)
            {
              fe_face_values.reinit(cell, face);
              fe_face_values.get_function_values(ghosted_solution, values);
              for (const unsigned int q : fe_face_values.quadrature_point_indices())
                {
                  integral += values[q][component] * fe_face_values.JxW(q);
                  measure += fe_face_values.JxW(q);
                }
            }
    integral = Utilities::MPI::sum(integral, comm);
    measure  = Utilities::MPI::sum(measure, comm);
    AssertThrow(measure > 0, ExcMessage("The boundary group used for a mean displacement has no faces."));
    return integral / measure;
  }

  template <int dim>
  double LinearElasticity<dim>::l2_error(const Function<dim> &exact) const
  {
    Vector<float> cellwise(tria.n_active_cells());
    VectorTools::integrate_difference(mapping, dof_handler, ghosted_solution, exact, cellwise,
                                      QGaussSimplex<dim>(degree + 2), VectorTools::L2_norm);
    return VectorTools::compute_global_error(tria, cellwise, VectorTools::L2_norm);
  }

  template <int dim>
  double LinearElasticity<dim>::max_vertex_error(const Function<dim> &exact) const
  {
    double                               worst = 0;
    Vector<double>                       exact_value(dim);
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dof_indices);
          for (const unsigned int v : cell->vertex_indices())
            {
              exact.vector_value(cell->vertex(v), exact_value);
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const auto i = dof_indices[fe.component_to_system_index(d, v)];
                  worst        = std::max(worst, std::abs(ghosted_solution[i] - exact_value[d]));
                }
            }
        }
    return Utilities::MPI::max(worst, comm);
  }

  template <int dim>
  double LinearElasticity<dim>::max_displacement() const
  {
    double                               largest = 0;
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dof_indices);
          for (const unsigned int v : cell->vertex_indices())
            {
              double norm2 = 0;
              for (unsigned int d = 0; d < dim; ++d)
                norm2 += std::pow(ghosted_solution[dof_indices[fe.component_to_system_index(d, v)]], 2);
              largest = std::max(largest, std::sqrt(norm2));
            }
        }
    return Utilities::MPI::max(largest, comm);
  }

  template <int dim>
  std::vector<std::pair<Point<dim>, Tensor<1, dim>>> LinearElasticity<dim>::vertex_displacements() const
  {
    std::vector<double>                  local; // (vertex index, u_0..u_dim-1) records
    std::vector<bool>                    seen(tria.n_vertices(), false);
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dof_indices);
          for (const unsigned int v : cell->vertex_indices())
            if (!seen[cell->vertex_index(v)])
              {
                seen[cell->vertex_index(v)] = true;
                local.push_back(cell->vertex_index(v));
                for (unsigned int d = 0; d < dim; ++d)
                  local.push_back(ghosted_solution[dof_indices[fe.component_to_system_index(d, v)]]);
              }
        }
    const auto                                         gathered = Utilities::MPI::gather(comm, local, 0);
    std::vector<std::pair<Point<dim>, Tensor<1, dim>>> result;
    if (Utilities::MPI::this_mpi_process(comm) != 0)
      return result;
    const auto                 &vertices = tria.get_vertices();
    std::vector<bool>           filled(vertices.size(), false);
    std::vector<Tensor<1, dim>> u(vertices.size());
    for (const auto &records : gathered)
      for (std::size_t r = 0; r < records.size(); r += dim + 1)
        {
          const auto v = static_cast<std::size_t>(records[r]);
          filled[v]    = true;
          for (unsigned int d = 0; d < dim; ++d)
            u[v][d] = records[r + 1 + d];
        }
    for (std::size_t v = 0; v < vertices.size(); ++v)
      if (filled[v])
        result.emplace_back(vertices[v], u[v]);
    return result;
  }

  template <int dim>
  std::string LinearElasticity<dim>::write_vtu(const std::string &directory,
                                               const std::string &basename) const
  {
    DataOut<dim> data_out;
    data_out.attach_dof_handler(dof_handler);
    const std::vector<std::string>                                              names(dim, "displacement");
    const std::vector<DataComponentInterpretation::DataComponentInterpretation> interpretation(
        dim, DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(ghosted_solution, names, DataOut<dim>::type_dof_data, interpretation);

    // Cell-wise von Mises stress at the centroid (Pa) and the MPI rank owning the cell.
    Vector<float> von_mises(tria.n_active_cells()), rank(tria.n_active_cells());
    {
      std::vector<Point<dim>> centre(1);
      for (unsigned int d = 0; d < dim; ++d)
        centre[0][d] = 1.0 / (dim + 1);
      const Quadrature<dim>                    q(centre);
      FEValues<dim>                            fe_values(mapping, fe, q, update_gradients);
      std::vector<std::vector<Tensor<1, dim>>> gradients(1, std::vector<Tensor<1, dim>>(dim));
      const double                             lambda = material.lame_lambda(), mu = material.shear_modulus();
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            fe_values.get_function_gradients(ghosted_solution, gradients);
            SymmetricTensor<2, dim> eps;
            for (unsigned int a = 0; a < dim; ++a)
              for (unsigned int b = a; b < dim; ++b)
                eps[a][b] = 0.5 * (gradients[0][a][b] + gradients[0][b][a]);
            SymmetricTensor<2, dim> sigma = lambda * trace(eps) * unit_symmetric_tensor<dim>() + 2 * mu * eps;
            const auto              dev   = deviator(sigma);
            von_mises(cell->active_cell_index()) = std::sqrt(1.5 * (dev * dev));
            rank(cell->active_cell_index())      = cell->subdomain_id();
          }
    }
    data_out.add_data_vector(von_mises, "von_mises_stress", DataOut<dim>::type_cell_data);
    data_out.add_data_vector(rank, "mpi_rank", DataOut<dim>::type_cell_data);
    data_out.build_patches(mapping, degree);

    const unsigned int this_rank = Utilities::MPI::this_mpi_process(comm);
    const unsigned int n_ranks   = Utilities::MPI::n_mpi_processes(comm);
    auto               piece = [&](unsigned int r) { return basename + "." + std::to_string(r) + ".vtu"; };
    {
      AtomicFile file((std::filesystem::path(directory) / piece(this_rank)).string());
      data_out.write_vtu(file.stream());
      file.commit();
    }
    const std::string record = basename + ".pvtu";
    if (this_rank == 0)
      {
        std::vector<std::string> pieces;
        for (unsigned int r = 0; r < n_ranks; ++r)
          pieces.push_back(piece(r));
        AtomicFile file((std::filesystem::path(directory) / record).string());
        data_out.write_pvtu_record(file.stream(), pieces);
        file.commit();
      }
    return record;
  }

  template class LinearElasticity<2>;
  template class LinearElasticity<3>;
} // namespace nlmech
