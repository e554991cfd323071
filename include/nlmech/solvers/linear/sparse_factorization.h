#pragma once
// A cached sparse factorisation of a symmetric matrix: CHOLMOD supernodal Cholesky when the matrix
// is positive definite, UMFPACK LU otherwise (past a limit point). The symbolic analysis is reused
// while the sparsity pattern does not change; factorisations, solves and their times are counted.

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>

namespace nlmech
{
  class SparseFactorization
  {
  public:
    SparseFactorization();

    /// Factorises A (Cholesky tried first only when `symmetric`); throws if A is singular. Every
    /// solve checks |A x - b| <= 1e-6 |b|, which catches (numerically) singular matrices whose
    /// factorisation went through with tiny pivots.
    void            factorize(const Eigen::SparseMatrix<double> &A, bool symmetric = true);
    Eigen::VectorXd solve(const Eigen::VectorXd &b);
    bool            positive_definite() const { return use_cholesky; }

    unsigned int n_factorizations = 0, n_solves = 0;
    double       factorization_seconds = 0, solve_seconds = 0;

  private:
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholesky;
    Eigen::UmfPackLU<Eigen::SparseMatrix<double>>            lu;
    Eigen::SparseMatrix<double> lu_matrix; // UMFPACK's solve reads the matrix: it must outlive it
    Eigen::SparseMatrix<double> matrix;    // for the residual check of every solve
    long                        cholesky_pattern = -1, lu_pattern = -1;
    double                      default_ordering = 0, default_strategy = 0; // UMFPACK's own
    bool                        use_cholesky = true;
  };
} // namespace nlmech
