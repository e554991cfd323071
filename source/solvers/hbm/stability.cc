// Stability of a periodic state: Floquet multipliers from the monodromy matrix (time domain, dense)
// and Hill's method (the Floquet exponents from the HBM Jacobian by shift-and-invert Arnoldi).
#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
  } // namespace

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
} // namespace nlmech
