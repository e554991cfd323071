#pragma once
// The bordered matrix [[J, h_l], [row^T, row_l]] of pseudo-arclength continuation in one scalar l
// (the frequency in continuation.h, a parameter segment in design_continuation.cc).

#include <Eigen/Sparse>

namespace nlmech
{
  /// J (compressed) with the column h_l and the row (row_z, row_l) appended, in compressed storage.
  Eigen::SparseMatrix<double> bordered(const Eigen::SparseMatrix<double> &J, const Eigen::VectorXd &h_l,
                                       const Eigen::VectorXd &row_z, double row_l);
} // namespace nlmech
