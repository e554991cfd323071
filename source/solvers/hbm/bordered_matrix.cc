// The bordered matrix of arclength continuation (bordered_matrix.h).
#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/hbm/bordered_matrix.h>

namespace nlmech
{
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
} // namespace nlmech
