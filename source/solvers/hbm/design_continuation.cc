// Continuation of a periodic state in the design parameters (HarmonicDesign::continue_case): when
// the state cannot be re-solved at new parameters from the last one, a fold of the state over the
// parameters lies between. The solution curve of h(z, p(t)) = 0 along the segment
// p(t) = p0 + t (p1 - p0) is then followed by pseudo-arclength continuation in t, as the frequency
// is in continuation.cc: unit tangents of the bordered system [[dh/dz, dh/dt], [tangent^T]], Newton
// correctors on the hyperplane through each prediction, steps that grow and shrink with the
// corrector's effort. Around a fold t runs backwards for a while; once t passes 1 the state at p1
// is solved from the interpolated point. dh/dt = (dh/dp) (p1 - p0) comes from the parameters'
// own derivatives (directional_parameter_derivative), exact like the gradient's.
#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/hbm/bordered_matrix.h>
#include <nlmech/solvers/hbm/design.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>

namespace nlmech
{
  namespace
  {
    struct CurvePoint
    {
      Eigen::VectorXd z, tz; // the state and the z part of the unit tangent
      double          t = 0, tt = 0;
    };
  } // namespace

  bool HarmonicDesign::continue_case(const std::size_t c, const Eigen::VectorXd &from,
                                     const Eigen::VectorXd &to, std::string *why)
  {
    const Eigen::VectorXd d = to - from;
    const double          w = cases[c].omega;
    // The weight of z in the arclength: the size of the state, so a unit step changes z by about
    // its own size or t by about the whole segment.
    const double z0 = std::max(states[c].squaredNorm(), 1e-24);
    double       wz = 1 / z0;
    const auto   at = [&](const double t) {
      apply(from + t * d);
      hb = rebuild();
    };
    const auto tolerance = [&](const Eigen::VectorXd &z) {
      return std::max(settings.solve.relative_tolerance * force_scale(*hb, z, w), residual_floor(*hb, z));
    };
    SparseFactorization factorization;
    // The unit tangent at (z, t) oriented along `previous` (its weighted row); false when the
    // bordered matrix is singular there.
    const auto tangent = [&](CurvePoint &p, const Eigen::VectorXd &row_z, const double row_t) {
      try
        {
          at(std::min(p.t, 1.0));
          const Eigen::VectorXd ht = directional_parameter_derivative(*hb, parameters, d, p.z, w);
          factorization.factorize(bordered(hb->jacobian(p.z, w), ht, row_z, row_t), false);
          Eigen::VectorXd rhs     = Eigen::VectorXd::Zero(p.z.size() + 1);
          rhs[p.z.size()]         = 1;
          const Eigen::VectorXd y = factorization.solve(rhs);
          const double n = std::sqrt(wz * y.head(p.z.size()).squaredNorm() + y[p.z.size()] * y[p.z.size()]);
          if (!(n > 0) || !y.allFinite())
            return false;
          p.tz = y.head(p.z.size()) / n, p.tt = y[p.z.size()] / n;
          return true;
        }
      catch (...)
        {
          return false;
        }
    };
    // Newton on h(z, t) = 0 and the hyperplane through the prediction normal to the tangent.
    const auto correct = [&](const CurvePoint &from_point, const double ds, CurvePoint &next,
                             unsigned int &iterations) {
      const Eigen::VectorXd zp = from_point.z + ds * from_point.tz;
      const double          tp = from_point.t + ds * from_point.tt;
      next.z = zp, next.t = tp;
      // Convergence is judged by the corrections (affine invariant), not by |h|: on a thin shell
      // a right Newton step can raise |h| a thousandfold (the membrane strain of a bending change).
      double last = std::numeric_limits<double>::infinity(), before_last = last;
      for (iterations = 0; iterations < 12; ++iterations)
        {
          if (next.t > 1 + 1e-3)
            return false;
          try
            {
              at(std::min(next.t, 1.0));
            }
          catch (const std::exception &)
            {
              return false; // a structure the parameters do not allow
            }
          const Eigen::VectorXd h = hb->residual(next.z, w);
          if (!h.allFinite())
            return false;
          const double size = h.lpNorm<Eigen::Infinity>();
          if (size <= tolerance(next.z))
            return true;
          const Eigen::VectorXd ht = directional_parameter_derivative(*hb, parameters, d, next.z, w);
          Eigen::VectorXd       r(h.size() + 1);
          r.head(h.size()) = -h;
          r[h.size()]      = -(wz * from_point.tz.dot(next.z - zp) + from_point.tt * (next.t - tp));
          try
            {
              factorization.factorize(
                  bordered(hb->jacobian(next.z, w), ht, wz * from_point.tz, from_point.tt), false);
              const Eigen::VectorXd dy = factorization.solve(r);
              if (!dy.allFinite())
                return false;
              const double step =
                  std::sqrt(wz * dy.head(h.size()).squaredNorm() + dy[h.size()] * dy[h.size()]);
              // Over two iterations: a shell's corrections may alternate in size as they shrink.
              if (iterations > 3 && step > 0.5 * before_last)
                return false; // not converging quadratically: a shorter step
              before_last = last, last = step;
              next.z += dy.head(h.size()), next.t += dy[h.size()];
            }
          catch (...)
            {
              return false;
            }
        }
      return false;
    };

    CurvePoint current;
    current.z = states[c], current.t = 0;
    if (!tangent(current, Eigen::VectorXd::Zero(current.z.size()), 1))
      {
        if (why)
          *why = "the parameter continuation found no tangent at the last solved design";
        return false;
      }
    double ds = 0.25;
    for (unsigned int step = 0; step < settings.continuation_steps; ++step)
      {
        ++continuation_steps;
        CurvePoint   next;
        unsigned int iterations = 0;
        // A step that would pass the new design ends on it (beyond it a parameter may leave its
        // bounds, a mass turn negative).
        const double length = current.t + ds * current.tt > 1 ? (1 - current.t) / current.tt : ds;
        // Accepted when the corrected point lies near the prediction and the curve turns by less
        // than about 30 degrees over the step (no jump to another branch).
        const auto near = [&]() {
          const Eigen::VectorXd dz = next.z - (current.z + length * current.tz);
          const double          dt = next.t - (current.t + length * current.tt);
          return std::sqrt(wz * dz.squaredNorm() + dt * dt) <= 0.5 * length;
        };
        const auto smooth    = [&]() { return wz * next.tz.dot(current.tz) + next.tt * current.tt >= 0.85; };
        const bool corrected = correct(current, length, next, iterations);
        const bool accepted  = corrected && near() && tangent(next, wz * current.tz, current.tt) && smooth();
        if (std::getenv("NLMECH_HBM_DEBUG"))
          std::cout << "parameter continuation step " << step << " t " << current.t << " -> " << next.t
                    << " length " << length << " iterations " << iterations
                    << (accepted    ? " accepted"
                        : corrected ? " corrected, rejected"
                                    : " not corrected")
                    << std::endl;
        if (!accepted)
          {
            ds *= 0.5;
            if (ds < 1e-3) // no progress: a fold the parameters cannot pass, or no state at all
              break;
            continue;
          }
        if (next.t >= 1 - 1e-6)
          {
            // Past the end: the state at t = 1 from the chord between the two points.
            const double    s = std::min(1.0, (1 - current.t) / (next.t - current.t));
            Eigen::VectorXd z = current.z + s * (next.z - current.z);
            at(1);
            for (const Eigen::VectorXd *guess : {&z, &next.z})
              {
                Eigen::VectorXd           y = *guess;
                const PeriodicSolveResult r = solve_periodic_state(*hb, y, w, settings.solve);
                newton_iterations += r.iterations;
                if (r.converged && y.allFinite())
                  {
                    states[c] = y;
                    return true;
                  }
              }
            if (why)
              *why = "the parameter continuation reached the new design but its state did not solve there";
            return false;
          }
        if (next.t < -1)
          break; // the curve turned away from the new design for good
        if ((next.tt > 0) != (current.tt > 0))
          ++continuation_folds; // t turned: a fold of the state over the parameters
        // The weight follows the size of the state (never below the start's), the tangent renormalised.
        wz                = 1 / std::max(next.z.squaredNorm(), z0);
        const double size = std::sqrt(wz * next.tz.squaredNorm() + next.tt * next.tt);
        next.tz /= size, next.tt /= size;
        current = next;
        ds      = iterations <= 4 ? std::min(2 * ds, 1.0) : iterations > 7 ? 0.5 * ds : ds;
      }
    if (why)
      *why = "the parameter continuation could not follow the periodic state at w = " + std::to_string(w) +
             " rad/s from the last design to the new one (it ended at t = " + std::to_string(current.t) + ")";
    return false;
  }
} // namespace nlmech
