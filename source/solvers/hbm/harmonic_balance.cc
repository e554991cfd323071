#include <deal.II/base/exceptions.h>

#include <nlmech/base/rank_sharing.h>
#include <nlmech/base/threads.h>
#include <nlmech/solvers/hbm/harmonic_balance.h>

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// The matrices' nonzero patterns coincide (same outer and inner index arrays).
    bool same_pattern(const Eigen::SparseMatrix<double> &a, const Eigen::SparseMatrix<double> &b)
    {
      return a.nonZeros() == b.nonZeros() && a.outerSize() == b.outerSize() &&
             std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()) &&
             std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
    }
    /// Entry (p, q) of the time derivative in the harmonic basis [c_0, s_1, c_1, ...]: harmonic k's
    /// derivative couples its sine and cosine, d/dt (s sin + c cos) = -k w c sin + k w s cos.
    double harmonic_derivative(const std::size_t p, const std::size_t q, const double omega)
    {
      if (p == 0 || (p + 1) / 2 != (q + 1) / 2 || p == q)
        return 0.0;
      const double k = double((p + 1) / 2);
      return p % 2 == 1 ? -k * omega : k * omega; // (s, c) and (c, s)
    }

    /// The (2H+1) n square matrix of harmonic blocks on the pattern of `tangent` (compressed) plus
    /// its diagonal: entry (p n + r, q n + c) = blocks(p B + q, e) for the tangent's nonzero e at
    /// (r, c), plus diagonal(p, q, i) where r = c = i. Written straight into compressed storage:
    /// a triplet list of (2H+1)^2 entries per nonzero took longer to sort than the rest of the
    /// Jacobian.
    template <typename Diagonal>
    Eigen::SparseMatrix<double> harmonic_block_matrix(const Eigen::SparseMatrix<double> &tangent,
                                                      const Eigen::MatrixXd &blocks, const std::size_t B,
                                                      const Diagonal &diagonal)
    {
      AssertThrow(tangent.isCompressed() && tangent.rows() == tangent.cols(),
                  dealii::ExcMessage("Harmonic balance: the tangent must be square and compressed."));
      const Eigen::Index n = tangent.cols();
      // Rows of every column with the tangent's entry (-1: a diagonal outside its pattern).
      std::vector<Eigen::Index> start(n + 1, 0), rows, entry;
      rows.reserve(tangent.nonZeros() + n), entry.reserve(tangent.nonZeros() + n);
      for (Eigen::Index c = 0; c < n; ++c)
        {
          bool has_diagonal = false;
          for (Eigen::Index e = tangent.outerIndexPtr()[c]; e < tangent.outerIndexPtr()[c + 1]; ++e)
            {
              const Eigen::Index r = tangent.innerIndexPtr()[e];
              if (!has_diagonal && r > c)
                rows.push_back(c), entry.push_back(-1), has_diagonal = true;
              has_diagonal = has_diagonal || r == c;
              rows.push_back(r), entry.push_back(e);
            }
          if (!has_diagonal)
            rows.push_back(c), entry.push_back(-1);
          start[c + 1] = Eigen::Index(rows.size());
        }
      Eigen::SparseMatrix<double> A(n * Eigen::Index(B), n * Eigen::Index(B));
      A.resizeNonZeros(Eigen::Index(rows.size() * B * B));
      Eigen::Index k       = 0;
      A.outerIndexPtr()[0] = 0;
      for (std::size_t q = 0; q < B; ++q)
        for (Eigen::Index c = 0; c < n; ++c)
          {
            for (std::size_t p = 0; p < B; ++p)
              for (Eigen::Index i = start[c]; i < start[c + 1]; ++i, ++k)
                {
                  A.innerIndexPtr()[k] = int(Eigen::Index(p) * n + rows[i]);
                  double value         = entry[i] >= 0 ? blocks(Eigen::Index(p * B + q), entry[i]) : 0.0;
                  if (rows[i] == c)
                    value += diagonal(p, q, std::size_t(c));
                  A.valuePtr()[k] = value;
                }
            A.outerIndexPtr()[Eigen::Index(q) * n + c + 1] = int(k);
          }
      return A;
    }
  } // namespace

  /// FFTW plans for all free unknowns at once (one real transform of length N per unknown).
  struct HarmonicBalance::FftPlans
  {
    FftPlans(unsigned int N, std::size_t n)
        : N(N)
        , n(n)
    {
      real                = fftw_alloc_real(std::max<std::size_t>(1, N * n));
      complex             = fftw_alloc_complex(std::max<std::size_t>(1, (N / 2 + 1) * n));
      const int length[1] = {int(N)};
      forward  = fftw_plan_many_dft_r2c(1, length, int(n), real, nullptr, 1, int(N), complex, nullptr, 1,
                                        int(N / 2 + 1), FFTW_ESTIMATE);
      backward = fftw_plan_many_dft_c2r(1, length, int(n), complex, nullptr, 1, int(N / 2 + 1), real, nullptr,
                                        1, int(N), FFTW_ESTIMATE);
      AssertThrow(forward && backward, dealii::ExcMessage("FFTW could not plan the AFT transforms."));
    }
    ~FftPlans()
    {
      fftw_destroy_plan(forward);
      fftw_destroy_plan(backward);
      fftw_free(real);
      fftw_free(complex);
    }
    unsigned int  N;
    std::size_t   n;
    double       *real;
    fftw_complex *complex;
    fftw_plan     forward, backward;
  };

  HarmonicBalance::HarmonicBalance(const Model &model, const HarmonicBalanceSettings &settings_in,
                                   std::vector<HarmonicForce> forces_in, std::vector<HarmonicDrive> drives_in)
      : system(model)
      , settings(settings_in)
      , H(settings_in.n_harmonics)
      , forces(std::move(forces_in))
      , drives(std::move(drives_in))
  {
    AssertThrow(H >= 1, dealii::ExcMessage("Harmonic balance needs at least one harmonic (N_H >= 1)."));
    N = settings.n_samples;
    if (N == 0)
      N = 4 * H + 2; // alias-free for cubic nonlinearities (3 H < N - H)
    AssertThrow(N >= 2 * H + 1,
                dealii::ExcMessage(
                    "The AFT needs N_AFT >= 2 N_H + 1 time samples (Nyquist): N_AFT = " + std::to_string(N) +
                    " < " + std::to_string(2 * H + 1) + " for N_H = " + std::to_string(H) + "."));
    AssertThrow(settings.rayleigh_mass >= 0 && settings.rayleigh_stiffness >= 0,
                dealii::ExcMessage("Rayleigh damping coefficients must not be negative."));
    const std::size_t n = model.n_unknowns();
    base                = Eigen::VectorXd::Zero(n);
    free_index.assign(n, -1);
    std::vector<HarmonicDrive> penalty;
    std::vector<bool>          driven(n, false);
    for (const auto &d : drives)
      {
        AssertThrow(
            d.dof < n && !model.is_fixed(d.dof) && d.stiffness >= 0,
            dealii::ExcMessage("A driven unknown is missing or fixed, or has a negative drive stiffness."));
        if (d.stiffness > 0)
          penalty.push_back(d);
        else
          prescribed.push_back(d), driven[d.dof] = true;
      }
    drives = penalty;
    for (std::size_t i = 0; i < n; ++i)
      if (!model.is_fixed(i) && !driven[i])
        free_index[i] = long(free_dofs.size()), free_dofs.push_back(i);
    AssertThrow(!free_dofs.empty(), dealii::ExcMessage("Harmonic balance: no free unknowns."));
    {
      std::map<std::size_t, double> not_free = model.fixed();
      for (const auto &d : prescribed)
        not_free[d.dof] = 0;
      restriction = std::make_unique<FreeDofMap>(n, not_free);
    }
    for (const auto &f : model.fixed())
      base[f.first] = f.second;
    mass.resize(free_dofs.size());
    for (std::size_t i = 0; i < free_dofs.size(); ++i)
      mass[i] = model.lumped_mass()[free_dofs[i]];
    AssertThrow(mass.minCoeff() > 0, dealii::ExcMessage("Every free unknown needs a positive mass."));
    for (const auto &f : forces)
      AssertThrow(f.dof < n && free_index[f.dof] >= 0,
                  dealii::ExcMessage("A harmonic force acts on a missing or fixed unknown."));

    gamma.resize(N, 2 * H + 1);
    gamma_inverse.resize(2 * H + 1, N);
    for (unsigned int i = 0; i < N; ++i)
      {
        const double theta  = 2 * pi * i / N;
        gamma(i, 0)         = 1;
        gamma_inverse(0, i) = 1.0 / N;
        for (unsigned int k = 1; k <= H; ++k)
          {
            gamma(i, 2 * k - 1)         = std::sin(k * theta);
            gamma(i, 2 * k)             = std::cos(k * theta);
            gamma_inverse(2 * k - 1, i) = 2.0 / N * std::sin(k * theta);
            gamma_inverse(2 * k, i)     = 2.0 / N * std::cos(k * theta);
          }
      }
    if (settings.use_fft)
      fft = std::make_unique<FftPlans>(N, free_dofs.size());
  }

  HarmonicBalance::~HarmonicBalance() = default;

  double HarmonicDrive::motion(const double theta) const
  {
    double x = amplitude * std::cos(theta + phase);
    for (std::size_t k = 1; k <= sine.size(); ++k)
      x += sine[k - 1] * std::sin(double(k) * theta);
    for (std::size_t k = 1; k <= cosine.size(); ++k)
      x += cosine[k - 1] * std::cos(double(k) * theta);
    return x;
  }

  double HarmonicDrive::velocity(const double theta, const double omega) const
  {
    double v = -omega * amplitude * std::sin(theta + phase);
    for (std::size_t k = 1; k <= sine.size(); ++k)
      v += double(k) * omega * sine[k - 1] * std::cos(double(k) * theta);
    for (std::size_t k = 1; k <= cosine.size(); ++k)
      v -= double(k) * omega * cosine[k - 1] * std::sin(double(k) * theta);
    return v;
  }

  std::vector<HarmonicDrive> rotation_drives(const std::vector<std::array<double, 3>>      &points,
                                             const std::vector<std::array<std::size_t, 3>> &dofs,
                                             const std::array<double, 3>                   &axis_in,
                                             const std::array<double, 3> &c, const double angle_amplitude,
                                             const unsigned int n_harmonics, const double stiffness)
  {
    AssertThrow(points.size() == dofs.size(),
                dealii::ExcMessage("rotation_drives: one dof triple per point."));
    const double norm =
        std::sqrt(axis_in[0] * axis_in[0] + axis_in[1] * axis_in[1] + axis_in[2] * axis_in[2]);
    AssertThrow(norm > 0, dealii::ExcMessage("The rotation axis must not be zero."));
    const std::array<double, 3> a = {{axis_in[0] / norm, axis_in[1] / norm, axis_in[2] / norm}};
    // Fourier coefficients by the trapezoidal rule on M samples: exact for trigonometric
    // polynomials of degree < M, and x(theta) is one up to J_M(phi_0), far below round-off.
    const unsigned int         M = std::max(64u, 8 * n_harmonics);
    std::vector<HarmonicDrive> drives;
    for (std::size_t p = 0; p < points.size(); ++p)
      {
        const std::array<double, 3> r     = {{points[p][0] - c[0], points[p][1] - c[1], points[p][2] - c[2]}};
        const double                along = r[0] * a[0] + r[1] * a[1] + r[2] * a[2];
        const std::array<double, 3> axr   = {
              {a[1] * r[2] - a[2] * r[1], a[2] * r[0] - a[0] * r[2], a[0] * r[1] - a[1] * r[0]}};
        for (int i = 0; i < 3; ++i)
          {
            HarmonicDrive d;
            d.dof = dofs[p][i], d.amplitude = 0, d.stiffness = stiffness;
            d.sine.assign(n_harmonics, 0.0), d.cosine.assign(n_harmonics, 0.0);
            double mean = 0;
            for (unsigned int j = 0; j < M; ++j)
              {
                const double theta = 2 * pi * j / M, phi = angle_amplitude * std::cos(theta);
                // Rodrigues: R r = r cos(phi) + (a x r) sin(phi) + a (a . r)(1 - cos(phi))
                const double x =
                    c[i] + r[i] * std::cos(phi) + axr[i] * std::sin(phi) + a[i] * along * (1 - std::cos(phi));
                mean += x / M;
                for (unsigned int k = 1; k <= n_harmonics; ++k)
                  d.sine[k - 1] += 2.0 / M * x * std::sin(k * theta),
                      d.cosine[k - 1] += 2.0 / M * x * std::cos(k * theta);
              }
            d.center = mean;
            drives.push_back(d);
          }
      }
    return drives;
  }

  Eigen::VectorXd HarmonicBalance::static_coefficients(const Eigen::VectorXd &x) const
  {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n_unknowns());
    for (std::size_t i = 0; i < free_dofs.size(); ++i)
      z[i] = x[free_dofs[i]];
    return z;
  }

  Eigen::MatrixXd HarmonicBalance::to_time(const Eigen::VectorXd &c) const
  {
    const std::size_t n = free_dofs.size();
    if (!fft)
      return Eigen::Map<const Eigen::MatrixXd>(c.data(), n, 2 * H + 1) * gamma.transpose();
    for (std::size_t i = 0; i < n; ++i)
      {
        fftw_complex *X = fft->complex + i * (N / 2 + 1);
        for (unsigned int k = 0; k <= N / 2; ++k)
          X[k][0] = X[k][1] = 0;
        X[0][0] = c[i];
        for (unsigned int k = 1; k <= H; ++k)
          X[k][0] = 0.5 * c[(2 * k) * n + i], X[k][1] = -0.5 * c[(2 * k - 1) * n + i];
      }
    fftw_execute(fft->backward);
    Eigen::MatrixXd samples(n, N);
    for (std::size_t i = 0; i < n; ++i)
      for (unsigned int j = 0; j < N; ++j)
        samples(i, j) = fft->real[i * N + j];
    return samples;
  }

  Eigen::VectorXd HarmonicBalance::to_frequency(const Eigen::MatrixXd &samples) const
  {
    const std::size_t n = free_dofs.size();
    Eigen::VectorXd   c(n * (2 * H + 1));
    if (!fft)
      {
        Eigen::Map<Eigen::MatrixXd>(c.data(), n, 2 * H + 1) = samples * gamma_inverse.transpose();
        return c;
      }
    for (std::size_t i = 0; i < n; ++i)
      for (unsigned int j = 0; j < N; ++j)
        fft->real[i * N + j] = samples(i, j);
    fftw_execute(fft->forward);
    for (std::size_t i = 0; i < n; ++i)
      {
        const fftw_complex *F = fft->complex + i * (N / 2 + 1);
        c[i]                  = F[0][0] / N;
        for (unsigned int k = 1; k <= H; ++k)
          c[(2 * k - 1) * n + i] = -2.0 * F[k][1] / N, c[(2 * k) * n + i] = 2.0 * F[k][0] / N;
      }
    return c;
  }

  Eigen::MatrixXd HarmonicBalance::sample_positions(const Eigen::VectorXd &z) const
  {
    const Eigen::MatrixXd free_samples = to_time(z);
    Eigen::MatrixXd       x(base.size(), N);
    for (unsigned int j = 0; j < N; ++j)
      x.col(j) = full(free_samples.col(j), 2 * pi * j / N);
    return x;
  }

  Eigen::MatrixXd HarmonicBalance::sample_free_velocities(const Eigen::VectorXd &z, const double omega) const
  {
    const std::size_t n = free_dofs.size();
    Eigen::VectorXd   v = Eigen::VectorXd::Zero(z.size());
    for (unsigned int k = 1; k <= H; ++k)
      for (std::size_t i = 0; i < n; ++i)
        {
          v[(2 * k - 1) * n + i] = -double(k) * omega * z[(2 * k) * n + i]; // sin coefficient of v
          v[(2 * k) * n + i]     = k * omega * z[(2 * k - 1) * n + i];
        }
    return to_time(v);
  }

  Eigen::MatrixXd HarmonicBalance::positions_at(const Eigen::VectorXd &z, const double omega,
                                                const std::vector<double> &t) const
  {
    const std::size_t n = free_dofs.size();
    Eigen::MatrixXd   x(base.size(), t.size());
    for (std::size_t j = 0; j < t.size(); ++j)
      {
        x.col(j) = full(Eigen::VectorXd::Zero(n), omega * t[j]);
        for (std::size_t i = 0; i < n; ++i)
          {
            double value = z[i];
            for (unsigned int k = 1; k <= H; ++k)
              value += z[(2 * k - 1) * n + i] * std::sin(k * omega * t[j]) +
                       z[(2 * k) * n + i] * std::cos(k * omega * t[j]);
            x(free_dofs[i], j) = value;
          }
      }
    return x;
  }

  std::pair<double, double> HarmonicBalance::coefficient(const Eigen::VectorXd &z, const std::size_t i,
                                                         const unsigned int k) const
  {
    const std::size_t n = free_dofs.size();
    if (k == 0)
      return {0.0, z[i]};
    return {z[(2 * k - 1) * n + i], z[(2 * k) * n + i]};
  }

  Eigen::VectorXd HarmonicBalance::full(const Eigen::VectorXd &free_values, const double theta) const
  {
    Eigen::VectorXd x = base;
    for (std::size_t i = 0; i < free_dofs.size(); ++i)
      x[free_dofs[i]] = free_values[i];
    for (const auto &d : prescribed)
      x[d.dof] = d.center + excitation * d.motion(theta);
    return x;
  }

  Eigen::VectorXd HarmonicBalance::full_velocity(const Eigen::VectorXd &free_velocities, const double theta,
                                                 const double omega) const
  {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(base.size());
    for (std::size_t i = 0; i < free_dofs.size(); ++i)
      v[free_dofs[i]] = free_velocities[i];
    for (const auto &d : prescribed)
      v[d.dof] = excitation * d.velocity(theta, omega);
    return v;
  }

  Eigen::MatrixXd HarmonicBalance::velocities_at(const Eigen::VectorXd &z, const double omega,
                                                 const std::vector<double> &t) const
  {
    const std::size_t n = free_dofs.size();
    Eigen::MatrixXd   v = Eigen::MatrixXd::Zero(base.size(), t.size());
    for (std::size_t j = 0; j < t.size(); ++j)
      v.col(j) = full_velocity(Eigen::VectorXd::Zero(n), omega * t[j], omega);
    for (std::size_t j = 0; j < t.size(); ++j)
      for (std::size_t i = 0; i < n; ++i)
        for (unsigned int k = 1; k <= H; ++k)
          v(free_dofs[i], j) += k * omega *
                                (z[(2 * k - 1) * n + i] * std::cos(k * omega * t[j]) -
                                 z[(2 * k) * n + i] * std::sin(k * omega * t[j]));
    return v;
  }

  Eigen::VectorXd HarmonicBalance::force(const Eigen::VectorXd &x, const Eigen::VectorXd &v_full,
                                         const double theta, Eigen::SparseMatrix<double> *df_dx,
                                         Eigen::SparseMatrix<double> *df_dv) const
  {
    const double      beta = settings.rayleigh_stiffness;
    const FreeDofMap &map  = *restriction;
    Eigen::VectorXd   f    = -map.restrict(system.gradient(x));
    AssertThrow(f.allFinite(), dealii::ExcMessage("The internal force is not finite (the motion is too large "
                                                  "for the model, e.g. an inverted element)."));
    if (beta > 0)
      f -= beta * map.restrict(system.hessian_vector_product(x, v_full));
    for (const auto &a : forces)
      f[free_index[a.dof]] += excitation * a.amplitude * std::cos(theta + a.phase);
    for (const auto &d : drives)
      f[free_index[d.dof]] -= d.stiffness * (x[d.dof] - d.center - excitation * d.motion(theta));
    if (df_dx)
      {
        const std::size_t                   n = free_dofs.size();
        Eigen::SparseMatrix<double>         drive_stiffness(n, n);
        std::vector<Eigen::Triplet<double>> t;
        for (const auto &d : drives)
          t.emplace_back(free_index[d.dof], free_index[d.dof], d.stiffness);
        drive_stiffness.setFromTriplets(t.begin(), t.end());
        // d(K(x) v)/dx: third derivatives of E along v (forward AD in element terms).
        const Eigen::SparseMatrix<double> K  = system.hessian(x);
        const Eigen::SparseMatrix<double> dK = beta > 0 ? system.directional_hessian(x, v_full) : K * 0.0;
        const Eigen::SparseMatrix<double> Kf = map.restrict(K), dKf = map.restrict(dK);
        *df_dx = -Kf - beta * dKf - drive_stiffness;
        *df_dv = -beta * Kf + 0.0 * dKf + 0.0 * drive_stiffness;
        df_dx->makeCompressed(), df_dv->makeCompressed();
      }
    return f;
  }

  Eigen::MatrixXd HarmonicBalance::sample_forces(const Eigen::VectorXd &z, const double omega,
                                                 std::vector<Eigen::SparseMatrix<double>> *df_dx,
                                                 std::vector<Eigen::SparseMatrix<double>> *df_dv) const
  {
    const std::size_t     n = free_dofs.size();
    const Eigen::MatrixXd x = sample_positions(z);
    const Eigen::MatrixXd v = sample_free_velocities(z, omega);
    Eigen::MatrixXd       f(n, N);
    if (df_dx)
      df_dx->assign(N, {}), df_dv->assign(N, {});
    auto samples = [&](const std::size_t begin, const std::size_t end) {
      for (std::size_t j = begin; j < end; ++j)
        f.col(Eigen::Index(j)) =
            force(x.col(Eigen::Index(j)), full_velocity(v.col(Eigen::Index(j)), 2 * pi * j / N, omega),
                  2 * pi * j / N, df_dx ? &(*df_dx)[j] : nullptr, df_dv ? &(*df_dv)[j] : nullptr);
    };
    // The samples are independent: one task each (the element loops inside still split further).
    // Ranks that share the element loops sum every evaluation collectively, in the same order on
    // every rank, so there the samples go one after the other.
    if (element_sharing_ranks() > 1)
      samples(0, N);
    else
      for_each_block(N, 1, samples);
    return f;
  }

  Eigen::VectorXd HarmonicBalance::linear_part(const Eigen::VectorXd &z, const double omega,
                                               const bool derivative) const
  {
    const std::size_t n   = free_dofs.size();
    Eigen::VectorXd   out = Eigen::VectorXd::Zero(z.size());
    for (unsigned int k = 1; k <= H; ++k)
      for (std::size_t i = 0; i < n; ++i)
        {
          const double s = z[(2 * k - 1) * n + i], c = z[(2 * k) * n + i];
          const double m = mass[i], d = settings.rayleigh_mass * mass[i];
          // (2.3.9): s-row -(k w)^2 m s - k w d c, c-row -(k w)^2 m c + k w d s.
          const double stiffness   = derivative ? -2.0 * k * k * omega * m : -std::pow(k * omega, 2) * m;
          const double damping     = derivative ? k * d : k * omega * d;
          out[(2 * k - 1) * n + i] = stiffness * s - damping * c;
          out[(2 * k) * n + i]     = stiffness * c + damping * s;
        }
    return out;
  }

  Eigen::VectorXd HarmonicBalance::mass_residual(const Eigen::VectorXd &z, const double omega,
                                                 const Eigen::VectorXd &mass_change) const
  {
    const std::size_t n   = free_dofs.size();
    Eigen::VectorXd   out = Eigen::VectorXd::Zero(z.size());
    for (unsigned int k = 1; k <= H; ++k)
      for (std::size_t i = 0; i < n; ++i)
        {
          const double m = mass_change[Eigen::Index(i)];
          if (m == 0)
            continue;
          const double s = z[(2 * k - 1) * n + i], c = z[(2 * k) * n + i];
          const double stiffness   = -std::pow(k * omega, 2) * m,
                       damping     = k * omega * settings.rayleigh_mass * m;
          out[(2 * k - 1) * n + i] = stiffness * s - damping * c;
          out[(2 * k) * n + i]     = stiffness * c + damping * s;
        }
    return out;
  }

  Eigen::VectorXd HarmonicBalance::coefficients_of_samples(const Eigen::MatrixXd &free_samples) const
  {
    AssertThrow(free_samples.rows() == Eigen::Index(free_dofs.size()) &&
                    free_samples.cols() == Eigen::Index(N),
                dealii::ExcMessage("coefficients_of_samples: n_free x N_AFT samples expected."));
    return to_frequency(free_samples);
  }

  Eigen::MatrixXd HarmonicBalance::adjoint_sample_weights(const Eigen::VectorXd &lambda) const
  {
    const std::size_t n = free_dofs.size();
    // to_frequency is c = S Ginv^T per unknown (row i of S), so lambda^T c = sum_ij (Lambda Ginv)_ij S_ij
    // with Lambda the n x (2H+1) view of lambda.
    return Eigen::Map<const Eigen::MatrixXd>(lambda.data(), Eigen::Index(n), 2 * H + 1) * gamma_inverse;
  }

  Eigen::MatrixXd HarmonicBalance::sample_velocities(const Eigen::VectorXd &z, const double omega) const
  {
    const Eigen::MatrixXd v = sample_free_velocities(z, omega);
    Eigen::MatrixXd       out(base.size(), N);
    for (unsigned int j = 0; j < N; ++j)
      out.col(j) = full_velocity(v.col(j), 2 * pi * j / N, omega);
    return out;
  }

  Eigen::VectorXd HarmonicBalance::residual(const Eigen::VectorXd &z, const double omega) const
  {
    AssertThrow(omega > 0, dealii::ExcMessage("Harmonic balance needs a positive frequency."));
    return linear_part(z, omega, false) - to_frequency(sample_forces(z, omega, nullptr, nullptr));
  }

  Eigen::VectorXd HarmonicBalance::d_residual_d_omega(const Eigen::VectorXd &z, const double omega) const
  {
    // Only the damping force -D_beta K(x) v depends on w at fixed z, through v ~ w: its derivative
    // is that force over w (2.3.18).
    const std::size_t n         = free_dofs.size();
    Eigen::MatrixXd   df_domega = Eigen::MatrixXd::Zero(n, N);
    if (settings.rayleigh_stiffness > 0)
      {
        const Eigen::MatrixXd x = sample_positions(z);
        const Eigen::MatrixXd v = sample_free_velocities(z, omega);
        for (unsigned int j = 0; j < N; ++j)
          df_domega.col(j) = -settings.rayleigh_stiffness *
                             restriction->restrict(system.hessian_vector_product(
                                 x.col(j), full_velocity(v.col(j), 2 * pi * j / N, omega))) /
                             omega;
      }
    return linear_part(z, omega, true) - to_frequency(df_domega);
  }

  Eigen::SparseMatrix<double> HarmonicBalance::hill_damping(const Eigen::VectorXd &z,
                                                            const double           omega) const
  {
    if (settings.rayleigh_stiffness > 0)
      {
        Eigen::SparseMatrix<double> D1;
        jacobian(z, omega, &D1);
        return D1;
      }
    // Without stiffness damping df/dv = 0: Delta_1 is constant, 2 M d/dt + D_alpha M per block.
    const std::size_t           n = free_dofs.size(), B = 2 * H + 1;
    Eigen::SparseMatrix<double> pattern{Eigen::Index(n), Eigen::Index(n)};
    pattern.setIdentity();
    pattern.makeCompressed();
    return harmonic_block_matrix(pattern, Eigen::MatrixXd::Zero(Eigen::Index(B * B), Eigen::Index(n)), B,
                                 [&](std::size_t p, std::size_t q, std::size_t i) {
                                   return 2 * mass[i] * harmonic_derivative(p, q, omega) +
                                          (p == q ? settings.rayleigh_mass * mass[i] : 0.0);
                                 });
  }

  Eigen::SparseMatrix<double> HarmonicBalance::jacobian(const Eigen::VectorXd &z, const double omega,
                                                        Eigen::SparseMatrix<double> *hill_damping) const
  {
    const std::size_t                        B = 2 * H + 1;
    std::vector<Eigen::SparseMatrix<double>> Kx, Kv;
    sample_forces(z, omega, &Kx, &Kv);
    for (unsigned int j = 1; j < N; ++j)
      AssertThrow(same_pattern(Kx[0], Kx[j]) && same_pattern(Kx[0], Kv[j]),
                  dealii::ExcMessage("Harmonic balance: the tangent's pattern changes over the period."));
    const Eigen::Index nnz = Kx[0].nonZeros();
    // C[(p, q), e] = sum_j Ginv[p, j] (Kx_j[e] G[j, q] + Kv_j[e] Gv[j, q]) for every nonzero e.
    Eigen::MatrixXd Wx(N, nnz), Wv(N, nnz), Px(B * B, N), Pv(B * B, N);
    for (unsigned int j = 0; j < N; ++j)
      {
        Wx.row(j)          = Eigen::Map<const Eigen::RowVectorXd>(Kx[j].valuePtr(), nnz);
        Wv.row(j)          = Eigen::Map<const Eigen::RowVectorXd>(Kv[j].valuePtr(), nnz);
        const double theta = 2 * pi * j / N;
        for (std::size_t q = 0; q < B; ++q)
          {
            const unsigned int k  = (q + 1) / 2;
            const double       gv = q == 0 ? 0.0
                                           : (q % 2 == 1 ? k * omega * std::cos(k * theta)
                                                         : -double(k) * omega * std::sin(k * theta));
            for (std::size_t p = 0; p < B; ++p)
              Px(p * B + q, j)               = gamma_inverse(p, j) * gamma(j, q),
                            Pv(p * B + q, j) = gamma_inverse(p, j) * gv;
          }
      }
    // Harmonic k's derivative couples its sine and cosine rows: d/dt (s sin + c cos) has sine part
    // -k w c and cosine part k w s. Mass terms: inertia -(k w)^2 m on the diagonal, damping
    // D_alpha m times the derivative.
    auto derivative         = [&](std::size_t p, std::size_t q) { return harmonic_derivative(p, q, omega); };
    const Eigen::MatrixXd C = -(Px * Wx + Pv * Wv);
    const auto J = harmonic_block_matrix(Kx[0], C, B, [&](std::size_t p, std::size_t q, std::size_t i) {
      const double k = double((p + 1) / 2);
      return (p == q ? -std::pow(k * omega, 2) * mass[i] : 0.0) +
             settings.rayleigh_mass * mass[i] * derivative(p, q);
    });
    if (hill_damping)
      {
        // Hill's Delta_1: the harmonic coefficients of 2 M p' + D_alpha M p - df/dv p.
        const Eigen::MatrixXd C1 = -(Px * Wv);
        *hill_damping = harmonic_block_matrix(Kx[0], C1, B, [&](std::size_t p, std::size_t q, std::size_t i) {
          return 2 * mass[i] * derivative(p, q) + (p == q ? settings.rayleigh_mass * mass[i] : 0.0);
        });
      }
    return J;
  }

  namespace
  {
    /// One coordinate over the period as the trigonometric polynomial
    /// x(theta) = c_0 + sum_k s_k sin(k theta) + c_k cos(k theta) of its harmonic coefficients.
    struct Coordinate
    {
      std::vector<double> s, c; // index k = 1..H (s[0], c[0] unused)

      double value(const double theta) const
      {
        double x = c[0];
        for (std::size_t k = 1; k < s.size(); ++k)
          x += s[k] * std::sin(double(k) * theta) + c[k] * std::cos(double(k) * theta);
        return x;
      }
      /// d^m x / d theta^m for m = 1, 2.
      double derivative(const double theta, const int m) const
      {
        double d = 0;
        for (std::size_t k = 1; k < s.size(); ++k)
          {
            const double kk = double(k), sn = std::sin(kk * theta), cs = std::cos(kk * theta);
            d += m == 1 ? kk * (s[k] * cs - c[k] * sn) : -kk * kk * (s[k] * sn + c[k] * cs);
          }
        return d;
      }
      /// Every turning point (x' = 0 with a sign change) in [0, 2 pi), sorted: the sign changes of
      /// x' on a fine grid (16 per harmonic), each root then found to round-off by Newton's method
      /// safeguarded by bisection. The extrema of a trigonometric polynomial are where it turns, so
      /// this gives its exact range and total variation, not a sampled one.
      std::vector<double> turning_points() const
      {
        const std::size_t H = s.size() - 1;
        const std::size_t M = std::max<std::size_t>(64, 16 * H);
        // The grid is offset so that symmetric motions (x' = 0 at theta = 0) turn between nodes.
        const double        offset = 0.318309886 * 2 * pi / double(M);
        std::vector<double> roots;
        double              a = offset, fa = derivative(a, 1);
        for (std::size_t j = 1; j <= M; ++j)
          {
            const double b = offset + 2 * pi * double(j) / double(M), fb = derivative(b, 1);
            if (fa != 0 && (fb == 0 || (fa < 0) != (fb < 0)))
              {
                double lo = a, hi = b, t = b;
                if (fb != 0)
                  for (int it = 0; it < 100 && hi - lo > 1e-15; ++it)
                    {
                      const double ft = derivative(t, 1);
                      if (ft == 0)
                        break;
                      if ((ft < 0) == (fa < 0))
                        lo = t;
                      else
                        hi = t;
                      const double d2   = derivative(t, 2);
                      double       next = d2 != 0 ? t - ft / d2 : 0.5 * (lo + hi);
                      if (!(next > lo && next < hi))
                        next = 0.5 * (lo + hi);
                      const bool done = std::abs(next - t) <= 4e-16 * (1 + t);
                      t               = next;
                      if (done)
                        break;
                    }
                roots.push_back(std::fmod(t, 2 * pi));
              }
            a = b, fa = fb;
          }
        std::sort(roots.begin(), roots.end());
        return roots;
      }
    };

    Coordinate coordinate(const Eigen::VectorXd &z, const std::size_t n, const std::size_t i,
                          const unsigned int H)
    {
      Coordinate x;
      x.s.assign(H + 1, 0.0), x.c.assign(H + 1, 0.0);
      x.c[0] = z[Eigen::Index(i)];
      for (unsigned int k = 1; k <= H; ++k)
        x.s[k] = z[Eigen::Index((2 * k - 1) * n + i)], x.c[k] = z[Eigen::Index((2 * k) * n + i)];
      return x;
    }

    /// Adds w d x(theta)/dz of coordinate i to g.
    void add_coordinate_gradient(Eigen::VectorXd &g, const std::size_t n, const std::size_t i,
                                 const unsigned int H, const double theta, const double w)
    {
      g[Eigen::Index(i)] += w;
      for (unsigned int k = 1; k <= H; ++k)
        g[Eigen::Index((2 * k - 1) * n + i)] += w * std::sin(k * theta),
            g[Eigen::Index((2 * k) * n + i)] += w * std::cos(k * theta);
    }
  } // namespace

  double HarmonicBalance::amplitude(const Eigen::VectorXd &z, const double omega,
                                    const std::vector<std::size_t> &dofs, Eigen::VectorXd *gradient,
                                    const unsigned int quadrature) const
  {
    (void)omega; // A = integral of |v| dt over T = 2 pi / w does not depend on w at fixed z
    const std::size_t n = free_dofs.size();
    if (gradient)
      gradient->setZero(z.size());
    std::vector<std::size_t> moving; // free indices of the group's moving coordinates
    for (const std::size_t d : dofs)
      if (free_index[d] >= 0)
        moving.push_back(std::size_t(free_index[d]));
    if (moving.size() == 1)
      {
        // One coordinate: A is its total variation over the period, the sum of |x| differences
        // between consecutive turning points, exact (a quadrature of |v| has kinks where v = 0 and
        // loses about 1e-4 at 256 samples). Its gradient: the turning points move, but x' = 0 there.
        const std::size_t         i     = moving[0];
        const Coordinate          x     = coordinate(z, n, i, H);
        const std::vector<double> turns = x.turning_points();
        double                    total = 0;
        for (std::size_t r = 0; r < turns.size(); ++r)
          {
            const double t0 = turns[r], t1 = turns[(r + 1) % turns.size()];
            const double dx = x.value(t1) - x.value(t0);
            total += std::abs(dx);
            if (gradient && dx != 0)
              {
                add_coordinate_gradient(*gradient, n, i, H, t1, dx > 0 ? 1.0 : -1.0);
                add_coordinate_gradient(*gradient, n, i, H, t0, dx > 0 ? -1.0 : 1.0);
              }
          }
        return total;
      }
    // A point moving in a plane or in space: |v| is smooth wherever the point does not stop, and the
    // trapezoidal rule on the periodic integrand converges spectrally.
    double total = 0;
    for (unsigned int j = 0; j < quadrature; ++j)
      {
        const double        theta = 2 * pi * j / quadrature;
        std::vector<double> v(moving.size(), 0.0);
        double              speed2 = 0;
        for (std::size_t d = 0; d < moving.size(); ++d)
          {
            const std::size_t i = moving[d];
            for (unsigned int k = 1; k <= H; ++k)
              v[d] += k * (z[(2 * k - 1) * n + i] * std::cos(k * theta) -
                           z[(2 * k) * n + i] * std::sin(k * theta));
            speed2 += v[d] * v[d];
          }
        const double speed = std::sqrt(speed2);
        total += 2 * pi / quadrature * speed; // |v| dt with v = w (...) and dt = dtheta / w
        if (gradient && speed > 0)
          for (std::size_t d = 0; d < moving.size(); ++d)
            {
              const std::size_t i = moving[d];
              for (unsigned int k = 1; k <= H; ++k)
                {
                  (*gradient)[(2 * k - 1) * n + i] +=
                      2 * pi / quadrature * v[d] / speed * k * std::cos(k * theta);
                  (*gradient)[(2 * k) * n + i] -=
                      2 * pi / quadrature * v[d] / speed * k * std::sin(k * theta);
                }
            }
      }
    return total;
  }

  double HarmonicBalance::half_range(const Eigen::VectorXd &z, const double omega,
                                     const std::size_t dof) const
  {
    if (free_index[dof] < 0)
      {
        // A fixed or prescribed unknown: sampled (its motion is given, not a polynomial of z).
        std::vector<double> t(256);
        for (std::size_t j = 0; j < t.size(); ++j)
          t[j] = 2 * pi / omega * j / t.size();
        const Eigen::MatrixXd x = positions_at(z, omega, t);
        return 0.5 * (x.row(dof).maxCoeff() - x.row(dof).minCoeff());
      }
    // The exact extremes: the largest and smallest value at a turning point.
    const Coordinate x  = coordinate(z, free_dofs.size(), std::size_t(free_index[dof]), H);
    double           hi = x.value(0), lo = hi;
    for (const double t : x.turning_points())
      hi = std::max(hi, x.value(t)), lo = std::min(lo, x.value(t));
    return 0.5 * (hi - lo);
  }
} // namespace nlmech
