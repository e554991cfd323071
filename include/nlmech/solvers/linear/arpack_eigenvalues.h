#pragma once
// Eigenvalues of largest magnitude of a real nonsymmetric operator given only by its action, by
// ARPACK's implicitly restarted Arnoldi method (dnaupd/dneupd, regular mode).

#include <complex>
#include <functional>
#include <vector>

namespace nlmech
{
  struct ArpackSettings
  {
    unsigned int n_eigenvalues = 6;     // wanted eigenvalues of largest magnitude (at most dimension - 2)
    unsigned int n_arnoldi     = 0;     // Krylov basis size (0: 2 n_eigenvalues + 1, within the dimension)
    double       tolerance     = 1e-12; // relative Ritz residual |A x - theta x| <= tol |theta|
    unsigned int max_restarts  = 1000;
  };

  struct ArpackResult
  {
    /// The converged Ritz values, largest magnitude first (complex pairs both listed).
    std::vector<std::complex<double>> eigenvalues;
    unsigned int                      n_converged = 0; // of the n_eigenvalues wanted
    unsigned int                      n_arnoldi   = 0;
    unsigned int                      restarts    = 0;
    unsigned int                      products    = 0; // applications of the operator
  };

  /// `apply(x, y)` sets y = A x for vectors of length `dimension`. Throws on an ARPACK error (bad
  /// sizes, a failed factorisation inside ARPACK); too few converged values within the restarts
  /// are reported in n_converged, not thrown.
  ArpackResult largest_eigenvalues(const std::function<void(const double *x, double *y)> &apply,
                                   unsigned int dimension, const ArpackSettings &settings);
} // namespace nlmech
