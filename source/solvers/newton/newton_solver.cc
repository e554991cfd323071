#include <nlmech/solvers/newton/newton_solver.h>

#include <algorithm>
#include <vector>

#include <deal.II/base/exceptions.h>

#include <Eigen/CholmodSupport>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace nlmech
{
  NewtonResult minimize_with_newton(const Model &model, Eigen::VectorXd &x, const NewtonSettings &settings)
  {
    const std::size_t n = model.n_unknowns();
    AssertThrow(std::size_t(x.size()) == n, dealii::ExcDimensionMismatch(x.size(), n));
    for (const auto &f : model.fixed())
      x[f.first] = f.second;
    AssertThrow(model.is_valid(x), dealii::ExcMessage("Newton: the initial state is not valid."));

    std::vector<long>        free_index(n, -1);
    std::vector<std::size_t> free_dofs;
    for (std::size_t i = 0; i < n; ++i)
      if (!model.is_fixed(i))
        {
          free_index[i] = free_dofs.size();
          free_dofs.push_back(i);
        }
    const std::size_t m = free_dofs.size();

    auto free_gradient = [&](const Eigen::VectorXd &state) {
      const Eigen::VectorXd g = model.gradient(state);
      Eigen::VectorXd       gf(m);
      for (std::size_t k = 0; k < m; ++k)
        gf[k] = g[free_dofs[k]];
      return gf;
    };

    NewtonResult                                             result;
    double                                                   energy = model.energy(x);
    Eigen::VectorXd                                          g      = free_gradient(x);
    const double                                             g0     = g.norm();
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholesky;
    long                                                     analysed_nonzeros = -1;
    std::vector<int>                                         analysed_outer, analysed_inner;
    double                                                   last_shift  = 0;
    unsigned int                                             short_steps = 0;
    cholesky.cholmod().print = 0; // silent: "not positive definite" is expected and handled by the shift

    for (result.iterations = 0;; ++result.iterations)
      {
        result.gradient_norm = g.norm();
        result.energy        = energy;
        if (result.gradient_norm <= std::max(settings.absolute_tolerance, settings.relative_tolerance * g0))
          return result;
        AssertThrow(result.iterations < settings.max_iterations,
                    dealii::ExcMessage("Newton did not converge in " +
                                       std::to_string(settings.max_iterations) +
                                       " iterations (gradient norm " + std::to_string(result.gradient_norm) +
                                       ", started at " + std::to_string(g0) + ")."));

        // Hessian restricted to the free unknowns.
        double diagonal_scale = 0;
        auto   free_matrix    = [&](const Eigen::SparseMatrix<double> &H) {
          Triplets free_triplets;
          // Explicit diagonal entries keep the sparsity pattern fixed when a shift is added.
          for (std::size_t k = 0; k < m; ++k)
            free_triplets.emplace_back(k, k, 0.0);
          for (int col = 0; col < H.outerSize(); ++col)
            for (Eigen::SparseMatrix<double>::InnerIterator it(H, col); it; ++it)
              if (free_index[it.row()] >= 0 && free_index[it.col()] >= 0)
                {
                  free_triplets.emplace_back(free_index[it.row()], free_index[it.col()], it.value());
                  if (it.row() == it.col())
                    diagonal_scale = std::max(diagonal_scale, std::abs(it.value()));
                }
          Eigen::SparseMatrix<double> Hf(m, m);
          Hf.setFromTriplets(free_triplets.begin(), free_triplets.end());
          Hf.makeCompressed();
          return Hf;
        };
        Eigen::SparseMatrix<double> Hf = free_matrix(model.hessian(x));
        // A descent direction from A + shift I, if its Cholesky factorisation exists.
        Eigen::VectorXd dx_free;
        auto            try_solve = [&](const Eigen::SparseMatrix<double> &M, const double shift) {
          Eigen::SparseMatrix<double> A = M;
          if (shift > 0)
            for (std::size_t k = 0; k < m; ++k)
              A.coeffRef(k, k) +=
                  shift * (settings.shift_metric.size() ? settings.shift_metric[free_dofs[k]] : 1.0);
          // The symbolic analysis is reused while the Hessian's pattern does not change (the whole
          // pattern is compared: contact problems trade pairs and can keep the count of nonzeros).
          const bool same_pattern =
              A.nonZeros() == analysed_nonzeros && A.outerSize() + 1 == Eigen::Index(analysed_outer.size()) &&
              std::equal(analysed_outer.begin(), analysed_outer.end(), A.outerIndexPtr()) &&
              std::equal(analysed_inner.begin(), analysed_inner.end(), A.innerIndexPtr());
          if (!same_pattern)
            {
              cholesky.analyzePattern(A);
              analysed_nonzeros = A.nonZeros();
              analysed_outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
              analysed_inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
            }
          cholesky.factorize(A);
          ++result.factorizations;
          if (cholesky.info() != Eigen::Success)
            return false;
          dx_free = cholesky.solve(-g);
          if (std::getenv("NLMECH_NEWTON_DEBUG") && !(dx_free.dot(g) < 0))
            std::fprintf(stderr,
                                    "newton: shift %.3e factorised but gives no descent (dx.g = %.3e, |dx| = %.3e)\n",
                                    shift, dx_free.dot(g), dx_free.norm());
          return dx_free.dot(g) < 0;
        };
        const double shift_floor = 1e-8 * (diagonal_scale > 0 ? diagonal_scale : 1.0);
        double       shift       = last_shift / 10 > shift_floor ? last_shift / 10 : 0;
        bool         projected   = false;
        if (settings.project_element_hessians)
          {
            // The exact Hessian where it is positive definite (quadratic convergence near a stable
            // minimum), else the projected one (a good model far from it, no global shift).
            shift = 0;
            if (!try_solve(Hf, 0))
              Hf = free_matrix(model.projected_hessian(x)), projected = true;
          }
        for (int attempt = 0; !settings.project_element_hessians || projected; ++attempt)
          {
            if (try_solve(Hf, shift))
              break;
            // At a numerically stationary point no shift gives descent (dx.g rounds to >= 0).
            if (attempt >= 20 && result.gradient_norm <= 1e-6 * g0)
              return result;
            if (attempt >= 20)
              {
                bool finite = true;
                for (Eigen::Index k = 0; k < Hf.nonZeros(); ++k)
                  finite = finite && std::isfinite(Hf.valuePtr()[k]);
                AssertThrow(false,
                            dealii::ExcMessage(finite ? "Newton: the Hessian could not be made positive "
                                                        "definite (shift " +
                                                            std::to_string(shift) + ")."
                                                      : "Newton: the Hessian has non-finite entries."));
              }
            shift = (shift == 0 ? shift_floor : 10 * shift);
          }
        last_shift = shift;

        Eigen::VectorXd dx = Eigen::VectorXd::Zero(n);
        for (std::size_t k = 0; k < m; ++k)
          dx[free_dofs[k]] = dx_free[k];
        const double safe         = model.max_safe_step(x, dx); // 1 when the full step is safe
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
        // A full projected step that the energy accepts may be too short: along directions of
        // negative curvature the projection makes the model stiffer than the energy. Extend it
        // (doubling) while the energy keeps falling by Armijo's rule.
        if (accepted && projected && alpha == 1.0)
          {
            const Eigen::VectorXd base = x - dx;
            for (double t = 2; t <= 64; t *= 2)
              {
                const Eigen::VectorXd longer = base + t * dx;
                if (model.max_safe_step(base, t * dx) < 1.0 || !model.is_valid(longer))
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
          return result;
        if (std::getenv("NLMECH_NEWTON_DEBUG"))
          {
            Eigen::Index largest;
            dx.cwiseAbs().maxCoeff(&largest);
            std::fprintf(
                stderr,
                "newton it %3u energy %.12e |g| %.3e safe %.3e alpha %.3e shift %.2e%s |dx| %.3e (largest: "
                "unknown %ld)\n",
                result.iterations, energy, g.norm(), safe, accepted ? alpha : 0.0, shift,
                projected ? " (projected)" : "", dx.norm(), long(largest));
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
            return result;
          }
        // Two short (collision-bounded) steps in a row: damp the near-null directions harder.
        short_steps = safe < 0.5 ? short_steps + 1 : 0;
        if (settings.grow_shift_on_short_steps && short_steps >= 2)
          last_shift = std::min(100 * std::max(shift, shift_floor), 1e3 * std::max(diagonal_scale, 1e-300));
        if (settings.step_tolerance > 0 && alpha == 1.0 &&
            dx.lpNorm<Eigen::Infinity>() <= settings.step_tolerance)
          {
            ++result.iterations;
            result.gradient_norm = g.norm();
            result.energy        = energy;
            return result;
          }
      }
  }
} // namespace nlmech
