#include <deal.II/base/exceptions.h>
#include <deal.II/lac/vector.h>
#include <deal.II/sundials/kinsol.h>

#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    Eigen::VectorXd to_eigen(const dealii::Vector<double> &v)
    {
      return Eigen::Map<const Eigen::VectorXd>(v.begin(), Eigen::Index(v.size()));
    }
    void to_dealii(const Eigen::VectorXd &e, dealii::Vector<double> &v)
    {
      std::copy(e.data(), e.data() + e.size(), v.begin());
    }

    /// [[J, h_w], [row^T, 0]] for the bordered systems of the continuation (2.3.19).
    Eigen::SparseMatrix<double> bordered(const Eigen::SparseMatrix<double> &J, const Eigen::VectorXd &h_omega,
                                         const Eigen::VectorXd &row_z, double row_omega)
    {
      const Eigen::Index                  n = J.rows();
      std::vector<Eigen::Triplet<double>> t;
      t.reserve(J.nonZeros() + 2 * n + 1);
      for (Eigen::Index c = 0; c < J.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it)
          t.emplace_back(it.row(), it.col(), it.value());
      for (Eigen::Index i = 0; i < n; ++i)
        {
          if (h_omega[i] != 0)
            t.emplace_back(i, n, h_omega[i]);
          if (row_z[i] != 0)
            t.emplace_back(n, i, row_z[i]);
        }
      t.emplace_back(n, n, row_omega);
      Eigen::SparseMatrix<double> B(n + 1, n + 1);
      B.setFromTriplets(t.begin(), t.end());
      B.makeCompressed();
      return B;
    }

    /// Continuation state with its unit tangent (weighted norm) and the amplitude slope dA/ds.
    struct PathPoint
    {
      Eigen::VectorXd z, tz;
      double          omega = 0, tomega = 0, amplitude = 0, dA_ds = 0;
      unsigned int    iterations = 0;
    };
  } // namespace

  double force_scale(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double omega)
  {
    double scale = 0;
    for (std::size_t i = 0; i < hb.n_free(); ++i)
      for (unsigned int k = 1; k <= hb.n_harmonics(); ++k)
        {
          const auto sc = hb.coefficient(z, i, k);
          scale =
              std::max(scale, std::pow(k * omega, 2) * hb.free_mass()[i] * std::hypot(sc.first, sc.second));
        }
    // Forcing: the first harmonic of the external force at the static state.
    const Eigen::VectorXd h0 = hb.residual(hb.static_coefficients(hb.full(z.head(hb.n_free()))), omega);
    scale                    = std::max(scale, h0.lpNorm<Eigen::Infinity>());
    return std::max(scale, 1e-300);
  }

  PeriodicSolveResult solve_periodic_state(const HarmonicBalance &hb, Eigen::VectorXd &z, const double omega,
                                           const PeriodicSolveSettings &settings)
  {
    PeriodicSolveResult result;
    const double        scale = force_scale(hb, z, omega);
    using KINSOL              = dealii::SUNDIALS::KINSOL<dealii::Vector<double>>;
    KINSOL::AdditionalData data(KINSOL::AdditionalData::linesearch, settings.max_iterations,
                                settings.relative_tolerance * scale,
                                1e-14 * std::max(1.0, z.lpNorm<Eigen::Infinity>()), false, 1);
    KINSOL                 solver(data);
    SparseFactorization    factorization;
    solver.reinit_vector = [&](dealii::Vector<double> &v) { v.reinit(hb.n_unknowns()); };
    solver.residual      = [&](const dealii::Vector<double> &u, dealii::Vector<double> &F) {
      try
        {
          const Eigen::VectorXd h = hb.residual(to_eigen(u), omega);
          if (!h.allFinite())
            return 1; // recoverable: KINSOL shortens the step
          to_dealii(h, F);
          return 0;
        }
      catch (...)
        {
          return 1;
        }
    };
    solver.setup_jacobian = [&](const dealii::Vector<double> &u, const dealii::Vector<double> &) {
      try
        {
          factorization.factorize(hb.jacobian(to_eigen(u), omega), false);
          return 0;
        }
      catch (...)
        {
          return -1;
        }
    };
    solver.solve_with_jacobian = [&](const dealii::Vector<double> &rhs, dealii::Vector<double> &dst, double) {
      try
        {
          to_dealii(factorization.solve(to_eigen(rhs)), dst);
          return 0;
        }
      catch (...)
        {
          return -1;
        }
    };
    dealii::Vector<double> u(hb.n_unknowns());
    to_dealii(z, u);
    try
      {
        result.iterations = solver.solve(u);
      }
    catch (const std::exception &e)
      {
        result.message = e.what();
      }
    const Eigen::VectorXd candidate = to_eigen(u);
    const Eigen::VectorXd h         = hb.residual(candidate, omega);
    result.residual                 = h.lpNorm<Eigen::Infinity>() / scale;
    result.converged = h.allFinite() && result.residual <= std::max(settings.relative_tolerance, 1e-13) * 10;
    if (result.converged)
      z = candidate;
    else if (result.message.empty())
      result.message = "relative residual " + std::to_string(result.residual);
    return result;
  }

  FloquetResult floquet_stability(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double omega,
                                  const unsigned int steps, const double tolerance)
  {
    const std::size_t      n = hb.n_free();
    const double           T = 2 * pi / omega, dt = T / steps;
    const Eigen::VectorXd &m     = hb.free_mass();
    const double           alpha = hb.parameters().rayleigh_mass;
    // A(t) = [[0, I], [M^-1 df/dx, M^-1 (df/dv - alpha M)]], sparse.
    auto system_matrix = [&](const double t) {
      const Eigen::VectorXd       x = hb.positions_at(z, omega, {t}).col(0);
      const Eigen::VectorXd       v = hb.velocities_at(z, omega, {t}).col(0);
      Eigen::SparseMatrix<double> Kx, Kv;
      hb.force(x, v, omega * t, &Kx, &Kv);
      std::vector<Eigen::Triplet<double>> trip;
      for (std::size_t i = 0; i < n; ++i)
        trip.emplace_back(i, n + i, 1.0), trip.emplace_back(n + i, n + i, -alpha);
      for (Eigen::Index c = 0; c < Kx.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(Kx, c); it; ++it)
          trip.emplace_back(n + it.row(), it.col(), it.value() / m[it.row()]);
      for (Eigen::Index c = 0; c < Kv.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(Kv, c); it; ++it)
          trip.emplace_back(n + it.row(), n + it.col(), it.value() / m[it.row()]);
      Eigen::SparseMatrix<double> A(2 * n, 2 * n);
      A.setFromTriplets(trip.begin(), trip.end());
      return A;
    };
    Eigen::MatrixXd             Phi = Eigen::MatrixXd::Identity(2 * n, 2 * n);
    Eigen::SparseMatrix<double> A0  = system_matrix(0);
    for (unsigned int s = 0; s < steps; ++s)
      {
        const double                      t  = s * dt;
        const Eigen::SparseMatrix<double> Am = system_matrix(t + 0.5 * dt), A1 = system_matrix(t + dt);
        const Eigen::MatrixXd             k1 = A0 * Phi;
        const Eigen::MatrixXd             k2 = Am * (Phi + 0.5 * dt * k1);
        const Eigen::MatrixXd             k3 = Am * (Phi + 0.5 * dt * k2);
        const Eigen::MatrixXd             k4 = A1 * (Phi + dt * k3);
        Phi += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        A0 = A1;
      }
    FloquetResult result;
    result.max_multiplier =
        Eigen::EigenSolver<Eigen::MatrixXd>(Phi, false).eigenvalues().cwiseAbs().maxCoeff();
    result.stable = result.max_multiplier <= 1 + tolerance;
    return result;
  }

  FrequencyResponse trace_frequency_response(const HarmonicBalance &hb, Eigen::VectorXd z,
                                             const ContinuationSettings &settings)
  {
    AssertThrow(settings.omega_start > 0 && settings.omega_end > 0 &&
                    settings.omega_start != settings.omega_end,
                dealii::ExcMessage("The frequency range needs two different positive frequencies."));
    AssertThrow(!settings.tracked_dofs.empty(), dealii::ExcMessage("No tracked unknowns for the amplitude."));
    FrequencyResponse     response;
    const double          direction = settings.omega_end > settings.omega_start ? 1.0 : -1.0;
    PeriodicSolveSettings fixed;
    fixed.relative_tolerance        = settings.relative_tolerance;
    const PeriodicSolveResult first = solve_periodic_state(hb, z, settings.omega_start, fixed);
    AssertThrow(first.converged,
                dealii::ExcMessage("Harmonic balance: no periodic state found at the start "
                                   "frequency " +
                                   std::to_string(settings.omega_start) + " rad/s (" + first.message + ")."));
    // Weighted norm: z in units of its harmonic size at the start, w in units of the range.
    double z_ref = 0;
    for (Eigen::Index i = Eigen::Index(hb.n_free()); i < z.size(); ++i)
      z_ref = std::max(z_ref, std::abs(z[i]));
    z_ref              = std::max(z_ref, 1e-9 * std::max(1.0, z.head(hb.n_free()).lpNorm<Eigen::Infinity>()));
    const double w_ref = std::abs(settings.omega_end - settings.omega_start);
    const double wz = 1 / (z_ref * z_ref), ww = 1 / (w_ref * w_ref);
    auto         norm = [&](const Eigen::VectorXd &dz, double dw) {
      return std::sqrt(wz * dz.squaredNorm() + ww * dw * dw);
    };

    SparseFactorization factorization;
    // Tangent at (z, w) with the sign of `previous` (2.3.19).
    auto tangent = [&](PathPoint &p, const Eigen::VectorXd &prev_z, double prev_w) {
      const Eigen::SparseMatrix<double> J  = hb.jacobian(p.z, p.omega);
      const Eigen::VectorXd             hw = hb.d_residual_d_omega(p.z, p.omega);
      factorization.factorize(bordered(J, hw, wz * prev_z, ww * prev_w), false);
      Eigen::VectorXd rhs     = Eigen::VectorXd::Zero(J.rows() + 1);
      rhs[J.rows()]           = 1;
      const Eigen::VectorXd t = factorization.solve(rhs);
      const double          s = norm(t.head(J.rows()), t[J.rows()]);
      p.tz = t.head(J.rows()) / s, p.tomega = t[J.rows()] / s;
      Eigen::VectorXd grad;
      p.amplitude = hb.amplitude(p.z, p.omega, settings.tracked_dofs, &grad);
      p.dA_ds     = grad.dot(p.tz);
    };
    // Corrector from a prediction: Newton on [h; <t, y - y_pred>] = 0.
    auto correct = [&](const PathPoint &from, const double ds, PathPoint &to) {
      to.z = from.z + ds * from.tz, to.omega = from.omega + ds * from.tomega;
      const Eigen::VectorXd zp    = to.z;
      const double          wp    = to.omega;
      const double          scale = force_scale(hb, to.z, to.omega);
      for (unsigned int it = 0; it < 10; ++it)
        {
          if (to.omega <= 0)
            return false;
          const Eigen::VectorXd h = hb.residual(to.z, to.omega);
          if (!h.allFinite())
            return false;
          const double arc = wz * from.tz.dot(to.z - zp) + ww * from.tomega * (to.omega - wp);
          if (it > 0 && h.lpNorm<Eigen::Infinity>() <= settings.relative_tolerance * scale &&
              std::abs(arc) < 1e-12)
            {
              to.iterations = it;
              return true;
            }
          factorization.factorize(bordered(hb.jacobian(to.z, to.omega), hb.d_residual_d_omega(to.z, to.omega),
                                           wz * from.tz, ww * from.tomega),
                                  false);
          Eigen::VectorXd rhs(h.size() + 1);
          rhs.head(h.size()) = -h, rhs[h.size()] = -arc;
          const Eigen::VectorXd d = factorization.solve(rhs);
          to.z += d.head(h.size()), to.omega += d[h.size()];
          if (it >= 2 && norm(d.head(h.size()), d[h.size()]) > 0.5 * ds)
            return false; // diverging
        }
      return false;
    };

    PathPoint current;
    current.z = z, current.omega = settings.omega_start;
    tangent(current, Eigen::VectorXd::Zero(z.size()), direction);
    current.iterations = first.iterations;
    auto record        = [&](const PathPoint &p) {
      ResponsePoint r;
      r.omega = p.omega, r.z = p.z, r.amplitude = p.amplitude, r.d_omega_ds = p.tomega,
      r.iterations = p.iterations;
      r.half_range = 0;
      for (const std::size_t d : settings.tracked_dofs)
        r.half_range = std::max(r.half_range, hb.half_range(p.z, p.omega, d));
      if (settings.stability && hb.n_free() <= settings.max_free_for_stability)
        {
          const FloquetResult f = floquet_stability(hb, p.z, p.omega);
          r.stable = f.stable, r.max_multiplier = f.max_multiplier;
        }
      if (!response.points.empty() && (response.points.back().d_omega_ds > 0) != (r.d_omega_ds > 0))
        response.points.back().fold = true;
      response.points.push_back(r);
    };
    record(current);
    std::vector<PathPoint> path = {current};
    double                 ds   = settings.initial_step;
    while (true)
      {
        if (response.points.size() >= settings.max_points)
          {
            response.stop_reason =
                "reached the largest number of points (" + std::to_string(settings.max_points) + ")";
            break;
          }
        PathPoint next;
        if (!correct(current, ds, next))
          {
            ++response.rejected_steps;
            ds *= 0.5;
            if (ds < settings.min_step)
              {
                response.stop_reason =
                    "the continuation step fell below its minimum at w = " + std::to_string(current.omega) +
                    " rad/s";
                break;
              }
            continue;
          }
        // Past the end of the range: land exactly on omega_end by a fixed-frequency solve.
        if ((next.omega - settings.omega_end) * direction >= 0)
          {
            const double    f   = (settings.omega_end - current.omega) / (next.omega - current.omega);
            Eigen::VectorXd z_e = current.z + f * (next.z - current.z);
            if (solve_periodic_state(hb, z_e, settings.omega_end, fixed).converged)
              {
                PathPoint end;
                end.z = z_e, end.omega = settings.omega_end;
                tangent(end, current.tz, current.tomega);
                record(end);
                path.push_back(end);
                response.completed = true;
              }
            else
              response.stop_reason = "no periodic state at the end frequency";
            break;
          }
        tangent(next, current.tz, current.tomega);
        record(next);
        path.push_back(next);
        if (settings.progress)
          settings.progress(std::clamp(
              (next.omega - settings.omega_start) / (settings.omega_end - settings.omega_start), 0.0, 1.0));
        if (settings.max_amplitude > 0 && response.points.back().half_range > settings.max_amplitude)
          {
            response.stop_reason = "the amplitude exceeded " + std::to_string(settings.max_amplitude) +
                                   " m at w = " + std::to_string(next.omega) +
                                   " rad/s (an undamped or weakly damped resonance: the amplitude diverges)";
            break;
          }
        if ((next.omega - settings.omega_start) * direction < -0.5 * w_ref)
          {
            response.stop_reason = "the curve turned back far below the start frequency";
            break;
          }
        if (next.iterations <= 3)
          ds = std::min(settings.max_step, 1.5 * ds);
        else if (next.iterations >= 6)
          ds *= 0.7;
        current = next;
      }
    // Resonance peaks: dA/ds from + to -; refined on the curve by the secant method on arclength.
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
      if (path[i].dA_ds > 0 && path[i + 1].dA_ds <= 0)
        {
          double a = 0, b = 0;
          // arclength between the points in the weighted norm, along the chord
          b            = norm(path[i + 1].z - path[i].z, path[i + 1].omega - path[i].omega);
          double    ga = path[i].dA_ds, gb = path[i + 1].dA_ds;
          PathPoint best = std::abs(ga) < std::abs(gb) ? path[i] : path[i + 1];
          for (int it = 0; it < 12 && std::abs(b - a) > 1e-10 * (1 + b); ++it)
            {
              const double s = b - gb * (b - a) / (gb - ga);
              PathPoint    trial;
              if (!correct(path[i], s, trial))
                break;
              tangent(trial, path[i].tz, path[i].tomega);
              a = b, ga = gb, b = s, gb = trial.dA_ds;
              best = trial;
              if (std::abs(gb) < 1e-12 * (1 + best.amplitude))
                break;
            }
          Resonance r;
          r.omega = best.omega, r.amplitude = best.amplitude, r.z = best.z;
          // Near a fold dA/ds can flip twice within a step or two: one peak.
          if (!response.peaks.empty() && std::abs(response.peaks.back().omega - r.omega) < 1e-2 * w_ref)
            {
              if (r.amplitude > response.peaks.back().amplitude)
                response.peaks.back() = r;
            }
          else
            response.peaks.push_back(r);
        }
    response.factorizations = factorization.n_factorizations;
    return response;
  }

  NewmarkResult newmark_steady_state(const HarmonicBalance &hb, const double omega, const Eigen::VectorXd &x0,
                                     const Eigen::VectorXd &v0, const NewmarkSettings &settings)
  {
    const auto               start = std::chrono::steady_clock::now();
    const double             beta = 0.25, gamma = 0.5;
    const unsigned           S     = settings.steps_per_period;
    const double             dt    = 2 * pi / omega / S;
    const std::size_t        n     = hb.n_free();
    const Eigen::VectorXd   &m     = hb.free_mass();
    const double             alpha = hb.parameters().rayleigh_mass;
    std::vector<std::size_t> free  = hb.free();
    auto restrict                  = [&](const Eigen::VectorXd &full) {
      Eigen::VectorXd r(n);
      for (std::size_t i = 0; i < n; ++i)
        r[i] = full[free[i]];
      return r;
    };
    Eigen::VectorXd x = restrict(x0), v = restrict(v0);
    auto            full_v = [&](const Eigen::VectorXd &vf) {
      return Eigen::VectorXd(hb.full(vf) - hb.full(Eigen::VectorXd::Zero(n)));
    };
    Eigen::VectorXd a = (hb.force(hb.full(x), full_v(v), 0.0) - alpha * m.cwiseProduct(v)).cwiseQuotient(m);
    NewmarkResult   result;
    result.last_period.resize(x0.size(), S);
    Eigen::MatrixXd     previous(n, S), this_period(n, S);
    SparseFactorization factorization;
    double              size = 0;
    for (unsigned int p = 0; p < settings.max_periods; ++p)
      {
        for (unsigned int s = 0; s < S; ++s)
          {
            this_period.col(s)    = x;
            const double    theta = omega * dt * (s + 1);
            Eigen::VectorXd xn    = x + dt * v + 0.5 * dt * dt * a; // predictor
            Eigen::VectorXd an, vn;
            double          previous = std::numeric_limits<double>::max();
            for (unsigned int it = 0;; ++it)
              {
                an = (xn - x) / (beta * dt * dt) - v / (beta * dt) - (1 - 2 * beta) / (2 * beta) * a;
                vn = gamma / (beta * dt) * (xn - x) + (1 - gamma / beta) * v +
                     dt * (1 - gamma / (2 * beta)) * a;
                Eigen::SparseMatrix<double> Kx, Kv;
                const Eigen::VectorXd       f       = hb.force(hb.full(xn), full_v(vn), theta, &Kx, &Kv);
                const Eigen::VectorXd       inertia = m.cwiseProduct(an);
                const Eigen::VectorXd       R       = inertia + alpha * m.cwiseProduct(vn) - f;
                const double                r       = R.lpNorm<Eigen::Infinity>();
                const double                scale =
                    std::max({f.lpNorm<Eigen::Infinity>(), inertia.lpNorm<Eigen::Infinity>(), 1e-300});
                // Converged, or stagnating at the round-off floor of the inertia term.
                if (r <= settings.newton_tolerance * scale ||
                    (it > 0 && r > 0.5 * previous && r <= 1e-8 * scale))
                  break;
                AssertThrow(
                    it < 30 && std::isfinite(r),
                    dealii::ExcMessage("Newmark: Newton did not converge in a time step (relative residual " +
                                       std::to_string(r / scale) + ")."));
                previous                      = r;
                Eigen::SparseMatrix<double> J = -Kx - gamma / (beta * dt) * Kv;
                for (std::size_t i = 0; i < n; ++i)
                  J.coeffRef(i, i) += m[i] / (beta * dt * dt) + alpha * m[i] * gamma / (beta * dt);
                factorization.factorize(J, false);
                xn -= factorization.solve(R);
                ++result.newton_iterations;
              }
            x = xn, v = vn, a = an;
          }
        ++result.periods;
        for (unsigned int s = 0; s < S; ++s)
          size = std::max(size, (this_period.col(s) - this_period.col(0)).lpNorm<Eigen::Infinity>());
        if (p > 0)
          {
            // (2.5.1), relative to the motion's size (and sample count).
            double e = 0;
            for (unsigned int s = 0; s < S; ++s)
              e += (this_period.col(s) - previous.col(s)).norm();
            result.period_difference = e / (S * std::max(size, 1e-300));
            if (result.period_difference < settings.period_tolerance)
              {
                result.converged = true;
                break;
              }
          }
        previous = this_period;
      }
    for (unsigned int s = 0; s < S; ++s)
      result.last_period.col(s) = hb.full(this_period.col(s));
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
} // namespace nlmech
