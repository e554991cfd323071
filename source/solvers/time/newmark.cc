// Newmark (beta = 1/4, gamma = 1/2) on the harmonic-balance system's equations of motion, to the
// periodic steady state by the period-difference criterion (thesis 2.5.1): the time-domain check.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/parameter_handler.h>

#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/sparse_factorization.h>
#include <nlmech/solvers/time/newmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace nlmech
{
  void NewmarkSettings::declare_parameters(dealii::ParameterHandler &prm)
  {
    prm.declare_entry("Steps per period", "1024", dealii::Patterns::Integer(16), "[-].");
    prm.declare_entry("Period tolerance", "1e-8", dealii::Patterns::Double(0),
                      "e_p of thesis eq. (2.5.1), relative [-].");
  }

  void NewmarkSettings::parse_parameters(const dealii::ParameterHandler &prm)
  {
    steps_per_period = unsigned(prm.get_integer("Steps per period"));
    period_tolerance = prm.get_double("Period tolerance");
  }

  namespace
  {
  } // namespace

  NewmarkResult newmark_steady_state(const HarmonicBalance &hb, const double omega, const Eigen::VectorXd &x0,
                                     const Eigen::VectorXd &v0, const NewmarkSettings &settings)
  {
    const auto               start = std::chrono::steady_clock::now();
    const double             beta = 0.25, gamma = 0.5;
    const unsigned           S     = settings.steps_per_period;
    const double             dt    = 2 * dealii::numbers::PI / omega / S;
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

    Eigen::VectorXd a =
        (hb.force(hb.full(x, 0.0), hb.full_velocity(v, 0.0, omega), 0.0) - alpha * m.cwiseProduct(v))
            .cwiseQuotient(m);
    NewmarkResult result;
    result.last_period.resize(x0.size(), S);
    Eigen::MatrixXd     previous(n, S), this_period(n, S);
    SparseFactorization factorization;
    double              size          = 0;
    const double        elastic_floor = residual_floor(hb, hb.static_coefficients(x0));
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
                const Eigen::VectorXd       f =
                    hb.force(hb.full(xn, theta), hb.full_velocity(vn, theta, omega), theta, &Kx, &Kv);
                const Eigen::VectorXd inertia = m.cwiseProduct(an);
                const Eigen::VectorXd R       = inertia + alpha * m.cwiseProduct(vn) - f;
                const double          r       = R.lpNorm<Eigen::Infinity>();
                const double          scale =
                    std::max({f.lpNorm<Eigen::Infinity>(), inertia.lpNorm<Eigen::Infinity>(), 1e-300});
                // Converged, or stagnating at the round-off floor of the inertia term.
                // Round-off of the inertia term (x_n+1 - x_n) / (beta dt^2) with positions of size |x|.
                const double floor = std::max(
                    elastic_floor, 100 * std::numeric_limits<double>::epsilon() * m.maxCoeff() *
                                       std::max(xn.lpNorm<Eigen::Infinity>(), 1e-300) / (beta * dt * dt));
                if (r <= std::max(settings.newton_tolerance * scale, floor) ||
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
      result.last_period.col(s) = hb.full(this_period.col(s), 2 * dealii::numbers::PI * s / S);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
} // namespace nlmech
