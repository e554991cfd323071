// Levenberg-Marquardt by Ceres: one residual block per free unknown (its row of r(q) - g) over
// the free unknowns its row of the tangent couples, all evaluated at once per point by an
// evaluation callback (one internal force and one tangent per trial point, as a hand-written
// loop would do), sparse normal equations factorised by SuiteSparse.
#include <nlmech/solvers/relaxation/levenberg_marquardt.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/multithread_info.h>

#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>

namespace nlmech
{
  namespace
  {
    /// The shared state of all residual blocks at the current point.
    struct RowEvaluator : public ceres::EvaluationCallback
    {
      const EquilibriumSystem                     *system = nullptr;
      const FreeDofMap                            *free   = nullptr;
      Eigen::VectorXd                              g, full;
      std::vector<double>                          x; // the free unknowns (Ceres' parameter memory)
      std::vector<std::size_t>                     free_dofs;
      Eigen::VectorXd                              R;
      Eigen::SparseMatrix<double, Eigen::RowMajor> J;
      bool                                         valid    = false;
      unsigned int                                 tangents = 0;

      void PrepareForEvaluation(const bool evaluate_jacobians, const bool new_point) override
      {
        if (new_point)
          {
            for (std::size_t i = 0; i < free_dofs.size(); ++i)
              full[free_dofs[i]] = x[i];
            valid = system->is_valid(full);
            if (valid)
              {
                R     = free->restrict(system->internal_force(full)) - g;
                valid = R.allFinite();
              }
            J.resize(0, 0);
          }
        if (evaluate_jacobians && valid && J.rows() == 0)
          {
            J = free->restrict(system->tangent(full));
            ++tangents;
          }
      }
    };

    /// Row i of the residual, over the free unknowns in row i of the tangent's pattern.
    class RowResidual : public ceres::CostFunction
    {
    public:
      RowResidual(const RowEvaluator &evaluator, const Eigen::Index row, std::vector<Eigen::Index> columns)
          : evaluator(evaluator)
          , row(row)
          , columns(std::move(columns))
      {
        set_num_residuals(1);
        for (std::size_t k = 0; k < this->columns.size(); ++k)
          mutable_parameter_block_sizes()->push_back(1);
      }

      bool Evaluate(double const *const *, double *residuals, double **jacobians) const override
      {
        if (!evaluator.valid)
          return false; // an inverted element or a non-finite force: Ceres rejects the step
        residuals[0] = evaluator.R[row];
        if (jacobians)
          {
            for (std::size_t k = 0; k < columns.size(); ++k)
              if (jacobians[k])
                jacobians[k][0] = 0;
            // Both the pattern and J are sorted by column.
            std::size_t k = 0;
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(evaluator.J, row); it; ++it)
              {
                while (k < columns.size() && columns[k] < it.col())
                  ++k;
                if (k < columns.size() && columns[k] == it.col() && jacobians[k])
                  jacobians[k][0] = it.value();
              }
          }
        return true;
      }

    private:
      const RowEvaluator       &evaluator;
      Eigen::Index              row;
      std::vector<Eigen::Index> columns;
    };

    /// Stops as soon as |r - g| <= tol |g| (the criterion every method of the comparison shares).
    class ResidualTarget : public ceres::IterationCallback
    {
    public:
      ResidualTarget(const double g_norm, const double tolerance)
          : g_norm(g_norm)
          , tolerance(tolerance)
      {
      }
      ceres::CallbackReturnType operator()(const ceres::IterationSummary &s) override
      {
        return std::sqrt(2 * s.cost) <= tolerance * g_norm ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                                           : ceres::SOLVER_CONTINUE;
      }

    private:
      double g_norm, tolerance;
    };
  } // namespace

  LevenbergMarquardtResult solve_with_levenberg_marquardt(const EquilibriumSystem &system,
                                                          const Eigen::VectorXd &load, Eigen::VectorXd &q,
                                                          const LevenbergMarquardtSettings &settings)
  {
    const auto               start = std::chrono::steady_clock::now();
    LevenbergMarquardtResult result;
    const FreeDofMap         free(system.n_unknowns(), system.fixed());
    for (const auto &f : system.fixed())
      q[f.first] = f.second;
    RowEvaluator evaluator;
    evaluator.system = &system, evaluator.free = &free;
    evaluator.g    = free.restrict(load);
    evaluator.full = q;
    for (std::size_t i = 0; i < system.n_unknowns(); ++i)
      if (!system.fixed().count(i))
        evaluator.free_dofs.push_back(i);
    const Eigen::Index n = Eigen::Index(evaluator.free_dofs.size());
    evaluator.x.resize(n);
    for (Eigen::Index i = 0; i < n; ++i)
      evaluator.x[i] = q[evaluator.free_dofs[i]];
    const double g_norm = evaluator.g.norm();
    AssertThrow(g_norm > 0, dealii::ExcMessage("Levenberg-Marquardt: the target load is zero."));
    // The coupling pattern: the tangent's at the start (a mesh's does not change).
    const Eigen::SparseMatrix<double, Eigen::RowMajor> pattern = free.restrict(system.tangent(q));

    ceres::Problem::Options problem_options;
    problem_options.evaluation_callback     = &evaluator;
    problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    problem_options.enable_fast_removal     = false;
    ceres::Problem problem(problem_options);
    for (Eigen::Index i = 0; i < n; ++i)
      problem.AddParameterBlock(&evaluator.x[i], 1);
    std::vector<double *> blocks;
    for (Eigen::Index i = 0; i < n; ++i)
      {
        std::vector<Eigen::Index> columns;
        blocks.clear();
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(pattern, i); it; ++it)
          columns.push_back(it.col()), blocks.push_back(&evaluator.x[it.col()]);
        problem.AddResidualBlock(new RowResidual(evaluator, i, std::move(columns)), nullptr, blocks);
      }

    ceres::Solver::Options options;
    options.minimizer_type                     = ceres::TRUST_REGION;
    options.trust_region_strategy_type         = ceres::LEVENBERG_MARQUARDT;
    options.linear_solver_type                 = ceres::SPARSE_NORMAL_CHOLESKY;
    options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    options.initial_trust_region_radius        = 1 / settings.initial_damping;
    options.max_num_iterations                 = int(settings.max_iterations);
    options.function_tolerance                 = 0; // only the residual target (and the
    options.gradient_tolerance                 = 0; // iteration limit) end the solve
    options.parameter_tolerance                = 0;
    options.max_num_consecutive_invalid_steps  = 30;
    options.max_solver_time_in_seconds         = settings.max_seconds;
    options.num_threads                        = int(dealii::MultithreadInfo::n_threads());
    options.logging_type                       = ceres::SILENT;
    options.minimizer_progress_to_stdout       = false;
    options.update_state_every_iteration       = true;
    ResidualTarget target(g_norm, settings.relative_tolerance);
    options.callbacks.push_back(&target);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    if (std::getenv("NLMECH_LM_DEBUG"))
      std::cerr << summary.FullReport() << std::endl;

    for (Eigen::Index i = 0; i < n; ++i)
      q[evaluator.free_dofs[i]] = evaluator.x[i];
    const Eigen::VectorXd R = free.restrict(system.internal_force(q)) - evaluator.g;
    // Ceres' iteration 0 is the starting point (it counts it as a successful step).
    result.iterations     = summary.iterations.empty() ? 0u : unsigned(summary.iterations.size() - 1);
    result.factorizations = unsigned(summary.num_linear_solves);
    result.residual       = R.norm() / g_norm;
    result.converged      = std::isfinite(result.residual) && result.residual <= settings.relative_tolerance;
    result.capped         = !result.converged && (summary.termination_type == ceres::NO_CONVERGENCE);
    result.seconds        = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
} // namespace nlmech
