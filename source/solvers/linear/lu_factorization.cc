#include <deal.II/base/exceptions.h>

#include <nlmech/base/serial_blas.h>
#include <nlmech/solvers/linear/lu_factorization.h>

#include <umfpack.h>

#include <algorithm>
#include <string>
#include <vector>

namespace nlmech
{
  LuFactorization::~LuFactorization()
  {
    release();
  }

  void LuFactorization::release()
  {
    if (numeric)
      umfpack_di_free_numeric(&numeric);
    if (symbolic)
      umfpack_di_free_symbolic(&symbolic);
    numeric = symbolic = nullptr;
    pattern_outer.clear(), pattern_inner.clear();
  }

  bool LuFactorization::factor_with(const double eps)
  {
    if (numeric)
      umfpack_di_free_numeric(&numeric);
    numeric = nullptr;
    shifted = matrix;
    if (eps > 0)
      for (Eigen::Index i = 0; i < shifted.rows(); ++i)
        shifted.coeffRef(i, i) += eps * diagonal_scale;
    shifted.makeCompressed();
    // The symbolic analysis (ordering, fronts) depends on the pattern only: kept while it stays the
    // same (a design's Jacobians, one per evaluation), about a fifth of a factorisation's time.
    const std::vector<int> outer(shifted.outerIndexPtr(), shifted.outerIndexPtr() + shifted.outerSize() + 1);
    const bool             same = symbolic && outer == pattern_outer &&
                      std::equal(shifted.innerIndexPtr(), shifted.innerIndexPtr() + shifted.nonZeros(),
                                 pattern_inner.begin(), pattern_inner.end());
    if (!same)
      {
        if (symbolic)
          umfpack_di_free_symbolic(&symbolic);
        symbolic         = nullptr;
        const int n      = int(shifted.rows());
        const int status = umfpack_di_symbolic(n, n, shifted.outerIndexPtr(), shifted.innerIndexPtr(),
                                               shifted.valuePtr(), &symbolic, nullptr, nullptr);
        if (status != UMFPACK_OK)
          {
            release();
            return false;
          }
        pattern_outer = outer;
        pattern_inner.assign(shifted.innerIndexPtr(), shifted.innerIndexPtr() + shifted.nonZeros());
      }
    const int numeric_status = umfpack_di_numeric(shifted.outerIndexPtr(), shifted.innerIndexPtr(),
                                                  shifted.valuePtr(), symbolic, &numeric, nullptr, nullptr);
    epsilon                  = eps;
    return numeric_status == UMFPACK_OK; // UMFPACK_WARNING_singular_matrix is > 0: refused
  }

  void LuFactorization::factorize(const Eigen::SparseMatrix<double> &A)
  {
    AssertThrow(A.rows() == A.cols() && A.rows() > 0, dealii::ExcMessage("LU: the matrix must be square."));
    const auto lock = lock_serial_blas();
    matrix          = A;
    matrix.makeCompressed();
    diagonal_scale = 0;
    for (Eigen::Index i = 0; i < matrix.rows(); ++i)
      diagonal_scale = std::max(diagonal_scale, std::abs(matrix.coeff(i, i)));
    diagonal_scale = diagonal_scale > 0 ? diagonal_scale : 1;
    for (const double eps : {0.0, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4})
      if (factor_with(eps))
        return;
    release();
    AssertThrow(false, dealii::ExcMessage("LU: the matrix is singular even with a diagonal regularisation of "
                                          "1e-4 of its largest diagonal entry."));
  }

  Eigen::VectorXd LuFactorization::solve(const Eigen::VectorXd &b, const bool transposed)
  {
    AssertThrow(numeric, dealii::ExcMessage("LU: solve before factorize."));
    AssertThrow(b.size() == matrix.rows(), dealii::ExcMessage("LU: right-hand side of the wrong size."));
    const auto      lock = lock_serial_blas();
    Eigen::VectorXd x(b.size());
    for (int attempt = 0; attempt < 8; ++attempt)
      {
        const int status = umfpack_di_solve(transposed ? UMFPACK_At : UMFPACK_A, shifted.outerIndexPtr(),
                                            shifted.innerIndexPtr(), shifted.valuePtr(), x.data(), b.data(),
                                            numeric, nullptr, nullptr);
        // The residual against the unregularised matrix: a regularised solve is accepted when it
        // still solves the original system to 1e-8 (the sensitivities stay exact) or when the
        // shift cannot be made smaller.
        const Eigen::VectorXd r =
            transposed ? Eigen::VectorXd(matrix.transpose() * x - b) : Eigen::VectorXd(matrix * x - b);
        if (status == UMFPACK_OK && x.allFinite() && r.norm() <= 1e-8 * std::max(b.norm(), 1e-300))
          return x;
        if (status == UMFPACK_OK && x.allFinite() && epsilon > 0 && r.norm() <= 1e-3 * b.norm())
          return x; // regularised: the best this shift gives
        const double next = epsilon == 0 ? 1e-12 : 100 * epsilon;
        AssertThrow(next <= 1e-4 && factor_with(next),
                    dealii::ExcMessage("LU: the solve leaves a residual of " +
                                       std::to_string(r.norm() / b.norm()) +
                                       " relative even with diagonal regularisation."));
      }
    return x;
  }
} // namespace nlmech
