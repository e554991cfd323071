// Frequency-response curves by pseudo-arclength continuation (thesis 2.3.19): predictor along the
// tangent of the bordered system, corrector, step control through folds, resonance peaks refined
// on the curve, stability of every point (continuation.h).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <nlmech/base/parse.h>
#include <nlmech/base/stopwatch.h>

#include <nlmech/solvers/hbm/bordered_matrix.h>
#include <nlmech/solvers/hbm/continuation.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>

namespace nlmech
{
  void ContinuationSettings::declare_parameters(dealii::ParameterHandler &prm)
  {
    using namespace dealii;
    prm.declare_entry("Frequency range", "0.5, 2.5", Patterns::Anything(),
                      "Start and end of the frequency-response curve [rad/s].");
    prm.declare_entry("Maximum step", "0.05", Patterns::Double(0), "Largest continuation step (scaled) [-].");
    prm.declare_entry("Maximum amplitude", "100", Patterns::Double(0),
                      "Stop the curve (partial result) beyond this half range [m].");
    prm.declare_entry("Tolerance", "1e-9", Patterns::Double(0), "|h| relative to the force scale [-].");
    prm.declare_entry("Maximum points", "2000", Patterns::Integer(1),
                      "Largest number of points on the frequency-response curve; beyond it the curve "
                      "stops (partial result) [-].");
    prm.declare_entry("Stability", "hill", Patterns::Selection("hill|floquet|none"),
                      "Stability of every point: hill (Hill's method: the Floquet exponents from the HBM "
                      "Jacobian by ARPACK's shift-and-invert Arnoldi, reusing the continuation's "
                      "factorisation; any size), floquet (monodromy matrix by RK4, dense: a time-domain "
                      "cross-check for models of up to a few dozen free unknowns) or none.");
  }

  void ContinuationSettings::parse_parameters(const dealii::ParameterHandler &prm)
  {
    const auto range = parse_number_list(prm.get("Frequency range"), "Frequency range");
    AssertThrow(range.size() == 2 && range[0] > 0 && range[1] > 0 && range[0] != range[1],
                dealii::ExcMessage("Frequency range needs two different positive frequencies [rad/s]."));
    omega_start = range[0], omega_end = range[1];
    max_step                 = prm.get_double("Maximum step");
    max_amplitude            = prm.get_double("Maximum amplitude");
    relative_tolerance       = prm.get_double("Tolerance");
    max_points               = unsigned(prm.get_integer("Maximum points"));
    const std::string method = prm.get("Stability");
    stability                = method == "floquet" ? StabilityMethod::floquet
                               : method == "none"  ? StabilityMethod::none
                                                   : StabilityMethod::hill;
  }

  PseudoArclengthContinuation::PseudoArclengthContinuation(const HarmonicBalance      &hb,
                                                           const ContinuationSettings &settings)
      : hb(hb)
      , settings(settings)
  {
    AssertThrow(settings.omega_start > 0 && settings.omega_end > 0 &&
                    settings.omega_start != settings.omega_end,
                dealii::ExcMessage("The frequency range needs two different positive frequencies."));
    AssertThrow(!settings.tracked_dofs.empty(), dealii::ExcMessage("No tracked unknowns for the amplitude."));
    fixed.relative_tolerance = settings.relative_tolerance;
    direction                = settings.omega_end > settings.omega_start ? 1.0 : -1.0;
  }

  Eigen::VectorXd PseudoArclengthContinuation::residual(const Eigen::VectorXd &z, const double w)
  {
    const auto      t0 = std::chrono::steady_clock::now();
    Eigen::VectorXd h  = hb.residual(z, w);
    response.residual_seconds += seconds_since(t0), ++response.residuals;
    return h;
  }

  Eigen::SparseMatrix<double> PseudoArclengthContinuation::jacobian(const Eigen::VectorXd &z, const double w,
                                                                    Eigen::VectorXd &h_omega)
  {
    const auto                  t0 = std::chrono::steady_clock::now();
    Eigen::SparseMatrix<double> J  = hb.jacobian(z, w);
    h_omega                        = hb.d_residual_d_omega(z, w);
    response.jacobian_seconds += seconds_since(t0), ++response.jacobians;
    return J;
  }

  void PseudoArclengthContinuation::tangent(PathPoint &p, const Eigen::VectorXd &row_z,
                                            const double row_omega)
  {
    Eigen::VectorXd                   hw;
    const Eigen::SparseMatrix<double> J = jacobian(p.z, p.omega, hw);
    p.row_z = row_z, p.row_omega = row_omega;
    at_current.factorize(bordered(J, hw, p.row_z, p.row_omega), false);
    Eigen::VectorXd rhs     = Eigen::VectorXd::Zero(J.rows() + 1);
    rhs[J.rows()]           = 1;
    const Eigen::VectorXd t = at_current.solve(rhs);
    const double          s = norm(t.head(J.rows()), t[J.rows()]);
    p.tz = t.head(J.rows()) / s, p.tomega = t[J.rows()] / s;
    Eigen::VectorXd grad;
    p.amplitude = hb.amplitude(p.z, p.omega, settings.tracked_dofs, &grad);
    p.dA_ds     = grad.dot(p.tz);
    p.scale     = force_scale(hb, p.z, p.omega);
  }

  bool PseudoArclengthContinuation::correct(const PathPoint &from, const double ds, PathPoint &to,
                                            const bool chord)
  {
    to.z = from.z + ds * from.tz, to.omega = from.omega + ds * from.tomega;
    if (to.omega <= 0)
      return false;
    const Eigen::VectorXd zp       = to.z;
    const double          wp       = to.omega;
    SparseFactorization  *solver   = chord ? &at_current : &work;
    bool                  fresh    = !chord;
    double                previous = std::numeric_limits<double>::max();
    for (unsigned int it = 0; it < 25; ++it)
      {
        if (to.omega <= 0)
          return false;
        const Eigen::VectorXd h = residual(to.z, to.omega);
        if (!h.allFinite())
          return false;
        const double arc = from.row_z.dot(to.z - zp) + from.row_omega * (to.omega - wp);
        const double r   = h.lpNorm<Eigen::Infinity>();
        if (std::getenv("NLMECH_HBM_DEBUG"))
          std::cerr << "corrector it " << it << " w " << to.omega << " r/scale " << r / from.scale << " arc "
                    << arc << " ds " << ds << (chord ? " chord" : " newton") << std::endl;
        if (it > 0 && r <= std::max(settings.relative_tolerance * from.scale, floor) &&
            std::abs(arc) <= 1e-9 * std::abs(ds))
          {
            to.iterations = it;
            return true;
          }
        // The chord iteration stalls (or this is a plain Newton step): refactorise here.
        if (fresh || (it > 0 && r > 0.3 * previous))
          {
            Eigen::VectorXd                   hw;
            const Eigen::SparseMatrix<double> J = jacobian(to.z, to.omega, hw);
            work.factorize(bordered(J, hw, from.row_z, from.row_omega), false);
            solver = &work, fresh = false;
            if (!chord)
              fresh = true; // full Newton: a new Jacobian every iteration
          }
        previous = r;
        Eigen::VectorXd rhs(h.size() + 1);
        rhs.head(h.size()) = -h, rhs[h.size()] = -arc;
        const Eigen::VectorXd d = solver->solve(rhs);
        to.z += d.head(h.size()), to.omega += d[h.size()];
        if (it >= 3 && norm(d.head(h.size()), d[h.size()]) > 0.5 * ds)
          return false; // diverging
      }
    return false;
  }

  bool PseudoArclengthContinuation::step(const PathPoint &current, const double ds, PathPoint &next,
                                         double &distance)
  {
    distance = 0; // of the corrected point from the prediction, weighted norm
    if (!correct(current, ds, next, true))
      return false;
    // The corrected point near the prediction, the curve turning by less than about 30 degrees;
    // otherwise the corrector may have jumped to another part of the curve.
    distance = norm(next.z - current.z - ds * current.tz, next.omega - current.omega - ds * current.tomega);
    if (distance > 0.5 * ds)
      return false;
    tangent(next, wz * current.tz, ww * current.tomega);
    return wz * next.tz.dot(current.tz) + ww * next.tomega * current.tomega >= 0.85;
  }

  double PseudoArclengthContinuation::next_step_length(const PathPoint &next, const double ds,
                                                       const double distance) const
  {
    // Grow where the corrector was quick or the prediction close (stiff structures, rods, need
    // several corrector iterations for their stretching forces however small the step: the
    // distance in the weighted norm tells the curve's own curvature).
    if (next.iterations <= 4 || distance <= 0.1 * ds)
      return std::min(settings.max_step, 1.5 * ds);
    if (next.iterations >= 8 || distance > 0.3 * ds)
      return 0.7 * ds;
    return ds;
  }

  void PseudoArclengthContinuation::reweight(PathPoint &current)
  {
    // A resonance many times larger than the start's motion would otherwise be crossed in tiny
    // steps. A new weight needs the tangent in the new norm (one more factorisation).
    const double harmonics = current.z.tail(current.z.size() - Eigen::Index(hb.n_free())).norm();
    if (harmonics > 2 * z_ref || (harmonics < 0.5 * z_ref && z_ref > z_ref_start))
      {
        const Eigen::VectorXd previous_tz = current.tz;
        z_ref                             = std::max(harmonics, z_ref_start);
        wz                                = 1 / (z_ref * z_ref);
        tangent(current, wz * previous_tz, ww * current.tomega);
        path.back() = current;
      }
  }

  void PseudoArclengthContinuation::record(const PathPoint &p)
  {
    ResponsePoint r;
    r.omega = p.omega, r.z = p.z, r.amplitude = p.amplitude, r.d_omega_ds = p.tomega,
    r.iterations = p.iterations;
    r.half_range = 0;
    for (const std::size_t d : settings.tracked_dofs)
      r.half_range = std::max(r.half_range, hb.half_range(p.z, p.omega, d));
    const auto started = std::chrono::steady_clock::now();
    if (settings.stability == StabilityMethod::floquet)
      {
        const FloquetResult f = floquet_stability(hb, p.z, p.omega);
        r.stable = f.stable, r.max_multiplier = f.max_multiplier;
      }
    else if (settings.stability != StabilityMethod::none)
      {
        // Solves with the Jacobian from the bordered factorisation at p (bordering lemma): with
        // [J h_w; r^T c] (u, mu) = (b, 0) and the tangent J t_z + h_w t_w = 0,
        // J^-1 b = u - mu t_z / t_w. Exactly at a fold (t_w = 0) J is singular.
        const Eigen::Index n_z   = p.z.size();
        auto               solve = [&](const Eigen::VectorXd &b) {
          Eigen::VectorXd rhs(n_z + 1);
          rhs.head(n_z) = b, rhs[n_z] = 0;
          const Eigen::VectorXd u = at_current.solve(rhs);
          return Eigen::VectorXd(u.head(n_z) - u[n_z] / p.tomega * p.tz);
        };
        try
          {
            // The previous point's count of eigenvalues within the radius is the first request.
            const HillResult h = std::abs(p.tomega) > 0
                                     ? hill_stability(hb, p.z, p.omega, solve, 1e-6, 400, hill_request)
                                     : hill_stability(hb, p.z, p.omega, {}, 1e-6, 400, hill_request);
            hill_request       = h.determined ? h.within_radius + 8 : 0;
            r.stable = h.determined ? int(h.stable) : -1, r.max_multiplier = h.max_multiplier;
            r.hill = true;
          }
        catch (const std::exception &)
          {
            r.stable = -1; // exactly singular (at a fold): left undetermined
          }
      }
    response.stability_seconds += seconds_since(started);
    response.points.push_back(r);
  }

  bool PseudoArclengthContinuation::refine_root(const std::size_t i, const bool fold, PathPoint &root)
  {
    // The extended system {h(z, w) = 0, q(z, w) = 0} with q = dA/ds (a peak) or q = dw/ds (a fold:
    // the bordered system's last tangent component, zero where dh/dz is singular), solved along
    // the curve: points between path[i] and path[i + 1] are the corrector's solutions on the
    // hyperplanes at distance s along path[i]'s tangent, so q is a smooth function of s, and its
    // root is bracketed by the two path points. Regula falsi with the Illinois modification keeps
    // the bracket and converges superlinearly; it stops when q vanishes to round-off or the
    // bracket is as narrow as the corrector can resolve.
    auto   q = [fold](const PathPoint &p) { return fold ? p.tomega : p.dA_ds; };
    double a = 0, b = path[i].step > 0 ? path[i].step
                                       : norm(path[i + 1].z - path[i].z, path[i + 1].omega - path[i].omega);
    double qa = q(path[i]), qb = q(path[i + 1]);
    root = std::abs(qa) < std::abs(qb) ? path[i] : path[i + 1];
    if (!(qa * qb < 0))
      return qa == 0 || qb == 0;
    // q's scale: dA/ds against the amplitude, dw/ds against the unit tangent.
    const double q_scale = fold ? 1.0 : std::max(std::abs(qa), std::abs(qb));
    int          side    = 0;
    for (int it = 0; it < 60 && b - a > 1e-13 * b; ++it)
      {
        const double s = (a * qb - b * qa) / (qb - qa);
        PathPoint    trial;
        if (!correct(path[i], s, trial, false))
          return false;
        tangent(trial, wz * path[i].tz, ww * path[i].tomega);
        const double qs = q(trial);
        root            = trial;
        if (std::abs(qs) <= 1e-14 * q_scale)
          break;
        if ((qs < 0) == (qa < 0))
          {
            a = s, qa = qs;
            if (side == -1)
              qb *= 0.5;
            side = -1;
          }
        else
          {
            b = s, qb = qs;
            if (side == 1)
              qa *= 0.5;
            side = 1;
          }
      }
    return true;
  }

  void PseudoArclengthContinuation::refine_peaks()
  {
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
      if (path[i].dA_ds > 0 && path[i + 1].dA_ds <= 0)
        {
          PathPoint best;
          refine_root(i, false, best);
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
  }

  void PseudoArclengthContinuation::refine_folds()
  {
    // Each turning point becomes a point of the curve of its own, between the two path points it
    // lies between (response.points and path are one to one); its stability is that of the branch
    // it closes (a Floquet multiplier is exactly 1 there).
    std::vector<ResponsePoint> points;
    for (std::size_t i = 0; i < path.size(); ++i)
      {
        points.push_back(response.points[i]);
        if (i + 1 == path.size() || (path[i].tomega > 0) == (path[i + 1].tomega > 0))
          continue;
        PathPoint turn;
        if (!refine_root(i, true, turn))
          {
            points.back().fold = true; // not located: the nearest point before it carries the mark
            continue;
          }
        ResponsePoint r;
        r.omega = turn.omega, r.z = turn.z, r.amplitude = turn.amplitude, r.d_omega_ds = turn.tomega;
        r.iterations = turn.iterations, r.fold = true;
        r.stable = points.back().stable, r.hill = points.back().hill, r.max_multiplier = 1;
        for (const std::size_t d : settings.tracked_dofs)
          r.half_range = std::max(r.half_range, hb.half_range(turn.z, turn.omega, d));
        points.push_back(r);
        TurningPoint t;
        t.omega = turn.omega, t.amplitude = turn.amplitude, t.z = turn.z;
        response.folds.push_back(t);
      }
    response.points = std::move(points);
  }

  FrequencyResponse PseudoArclengthContinuation::trace(Eigen::VectorXd z)
  {
    response = FrequencyResponse();
    path.clear();
    const auto                started = std::chrono::steady_clock::now();
    const PeriodicSolveResult first   = solve_with_excitation_ramp(hb, z, settings.omega_start, fixed);
    AssertThrow(first.converged,
                dealii::ExcMessage("Harmonic balance: no periodic state found at the start "
                                   "frequency " +
                                   std::to_string(settings.omega_start) + " rad/s (" + first.message + ")."));
    // Weighted norm: z in units of its harmonic size at the start, w in units of the range.
    z_ref       = z.tail(z.size() - Eigen::Index(hb.n_free())).norm();
    z_ref       = std::max(z_ref, 1e-9 * std::max(1.0, z.head(hb.n_free()).lpNorm<Eigen::Infinity>()));
    w_ref       = std::abs(settings.omega_end - settings.omega_start);
    z_ref_start = z_ref;
    wz          = 1 / (z_ref * z_ref);
    ww          = 1 / (w_ref * w_ref);
    floor       = residual_floor(hb, z); // round-off level of the residual (positions ~ |x|)

    PathPoint current;
    current.z = z, current.omega = settings.omega_start;
    tangent(current, Eigen::VectorXd::Zero(z.size()), ww * direction);
    current.iterations = first.iterations;
    record(current);
    path      = {current};
    double ds = settings.initial_step;
    while (true)
      {
        if (response.points.size() >= settings.max_points)
          {
            response.stop_reason =
                "reached the largest number of points (" + std::to_string(settings.max_points) + ")";
            break;
          }
        PathPoint next;
        double    distance = 0;
        if (!step(current, ds, next, distance))
          {
            if (next.tz.size() > 0) // rejected for its turn: restore the factorisation at current
              tangent(current, current.row_z, current.row_omega);
            if (std::getenv("NLMECH_HBM_DEBUG"))
              std::cerr << "step rejected at w " << current.omega << " ds " << ds << " distance/ds "
                        << distance / ds << std::endl;
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
                tangent(end, wz * current.tz, ww * current.tomega);
                record(end);
                path.push_back(end);
                response.completed = true;
              }
            else
              response.stop_reason = "no periodic state at the end frequency";
            break;
          }
        path.back().step = ds;
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
        if (settings.stop_after_first_peak && path.size() >= 2 && path[path.size() - 2].dA_ds > 0 &&
            path.back().dA_ds <= 0)
          {
            response.stop_reason = "passed the first resonance peak";
            break;
          }
        if ((next.omega - settings.omega_start) * direction < -0.5 * w_ref)
          {
            response.stop_reason = "the curve turned back far below the start frequency";
            break;
          }
        ds      = next_step_length(next, ds, distance);
        current = next;
        reweight(current);
      }
    refine_peaks();
    refine_folds();
    response.factorizations        = at_current.n_factorizations + work.n_factorizations;
    response.factorization_seconds = at_current.factorization_seconds + work.factorization_seconds;
    response.solve_seconds         = at_current.solve_seconds + work.solve_seconds;
    response.seconds               = seconds_since(started);
    return response;
  }

  FrequencyResponse trace_frequency_response(const HarmonicBalance &hb, Eigen::VectorXd z,
                                             const ContinuationSettings &settings)
  {
    return PseudoArclengthContinuation(hb, settings).trace(std::move(z));
  }
} // namespace nlmech
