// Bound-constrained L-BFGS on the harmonic-balance design objective (NLopt, design.h).
#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/hbm/design.h>

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

namespace nlmech
{
  OptimizationResult optimize_design(HarmonicDesign &design, const OptimizationSettings &settings)
  {
    const std::size_t n = design.n_parameters();
    // L-BFGS runs on u = (p - lower) / range in [0, 1]: parameters of different units (kg, Pa,
    // radians) become comparable, and its first step is a fraction of the box, not of |g|.
    std::vector<double> lower(n), upper(n), x(n), range(n);
    const auto          p0 = design.values();
    for (std::size_t k = 0; k < n; ++k)
      {
        lower[k] = design.design_parameters()[k]->lower, upper[k] = design.design_parameters()[k]->upper;
        range[k] = upper[k] > lower[k] ? upper[k] - lower[k] : 1.0;
        x[k]     = (p0[Eigen::Index(k)] - lower[k]) / range[k];
      }
    const auto to_parameters = [&](const std::vector<double> &u) {
      Eigen::VectorXd p(static_cast<Eigen::Index>(n));
      for (std::size_t k = 0; k < n; ++k)
        p[Eigen::Index(k)] = std::clamp(lower[k] + range[k] * u[k], lower[k], upper[k]);
      return p;
    };
    OptimizationResult result;
    const auto         started   = std::chrono::steady_clock::now();
    Eigen::VectorXd    last_good = p0;
    double             best_f    = std::numeric_limits<double>::infinity();

    bool at_limit = false;
    auto evaluate = [&](const std::vector<double> &q, std::vector<double> &grad) {
      // NLopt's L-BFGS checks maxeval only between its iterations (its line search may overrun):
      // the limit is kept here, exactly.
      if (result.evaluations >= settings.max_iterations)
        {
          at_limit = true;
          throw nlopt::forced_stop();
        }
      const Eigen::VectorXd p = to_parameters(q);
      ++result.evaluations;
      std::string why;
      if (!design.update(p, &why))
        {
          // No periodic state here (beyond a fold the continuation could not cross): a large value
          // with a gradient pointing back to the last design that solved, so the line search
          // steps back.
          const double big = 10 * std::abs(std::isfinite(best_f) ? best_f : 1.0) + 1;
          double       d2  = 0;
          for (std::size_t k = 0; k < n; ++k)
            {
              const double du = (p[Eigen::Index(k)] - last_good[Eigen::Index(k)]) / range[k];
              d2 += du * du;
              if (!grad.empty())
                grad[k] = 2 * big * du; // in u
            }
          return big * (1 + d2);
        }
      last_good = p;
      Eigen::VectorXd g;
      const double    f = design.objective(grad.empty() ? nullptr : &g);
      for (std::size_t k = 0; k < grad.size(); ++k)
        grad[k] = g[Eigen::Index(k)] * range[k];
      DesignIterate it;
      it.iteration = result.evaluations, it.objective = f, it.parameters = p;
      it.gradient_norm = g.size() > 0 ? g.norm() : 0.0;
      it.seconds       = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      result.history.push_back(it);
      if (f < best_f)
        best_f = f, result.best = it;
      if (settings.progress)
        settings.progress(it);
      return f;
    };
    std::function<double(const std::vector<double> &, std::vector<double> &)> function = evaluate;
    nlopt::opt opt(nlopt::LD_LBFGS, unsigned(n));
    opt.set_lower_bounds(std::vector<double>(n, 0.0));
    opt.set_upper_bounds(std::vector<double>(n, 1.0));
    opt.set_min_objective([](const std::vector<double> &q, std::vector<double> &grad,
                             void *data) { return (*static_cast<decltype(function) *>(data))(q, grad); },
                          &function);
    opt.set_ftol_rel(settings.relative_tolerance);
    opt.set_maxeval(int(settings.max_iterations));
    if (settings.time_limit > 0)
      opt.set_maxtime(settings.time_limit);
    double value = 0;
    try
      {
        const nlopt::result r = opt.optimize(x, value);
        result.converged      = r == nlopt::SUCCESS || r == nlopt::FTOL_REACHED || r == nlopt::XTOL_REACHED;
        result.stop_reason    = r == nlopt::MAXEVAL_REACHED ? "the largest number of evaluations was reached"
                                : r == nlopt::MAXTIME_REACHED ? "the time limit was reached"
                                : r == nlopt::FTOL_REACHED ? "the objective changed by less than its tolerance"
                                : r == nlopt::XTOL_REACHED
                                    ? "the parameters changed by less than their tolerance"
                                    : "converged";
      }
    catch (const nlopt::forced_stop &)
      {
        result.stop_reason = "the largest number of evaluations was reached";
      }
    catch (const nlopt::roundoff_limited &)
      {
        // NLopt's L-BFGS ends this way when its line search cannot improve the objective at
        // double precision: a (local) optimum to round-off.
        result.converged   = true;
        result.stop_reason = "the line search reached round-off (a local optimum)";
      }
    catch (const std::exception &e)
      {
        // After a forced stop at the evaluation limit NLopt's L-BFGS may report a generic failure.
        result.stop_reason = at_limit ? "the largest number of evaluations was reached"
                                      : std::string("the optimiser stopped: ") + e.what();
      }
    AssertThrow(!result.history.empty(),
                dealii::ExcMessage("Design: the optimiser evaluated nothing (" + result.stop_reason + ")."));
    // Leave the best design set (the last evaluation may have been a line-search trial).
    std::string why;
    AssertThrow(design.update(result.best.parameters, &why),
                dealii::ExcMessage("Design: the best design no longer solves (" + why + ")."));
    return result;
  }
} // namespace nlmech
