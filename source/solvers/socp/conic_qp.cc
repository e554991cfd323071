#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/socp/conic_qp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace nlmech
{
  namespace
  {
    using Clock = std::chrono::steady_clock;
    double since(Clock::time_point t0)
    {
      return std::chrono::duration<double>(Clock::now() - t0).count();
    }

    /// u^T J u with J = diag(1, -1, ..., -1).
    double jnorm2(const Eigen::Ref<const Eigen::VectorXd> &u)
    {
      return u[0] * u[0] - u.tail(u.size() - 1).squaredNorm();
    }
    /// Jordan product of the second-order cone: (u^T v, u_0 v_1 + v_0 u_1).
    Eigen::VectorXd jordan(const Eigen::Ref<const Eigen::VectorXd> &u,
                           const Eigen::Ref<const Eigen::VectorXd> &v)
    {
      Eigen::VectorXd r(u.size());
      r[0]                 = u.dot(v);
      r.tail(u.size() - 1) = u[0] * v.tail(v.size() - 1) + v[0] * u.tail(u.size() - 1);
      return r;
    }
    /// Solves lambda o d = r for d (lambda in the interior).
    Eigen::VectorXd jordan_solve(const Eigen::Ref<const Eigen::VectorXd> &l,
                                 const Eigen::Ref<const Eigen::VectorXd> &r)
    {
      const Eigen::Index k = l.size() - 1;
      Eigen::VectorXd    d(l.size());
      d[0]      = (l[0] * r[0] - l.tail(k).dot(r.tail(k))) / jnorm2(l);
      d.tail(k) = (r.tail(k) - d[0] * l.tail(k)) / l[0];
      return d;
    }
    /// Largest alpha >= 0 with u + alpha du in the cone (u inside); infinity if unbounded.
    double step_to_boundary(const Eigen::Ref<const Eigen::VectorXd> &u,
                            const Eigen::Ref<const Eigen::VectorXd> &du)
    {
      const Eigen::Index k = u.size() - 1;
      const double       a = jnorm2(du), b = u[0] * du[0] - u.tail(k).dot(du.tail(k)), c = jnorm2(u);
      const double       disc = b * b - a * c;
      if ((a >= 0 && b >= 0) || (a > 0 && disc < 0))
        return std::numeric_limits<double>::infinity();
      // The smaller positive root of a t^2 + 2 b t + c, in the cancellation-free form.
      return c / (-b + std::sqrt(std::max(disc, 0.0)));
    }
    /// Smallest eigenvalue u_0 - |u_1| of u in the cone's Jordan algebra.
    double min_eigenvalue(const Eigen::Ref<const Eigen::VectorXd> &u)
    {
      return u[0] - u.tail(u.size() - 1).norm();
    }
  } // namespace

  std::string to_string(const ConicStatus status)
  {
    switch (status)
      {
        case ConicStatus::solved: return "solved";
        case ConicStatus::almost_solved: return "almost solved";
        case ConicStatus::primal_infeasible: return "primal infeasible";
        case ConicStatus::iteration_limit: return "iteration limit";
        default: return "numerical error";
      }
  }

  ConicQPSolver::ConicQPSolver()
  {
    cholesky.cholmod().print = 0;
  }

  void ConicQPSolver::analyse(const ConicQP &problem)
  {
    const Eigen::Index                                 n = problem.G.cols();
    const Eigen::SparseMatrix<double, Eigen::RowMajor> Gr(problem.G);
    cone_columns.assign(problem.cones.size(), {});
    std::vector<Eigen::Triplet<double>> t;
    Eigen::Index                        row = 0;
    for (std::size_t i = 0; i < problem.cones.size(); ++i)
      {
        std::vector<int> &cols = cone_columns[i];
        for (unsigned int r = 0; r < problem.cones[i]; ++r, ++row)
          for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Gr, row); it; ++it)
            cols.push_back(int(it.col()));
        std::sort(cols.begin(), cols.end());
        cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
        for (std::size_t a = 0; a < cols.size(); ++a)
          for (std::size_t b = 0; b <= a; ++b)
            t.emplace_back(cols[a], cols[b], 0.0);
      }
    for (Eigen::Index j = 0; j < n; ++j)
      t.emplace_back(j, j, 0.0);
    normal.resize(n, n);
    normal.setFromTriplets(t.begin(), t.end());
    normal.makeCompressed();
    auto slot = [&](int r, int c) {
      const int *begin = normal.innerIndexPtr() + normal.outerIndexPtr()[c];
      const int *end   = normal.innerIndexPtr() + normal.outerIndexPtr()[c + 1];
      return long(std::lower_bound(begin, end, r) - normal.innerIndexPtr());
    };
    cone_slots.assign(problem.cones.size(), {});
    for (std::size_t i = 0; i < problem.cones.size(); ++i)
      {
        const auto &cols = cone_columns[i];
        for (std::size_t a = 0; a < cols.size(); ++a)
          for (std::size_t b = 0; b <= a; ++b)
            cone_slots[i].push_back(slot(cols[a], cols[b]));
      }
    diagonal_slot.resize(std::size_t(n));
    for (Eigen::Index j = 0; j < n; ++j)
      diagonal_slot[std::size_t(j)] = slot(int(j), int(j));
    cholesky.analyzePattern(normal);
    ++n_symbolic_analyses;
    pattern_rows = problem.G.rows(), pattern_cols = n, pattern_nonzeros = problem.G.nonZeros();
    pattern_outer.assign(problem.G.outerIndexPtr(), problem.G.outerIndexPtr() + n + 1);
    pattern_inner.assign(problem.G.innerIndexPtr(), problem.G.innerIndexPtr() + problem.G.nonZeros());
  }

  void ConicQPSolver::assemble(const ConicQP &problem, const std::vector<Eigen::MatrixXd> &Winv2)
  {
    std::fill(normal.valuePtr(), normal.valuePtr() + normal.nonZeros(), 0.0);
    const double regularisation = 1e-13 * std::max(1.0, problem.P_diagonal.lpNorm<Eigen::Infinity>());
    for (std::size_t j = 0; j < diagonal_slot.size(); ++j)
      normal.valuePtr()[diagonal_slot[j]] += problem.P_diagonal[Eigen::Index(j)] + regularisation;
    for (std::size_t i = 0; i < cone_columns.size(); ++i)
      {
        const Eigen::MatrixXd local = cone_G[i].transpose() * Winv2[i] * cone_G[i];
        std::size_t           k     = 0;
        for (Eigen::Index a = 0; a < local.rows(); ++a)
          for (Eigen::Index b = 0; b <= a; ++b, ++k)
            normal.valuePtr()[cone_slots[i][k]] += local(a, b);
      }
  }

  ConicResult ConicQPSolver::solve(const ConicQP &problem, const ConicSettings &settings,
                                   const Eigen::VectorXd *x_start)
  {
    const auto         started = Clock::now();
    const Eigen::Index n = problem.G.cols(), rows = problem.G.rows();
    const std::size_t  m     = problem.cones.size();
    Eigen::Index       total = 0;
    for (const unsigned int d : problem.cones)
      {
        AssertThrow(d >= 2, dealii::ExcMessage("Conic QP: every second-order cone needs dimension >= 2."));
        total += d;
      }
    AssertThrow(total == rows && problem.h.size() == rows && problem.q.size() == n &&
                    problem.P_diagonal.size() == n && problem.G.isCompressed(),
                dealii::ExcMessage("Conic QP: inconsistent sizes of P, q, G, h and the cones."));
    AssertThrow(problem.P_diagonal.minCoeff() >= 0 && problem.P_diagonal.allFinite() &&
                    problem.q.allFinite() && problem.h.allFinite(),
                dealii::ExcMessage("Conic QP: P must be positive semi-definite and the data finite."));

    const bool same_pattern =
        rows == pattern_rows && n == pattern_cols && problem.G.nonZeros() == pattern_nonzeros &&
        std::equal(pattern_outer.begin(), pattern_outer.end(), problem.G.outerIndexPtr()) &&
        std::equal(pattern_inner.begin(), pattern_inner.end(), problem.G.innerIndexPtr());
    if (!same_pattern)
      analyse(problem);
    // Dense per-cone blocks of G on the columns each cone touches.
    {
      const Eigen::SparseMatrix<double, Eigen::RowMajor> Gr(problem.G);
      cone_G.resize(m);
      Eigen::Index row = 0;
      for (std::size_t i = 0; i < m; ++i)
        {
          const auto &cols = cone_columns[i];
          cone_G[i].setZero(problem.cones[i], Eigen::Index(cols.size()));
          for (unsigned int r = 0; r < problem.cones[i]; ++r, ++row)
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Gr, row); it; ++it)
              cone_G[i](r, std::lower_bound(cols.begin(), cols.end(), int(it.col())) - cols.begin()) =
                  it.value();
        }
    }
    std::vector<Eigen::Index> offset(m + 1, 0);
    for (std::size_t i = 0; i < m; ++i)
      offset[i + 1] = offset[i] + problem.cones[i];
    auto block  = [&](Eigen::VectorXd &v, std::size_t i) { return v.segment(offset[i], problem.cones[i]); };
    auto cblock = [&](const Eigen::VectorXd &v, std::size_t i) {
      return v.segment(offset[i], problem.cones[i]);
    };

    ConicResult result;
    auto        factorize = [&]() {
      const auto t0 = Clock::now();
      cholesky.factorize(normal);
      ++n_factorizations;
      result.factorization_seconds += since(t0);
      return cholesky.info() == Eigen::Success;
    };
    // Normal-equation solve with one step of iterative refinement.
    auto normal_solve = [&](const Eigen::VectorXd &rhs) {
      Eigen::VectorXd       x = cholesky.solve(rhs);
      const Eigen::VectorXd r = rhs - normal.selfadjointView<Eigen::Lower>() * x;
      x += cholesky.solve(r);
      return x;
    };

    // Starting point: (P + G^T G) x = -q + G^T h, s = h - G x, z = -s, shifted into the cones.
    std::vector<Eigen::MatrixXd> W(m), Winv(m), Winv2(m);
    for (std::size_t i = 0; i < m; ++i)
      Winv2[i] = Eigen::MatrixXd::Identity(problem.cones[i], problem.cones[i]);
    assemble(problem, Winv2);
    if (!factorize())
      {
        result.status  = ConicStatus::numerical_error;
        result.seconds = since(started);
        return result;
      }
    Eigen::VectorXd x = x_start ? *x_start : normal_solve(-problem.q + problem.G.transpose() * problem.h);
    Eigen::VectorXd s = problem.h - problem.G * x, z = -s;
    auto            shift = [&](Eigen::VectorXd &u) {
      double worst = -std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < m; ++i)
        worst = std::max(worst, -min_eigenvalue(cblock(u, i)));
      if (worst >= -1e-8)
        for (std::size_t i = 0; i < m; ++i)
          block(u, i)[0] += 1 + std::max(worst, 0.0);
    };
    shift(s), shift(z);

    const double    h_scale = std::max(1.0, problem.h.norm()), q_scale = std::max(1.0, problem.q.norm());
    Eigen::VectorXd lambda(rows);
    ConicStatus     status = ConicStatus::iteration_limit;
    ConicResult     last;
    last.primal_residual = last.dual_residual = last.gap = std::numeric_limits<double>::infinity();
    for (result.iterations = 0;; ++result.iterations)
      {
        const Eigen::VectorXd Gx = problem.G * x, Gtz = problem.G.transpose() * z;
        const Eigen::VectorXd rx        = problem.P_diagonal.cwiseProduct(x) + problem.q + Gtz;
        const Eigen::VectorXd rz        = s + Gx - problem.h;
        const double          gap       = s.dot(z);
        const double          objective = 0.5 * x.dot(problem.P_diagonal.cwiseProduct(x)) + problem.q.dot(x);
        result.primal_residual          = rz.norm() / h_scale;
        result.dual_residual            = rx.norm() / q_scale;
        result.gap                      = std::abs(gap) / std::max(1.0, std::abs(objective));
        result.objective                = objective;
        if (std::getenv("NLMECH_SOCP_DEBUG"))
          std::fprintf(stderr, "socp it %2u pres %.3e dres %.3e gap %.3e obj %.10g\n", result.iterations,
                       result.primal_residual, result.dual_residual, result.gap, objective);
        if (!(x.allFinite() && s.allFinite() && z.allFinite()) || !std::isfinite(result.gap))
          {
            // Back to the last finite iterate and its figures (the loose tolerances may hold).
            x = last.x, s = last.s, z = last.z;
            result.primal_residual = last.primal_residual, result.dual_residual = last.dual_residual;
            result.gap = last.gap, result.objective = last.objective;
            status = ConicStatus::numerical_error;
            break;
          }
        last.x = x, last.s = s, last.z = z, last.primal_residual = result.primal_residual;
        last.dual_residual = result.dual_residual, last.gap = result.gap, last.objective = objective;
        if (result.primal_residual <= settings.feasibility_tolerance &&
            result.dual_residual <= settings.feasibility_tolerance && result.gap <= settings.gap_tolerance)
          {
            status = ConicStatus::solved;
            break;
          }
        const double hz = problem.h.dot(z);
        if (hz < 0 && Gtz.norm() <= settings.infeasibility_tolerance * -hz)
          {
            status = ConicStatus::primal_infeasible;
            break;
          }
        if (result.iterations >= settings.max_iterations)
          break;

        // Nesterov-Todd scaling per cone: W z = W^-1 s = lambda.
        for (std::size_t i = 0; i < m; ++i)
          {
            const auto         si = cblock(s, i), zi = cblock(z, i);
            const Eigen::Index d  = si.size();
            const double       ss = std::sqrt(jnorm2(si)), zz = std::sqrt(jnorm2(zi));
            Eigen::VectorXd    sb = si / ss, zb = zi / zz;
            const double       gamma = std::sqrt(0.5 * (1 + zb.dot(sb)));
            Eigen::VectorXd    Jz    = -zb;
            Jz[0]                    = zb[0];
            const Eigen::VectorXd w  = (sb + Jz) / (2 * gamma);
            // W = eta [[w_0, w_1^T], [w_1, I + w_1 w_1^T / (1 + w_0)]] (a hyperbolic Householder
            // form; W^2 = eta^2 (2 w w^T - J)), W^-1 = J W J / eta^2.
            const double    eta = std::sqrt(ss / zz);
            Eigen::MatrixXd Wb(d, d);
            Wb(0, 0)                           = w[0];
            Wb.block(0, 1, 1, d - 1)           = w.tail(d - 1).transpose();
            Wb.block(1, 0, d - 1, 1)           = w.tail(d - 1);
            Wb.bottomRightCorner(d - 1, d - 1) = Eigen::MatrixXd::Identity(d - 1, d - 1) +
                                                 w.tail(d - 1) * w.tail(d - 1).transpose() / (1 + w[0]);
            W[i]    = eta * Wb;
            Winv[i] = Wb / eta;
            Winv[i].block(0, 1, 1, d - 1) *= -1;
            Winv[i].block(1, 0, d - 1, 1) *= -1;
            Winv2[i]         = Winv[i] * Winv[i];
            block(lambda, i) = W[i] * zi;
          }
        assemble(problem, Winv2);
        if (!factorize())
          {
            status = ConicStatus::numerical_error;
            break;
          }
        // Newton step for a right-hand side d of the linearised centrality lambda o (W^-1 ds + W dz) = ...
        auto newton = [&](const Eigen::VectorXd &d, Eigen::VectorXd &dx, Eigen::VectorXd &ds,
                          Eigen::VectorXd &dz) {
          Eigen::VectorXd t(rows);
          for (std::size_t i = 0; i < m; ++i)
            block(t, i) = Winv[i] * (Winv[i] * cblock(rz, i) + cblock(d, i));
          dx                        = normal_solve(-rx - problem.G.transpose() * t);
          const Eigen::VectorXd Gdx = problem.G * dx;
          dz.resize(rows), ds.resize(rows);
          for (std::size_t i = 0; i < m; ++i)
            {
              block(dz, i) = Winv2[i] * cblock(Gdx, i) + cblock(t, i);
              // ds = W (d - W dz) equals this; from the linear equation it keeps G x + s = h to
              // round-off where W is ill-conditioned (near the cone boundaries at the end).
              block(ds, i) = -cblock(rz, i) - cblock(Gdx, i);
            }
        };
        auto max_step = [&](const Eigen::VectorXd &ds, const Eigen::VectorXd &dz) {
          double alpha = std::numeric_limits<double>::infinity();
          for (std::size_t i = 0; i < m; ++i)
            alpha = std::min({alpha, step_to_boundary(cblock(s, i), cblock(ds, i)),
                              step_to_boundary(cblock(z, i), cblock(dz, i))});
          return alpha;
        };
        // Predictor (affine scaling): lambda o d = -lambda o lambda, i.e. d = -lambda.
        Eigen::VectorXd dx, ds, dz;
        newton(-lambda, dx, ds, dz);
        const double alpha_a = std::min(1.0, max_step(ds, dz));
        const double mu      = gap / double(m);
        const double mu_a    = (s + alpha_a * ds).dot(z + alpha_a * dz) / double(m);
        const double sigma   = std::clamp(std::pow(std::max(mu_a, 0.0) / mu, 3), 0.0, 1.0);
        // Corrector: lambda o d = sigma mu e - lambda o lambda - (W^-1 ds_a) o (W dz_a).
        Eigen::VectorXd d(rows);
        for (std::size_t i = 0; i < m; ++i)
          {
            Eigen::VectorXd r = -jordan(cblock(lambda, i), cblock(lambda, i)) -
                                jordan(Winv[i] * cblock(ds, i), W[i] * cblock(dz, i));
            r[0] += sigma * mu;
            block(d, i) = jordan_solve(cblock(lambda, i), r);
          }
        newton(d, dx, ds, dz);
        const double alpha = std::min(1.0, settings.step_fraction * max_step(ds, dz));
        x += alpha * dx, s += alpha * ds, z += alpha * dz;
        if (alpha < 1e-10)
          break; // stalled
      }
    if (status == ConicStatus::iteration_limit || status == ConicStatus::numerical_error)
      {
        const double loose = settings.almost_factor;
        if (result.primal_residual <= loose * settings.feasibility_tolerance &&
            result.dual_residual <= loose * settings.feasibility_tolerance &&
            result.gap <= loose * settings.gap_tolerance)
          status = ConicStatus::almost_solved;
      }
    result.status = status;
    result.x = x, result.s = s, result.z = z;
    result.seconds = since(started);
    return result;
  }
} // namespace nlmech
