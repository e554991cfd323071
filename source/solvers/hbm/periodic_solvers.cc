#include <deal.II/base/exceptions.h>
#include <deal.II/lac/vector.h>
#include <deal.II/sundials/kinsol.h>

#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
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

    /// [[J, h_w], [row^T, row_omega]] for the bordered systems of the continuation (2.3.19), copied
    /// column by column into compressed storage (J is compressed, the new row is the last).
    Eigen::SparseMatrix<double> bordered(const Eigen::SparseMatrix<double> &J, const Eigen::VectorXd &h_omega,
                                         const Eigen::VectorXd &row_z, double row_omega)
    {
      AssertThrow(J.isCompressed(), dealii::ExcMessage("bordered: the Jacobian must be compressed."));
      const Eigen::Index          n = J.rows();
      Eigen::SparseMatrix<double> B(n + 1, n + 1);
      B.resizeNonZeros(J.nonZeros() + (row_z.array() != 0).count() + (h_omega.array() != 0).count() + 1);
      Eigen::Index k = 0;
      for (Eigen::Index c = 0; c < n; ++c)
        {
          B.outerIndexPtr()[c] = int(k);
          for (Eigen::Index e = J.outerIndexPtr()[c]; e < J.outerIndexPtr()[c + 1]; ++e, ++k)
            B.innerIndexPtr()[k] = J.innerIndexPtr()[e], B.valuePtr()[k] = J.valuePtr()[e];
          if (row_z[c] != 0)
            B.innerIndexPtr()[k] = int(n), B.valuePtr()[k++] = row_z[c];
        }
      B.outerIndexPtr()[n] = int(k);
      for (Eigen::Index i = 0; i < n; ++i)
        if (h_omega[i] != 0)
          B.innerIndexPtr()[k] = int(i), B.valuePtr()[k++] = h_omega[i];
      B.innerIndexPtr()[k] = int(n), B.valuePtr()[k++] = row_omega;
      B.outerIndexPtr()[n + 1] = int(k);
      return B;
    }

    /// Continuation state with its unit tangent (weighted norm) and the amplitude slope dA/ds.
    struct PathPoint
    {
      Eigen::VectorXd z, tz, row_z;
      double          omega = 0, tomega = 0, amplitude = 0, dA_ds = 0, row_omega = 0, scale = 1;
      double          step       = 0; // the predictor step along tz that led to the next point on the path
      unsigned int    iterations = 0;
    };
  } // namespace

  double force_scale(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double omega)
  {
    // Inertial forces of the motion and the forcing amplitudes. Not the drive penalties: a stiff
    // penalty's force at rest (stiffness x amplitude) would make every relative tolerance meaningless.
    double scale = 0;
    for (std::size_t i = 0; i < hb.n_free(); ++i)
      for (unsigned int k = 1; k <= hb.n_harmonics(); ++k)
        {
          const auto sc = hb.coefficient(z, i, k);
          scale =
              std::max(scale, std::pow(k * omega, 2) * hb.free_mass()[i] * std::hypot(sc.first, sc.second));
        }
    for (const auto &f : hb.harmonic_forces())
      scale = std::max(scale, hb.excitation_scale() * std::abs(f.amplitude));
    // Inertial force of a driven unknown: w^2 m times its acceleration-weighted motion.
    auto drive_scale = [&](const HarmonicDrive &d) {
      double size = std::abs(d.amplitude);
      for (std::size_t k = 1; k <= d.sine.size(); ++k)
        size += double(k * k) * std::abs(d.sine[k - 1]);
      for (std::size_t k = 1; k <= d.cosine.size(); ++k)
        size += double(k * k) * std::abs(d.cosine[k - 1]);
      return std::pow(omega, 2) * hb.model().lumped_mass()[d.dof] * hb.excitation_scale() * size;
    };
    for (const auto &d : hb.prescribed_drives())
      scale = std::max(scale, drive_scale(d));
    for (const auto &d : hb.harmonic_drives())
      scale = std::max(scale, drive_scale(d));
    return std::max(scale, 1e-300);
  }

  double residual_floor(const HarmonicBalance &hb, const Eigen::VectorXd &z)
  {
    const Eigen::VectorXd             x = hb.full(z.head(hb.n_free()));
    const Eigen::SparseMatrix<double> K = hb.model().hessian(x);
    double                            k = 0;
    for (Eigen::Index i = 0; i < K.rows(); ++i)
      k = std::max(k, std::abs(K.coeff(i, i)));
    return 100 * std::numeric_limits<double>::epsilon() * k * std::max(x.lpNorm<Eigen::Infinity>(), 1e-300);
  }

  PeriodicSolveResult solve_periodic_state(const HarmonicBalance &hb, Eigen::VectorXd &z, const double omega,
                                           const PeriodicSolveSettings &settings)
  {
    PeriodicSolveResult result;
    const double        scale = force_scale(hb, z, omega);
    const double        floor = residual_floor(hb, z);
    using KINSOL              = dealii::SUNDIALS::KINSOL<dealii::Vector<double>>;
    KINSOL::AdditionalData data(KINSOL::AdditionalData::linesearch, settings.max_iterations,
                                std::max(settings.relative_tolerance * scale, floor),
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
    result.converged =
        h.allFinite() && h.lpNorm<Eigen::Infinity>() <=
                             10 * std::max(std::max(settings.relative_tolerance, 1e-13) * scale, floor);
    if (result.converged)
      z = candidate;
    else if (result.message.empty())
      result.message = "relative residual " + std::to_string(result.residual);
    return result;
  }

  PeriodicSolveResult solve_with_excitation_ramp(const HarmonicBalance &hb, Eigen::VectorXd &z,
                                                 const double omega, const PeriodicSolveSettings &settings)
  {
    PeriodicSolveResult result = solve_periodic_state(hb, z, omega, settings);
    if (result.converged)
      return result;
    // Continuation in the excitation amplitude from the state given (e.g. rest, where the
    // linearisation is poor for thin structures: membranes only stiffen out of plane when stretched).
    double       done = 0, step = 0.1;
    unsigned int total = result.iterations;
    while (done < 1)
      {
        const double    next  = std::min(1.0, done + step);
        Eigen::VectorXd trial = z;
        hb.set_excitation_scale(next);
        result = solve_periodic_state(hb, trial, omega, settings);
        total += result.iterations;
        if (std::getenv("NLMECH_HBM_DEBUG"))
          std::cerr << "ramp " << next << " converged " << result.converged << " residual " << result.residual
                    << " scale " << force_scale(hb, trial, omega) << std::endl;
        if (result.converged)
          z = trial, done = next, step = std::min(0.5, 1.5 * step);
        else if ((step *= 0.5) < 1e-4)
          break;
      }
    hb.set_excitation_scale(1.0);
    result.iterations = total;
    if (done < 1)
      {
        result.converged = false;
        result.message   = "the excitation ramp stalled at " + std::to_string(done) + " of the amplitude";
      }
    return result;
  }

  FloquetResult floquet_stability(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double omega,
                                  const unsigned int min_steps, const double tolerance)
  {
    const std::size_t      n     = hb.n_free();
    const double           T     = 2 * pi / omega;
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
    // Explicit RK4 is stable for |lambda dt| below about 2.8 on the imaginary axis: stiff parts
    // (penalty links, membranes) with eigenvalues far above w would blow up and fake an
    // instability. Steps so that |lambda|_max dt <= 1, from the spectrum at t = 0.
    const double fastest =
        Eigen::EigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(A0), false).eigenvalues().cwiseAbs().maxCoeff();
    AssertThrow(std::isfinite(fastest), dealii::ExcMessage("Floquet: the linearised system is not finite."));
    const unsigned int steps = std::max(min_steps, unsigned(std::min(2e6, std::ceil(T * fastest))));
    const double       dt    = T / steps;
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

  HillResult hill_stability(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double omega,
                            const std::function<Eigen::VectorXd(const Eigen::VectorXd &)> &solve_jacobian,
                            const double tolerance, const unsigned int max_krylov_dimension)
  {
    const Eigen::SparseMatrix<double> D1 = hb.hill_damping(z, omega);
    const Eigen::Index                N = D1.rows(), n = Eigen::Index(hb.n_free());
    SparseFactorization               own;
    if (!solve_jacobian)
      own.factorize(hb.jacobian(z, omega), false);
    auto solve = [&](const Eigen::VectorXd &b) { return solve_jacobian ? solve_jacobian(b) : own.solve(b); };
    // Delta_2: the free masses in every harmonic block.
    Eigen::VectorXd D2(N);
    for (Eigen::Index b = 0; b < N / n; ++b)
      D2.segment(b * n, n) = hb.free_mass();
    // First-order form A y = lambda B y with y = (u, lambda u), A = [[0, I], [-D0, -D1]],
    // B = diag(I, D2). Shift-and-invert at 0: T = A^-1 B, theta = 1 / lambda,
    // T (y1, y2) = (-D0^-1 (D1 y1 + D2 y2), y1).
    auto apply = [&](const Eigen::VectorXd &y) {
      Eigen::VectorXd out(2 * N);
      out.head(N) = -solve(D1 * y.head(N) + D2.cwiseProduct(y.tail(N)));
      out.tail(N) = y.head(N);
      return out;
    };
    const Eigen::Index m_max  = std::min<Eigen::Index>(2 * N, max_krylov_dimension);
    const double       radius = omega, T       = 2 * pi / omega;
    Eigen::MatrixXd    V(2 * N, m_max + 1), Hm = Eigen::MatrixXd::Zero(m_max + 1, m_max);
    // A fixed, generic start vector (a deterministic pseudo-random sequence).
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    for (Eigen::Index i = 0; i < 2 * N; ++i)
      {
        state ^= state << 13, state ^= state >> 7, state ^= state << 17;
        V(i, 0) = double(state % 2000001) / 1e6 - 1.0;
      }
    V.col(0).normalize();
    HillResult   result;
    Eigen::Index m         = 0;
    bool         invariant = false;
    while (true)
      {
        const Eigen::Index target = std::min(m_max, m == 0 ? std::min<Eigen::Index>(m_max, 30) : m + 30);
        for (; m < target && !invariant; ++m)
          {
            Eigen::VectorXd w = apply(V.col(m));
            AssertThrow(w.allFinite(),
                        dealii::ExcMessage("Hill's method: the solve with the Jacobian failed."));
            const double norm0 = w.norm();
            // Classical Gram-Schmidt, twice (full reorthogonalisation).
            for (int pass = 0; pass < 2; ++pass)
              {
                const Eigen::VectorXd h = V.leftCols(m + 1).transpose() * w;
                w -= V.leftCols(m + 1) * h;
                Hm.col(m).head(m + 1) += h;
              }
            Hm(m + 1, m) = w.norm();
            if (Hm(m + 1, m) <= 1e-13 * norm0)
              invariant = true, Hm(m + 1, m) = 0;
            else
              V.col(m + 1) = w / Hm(m + 1, m);
          }
        // Ritz pairs; residual |h_{m+1,m}| |e_m^T s| of unit eigenvectors s.
        Eigen::EigenSolver<Eigen::MatrixXd> eig(Hm.topLeftCorner(m, m), true);
        const double                        beta          = Hm(m, m - 1);
        bool                                all_converged = true;
        unsigned int                        inside        = 0;
        result.exponents.clear();
        double max_real = -std::numeric_limits<double>::infinity();
        for (Eigen::Index i = 0; i < m; ++i)
          {
            const std::complex<double> theta = eig.eigenvalues()[i];
            if (std::abs(theta) * radius < 1) // |lambda| > radius
              continue;
            ++inside;
            const double residual =
                beta * std::abs(eig.eigenvectors()(m - 1, i)) / eig.eigenvectors().col(i).norm();
            if (residual > 1e-8 * std::abs(theta))
              {
                all_converged = false;
                continue;
              }
            const std::complex<double> lambda = 1.0 / theta;
            if (std::abs(lambda.imag()) <= 0.5 * omega * (1 + 1e-9))
              {
                result.exponents.push_back(lambda);
                max_real = std::max(max_real, lambda.real());
              }
          }
        result.krylov_dimension = unsigned(m);
        // Done when everything within the radius has converged and the Krylov space reaches well
        // beyond it (half of the Ritz values outside), or the space is exhausted.
        const bool done = (all_converged && 2 * Eigen::Index(inside) < m) || invariant || m >= m_max;
        if (!done)
          continue;
        result.determined = all_converged;
        if (max_real == -std::numeric_limits<double>::infinity())
          max_real = -std::sqrt(0.75) * radius; // no exponent within the radius: all are below this
        result.max_real_part  = max_real;
        result.max_multiplier = std::exp(max_real * T);
        result.stable         = max_real * T <= std::log1p(tolerance);
        std::sort(result.exponents.begin(), result.exponents.end(),
                  [](auto a, auto b) { return a.real() > b.real(); });
        return result;
      }
  }

  FrequencyResponse trace_frequency_response(const HarmonicBalance &hb, Eigen::VectorXd z,
                                             const ContinuationSettings &settings)
  {
    AssertThrow(settings.omega_start > 0 && settings.omega_end > 0 &&
                    settings.omega_start != settings.omega_end,
                dealii::ExcMessage("The frequency range needs two different positive frequencies."));
    AssertThrow(!settings.tracked_dofs.empty(), dealii::ExcMessage("No tracked unknowns for the amplitude."));
    FrequencyResponse response;
    const auto        started = std::chrono::steady_clock::now();
    auto              since   = [](std::chrono::steady_clock::time_point t0) {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    // Timed evaluations of h, its Jacobian and dh/dw.
    auto residual = [&](const Eigen::VectorXd &z, double w) {
      const auto      t0 = std::chrono::steady_clock::now();
      Eigen::VectorXd h  = hb.residual(z, w);
      response.residual_seconds += since(t0), ++response.residuals;
      return h;
    };
    auto jacobian = [&](const Eigen::VectorXd &z, double w, Eigen::VectorXd &hw) {
      const auto                  t0 = std::chrono::steady_clock::now();
      Eigen::SparseMatrix<double> J  = hb.jacobian(z, w);
      hw                             = hb.d_residual_d_omega(z, w);
      response.jacobian_seconds += since(t0), ++response.jacobians;
      return J;
    };
    const double          direction = settings.omega_end > settings.omega_start ? 1.0 : -1.0;
    PeriodicSolveSettings fixed;
    fixed.relative_tolerance        = settings.relative_tolerance;
    const PeriodicSolveResult first = solve_with_excitation_ramp(hb, z, settings.omega_start, fixed);
    AssertThrow(first.converged,
                dealii::ExcMessage("Harmonic balance: no periodic state found at the start "
                                   "frequency " +
                                   std::to_string(settings.omega_start) + " rad/s (" + first.message + ")."));
    // Weighted norm: z in units of its harmonic size at the start, w in units of the range.
    double z_ref       = z.tail(z.size() - Eigen::Index(hb.n_free())).norm();
    z_ref              = std::max(z_ref, 1e-9 * std::max(1.0, z.head(hb.n_free()).lpNorm<Eigen::Infinity>()));
    const double w_ref = std::abs(settings.omega_end - settings.omega_start);
    const double z_ref_start = z_ref;
    double       wz          = 1 / (z_ref * z_ref);
    const double ww          = 1 / (w_ref * w_ref);
    const double floor       = residual_floor(hb, z); // round-off level of the residual (positions ~ |x|)
    auto         norm        = [&](const Eigen::VectorXd &dz, double dw) {
      return std::sqrt(wz * dz.squaredNorm() + ww * dw * dw);
    };

    // `at_current`: the bordered matrix of the last tangent, [J(y_i), h_w(y_i); r_i^T], with the
    // border row r_i = W t_{i-1}; the corrector from y_i reuses it (chord Newton) with the hyperplane
    // r_i^T (y - y_pred) = 0, and refactorises only when that stalls.
    SparseFactorization at_current, work;
    // Tangent at (z, w) with the sign of the previous tangent (2.3.19).
    auto tangent = [&](PathPoint &p, const Eigen::VectorXd &row_z, double row_omega) {
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
    };
    // Corrector from the prediction y_i + ds t_i on the hyperplane r_i^T (y - y_pred) = 0. With
    // `chord`, `at_current` must hold the factorisation at `from`.
    auto correct = [&](const PathPoint &from, const double ds, PathPoint &to, bool chord) {
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
            std::cerr << "corrector it " << it << " w " << to.omega << " r/scale " << r / from.scale
                      << " arc " << arc << " ds " << ds << (chord ? " chord" : " newton") << std::endl;
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
    };

    PathPoint current;
    current.z = z, current.omega = settings.omega_start;
    tangent(current, Eigen::VectorXd::Zero(z.size()), ww * direction);
    current.iterations = first.iterations;
    auto record        = [&](const PathPoint &p) {
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
              const HillResult h = std::abs(p.tomega) > 0 ? hill_stability(hb, p.z, p.omega, solve)
                                                                 : hill_stability(hb, p.z, p.omega);
              r.stable = h.determined ? int(h.stable) : -1, r.max_multiplier = h.max_multiplier;
              r.hill = true;
            }
          catch (const std::exception &)
            {
              r.stable = -1; // exactly singular (at a fold): left undetermined
            }
        }
      response.stability_seconds += since(started);
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
        double    distance = 0; // of the corrected point from the prediction, weighted norm
        bool      accepted = correct(current, ds, next, true);
        if (accepted)
          {
            // Step control: the corrected point near the prediction, the curve turning by less than
            // about 30 degrees; otherwise the corrector may have jumped to another part of the curve.
            distance =
                norm(next.z - current.z - ds * current.tz, next.omega - current.omega - ds * current.tomega);
            accepted = distance <= 0.5 * ds;
            if (accepted)
              {
                tangent(next, wz * current.tz, ww * current.tomega);
                accepted = wz * next.tz.dot(current.tz) + ww * next.tomega * current.tomega >= 0.85;
                if (!accepted) // restore the factorisation at the current point
                  tangent(current, current.row_z, current.row_omega);
              }
          }
        if (!accepted)
          {
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
        if ((next.omega - settings.omega_start) * direction < -0.5 * w_ref)
          {
            response.stop_reason = "the curve turned back far below the start frequency";
            break;
          }
        // Step size: grow where the corrector was quick or the prediction close (stiff structures,
        // rods, need several corrector iterations for their stretching forces however small the
        // step: the distance in the weighted norm tells the curve's own curvature).
        if (next.iterations <= 4 || distance <= 0.1 * ds)
          ds = std::min(settings.max_step, 1.5 * ds);
        else if (next.iterations >= 8 || distance > 0.3 * ds)
          ds *= 0.7;
        current = next;
        // The weight of z follows the size of the motion (never below its size at the start): a
        // resonance many times larger than the start's motion would otherwise be crossed in tiny
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
    // Resonance peaks: dA/ds from + to -; refined on the curve by the secant method on arclength.
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
      if (path[i].dA_ds > 0 && path[i + 1].dA_ds <= 0)
        {
          double a = 0, b = 0;
          // arclength between the points in the weighted norm, along the chord
          // (the step that produced path[i + 1], so that both ends are the same function of s)
          b            = path[i].step > 0 ? path[i].step
                                          : norm(path[i + 1].z - path[i].z, path[i + 1].omega - path[i].omega);
          double    ga = path[i].dA_ds, gb = path[i + 1].dA_ds;
          PathPoint best = std::abs(ga) < std::abs(gb) ? path[i] : path[i + 1];
          for (int it = 0; it < 12 && std::abs(b - a) > 1e-10 * (1 + b); ++it)
            {
              const double s = b - gb * (b - a) / (gb - ga);
              PathPoint    trial;
              if (!correct(path[i], s, trial, false))
                break;
              tangent(trial, wz * path[i].tz, ww * path[i].tomega);
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
    response.factorizations        = at_current.n_factorizations + work.n_factorizations;
    response.factorization_seconds = at_current.factorization_seconds + work.factorization_seconds;
    response.solve_seconds         = at_current.solve_seconds + work.solve_seconds;
    response.seconds               = since(started);
    return response;
  }

  HarmonicsChoice choose_harmonics(const Model &model, const HarmonicBalanceSettings &settings_in,
                                   const std::vector<HarmonicForce> &forces,
                                   const std::vector<HarmonicDrive> &drives,
                                   const Eigen::VectorXd &static_state, const double omega,
                                   const double threshold, const unsigned int first, const unsigned int last,
                                   const unsigned int step)
  {
    AssertThrow(
        first >= 1 && step >= 1 && last >= first && threshold > 0 && omega > 0,
        dealii::ExcMessage("choose_harmonics: needs 1 <= first <= last, step >= 1, a positive threshold "
                           "and frequency."));
    HarmonicsChoice     choice;
    Eigen::VectorXd     previous_z;
    Eigen::MatrixXd     previous;
    std::vector<double> t(256);
    for (std::size_t j = 0; j < t.size(); ++j)
      t[j] = 2 * pi / omega * double(j) / double(t.size());
    for (unsigned int H = first; H <= last; H += step)
      {
        HarmonicBalanceSettings settings = settings_in;
        settings.n_harmonics             = H;
        if (settings_in.n_samples != 0)
          settings.n_samples = std::max(settings_in.n_samples, 2 * H + 1);
        const HarmonicBalance hb(model, settings, forces, drives);
        Eigen::VectorXd       z = hb.static_coefficients(static_state);
        if (previous_z.size() > 0) // the lower harmonics from the previous solution
          z.head(std::min(z.size(), previous_z.size())) =
              previous_z.head(std::min(z.size(), previous_z.size()));
        const PeriodicSolveResult r = solve_with_excitation_ramp(hb, z, omega);
        AssertThrow(r.converged, dealii::ExcMessage("choose_harmonics: no periodic state at N_H = " +
                                                    std::to_string(H) + " (" + r.message + ")."));
        Eigen::MatrixXd x  = hb.positions_at(z, omega, t);
        choice.n_harmonics = H, choice.z = z;
        if (previous.size() > 0)
          {
            double size = 0;
            for (Eigen::Index i = 0; i < x.rows(); ++i)
              size = std::max(size, x.row(i).maxCoeff() - x.row(i).minCoeff());
            const double change = (x - previous).lpNorm<Eigen::Infinity>() / std::max(size, 1e-300);
            choice.changes.emplace_back(H, change);
            if (change < threshold)
              {
                choice.converged = true;
                break;
              }
          }
        previous = std::move(x), previous_z = z;
      }
    return choice;
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
      result.last_period.col(s) = hb.full(this_period.col(s), 2 * pi * s / S);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
} // namespace nlmech
