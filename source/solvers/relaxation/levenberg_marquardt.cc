#include <nlmech/solvers/linear/sparse_factorization.h>
#include <nlmech/solvers/relaxation/levenberg_marquardt.h>

#include <deal.II/base/exceptions.h>

#include <chrono>

namespace nlmech
{
  LevenbergMarquardtResult solve_with_levenberg_marquardt(const EquilibriumSystem &system,
                                                          const Eigen::VectorXd &load, Eigen::VectorXd &q,
                                                          const LevenbergMarquardtSettings &settings)
  {
    const auto               start = std::chrono::steady_clock::now();
    LevenbergMarquardtResult result;
    const FreeDofMap         free(system.n_unknowns(), system.fixed());
    const Eigen::VectorXd    g      = free.restrict(load);
    const double             g_norm = g.norm();
    for (const auto &f : system.fixed())
      q[f.first] = f.second;
    auto residual = [&](const Eigen::VectorXd &state) {
      return Eigen::VectorXd(free.restrict(system.internal_force(state)) - g);
    };
    Eigen::VectorXd     R  = residual(q);
    double              mu = settings.initial_damping;
    SparseFactorization factorization;
    for (result.iterations = 0; result.iterations < settings.max_iterations; ++result.iterations)
      {
        result.residual = R.norm() / g_norm;
        if (result.residual <= settings.relative_tolerance)
          {
            result.converged = true;
            break;
          }
        const Eigen::SparseMatrix<double> J        = free.restrict(system.tangent(q));
        const Eigen::SparseMatrix<double> JtJ      = Eigen::SparseMatrix<double>(J.transpose() * J);
        const Eigen::VectorXd             JtR      = J.transpose() * R;
        bool                              accepted = false;
        for (int attempt = 0; attempt < 30 && !accepted; ++attempt)
          {
            Eigen::SparseMatrix<double> A = JtJ;
            for (int k = 0; k < A.rows(); ++k)
              A.coeffRef(k, k) *= (1 + mu);
            factorization.factorize(A);
            const Eigen::VectorXd trial = q + free.expand(factorization.solve(-JtR));
            if (system.is_valid(trial))
              {
                const Eigen::VectorXd R_trial = residual(trial);
                if (R_trial.allFinite() && R_trial.norm() < R.norm())
                  {
                    q = trial, R = R_trial, accepted = true;
                    mu = std::max(mu / 10, 1e-12);
                    break;
                  }
              }
            mu *= 10;
          }
        if (!accepted)
          break;
      }
    result.residual       = R.norm() / g_norm;
    result.converged      = result.residual <= settings.relative_tolerance;
    result.factorizations = factorization.n_factorizations;
    result.seconds        = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
} // namespace nlmech
