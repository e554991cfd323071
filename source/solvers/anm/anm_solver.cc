#include <nlmech/base/stopwatch.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/linear/sparse_factorization.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <deal.II/base/exceptions.h>

#include <Eigen/QR>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>

namespace nlmech
{
  namespace
  {
    using Clock = std::chrono::steady_clock;

    /// sum_k c[k] a^k
    template <typename V>
    V evaluate_series(const std::vector<V> &c, double a)
    {
      V value = c.back();
      for (int k = static_cast<int>(c.size()) - 2; k >= 0; --k)
        value = c[k] + a * value;
      return value;
    }

    /// First a in (0, a_max] where lambda(a) crosses target, or a negative number if none.
    double first_crossing_of(const std::function<double(double)> &lambda, double target, double a_max)
    {
      auto      f       = [&](double a) { return lambda(a) - target; };
      const int samples = 200;
      double    a0 = 0, f0 = f(0);
      if (f0 == 0)
        return 0;
      for (int s = 1; s <= samples; ++s)
        {
          const double a1 = a_max * s / samples, f1 = f(a1);
          if ((f0 > 0) != (f1 > 0) || f1 == 0)
            {
              double lo = a0, hi = a1;
              for (int it = 0; it < 100 && hi - lo > 1e-16 * hi; ++it)
                {
                  const double mid                     = 0.5 * (lo + hi);
                  ((f(mid) > 0) == (f0 > 0) ? lo : hi) = mid;
                }
              return hi;
            }
          a0 = a1, f0 = f1;
        }
      return -1;
    }
    double first_crossing(const std::vector<double> &lambda, double target, double a_max)
    {
      return first_crossing_of([&](double a) { return evaluate_series(lambda, a); }, target, a_max);
    }

    /// Rational (Pade) approximants with a common denominator of the series increments
    /// v(a) = sum_{k=1}^n a^k v_k, v_k = (x_k, lambda_k) (Cochelin, Damil, Potier-Ferry 1994): the
    /// denominator D(a) = sum_{i=0}^m d_i a^i (d_0 = 1) makes D v - P vanish to order m + 1 in the
    /// least-squares sense, min |v_{m+1} + sum_{i=1}^m d_i v_{m+1-i}|, and
    /// P(a) = sum_{k=1}^m a^k sum_{i=0}^{k-1} d_i v_{k-i}.
    struct Pade
    {
      std::vector<double>          d;      // d_0 .. d_m
      std::vector<Eigen::VectorXd> x;      // numerator coefficients of the free unknowns, 0..m
      std::vector<double>          lambda; // numerator coefficients of lambda, 0..m

      Pade(const std::vector<Eigen::VectorXd> &vx, const std::vector<double> &vl, int m)
      {
        const Eigen::Index n = vx[1].size() + 1;
        Eigen::MatrixXd    M(n, m);
        Eigen::VectorXd    rhs(n);
        for (int i = 1; i <= m; ++i)
          {
            M.col(i - 1).head(n - 1) = vx[m + 1 - i];
            M(n - 1, i - 1)          = vl[m + 1 - i];
          }
        rhs.head(n - 1)          = -vx[m + 1];
        rhs(n - 1)               = -vl[m + 1];
        const Eigen::VectorXd dd = M.colPivHouseholderQr().solve(rhs);
        d                        = {1.0};
        for (int i = 0; i < m; ++i)
          d.push_back(dd[i]);
        x.assign(m + 1, Eigen::VectorXd::Zero(n - 1));
        lambda.assign(m + 1, 0.0);
        for (int k = 1; k <= m; ++k)
          for (int i = 0; i <= k - 1; ++i)
            {
              x[k] += d[i] * vx[k - i];
              lambda[k] += d[i] * vl[k - i];
            }
      }
      double          denominator(double a) const { return evaluate_series(d, a); }
      Eigen::VectorXd increment(double a) const { return evaluate_series(x, a) / denominator(a); }
      double          lambda_increment(double a) const { return evaluate_series(lambda, a) / denominator(a); }
    };
  } // namespace

  AnmSolver::AnmSolver(const EquilibriumSystem &system, const Eigen::VectorXd &load,
                       const AnmSettings &settings)
      : system(system)
      , load(load)
      , settings(settings)
  {
    AssertThrow(settings.order >= 2, dealii::ExcMessage("The ANM truncation order must be at least 2."));
  }

  AnmSolver::AnmSolver(const Model &internal, const Eigen::VectorXd &load, const AnmSettings &settings)
      : owned(std::make_shared<ModelEquilibrium>(internal))
      , system(*owned)
      , load(load)
      , settings(settings)
  {
    AssertThrow(settings.order >= 2, dealii::ExcMessage("The ANM truncation order must be at least 2."));
    AssertThrow(internal.has_series(),
                dealii::ExcMessage("Every energy term of an ANM model needs Taylor series."));
  }

  AnmSeries AnmSolver::expand(const Eigen::VectorXd &x, const double lambda, const double direction,
                              const Eigen::VectorXd &previous_x1, const double previous_lambda1,
                              SparseFactorization &factorization, const FreeDofMap &free,
                              const Eigen::VectorXd &g, double &series_seconds) const
  {
    // The tangent at the series origin, factorised once for every order.
    factorization.factorize(free.restrict(system.tangent(x)), system.symmetric_tangent());
    const Eigen::VectorXd xt      = factorization.solve(g);
    double                lambda1 = 1.0 / std::sqrt(1.0 + xt.squaredNorm());
    if (previous_x1.size() == 0)
      lambda1 *= direction;
    else if ((lambda1 * xt).dot(previous_x1) + lambda1 * previous_lambda1 < 0)
      lambda1 = -lambda1; // keep going the way the previous series was heading at its end
    const Eigen::VectorXd x1 = lambda1 * xt;

    const auto series_start = Clock::now();
    AnmSeries  series;
    series.x          = {x, free.expand(x1)};
    series.free_x     = {free.restrict(x), x1};
    series.lambda     = {lambda, lambda1};
    double solve_time = 0;
    for (unsigned int k = 2; k <= settings.order; ++k)
      {
        const Eigen::VectorXd f_nl = free.restrict(system.internal_force_series_coefficient(series.x, k));
        const auto            t0   = Clock::now();
        const Eigen::VectorXd x_nl = factorization.solve(-f_nl);
        solve_time += seconds_since(t0);
        const double          lambda_k = -x_nl.dot(x1) / (xt.dot(x1) + lambda1); // eq. (12)
        const Eigen::VectorXd xk       = lambda_k * xt + x_nl;                   // eq. (18)
        series.free_x.push_back(xk);
        series.x.push_back(free.expand(xk));
        series.lambda.push_back(lambda_k);
      }
    series_seconds += seconds_since(series_start) - solve_time;
    const double xn = series.free_x.back().norm();
    series.radius =
        xn > 0 ? std::pow(settings.series_tolerance * x1.norm() / xn, 1.0 / (settings.order - 1)) : 1e30;
    return series;
  }

  Eigen::VectorXd AnmSeries::state(const double a) const
  {
    return evaluate_series(x, a);
  }

  double AnmSeries::load_factor(const double a) const
  {
    return evaluate_series(lambda, a);
  }

  double AnmSeries::parameter_for(const double target) const
  {
    // The root of lambda(a) = target nearest to a = 0, searched both ways within the radius.
    const double        forward  = first_crossing(lambda, target, radius);
    std::vector<double> mirrored = lambda;
    for (std::size_t k = 1; k < mirrored.size(); k += 2)
      mirrored[k] = -mirrored[k]; // lambda(-a)
    const double backward = first_crossing(mirrored, target, radius);
    if (forward < 0 && backward < 0)
      return std::numeric_limits<double>::quiet_NaN();
    if (backward < 0 || (forward >= 0 && forward <= backward))
      return forward;
    return -backward;
  }

  Eigen::VectorXd reduced_basis_rest_shape(const std::vector<AnmSeries> &series)
  {
    AssertThrow(!series.empty(), dealii::ExcMessage("Multi-target design needs at least one target."));
    const Eigen::Index n_rows = series.front().x.front().size();
    Eigen::Index       n_cols = 0;
    for (const auto &s : series)
      n_cols += s.x.size();
    Eigen::MatrixXd U(n_rows, n_cols);
    Eigen::Index    column = 0;
    Eigen::VectorXd sum    = Eigen::VectorXd::Zero(n_rows);
    for (const auto &s : series)
      {
        for (const auto &coefficient : s.x)
          U.col(column++) = coefficient;
        sum += s.x.front();
      }
    // Normal equations of sum_t |U q - X_t|^2: U^T U q = U^T (sum_t X_t) / T.
    const Eigen::VectorXd q = U.colPivHouseholderQr().solve(sum / double(series.size()));
    return U * q;
  }

  AnmSeries AnmSolver::series_at(const Eigen::VectorXd &x, const double lambda) const
  {
    const FreeDofMap    free(system.n_unknowns(), system.fixed());
    SparseFactorization factorization;
    double              seconds = 0;
    return expand(x, lambda, 1.0, Eigen::VectorXd(), 0.0, factorization, free, free.restrict(load), seconds);
  }

  AnmResult AnmSolver::solve(Eigen::VectorXd &x, const double lambda_start, const double lambda_target) const
  {
    const auto            start = Clock::now();
    const FreeDofMap      free(system.n_unknowns(), system.fixed());
    const bool            symmetric = system.symmetric_tangent();
    const Eigen::VectorXd g         = free.restrict(load);
    const double          g_norm    = g.norm();
    AssertThrow(g_norm > 0, dealii::ExcMessage("The ANM needs a non-zero load."));
    for (const auto &f : system.fixed())
      x[f.first] = f.second;

    AnmResult           result;
    SparseFactorization factorization;
    double              lambda              = lambda_start;
    const double        direction_of_target = lambda_target > lambda_start ? 1.0 : -1.0;
    Eigen::VectorXd     previous_x1;
    double              previous_lambda1 = 0, highest_lambda = lambda;

    auto residual = [&](const Eigen::VectorXd &state, double lam) {
      return Eigen::VectorXd(free.restrict(system.internal_force(state)) - lam * g);
    };
    auto finish = [&](bool completed, const std::string &reason) {
      result.completed             = completed;
      result.lambda                = lambda;
      result.extreme_lambda        = highest_lambda;
      result.stop_reason           = reason;
      result.factorizations        = factorization.n_factorizations;
      result.back_substitutions    = factorization.n_solves;
      result.factorization_seconds = factorization.factorization_seconds;
      result.solve_seconds         = factorization.solve_seconds;
      result.total_seconds         = seconds_since(start);
      return result;
    };

    // A failure inside a step (a singular tangent, a non-finite solve) ends the continuation with
    // the state and load factor reached so far, like a collapse: the caller gets a result, not a throw.
    try
      {
        for (unsigned int step = 0; step < settings.max_steps; ++step)
          {
            const AnmSeries series = expand(x, lambda, direction_of_target, previous_x1, previous_lambda1,
                                            factorization, free, g, result.series_seconds);
            const std::vector<Eigen::VectorXd> &path      = series.x;
            const std::vector<Eigen::VectorXd> &free_path = series.free_x;
            const std::vector<double>          &lambdas   = series.lambda;
            const Eigen::VectorXd              &x1        = free_path[1];

            AnmStepRecord record;
            record.lambda_begin  = lambda;
            record.series_radius = series.radius;
            double a_max         = record.series_radius;
            {
              const double inversion = system.first_invalid_along_series(path, a_max);
              if (inversion < a_max)
                {
                  a_max                       = 0.9 * inversion;
                  record.limited_by_inversion = true;
                }
            }
            // The representation of the branch: the series, or Pade approximants where they reach
            // further (poles of the denominator excluded).
            std::function<Eigen::VectorXd(double)> state_at = [&](double a) {
              return evaluate_series(path, a);
            };
            std::function<double(double)> lambda_at = [&](double a) { return evaluate_series(lambdas, a); };
            std::shared_ptr<Pade>         pade, pade_lower;
            if (settings.pade && settings.order >= 4)
              {
                pade         = std::make_shared<Pade>(free_path, lambdas, settings.order - 1);
                pade_lower   = std::make_shared<Pade>(free_path, lambdas, settings.order - 2);
                double reach = 0;
                for (double a = record.series_radius / 4; a <= 5 * record.series_radius; a *= 1.02)
                  {
                    if (pade->denominator(a) < 0.05 || pade_lower->denominator(a) < 0.05)
                      break; // approaching a pole
                    const Eigen::VectorXd high = pade->increment(a), low = pade_lower->increment(a);
                    const double          dl = pade->lambda_increment(a) - pade_lower->lambda_increment(a);
                    if (std::sqrt((high - low).squaredNorm() + dl * dl) >
                        settings.series_tolerance *
                            std::sqrt(high.squaredNorm() + std::pow(pade->lambda_increment(a), 2)))
                      break;
                    reach = a;
                  }
                record.pade_radius = reach;
                if (reach > a_max && !record.limited_by_inversion)
                  {
                    a_max    = reach;
                    state_at = [&, x0 = x](double a) {
                      return Eigen::VectorXd(x0 + free.expand(pade->increment(a)));
                    };
                    lambda_at        = [&, l0 = lambda](double a) { return l0 + pade->lambda_increment(a); };
                    record.used_pade = true;
                  }
              }
            const double landing = first_crossing_of(lambda_at, lambda_target, a_max);
            bool         final   = landing >= 0;
            double       a       = final ? landing : a_max;

            // Evaluate the series and correct; shorten the step if the corrections do not converge.
            Eigen::VectorXd trial;
            bool            converged = false;
            for (int attempt = 0; attempt < 8 && !converged; ++attempt)
              {
                if (a < settings.min_step)
                  break;
                trial               = state_at(a);
                double lambda_trial = lambda_at(a);
                if (final)
                  lambda_trial = lambda_target;
                record.corrections       = 0;
                double previous_residual = std::numeric_limits<double>::max();
                for (;;)
                  {
                    const Eigen::VectorXd R = residual(trial, lambda_trial);
                    record.residual         = R.norm() / g_norm;
                    if (!std::isfinite(record.residual))
                      break;
                    const double tolerance = final ? settings.residual_tolerance : settings.path_tolerance;
                    // Round-off floor: a Newton correction that no longer halves a residual already below
                    // the path tolerance has reached what double precision allows for this stiffness.
                    const bool at_round_off = record.corrections > 0 &&
                                              record.residual > 0.5 * previous_residual &&
                                              record.residual <= settings.path_tolerance;
                    previous_residual = record.residual;
                    if ((record.residual <= tolerance || at_round_off) && system.is_valid(trial))
                      {
                        converged = true;
                        lambda    = lambda_trial;
                        break;
                      }
                    if (record.corrections == settings.max_corrections || !system.is_valid(trial))
                      break;
                    factorization.factorize(free.restrict(system.tangent(trial)), symmetric);
                    const Eigen::VectorXd dx = free.expand(factorization.solve(-R));
                    const double safe = system.max_safe_step(trial, dx); // 1 when the full step is safe
                    trial += (safe < 1.0 ? 0.9 * safe : 1.0) * dx;
                    ++record.corrections;
                  }
                if (!converged)
                  {
                    a *= 0.5;
                    final = false;
                  }
              }
            if (!converged)
              {
                std::ostringstream reason;
                reason << "the ANM step length collapsed (a < " << settings.min_step
                       << ") at lambda = " << lambda
                       << ": no equilibrium could be followed further (a load beyond a limit point, or an "
                          "element "
                          "about to invert)";
                return finish(false, reason.str());
              }
            x                  = trial;
            record.step_length = a;
            record.lambda_end  = lambda;
            result.steps.push_back(record);
            // The previous series' direction at its end point: d/da of (x(a), lambda(a)) at a.
            previous_x1      = Eigen::VectorXd::Zero(x1.size());
            previous_lambda1 = 0;
            for (unsigned int k = 1; k < free_path.size(); ++k)
              {
                const double weight = k * std::pow(a, k - 1.0);
                previous_x1 += weight * free_path[k];
                previous_lambda1 += weight * lambdas[k];
              }

            // The extreme load factor along the whole step, the last one included: the series may pass
            // a limit point mid-step.
            for (int sample = 1; sample <= 1000; ++sample)
              {
                const double l = lambda_at(a * sample / 1000.0);
                highest_lambda =
                    direction_of_target > 0 ? std::max(highest_lambda, l) : std::min(highest_lambda, l);
              }
            highest_lambda =
                direction_of_target > 0 ? std::max(highest_lambda, lambda) : std::min(highest_lambda, lambda);
            if (final)
              return finish(true, "reached lambda = " + std::to_string(lambda_target));
            if (direction_of_target * (highest_lambda - lambda) >
                0.05 * std::abs(lambda_target - lambda_start))
              {
                std::ostringstream reason;
                reason << "the load path turned back at lambda = " << highest_lambda
                       << " (a limit point): there is no equilibrium at lambda = " << lambda_target
                       << " on this branch";
                return finish(false, reason.str());
              }
          }
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream message;
        e.print_info(message);
        std::string text = message.str();
        text.erase(0, text.find_first_not_of(" \n"));
        while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '.'))
          text.pop_back();
        std::ostringstream reason;
        reason << "stopped at lambda = " << lambda << ": " << text;
        return finish(false, reason.str());
      }
    return finish(false, "the ANM did not reach lambda = " + std::to_string(lambda_target) + " in " +
                             std::to_string(settings.max_steps) + " steps");
  }

  LoadSteppingResult solve_with_load_stepping(const Model &internal, const Eigen::VectorXd &load,
                                              Eigen::VectorXd &x, const unsigned int n_steps,
                                              const double relative_tolerance, const NewtonSettings &newton)
  {
    const auto         start = Clock::now();
    LoadSteppingResult result;
    const FreeDofMap   free(internal);
    const double       g_norm = free.restrict(load).norm();
    for (unsigned int i = 1; i <= n_steps; ++i)
      {
        Model stepped = internal;
        stepped.add_term(std::make_shared<ConstantForceTerm>("load", load * (double(i) / n_steps)));
        NewtonSettings settings     = newton;
        settings.relative_tolerance = 0;
        settings.absolute_tolerance = relative_tolerance * g_norm;
        const NewtonResult r        = minimize_with_newton(stepped, x, settings);
        result.iterations += r.iterations;
        result.factorizations += r.factorizations;
      }
    result.seconds = seconds_since(start);
    return result;
  }
} // namespace nlmech

namespace nlmech
{
  LoadSteppingResult solve_equilibrium_with_newton(const EquilibriumSystem &system,
                                                   const Eigen::VectorXd &load, Eigen::VectorXd &q,
                                                   const unsigned int    n_steps,
                                                   const double          relative_tolerance,
                                                   const NewtonSettings &newton)
  {
    const auto            start = Clock::now();
    LoadSteppingResult    result;
    const FreeDofMap      free(system.n_unknowns(), system.fixed());
    const Eigen::VectorXd g = free.restrict(load);
    SparseFactorization   factorization;
    for (const auto &f : system.fixed())
      q[f.first] = f.second;

    // Newton at one load factor from q; false (q unchanged) when it does not converge in the
    // iteration limit or the line search finds no decrease. The factorisation is left at the last
    // tangent (the predictor of the next step uses it).
    const auto newton_at = [&](const double lambda, Eigen::VectorXd &state, unsigned int &iterations) {
      auto residual = [&](const Eigen::VectorXd &s) {
        return Eigen::VectorXd(free.restrict(system.internal_force(s)) - lambda * g);
      };
      Eigen::VectorXd x        = state;
      Eigen::VectorXd R        = residual(x);
      double          previous = std::numeric_limits<double>::max();
      iterations               = 0;
      for (;; ++iterations)
        {
          if (!R.allFinite())
            return false;
          // Converged, or stagnating at the round-off floor well below the requested accuracy.
          if (R.norm() <= relative_tolerance * g.norm() ||
              (iterations > 0 && R.norm() > 0.5 * previous && R.norm() <= 1e-6 * g.norm()))
            break;
          if (iterations >= newton.max_iterations)
            return false;
          previous = R.norm();
          try
            {
              factorization.factorize(free.restrict(system.tangent(x)), system.symmetric_tangent());
            }
          catch (const dealii::ExceptionBase &)
            {
              return false; // a singular tangent: a smaller load increment may avoid it
            }
          const Eigen::VectorXd dq       = free.expand(factorization.solve(-R));
          const double          safe     = system.max_safe_step(x, dq);
          double                alpha    = safe < 1.0 ? 0.9 * safe : 1.0;
          bool                  accepted = false;
          for (unsigned int ls = 0; ls < newton.max_line_search; ++ls, alpha *= 0.5)
            {
              const Eigen::VectorXd trial = x + alpha * dq;
              if (!system.is_valid(trial))
                continue;
              const Eigen::VectorXd R_trial = residual(trial);
              if (R_trial.allFinite() && R_trial.norm() < (1 - 1e-4 * alpha) * R.norm())
                {
                  x = trial, R = R_trial, accepted = true;
                  break;
                }
            }
          if (!accepted)
            return false;
        }
      state = x;
      return true;
    };

    // Adaptive load steps: the increment starts at 1 / n_steps, halves after a failed step (from
    // the last equilibrium) and doubles after a step that converged in at most four iterations.
    // Each step starts from the tangent predictor q + dlambda K^{-1} g (K from the last
    // factorisation, the tangent near the last equilibrium), cut back to stay valid.
    double       lambda = 0, increment = 1.0 / n_steps;
    const double smallest       = 1.0 / (n_steps * 1024.0);
    bool         have_predictor = false;
    while (lambda < 1)
      {
        const double    step_to = std::min(1.0, lambda + increment);
        Eigen::VectorXd trial   = q;
        if (have_predictor)
          {
            const Eigen::VectorXd dq   = free.expand(factorization.solve(g)) * (step_to - lambda);
            const double          safe = system.max_safe_step(q, dq);
            trial += (safe < 1.0 ? 0.9 * safe : 1.0) * dq;
            if (!system.is_valid(trial))
              trial = q;
          }
        unsigned int iterations = 0;
        if (newton_at(step_to, trial, iterations))
          {
            result.smallest_increment = std::min(result.smallest_increment, step_to - lambda);
            q                         = trial;
            lambda                    = step_to;
            result.iterations += iterations;
            ++result.load_steps;
            have_predictor = factorization.n_factorizations > 0;
            if (iterations <= 4)
              increment *= 2;
          }
        else
          {
            result.iterations += iterations;
            ++result.rejected_steps;
            increment *= 0.5;
            have_predictor = false; // the factorisation is at a rejected state now
            AssertThrow(increment >= smallest,
                        dealii::ExcMessage("Newton did not converge at load factor " +
                                           std::to_string(step_to) + " even with load increments of " +
                                           std::to_string(2 * increment) + " (" +
                                           std::to_string(result.load_steps) + " steps accepted, " +
                                           std::to_string(result.rejected_steps) + " rejected)."));
          }
      }
    result.factorizations = factorization.n_factorizations;
    result.seconds        = seconds_since(start);
    return result;
  }
} // namespace nlmech
