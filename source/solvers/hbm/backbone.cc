#include <nlmech/solvers/hbm/backbone.h>
#include <nlmech/solvers/hbm/linear_modal.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nlmech
{
  namespace
  {
    /// Gauss-Newton on h(z, w) = 0 over the unknowns other than z[cos] = a and z[sin] = 0, and w.
    bool correct(const HarmonicBalance &hb, Eigen::VectorXd &z, double &omega, const std::size_t cos_index,
                 const std::size_t sin_index, const BackboneSettings &settings, BackbonePoint &point)
    {
      const Eigen::Index n = Eigen::Index(hb.n_unknowns());
      // Column map: every z entry but the two prescribed ones, then w.
      std::vector<Eigen::Index> column(std::size_t(n), -1);
      Eigen::Index              k = 0;
      for (Eigen::Index i = 0; i < n; ++i)
        if (std::size_t(i) != cos_index && std::size_t(i) != sin_index)
          column[std::size_t(i)] = k++;
      const Eigen::Index omega_column = k;
      auto               scale        = [&](const Eigen::VectorXd &zz, double w) {
        return std::max(1e-300, w * w * hb.free_mass().maxCoeff() * zz.lpNorm<Eigen::Infinity>());
      };
      for (point.iterations = 0; point.iterations <= settings.max_iterations; ++point.iterations)
        {
          const Eigen::VectorXd h = hb.residual(z, omega);
          point.residual          = h.lpNorm<Eigen::Infinity>() / scale(z, omega);
          if (!std::isfinite(point.residual))
            return false;
          if (point.residual <= settings.tolerance)
            return true;
          const Eigen::SparseMatrix<double>   J  = hb.jacobian(z, omega);
          const Eigen::VectorXd               dw = hb.d_residual_d_omega(z, omega);
          std::vector<Eigen::Triplet<double>> t;
          t.reserve(std::size_t(J.nonZeros() + n));
          for (Eigen::Index c = 0; c < J.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it)
              if (column[std::size_t(it.col())] >= 0)
                t.emplace_back(it.row(), column[std::size_t(it.col())], it.value());
          for (Eigen::Index r = 0; r < n; ++r)
            if (dw[r] != 0)
              t.emplace_back(r, omega_column, dw[r]);
          Eigen::SparseMatrix<double> A(n, omega_column + 1);
          A.setFromTriplets(t.begin(), t.end());
          // Normal equations of the consistent least-squares problem (its residual goes to zero).
          const Eigen::SparseMatrix<double> N = Eigen::SparseMatrix<double>(A.transpose()) * A;
          SparseFactorization               factorization;
          Eigen::VectorXd                   step;
          try
            {
              factorization.factorize(N, true);
              step = factorization.solve(-(A.transpose() * h));
            }
          catch (const dealii::ExceptionBase &)
            {
              return false; // a singular system: the curve turns or branches here
            }
          if (!step.allFinite())
            return false;
          for (Eigen::Index i = 0; i < n; ++i)
            if (column[std::size_t(i)] >= 0)
              z[i] += step[column[std::size_t(i)]];
          omega += step[omega_column];
          if (!(omega > 0))
            return false;
        }
      return false;
    }
  } // namespace

  std::vector<BackbonePoint> trace_backbone(const HarmonicBalance &hb, const Eigen::VectorXd &static_state,
                                            const std::vector<double> &amplitudes,
                                            const BackboneSettings &settings, std::string *stop_reason)
  {
    const auto &p = hb.parameters();
    AssertThrow(hb.harmonic_forces().empty() && hb.harmonic_drives().empty() &&
                    hb.prescribed_drives().empty() && p.rayleigh_mass == 0 && p.rayleigh_stiffness == 0,
                dealii::ExcMessage("Backbone: the harmonic-balance system must be undamped and unforced."));
    AssertThrow(settings.reference < hb.n_free(),
                dealii::ExcMessage("Backbone: the reference unknown is not a free unknown."));
    AssertThrow(!amplitudes.empty() && std::is_sorted(amplitudes.begin(), amplitudes.end()) &&
                    amplitudes.front() > 0,
                dealii::ExcMessage("Backbone: give positive amplitudes in ascending order."));
    const LinearModes modes = linear_modes(hb, static_state);
    AssertThrow(
        settings.mode >= 1 && settings.mode <= modes.frequencies.size(),
        dealii::ExcMessage("Backbone: there is no linear mode " + std::to_string(settings.mode) + "."));
    const std::size_t     nf = hb.n_free(), r = settings.reference;
    const Eigen::VectorXd shape = modes.shapes.col(Eigen::Index(settings.mode - 1));
    AssertThrow(std::abs(shape[Eigen::Index(r)]) > 1e-12 * shape.lpNorm<Eigen::Infinity>(),
                dealii::ExcMessage("Backbone: the reference unknown does not move in mode " +
                                   std::to_string(settings.mode) + "; choose another tracked point."));
    // z layout: static block, then per harmonic k its sine block (2k - 1) and cosine block (2k).
    const std::size_t          sin_index = nf + r, cos_index = 2 * nf + r;
    Eigen::VectorXd            z     = hb.static_coefficients(static_state);
    double                     omega = modes.frequencies[Eigen::Index(settings.mode - 1)];
    double                     a     = 0;
    std::vector<BackbonePoint> out;
    for (const double target : amplitudes)
      {
        // Continue from the last amplitude in substeps, scaling the harmonics with the amplitude.
        const unsigned int substeps = out.empty() ? 1 : settings.substeps;
        BackbonePoint      point;
        for (unsigned int s = 1; s <= substeps; ++s)
          {
            const double next = out.empty() ? target : a + (target - a) * s / substeps;
            if (a == 0)
              z.segment(Eigen::Index(2 * nf), Eigen::Index(nf)) = next / shape[Eigen::Index(r)] * shape;
            else
              z.tail(z.size() - Eigen::Index(nf)) *= next / a;
            z[Eigen::Index(cos_index)] = next, z[Eigen::Index(sin_index)] = 0;
            point.converged = correct(hb, z, omega, cos_index, sin_index, settings, point);
            if (!point.converged)
              {
                if (stop_reason)
                  {
                    std::ostringstream why;
                    why << "the backbone did not converge at amplitude " << next << " (residual "
                        << point.residual << " after " << point.iterations << " Gauss-Newton iterations)";
                    *stop_reason = why.str();
                  }
                return out;
              }
            a = next;
          }
        point.amplitude = target, point.omega = omega, point.z = z;
        out.push_back(point);
      }
    return out;
  }
} // namespace nlmech
