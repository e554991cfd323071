#include <nlmech/solvers/linear/sparse_factorization.h>
#include <nlmech/solvers/newton/newton_solver.h>
#include <nlmech/solvers/relaxation/kinetic_damping.h>

#include <deal.II/base/exceptions.h>

#include <chrono>
#include <cmath>

namespace nlmech
{
  namespace
  {
    /// (1 / 2 dt^2) (x - x_hat)^T M (x - x_hat): the inertia of an implicit Euler step.
    class InertiaTerm : public EnergyTerm
    {
    public:
      InertiaTerm(const Eigen::VectorXd &mass, const Eigen::VectorXd &predicted, double dt)
          : mass(mass)
          , predicted(predicted)
          , scale(1.0 / (dt * dt))
      {
      }
      std::string name() const override { return "inertia"; }
      double      value(const Eigen::VectorXd &x) const override
      {
        const Eigen::VectorXd d = x - predicted;
        return 0.5 * scale * d.dot(mass.cwiseProduct(d));
      }
      void add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const override
      {
        g += scale * mass.cwiseProduct(x - predicted);
      }
      void add_hessian(const Eigen::VectorXd &, Triplets &h) const override
      {
        for (int i = 0; i < mass.size(); ++i)
          if (mass[i] > 0)
            h.emplace_back(i, i, scale * mass[i]);
      }

    private:
      const Eigen::VectorXd &mass;
      Eigen::VectorXd        predicted;
      double                 scale;
    };
  } // namespace

  KineticDampingResult solve_with_kinetic_damping(const Model &internal, const Eigen::VectorXd &load,
                                                  Eigen::VectorXd &x, const KineticDampingSettings &settings)
  {
    const auto             start = std::chrono::steady_clock::now();
    KineticDampingResult   result;
    const FreeDofMap       free(internal);
    const Eigen::VectorXd &M      = internal.lumped_mass();
    const double           g_norm = free.restrict(load).norm();
    AssertThrow(g_norm > 0, dealii::ExcMessage("Kinetic damping needs a non-zero load."));
    AssertThrow(
        free.restrict(M).minCoeff() > 0,
        dealii::ExcMessage("Kinetic damping needs a positive mass at every free unknown (set a density)."));
    for (const auto &f : internal.fixed())
      x[f.first] = f.second;

    double dt = settings.time_step;
    if (dt <= 0)
      {
        // Period of the load's linear response: omega^2 = u^T K u / u^T M u with K u = g.
        SparseFactorization               factorization;
        const Eigen::SparseMatrix<double> K = free.restrict(internal.hessian(x));
        factorization.factorize(K);
        ++result.factorizations;
        const Eigen::VectorXd u      = factorization.solve(free.restrict(load));
        const double          omega2 = u.dot(K * u) / u.dot(free.restrict(M).cwiseProduct(u));
        dt                           = 2 * M_PI / std::sqrt(omega2) / 20;
      }
    result.time_step = dt;

    Eigen::VectorXd v              = Eigen::VectorXd::Zero(x.size());
    double          kinetic_before = 0;
    Model           loaded         = internal;
    loaded.add_term(std::make_shared<ConstantForceTerm>("load", load));
    for (result.time_steps = 0; result.time_steps < settings.max_time_steps; ++result.time_steps)
      {
        result.residual = free.restrict(loaded.gradient(x)).norm() / g_norm;
        if (result.residual <= settings.relative_tolerance)
          {
            result.converged = true;
            break;
          }
        Model step = loaded;
        step.add_term(std::make_shared<InertiaTerm>(M, x + dt * v, dt));
        Eigen::VectorXd x_new = x;
        NewtonSettings  newton;
        newton.relative_tolerance = 0;
        newton.absolute_tolerance = 0.1 * settings.relative_tolerance * g_norm;
        // Large meshes: the gradient's round-off floor may lie above a tenth of the tolerance.
        newton.stagnation_tolerance = settings.relative_tolerance * g_norm;
        const NewtonResult r        = minimize_with_newton(step, x_new, newton);
        result.newton_iterations += r.iterations;
        result.factorizations += r.factorizations;
        v                    = (x_new - x) / dt;
        x                    = x_new;
        const double kinetic = 0.5 * v.dot(M.cwiseProduct(v));
        if (kinetic < kinetic_before)
          {
            v.setZero(); // kinetic damping: the kinetic energy peaked, restart from rest here
            ++result.velocity_resets;
            kinetic_before = 0;
          }
        else
          kinetic_before = kinetic;
      }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
} // namespace nlmech
