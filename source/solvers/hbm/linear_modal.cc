#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/hbm/linear_modal.h>

#include <Eigen/Eigenvalues>

#include <cmath>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
  }

  LinearModes linear_modes(const HarmonicBalance &hb, const Eigen::VectorXd &x_s)
  {
    const std::size_t n = hb.n_free();
    AssertThrow(n <= 6000, dealii::ExcMessage("Linear modal analysis is dense: " + std::to_string(n) +
                                              " free unknowns are too many (at most 6000)."));
    const Eigen::SparseMatrix<double> K_full = hb.model().hessian(x_s);
    std::vector<long>                 index(K_full.rows(), -1);
    for (std::size_t i = 0; i < n; ++i)
      index[hb.free()[i]] = long(i);
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n); // the free block, from the nonzeros
    for (Eigen::Index c = 0; c < K_full.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K_full, c); it; ++it)
        if (index[it.row()] >= 0 && index[it.col()] >= 0)
          K(index[it.row()], index[it.col()]) += it.value();
    for (const auto &d : hb.harmonic_drives()) // penalty drives: their springs
      {
        const auto it = std::find(hb.free().begin(), hb.free().end(), d.dof);
        K(it - hb.free().begin(), it - hb.free().begin()) += d.stiffness;
      }
    const Eigen::MatrixXd                                     M = hb.free_mass().asDiagonal();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (K + K.transpose()), M);
    AssertThrow(eig.info() == Eigen::Success, dealii::ExcMessage("The modal eigenproblem did not converge."));
    const Eigen::VectorXd lambda = eig.eigenvalues();
    AssertThrow(lambda.minCoeff() > 1e-12 * std::abs(lambda.maxCoeff()),
                dealii::ExcMessage("Linear modal analysis: the stiffness at the static state is not positive "
                                   "definite (smallest eigenvalue " +
                                   std::to_string(lambda.minCoeff()) +
                                   "): the structure is unconstrained or the state unstable."));
    LinearModes modes;
    modes.frequencies  = lambda.cwiseSqrt();
    modes.shapes       = eig.eigenvectors(); // M-orthonormal
    modes.static_state = x_s;
    return modes;
  }

  Eigen::VectorXcd linear_modal_response(const HarmonicBalance &hb, const LinearModes &modes,
                                         const double omega, const unsigned int n_modes_in)
  {
    using complex           = std::complex<double>;
    const std::size_t n     = hb.n_free();
    const double      alpha = hb.parameters().rayleigh_mass, beta = hb.parameters().rayleigh_stiffness;
    const double      scale = hb.excitation_scale();
    Eigen::VectorXcd  F     = Eigen::VectorXcd::Zero(n);
    std::vector<long> index(hb.model().n_unknowns(), -1);
    for (std::size_t i = 0; i < n; ++i)
      index[hb.free()[i]] = long(i);
    for (const auto &f : hb.harmonic_forces())
      F[index[f.dof]] += scale * f.amplitude * std::polar(1.0, f.phase);
    auto first_harmonic = [&](const HarmonicDrive &d) {
      complex U = d.amplitude * std::polar(1.0, d.phase);
      if (!d.cosine.empty())
        U += d.cosine[0];
      if (!d.sine.empty())
        U -= complex(0, 1) * d.sine[0];
      return scale * U;
    };
    for (const auto &d : hb.harmonic_drives())
      F[index[d.dof]] += d.stiffness * first_harmonic(d);
    if (!hb.prescribed_drives().empty())
      {
        const Eigen::SparseMatrix<double> K = hb.model().hessian(modes.static_state);
        Eigen::VectorXcd                  U = Eigen::VectorXcd::Zero(hb.model().n_unknowns());
        for (const auto &d : hb.prescribed_drives())
          U[d.dof] += first_harmonic(d);
        const Eigen::VectorXcd coupling = K.cast<complex>() * U;
        for (std::size_t i = 0; i < n; ++i)
          F[i] -= complex(1, omega * beta) * coupling[hb.free()[i]];
      }
    const Eigen::Index m = n_modes_in == 0 ? modes.frequencies.size()
                                           : std::min<Eigen::Index>(n_modes_in, modes.frequencies.size());
    Eigen::VectorXcd   X = Eigen::VectorXcd::Zero(n);
    for (Eigen::Index k = 0; k < m; ++k)
      {
        const double  wk = modes.frequencies[k];
        const complex q  = modes.shapes.col(k).cast<complex>().dot(F) /
                          complex(wk * wk - omega * omega, omega * (alpha + beta * wk * wk));
        X += q * modes.shapes.col(k).cast<complex>();
      }
    return X;
  }

  double linear_amplitude(const Eigen::VectorXcd &U, const double omega,
                          const std::vector<std::size_t> &free_indices)
  {
    // v(t) = Re(i w U e^{i w t}); integral of |v| over T by the trapezoidal rule on 256 samples, as
    // HarmonicBalance::amplitude does.
    const unsigned int samples = 256;
    const double       T       = 2 * pi / omega;
    double             total   = 0;
    for (unsigned int j = 0; j < samples; ++j)
      {
        const std::complex<double> phase =
            std::polar(1.0, 2 * pi * j / samples) * std::complex<double>(0, omega);
        double v2 = 0;
        for (const std::size_t i : free_indices)
          v2 += std::pow((phase * U[i]).real(), 2);
        total += std::sqrt(v2) * T / samples;
      }
    return total;
  }
} // namespace nlmech
