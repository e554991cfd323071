#pragma once
// A sparse LU factorisation (UMFPACK) of a general square matrix with solves by the matrix and by
// its transpose from the same factors: the sensitivity S = -J^-1 dh/dp and the adjoint
// J^T lambda = df/dz of harmonic-balance design need both. When the matrix is (numerically)
// singular, or a solve leaves a residual above 1e-8 |b|, the diagonal is regularised adaptively
// (thesis 2.4.1): J + eps d I with d the largest diagonal magnitude, eps = 1e-12, 1e-10, ... 1e-4.

#include <Eigen/Sparse>

#include <vector>

namespace nlmech
{
  class LuFactorization
  {
  public:
    LuFactorization() = default;
    ~LuFactorization();
    LuFactorization(const LuFactorization &)            = delete;
    LuFactorization &operator=(const LuFactorization &) = delete;

    /// Factorises A (square); throws a clear error when even the largest regularisation fails.
    void factorize(const Eigen::SparseMatrix<double> &A);
    /// x with A x = b (transposed: A^T x = b), regularised as needed.
    Eigen::VectorXd solve(const Eigen::VectorXd &b, bool transposed = false);
    /// The regularisation eps now in use (0: none).
    double regularization() const { return epsilon; }

  private:
    bool factor_with(double eps);
    void release();

    Eigen::SparseMatrix<double> matrix, shifted;
    void                       *symbolic = nullptr, *numeric = nullptr;
    std::vector<int>            pattern_outer, pattern_inner; // the pattern `symbolic` was made for
    double                      epsilon = 0, diagonal_scale = 1;
  };
} // namespace nlmech
