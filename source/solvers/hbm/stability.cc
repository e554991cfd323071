// Stability of a periodic state: Floquet multipliers from the monodromy matrix (time domain, dense)
// and Hill's method (the Floquet exponents from the HBM Jacobian by shift-and-invert Arnoldi, ARPACK).
#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/arpack_eigenvalues.h>
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
                            const double tolerance, const unsigned int max_krylov_dimension,
                            const unsigned int first_request)
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
    const Eigen::Index dim   = 2 * N;
    auto               apply = [&](const double *x, double *y) {
      const Eigen::Map<const Eigen::VectorXd> in(x, dim);
      Eigen::Map<Eigen::VectorXd>             out(y, dim);
      const Eigen::VectorXd                   top = -solve(D1 * in.head(N) + D2.cwiseProduct(in.tail(N)));
      AssertThrow(top.allFinite(), dealii::ExcMessage("Hill's method: the solve with the Jacobian failed."));
      out.head(N) = top;
      out.tail(N) = in.head(N);
    };
    const double radius = omega, T = 2 * pi / omega;
    // Every eigenvalue with |lambda| < radius is wanted: two copies (|Im| < w) of each exponent
    // family the harmonics resolve (modes below about N_H w). ARPACK is asked for `first_request`
    // of largest |theta| (the continuation passes the previous point's count), and for twice as
    // many while the smallest one it returns still lies within the radius.
    const Eigen::Index cap     = std::min<Eigen::Index>(dim, max_krylov_dimension);
    const Eigen::Index largest = (cap - 1) / 2; // so that the basis holds 2 nev + 1 vectors
    Eigen::Index nev = std::min<Eigen::Index>(first_request > 0 ? Eigen::Index(first_request) : 24, largest);
    std::vector<std::complex<double>> thetas;
    HillResult                        result;
    while (nev >= 1)
      {
        ArpackSettings as;
        as.n_eigenvalues        = unsigned(nev);
        as.n_arnoldi            = unsigned(2 * nev + 1);
        as.tolerance            = 1e-12;
        const ArpackResult r    = largest_eigenvalues(apply, unsigned(dim), as);
        result.krylov_dimension = r.n_arnoldi;
        result.requested        = unsigned(nev);
        result.operator_products += r.products;
        thetas                   = r.eigenvalues;
        const bool all_converged = r.n_converged >= unsigned(nev);
        const bool beyond =
            !thetas.empty() && std::abs(thetas.back()) * radius < 1; // the smallest |theta| is outside
        result.determined = all_converged && beyond;
        if (result.determined || !all_converged || nev >= largest)
          break;
        nev = std::min<Eigen::Index>(2 * nev, largest);
      }
    if (!result.determined && dim <= Eigen::Index(max_krylov_dimension))
      {
        // A small problem whose radius holds nearly all eigenvalues: the dense operator.
        Eigen::MatrixXd Td(dim, dim);
        Eigen::VectorXd e = Eigen::VectorXd::Zero(dim);
        for (Eigen::Index j = 0; j < dim; ++j)
          {
            e[j] = 1;
            apply(e.data(), Td.col(j).data());
            e[j] = 0;
          }
        const Eigen::VectorXcd all = Eigen::EigenSolver<Eigen::MatrixXd>(Td, false).eigenvalues();
        thetas.assign(all.data(), all.data() + all.size());
        result.determined       = true;
        result.krylov_dimension = unsigned(dim);
      }
    double max_real = -std::numeric_limits<double>::infinity();
    for (const std::complex<double> theta : thetas)
      {
        if (std::abs(theta) * radius < 1) // |lambda| > radius
          continue;
        ++result.within_radius;
        const std::complex<double> lambda = 1.0 / theta;
        if (std::abs(lambda.imag()) <= 0.5 * omega * (1 + 1e-9))
          {
            result.exponents.push_back(lambda);
            max_real = std::max(max_real, lambda.real());
          }
      }
    if (max_real == -std::numeric_limits<double>::infinity())
      max_real = -std::sqrt(0.75) * radius; // no exponent within the radius: all are below this
    result.max_real_part  = max_real;
    result.max_multiplier = std::exp(max_real * T);
    result.stable         = max_real * T <= std::log1p(tolerance);
    std::sort(result.exponents.begin(), result.exponents.end(),
              [](auto a, auto b) { return a.real() > b.real(); });
    return result;
  }
} // namespace nlmech
