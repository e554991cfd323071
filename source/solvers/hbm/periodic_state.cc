// Periodic states at one frequency: KINSOL with the sparse direct solve of the HBM Jacobian, the
// excitation ramp, and the adaptive choice of the number of harmonics.
#include <deal.II/base/exceptions.h>
#include <deal.II/lac/vector.h>
#include <deal.II/sundials/kinsol.h>

#include <nlmech/base/quiet_stderr.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    Eigen::VectorXd to_eigen(const dealii::Vector<double> &v)
    {
      return Eigen::Map<const Eigen::VectorXd>(v.begin(), Eigen::Index(v.size()));
    }
    void to_dealii(const Eigen::VectorXd &e, dealii::Vector<double> &v)
    {
      std::copy(e.data(), e.data() + e.size(), v.begin());
    }
  } // namespace

  double force_scale(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double omega)
  {
    // Inertial forces of the motion and the forcing amplitudes. Not the drive penalties: a stiff
    // penalty's force at rest (stiffness x amplitude) would make every relative tolerance meaningless.
    double scale = 0;
    for (std::size_t i = 0; i < hb.n_free(); ++i)
      for (unsigned int k = 1; k <= hb.n_harmonics(); ++k)
        {
          const auto sc = hb.coefficient(z, i, k);
          scale =
              std::max(scale, std::pow(k * omega, 2) * hb.free_mass()[i] * std::hypot(sc.first, sc.second));
        }
    for (const auto &f : hb.harmonic_forces())
      scale = std::max(scale, hb.excitation_scale() * std::abs(f.amplitude));
    // Inertial force of a driven unknown: w^2 m times its acceleration-weighted motion.
    auto drive_scale = [&](const HarmonicDrive &d) {
      double size = std::abs(d.amplitude);
      for (std::size_t k = 1; k <= d.sine.size(); ++k)
        size += double(k * k) * std::abs(d.sine[k - 1]);
      for (std::size_t k = 1; k <= d.cosine.size(); ++k)
        size += double(k * k) * std::abs(d.cosine[k - 1]);
      return std::pow(omega, 2) * hb.model().lumped_mass()[d.dof] * hb.excitation_scale() * size;
    };
    for (const auto &d : hb.prescribed_drives())
      scale = std::max(scale, drive_scale(d));
    for (const auto &d : hb.harmonic_drives())
      scale = std::max(scale, drive_scale(d));
    return std::max(scale, 1e-300);
  }

  double residual_floor(const HarmonicBalance &hb, const Eigen::VectorXd &z)
  {
    const Eigen::VectorXd             x = hb.full(z.head(hb.n_free()));
    const Eigen::SparseMatrix<double> K = hb.model().hessian(x);
    double                            k = 0;
    for (Eigen::Index i = 0; i < K.rows(); ++i)
      k = std::max(k, std::abs(K.coeff(i, i)));
    return 100 * std::numeric_limits<double>::epsilon() * k * std::max(x.lpNorm<Eigen::Infinity>(), 1e-300);
  }

  namespace
  {
    /// KINSOL with the given strategy and iteration cap.
    PeriodicSolveResult kinsol_solve(const HarmonicBalance &hb, Eigen::VectorXd &z, const double omega,
                                     const PeriodicSolveSettings &settings, const bool line_search,
                                     const unsigned int max_iterations,
                                     Eigen::VectorXd   *last_iterate = nullptr)
    {
      PeriodicSolveResult result;
      const double        scale = force_scale(hb, z, omega);
      const double        floor = residual_floor(hb, z);
      using KINSOL              = dealii::SUNDIALS::KINSOL<dealii::Vector<double>>;
      KINSOL::AdditionalData data(line_search ? KINSOL::AdditionalData::linesearch
                                              : KINSOL::AdditionalData::newton,
                                  max_iterations, std::max(settings.relative_tolerance * scale, floor),
                                  1e-14 * std::max(1.0, z.lpNorm<Eigen::Infinity>()), false, 1);
      KINSOL              solver(data);
      SparseFactorization factorization;
      const bool          debug = std::getenv("NLMECH_HBM_DEBUG") != nullptr;
      solver.reinit_vector      = [&](dealii::Vector<double> &v) { v.reinit(hb.n_unknowns()); };
      solver.residual           = [&](const dealii::Vector<double> &u, dealii::Vector<double> &F) {
        try
          {
            const Eigen::VectorXd h = hb.residual(to_eigen(u), omega);
            if (debug)
              std::cout << "hbm residual " << h.lpNorm<Eigen::Infinity>() / scale << std::endl;
            if (!h.allFinite())
              return 1; // recoverable: KINSOL shortens the step
            to_dealii(h, F);
            return 0;
          }
        catch (...)
          {
            return 1;
          }
      };
      solver.setup_jacobian = [&](const dealii::Vector<double> &u, const dealii::Vector<double> &) {
        try
          {
            const auto t0 = std::chrono::steady_clock::now();
            if (last_iterate)
              *last_iterate = to_eigen(u); // where a Newton step starts: kept for a failed solve
            const Eigen::SparseMatrix<double> J  = hb.jacobian(to_eigen(u), omega);
            const auto                        t1 = std::chrono::steady_clock::now();
            factorization.factorize(J, false);
            if (debug)
              std::cout << "hbm jacobian " << std::chrono::duration<double>(t1 - t0).count() << " s, nnz "
                        << J.nonZeros() << ", factorisation "
                        << std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count()
                        << " s" << std::endl;
            return 0;
          }
        catch (...)
          {
            return -1;
          }
      };
      solver.solve_with_jacobian = [&](const dealii::Vector<double> &rhs, dealii::Vector<double> &dst,
                                       double) {
        try
          {
            to_dealii(factorization.solve(to_eigen(rhs)), dst);
            return 0;
          }
        catch (...)
          {
            return -1;
          }
      };
      dealii::Vector<double> u(hb.n_unknowns());
      to_dealii(z, u);
      try
        {
          const QuietStderr quiet; // KINSOL prints every failed solve; the result says why instead
          result.iterations = solver.solve(u);
        }
      catch (const std::exception &e)
        {
          result.message = e.what();
        }
      const Eigen::VectorXd candidate = to_eigen(u);
      const Eigen::VectorXd h         = hb.residual(candidate, omega);
      result.residual                 = h.lpNorm<Eigen::Infinity>() / scale;
      result.converged =
          h.allFinite() && h.lpNorm<Eigen::Infinity>() <=
                               10 * std::max(std::max(settings.relative_tolerance, 1e-13) * scale, floor);
      if (result.converged)
        z = candidate;
      else if (result.message.empty())
        result.message = "relative residual " + std::to_string(result.residual);
      return result;
    }
  } // namespace

  PeriodicSolveResult solve_periodic_state(const HarmonicBalance &hb, Eigen::VectorXd &z, const double omega,
                                           const PeriodicSolveSettings &settings)
  {
    // Full Newton steps first: thin shells' membranes make the residual of a good step grow before
    // the next step removes it (the quadratic membrane strain of a bending deflection), which a line
    // search on |h| refuses, crawling instead. Where they fail, the line search from the same start.
    // Rounds of at most 12 full steps go on from where the last one ended while each reduced the
    // residual tenfold (a slow but sure Newton iteration, e.g. a shell design whose added
    // masses grew tenfold: 1146 -> 0.024 in 12 steps, alternating); otherwise the line search.
    const double    scale       = force_scale(hb, z, omega);
    const double    start       = hb.residual(z, omega).lpNorm<Eigen::Infinity>() / scale;
    Eigen::VectorXd trial       = z;
    unsigned int    used        = 0;
    double          round_start = start;
    while (used < settings.max_iterations)
      {
        const unsigned int  cap = std::min(settings.max_iterations - used, 12u);
        Eigen::VectorXd     last;
        PeriodicSolveResult plain = kinsol_solve(hb, trial, omega, settings, false, cap, &last);
        used += plain.converged ? plain.iterations : cap;
        if (plain.converged)
          {
            z                = trial;
            plain.iterations = used;
            return plain;
          }
        if (last.size() != z.size() || !last.allFinite())
          break;
        const Eigen::VectorXd h = hb.residual(last, omega);
        const double          r = h.lpNorm<Eigen::Infinity>() / scale;
        if (!h.allFinite() || !(r < 0.1 * round_start))
          break;
        trial = last, round_start = r;
      }
    PeriodicSolveResult searched = kinsol_solve(hb, z, omega, settings, true, settings.max_iterations);
    searched.iterations += used;
    return searched;
  }

  PeriodicSolveResult solve_with_excitation_ramp(const HarmonicBalance &hb, Eigen::VectorXd &z,
                                                 const double omega, const PeriodicSolveSettings &settings)
  {
    PeriodicSolveResult result = solve_periodic_state(hb, z, omega, settings);
    if (result.converged)
      return result;
    // Continuation in the excitation amplitude from the state given (e.g. rest, where the
    // linearisation is poor for thin structures: membranes only stiffen out of plane when stretched).
    double       done = 0, step = 0.1;
    unsigned int total = result.iterations;
    while (done < 1)
      {
        const double    next  = std::min(1.0, done + step);
        Eigen::VectorXd trial = z;
        hb.set_excitation_scale(next);
        result = solve_periodic_state(hb, trial, omega, settings);
        total += result.iterations;
        if (std::getenv("NLMECH_HBM_DEBUG"))
          std::cerr << "ramp " << next << " converged " << result.converged << " residual " << result.residual
                    << " scale " << force_scale(hb, trial, omega) << std::endl;
        if (result.converged)
          z = trial, done = next, step = std::min(0.5, 1.5 * step);
        else if ((step *= 0.5) < 1e-4)
          break;
      }
    hb.set_excitation_scale(1.0);
    result.iterations = total;
    if (done < 1)
      {
        result.converged = false;
        result.message   = "the excitation ramp stalled at " + std::to_string(done) + " of the amplitude";
      }
    return result;
  }

  HarmonicsChoice choose_harmonics(const Model &model, const HarmonicBalanceSettings &settings_in,
                                   const std::vector<HarmonicForce> &forces,
                                   const std::vector<HarmonicDrive> &drives,
                                   const Eigen::VectorXd &static_state, const double omega,
                                   const double threshold, const unsigned int first, const unsigned int last,
                                   const unsigned int step)
  {
    AssertThrow(
        first >= 1 && step >= 1 && last >= first && threshold > 0 && omega > 0,
        dealii::ExcMessage("choose_harmonics: needs 1 <= first <= last, step >= 1, a positive threshold "
                           "and frequency."));
    HarmonicsChoice     choice;
    Eigen::VectorXd     previous_z;
    Eigen::MatrixXd     previous;
    std::vector<double> t(256);
    for (std::size_t j = 0; j < t.size(); ++j)
      t[j] = 2 * pi / omega * double(j) / double(t.size());
    for (unsigned int H = first; H <= last; H += step)
      {
        HarmonicBalanceSettings settings = settings_in;
        settings.n_harmonics             = H;
        if (settings_in.n_samples != 0)
          settings.n_samples = std::max(settings_in.n_samples, 2 * H + 1);
        const HarmonicBalance hb(model, settings, forces, drives);
        Eigen::VectorXd       z = hb.static_coefficients(static_state);
        if (previous_z.size() > 0) // the lower harmonics from the previous solution
          z.head(std::min(z.size(), previous_z.size())) =
              previous_z.head(std::min(z.size(), previous_z.size()));
        const PeriodicSolveResult r = solve_with_excitation_ramp(hb, z, omega);
        AssertThrow(r.converged, dealii::ExcMessage("choose_harmonics: no periodic state at N_H = " +
                                                    std::to_string(H) + " (" + r.message + ")."));
        Eigen::MatrixXd x  = hb.positions_at(z, omega, t);
        choice.n_harmonics = H, choice.z = z;
        if (previous.size() > 0)
          {
            double size = 0;
            for (Eigen::Index i = 0; i < x.rows(); ++i)
              size = std::max(size, x.row(i).maxCoeff() - x.row(i).minCoeff());
            const double change = (x - previous).lpNorm<Eigen::Infinity>() / std::max(size, 1e-300);
            choice.changes.emplace_back(H, change);
            if (change < threshold)
              {
                choice.converged = true;
                break;
              }
          }
        previous = std::move(x), previous_z = z;
      }
    return choice;
  }
} // namespace nlmech
