#include <nlmech/solvers/newton/newton_solver.h>

#include <nlmech/base/serial_blas.h>
#include <nlmech/base/threads.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

namespace nlmech
{
  void NewtonSettings::declare_parameters(dealii::ParameterHandler &prm, const NewtonSettings &defaults)
  {
    using dealii::Patterns::Integer;
    prm.declare_entry("Newton max iterations", std::to_string(defaults.max_iterations), Integer(1),
                      "Newton iterations before a solve counts as failed [-].");
    prm.declare_entry("Newton max line search", std::to_string(defaults.max_line_search), Integer(1),
                      "Step halvings of Newton's line search before it gives up [-].");
  }

  void NewtonSettings::declare_parameters(dealii::ParameterHandler &prm)
  {
    declare_parameters(prm, NewtonSettings());
  }

  void NewtonSettings::parse_parameters(const dealii::ParameterHandler &prm)
  {
    max_iterations  = prm.get_integer("Newton max iterations");
    max_line_search = prm.get_integer("Newton max line search");
  }

  // ---------------------------------------------------------------------------------------------

  struct NewtonSystem::Factorization
  {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholesky;
    long                                                     analysed_nonzeros = -1;
    std::vector<int>                                         analysed_outer, analysed_inner;
  };

  Eigen::SparseMatrix<double> NewtonSystem::free_matrix(const Eigen::SparseMatrix<double> &H,
                                                        double                            *scale) const
  {
    const std::size_t m = free_dofs.size();
    Triplets          free_triplets;
    // Explicit diagonal entries keep the sparsity pattern fixed when a shift is added.
    for (std::size_t k = 0; k < m; ++k)
      free_triplets.emplace_back(k, k, 0.0);
    for (int col = 0; col < H.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(H, col); it; ++it)
        if (free_index[it.row()] >= 0 && free_index[it.col()] >= 0)
          {
            free_triplets.emplace_back(free_index[it.row()], free_index[it.col()], it.value());
            if (scale && it.row() == it.col())
              *scale = std::max(*scale, std::abs(it.value()));
          }
    Eigen::SparseMatrix<double> Hf(m, m);
    Hf.setFromTriplets(free_triplets.begin(), free_triplets.end());
    Hf.makeCompressed();
    return Hf;
  }

  const Eigen::SparseMatrix<double> &NewtonSystem::projected_hessian()
  {
    if (!has_projected)
      projected = free_matrix(model->projected_hessian(*state), nullptr), has_projected = true;
    return projected;
  }

  bool NewtonSystem::solve(const Eigen::SparseMatrix<double> &H, const double shift,
                           const Eigen::VectorXd &metric)
  {
    const std::size_t           m = free_dofs.size();
    Eigen::SparseMatrix<double> A = H;
    if (shift > 0)
      for (std::size_t k = 0; k < m; ++k)
        A.coeffRef(k, k) += shift * (metric.size() ? metric[free_dofs[k]] : 1.0);
    // The symbolic analysis is reused while the Hessian's pattern does not change (the whole
    // pattern is compared: contact problems trade pairs and can keep the count of nonzeros).
    serialise_openmp(); // CHOLMOD's OpenMP teams, on whichever thread this solve runs
    Factorization &f = *factorization;
    const bool     same_pattern =
        A.nonZeros() == f.analysed_nonzeros && A.outerSize() + 1 == Eigen::Index(f.analysed_outer.size()) &&
        std::equal(f.analysed_outer.begin(), f.analysed_outer.end(), A.outerIndexPtr()) &&
        std::equal(f.analysed_inner.begin(), f.analysed_inner.end(), A.innerIndexPtr());
    if (!same_pattern)
      {
        f.cholesky.analyzePattern(A);
        f.analysed_nonzeros = A.nonZeros();
        f.analysed_outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
        f.analysed_inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
      }
    {
      const auto blas = lock_serial_blas();
      f.cholesky.factorize(A);
      ++factorizations;
      if (f.cholesky.info() != Eigen::Success)
        return false;
      direction = f.cholesky.solve(-gradient);
    }
    if (std::getenv("NLMECH_NEWTON_DEBUG") && !(direction.dot(gradient) < 0))
      std::fprintf(stderr, "newton: shift %.3e factorised but gives no descent (dx.g = %.3e, |dx| = %.3e)\n",
                   shift, direction.dot(gradient), direction.norm());
    return direction.dot(gradient) < 0;
  }

  // ---------------------------------------------------------------------------------------------

  void DiagonalShift::start()
  {
    shift = previous = 0;
    short_steps      = 0;
  }

  HessianRegularization::Outcome DiagonalShift::shift_until_descent(NewtonSystem                      &system,
                                                                    const Eigen::SparseMatrix<double> &H,
                                                                    const double                       s0)
  {
    scale = system.diagonal_scale();
    floor = 1e-8 * (scale > 0 ? scale : 1.0);
    shift = s0;
    for (int attempt = 0;; ++attempt)
      {
        if (system.solve(H, shift, settings.metric))
          break;
        // At a numerically stationary point no shift gives descent (dx.g rounds to >= 0).
        if (attempt >= 20 && system.gradient_norm() <= 1e-6 * system.initial_gradient_norm())
          return Outcome::stationary;
        if (attempt >= 20)
          {
            bool finite = true;
            for (Eigen::Index k = 0; k < H.nonZeros(); ++k)
              finite = finite && std::isfinite(H.valuePtr()[k]);
            AssertThrow(false, dealii::ExcMessage(finite ? "Newton: the Hessian could not be made positive "
                                                           "definite (shift " +
                                                               std::to_string(shift) + ")."
                                                         : "Newton: the Hessian has non-finite entries."));
          }
        shift = (shift == 0 ? floor : 10 * shift);
      }
    previous = shift;
    return Outcome::direction;
  }

  HessianRegularization::Outcome DiagonalShift::find_direction(NewtonSystem &system)
  {
    const double f = 1e-8 * (system.diagonal_scale() > 0 ? system.diagonal_scale() : 1.0);
    return shift_until_descent(system, system.exact_hessian(), previous / 10 > f ? previous / 10 : 0);
  }

  void DiagonalShift::step_accepted(const double bound)
  {
    // Two short (bounded) steps in a row: damp the near-null directions harder.
    short_steps = bound < 0.5 ? short_steps + 1 : 0;
    if (settings.grow_on_short_steps && short_steps >= 2)
      previous = std::min(100 * std::max(shift, floor), 1e3 * std::max(scale, 1e-300));
  }

  HessianRegularization::Outcome ProjectedElementHessians::find_direction(NewtonSystem &system)
  {
    projected = false;
    if (system.solve(system.exact_hessian(), 0))
      return Outcome::direction;
    projected = true;
    return fallback.shift_until_descent(system, system.projected_hessian(), 0);
  }

  // ---------------------------------------------------------------------------------------------

  NewtonSolver::NewtonSolver(NewtonSettings                         settings_in,
                             std::shared_ptr<HessianRegularization> regularization_in,
                             std::shared_ptr<const StepBound>       step_bound_in)
      : settings(std::move(settings_in))
      , regularization(regularization_in ? std::move(regularization_in) : std::make_shared<DiagonalShift>())
      , step_bound(step_bound_in ? std::move(step_bound_in) : std::make_shared<ModelSafeStep>())
  {
  }

  NewtonResult NewtonSolver::minimize(const Model &model, Eigen::VectorXd &x)
  {
    const std::size_t n = model.n_unknowns();
    AssertThrow(std::size_t(x.size()) == n, dealii::ExcDimensionMismatch(x.size(), n));
    for (const auto &f : model.fixed())
      x[f.first] = f.second;
    AssertThrow(model.is_valid(x), dealii::ExcMessage("Newton: the initial state is not valid."));

    NewtonSystem system;
    system.model = &model;
    system.state = &x;
    system.free_index.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i)
      if (!model.is_fixed(i))
        {
          system.free_index[i] = system.free_dofs.size();
          system.free_dofs.push_back(i);
        }
    const std::size_t m                            = system.free_dofs.size();
    system.factorization                           = std::make_shared<NewtonSystem::Factorization>();
    system.factorization->cholesky.cholmod().print = 0; // silent: "not positive definite" is handled

    auto free_gradient = [&](const Eigen::VectorXd &state) {
      const Eigen::VectorXd g = model.gradient(state);
      Eigen::VectorXd       gf(m);
      for (std::size_t k = 0; k < m; ++k)
        gf[k] = g[system.free_dofs[k]];
      return gf;
    };
    auto finish = [&](NewtonResult &result) {
      result.factorizations = system.factorizations;
      return result;
    };

    NewtonResult     result;
    double           energy = model.energy(x);
    Eigen::VectorXd &g      = system.gradient;
    g                       = free_gradient(x);
    const double g0         = g.norm();
    system.initial_norm     = g0;
    regularization->start();

    double previous_norm = std::numeric_limits<double>::infinity();
    for (result.iterations = 0;; ++result.iterations)
      {
        result.gradient_norm = g.norm();
        result.energy        = energy;
        if (result.gradient_norm <= std::max(settings.absolute_tolerance, settings.relative_tolerance * g0))
          return finish(result);
        if (result.gradient_norm <= settings.stagnation_tolerance &&
            result.gradient_norm > 0.5 * previous_norm)
          return finish(result);
        previous_norm = result.gradient_norm;
        AssertThrow(result.iterations < settings.max_iterations,
                    dealii::ExcMessage("Newton did not converge in " +
                                       std::to_string(settings.max_iterations) +
                                       " iterations (gradient norm " + std::to_string(result.gradient_norm) +
                                       ", started at " + std::to_string(g0) + ")."));

        system.diagonal      = 0;
        system.exact         = system.free_matrix(model.hessian(x), &system.diagonal);
        system.has_projected = false;
        if (regularization->find_direction(system) == HessianRegularization::Outcome::stationary)
          return finish(result);
        const Eigen::VectorXd &dx_free   = system.direction;
        const bool             projected = regularization->model_stiffer_than_energy();

        Eigen::VectorXd dx = Eigen::VectorXd::Zero(n);
        for (std::size_t k = 0; k < m; ++k)
          dx[system.free_dofs[k]] = dx_free[k];
        const double safe         = step_bound->largest_fraction(model, x, dx); // 1: the full step
        double       alpha        = safe < 1.0 ? 0.9 * safe : 1.0;
        const double slope        = g.dot(dx_free);
        const double start_energy = energy;
        bool         accepted     = false;
        for (unsigned int ls = 0; ls < settings.max_line_search; ++ls, alpha *= 0.5)
          {
            const Eigen::VectorXd trial = x + alpha * dx;
            if (!model.is_valid(trial))
              continue;
            const double trial_energy = model.energy(trial);
            AssertThrow(
                std::isfinite(trial_energy),
                dealii::ExcMessage("Newton: the energy is not finite along the step; the model may have no "
                                   "minimum (missing boundary conditions?)."));
            // Armijo, with a round-off allowance once the energy stagnates at machine precision.
            if (trial_energy <= energy + 1e-4 * alpha * slope + 1e-14 * std::abs(energy))
              {
                x        = trial;
                energy   = trial_energy;
                accepted = true;
                if (settings.on_accepted)
                  settings.on_accepted(x);
                break;
              }
          }
        // A full step on a model stiffer than the energy may be too short: along directions of
        // negative curvature the projection makes the model stiffer than the energy. Extend it
        // (doubling) while the energy keeps falling by Armijo's rule.
        if (accepted && projected && alpha == 1.0)
          {
            const Eigen::VectorXd base = x - dx;
            for (double t = 2; t <= 64; t *= 2)
              {
                const Eigen::VectorXd longer = base + t * dx;
                if (step_bound->largest_fraction(model, base, t * dx) < 1.0 || !model.is_valid(longer))
                  break;
                const double longer_energy = model.energy(longer);
                if (!(longer_energy < energy && longer_energy <= start_energy + 1e-4 * t * slope))
                  break;
                x = longer, energy = longer_energy, alpha = t;
                if (settings.on_accepted)
                  settings.on_accepted(x);
              }
          }
        // No decrease at round-off level: the gradient is as small as double precision allows.
        if (!accepted && g.norm() <= 1e-8 * g0)
          return finish(result);
        if (std::getenv("NLMECH_NEWTON_DEBUG"))
          {
            Eigen::Index largest;
            dx.cwiseAbs().maxCoeff(&largest);
            std::fprintf(
                stderr,
                "newton it %3u energy %.12e |g| %.3e safe %.3e alpha %.3e shift %.2e%s |dx| %.3e (largest: "
                "unknown %ld)\n",
                result.iterations, energy, g.norm(), safe, accepted ? alpha : 0.0,
                regularization->last_shift(), projected ? " (projected)" : "", dx.norm(), long(largest));
          }
        AssertThrow(accepted, dealii::ExcMessage("Newton: the line search found no decrease (gradient norm " +
                                                 std::to_string(g.norm()) + ")."));
        g = free_gradient(x);
        AssertThrow(g.allFinite(),
                    dealii::ExcMessage("Newton: the gradient is not finite at an accepted state "
                                       "(energy " +
                                       std::to_string(energy) + ")."));
        if (settings.converged && settings.converged(x, g.norm(), g0))
          {
            ++result.iterations;
            result.gradient_norm = g.norm();
            result.energy        = energy;
            return finish(result);
          }
        regularization->step_accepted(safe);
        if (settings.step_tolerance > 0 && alpha == 1.0 &&
            dx.lpNorm<Eigen::Infinity>() <= settings.step_tolerance)
          {
            ++result.iterations;
            result.gradient_norm = g.norm();
            result.energy        = energy;
            return finish(result);
          }
      }
  }

  NewtonResult minimize_with_newton(const Model &model, Eigen::VectorXd &x, const NewtonSettings &settings)
  {
    return NewtonSolver(settings).minimize(model, x);
  }
} // namespace nlmech
