#pragma once
// Harmonic balance (thesis ch. 2, eqs. 2.3.1-2.3.18, appendix 2.A.1-2.A.2) on any Model: the
// periodic steady state of M x'' + D x' = f_int(x) + f_ext(x, w, t) - D_beta K(x) x' with Rayleigh
// damping D = D_alpha M + D_beta K(x), f_int = -grad E, K = Hessian of E.
//
// Unknowns z: Fourier coefficients of the free positions, harmonic-major as in eq. (2.3.6):
// z = [c_0, s_1, c_1, ..., s_H, c_H], each block n_free long. The nonlinear forces go through the
// alternating frequency/time scheme (2.3.10): inverse real FFT (FFTW) to N time samples, forces and
// tangents per sample, forward real FFT back. The residual is h(z, w) = A(w) z - b(z, w) (2.3.8)
// and its Jacobian (2.3.13) is assembled sparse from the per-sample tangents.

#include <nlmech/models/model.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <array>
#include <memory>
#include <vector>

namespace nlmech
{
  /// f = amplitude cos(w t + phase) on one unknown [N].
  struct HarmonicForce
  {
    std::size_t dof;
    double      amplitude;
    double      phase = 0;
  };

  /// A driven unknown (motor, shaker) moving as x_0 + amplitude cos(w t + phase). With a positive
  /// stiffness, a stiff spring pulls it there (the penalty of thesis appendix 2.A.5; its forces set
  /// a round-off floor of about 1e-16 stiffness |x| on the residual); with stiffness 0 the motion is
  /// prescribed exactly and the unknown leaves the harmonic-balance system. The unknown must not be
  /// fixed in the Model.
  struct HarmonicDrive
  {
    std::size_t dof;
    double      amplitude;
    double      phase     = 0;
    double      stiffness = 0; // [N/m]; 0: exact prescribed motion
    double      center    = 0; // x_0
    /// Higher harmonics of a motion that is not a pure cosine (a rotation, a measured signal):
    /// x += sum_k sine[k-1] sin(k w t) + cosine[k-1] cos(k w t), k = 1, 2, ...
    std::vector<double> sine, cosine;

    /// x(theta) - x_0 at phase theta = w t, and its time derivative.
    double motion(double theta) const;
    double velocity(double theta, double omega) const;
  };

  /// Exact drives of points turning rigidly about the axis through `center` along `axis` by the
  /// angle phi(t) = angle_amplitude cos(w t) (a servo horn, a rotating clamp): x(t) = c + R(phi(t))
  /// (X - c), expanded in Fourier series to `n_harmonics` (harmonic k is of the size of the Bessel
  /// function J_k(phi_0), so a few harmonics are exact to round-off for moderate angles).
  /// `dofs[p]` are the unknowns of point p's coordinates. With `stiffness` > 0 as penalty drives.
  std::vector<HarmonicDrive> rotation_drives(const std::vector<std::array<double, 3>>      &points,
                                             const std::vector<std::array<std::size_t, 3>> &dofs,
                                             const std::array<double, 3>                   &axis,
                                             const std::array<double, 3> &center, double angle_amplitude,
                                             unsigned int n_harmonics, double stiffness = 0);

  struct HarmonicBalanceSettings
  {
    unsigned int n_harmonics        = 5;    // N_H
    unsigned int n_samples          = 0;    // N_AFT; 0: 4 N_H + 2 (alias-free for cubic terms)
    bool         use_fft            = true; // false: dense DFT matrices (for comparison)
    double       rayleigh_mass      = 0;    // D_alpha [1/s]
    double       rayleigh_stiffness = 0;    // D_beta [s]
  };

  class HarmonicBalance
  {
  public:
    /// Throws a clear error for N_H < 1, N_AFT < 2 N_H + 1 or a drive on a fixed unknown.
    HarmonicBalance(const Model &model, const HarmonicBalanceSettings &settings,
                    std::vector<HarmonicForce> forces = {}, std::vector<HarmonicDrive> drives = {});
    ~HarmonicBalance();

    std::size_t                     n_free() const { return free_dofs.size(); }
    std::size_t                     n_unknowns() const { return (2 * H + 1) * free_dofs.size(); }
    unsigned int                    n_harmonics() const { return H; }
    unsigned int                    n_samples() const { return N; }
    const Model                    &model() const { return system; }
    const std::vector<std::size_t> &free() const { return free_dofs; }

    /// z of the static configuration x (c_0 = free part of x, all harmonics zero).
    Eigen::VectorXd static_coefficients(const Eigen::VectorXd &x) const;

    Eigen::VectorXd residual(const Eigen::VectorXd &z, double omega) const;
    /// dh/dz (2.3.13); with `hill_damping`, also Delta_1 of Hill's quadratic eigenproblem
    /// (Delta_0 + lambda Delta_1 + lambda^2 Delta_2) u = 0 for the Floquet exponents lambda, where
    /// Delta_0 = dh/dz, Delta_2 = M in every harmonic block: the coefficients of
    /// 2 M u' + D_alpha M u - df/dv u.
    Eigen::SparseMatrix<double> jacobian(const Eigen::VectorXd &z, double omega,
                                         Eigen::SparseMatrix<double> *hill_damping = nullptr) const;
    /// Delta_1 alone (constant, without sampling, when D_beta = 0).
    Eigen::SparseMatrix<double> hill_damping(const Eigen::VectorXd &z, double omega) const;
    /// dh/dw at fixed z (2.3.18).
    Eigen::VectorXd d_residual_d_omega(const Eigen::VectorXd &z, double omega) const;

    /// Full-length positions at the N samples t_i = i T / N (one column per sample).
    Eigen::MatrixXd sample_positions(const Eigen::VectorXd &z) const;
    /// Full-length positions at times t (any, not only samples).
    Eigen::MatrixXd positions_at(const Eigen::VectorXd &z, double omega, const std::vector<double> &t) const;
    /// Free velocities at the N samples (n_free x N).
    Eigen::MatrixXd sample_free_velocities(const Eigen::VectorXd &z, double omega) const;

    /// Thesis eq. (2.3.14): A = integral over a period of |v| for the given group of unknowns
    /// (one point: its 1-3 coordinates), by the trapezoidal rule on `quadrature` samples; and its
    /// gradient with respect to z.
    double amplitude(const Eigen::VectorXd &z, double omega, const std::vector<std::size_t> &dofs,
                     Eigen::VectorXd *gradient = nullptr, unsigned int quadrature = 256) const;
    /// Peak-to-peak half range (max - min)/2 of one unknown over the period, from 256 samples.
    double half_range(const Eigen::VectorXd &z, double omega, std::size_t dof) const;

    /// The time-domain force f(x, v, theta) = f_int - D_beta K(x) v + f_ext on the free unknowns at
    /// phase theta = w t, with df/dx and df/dv (free x free, one pattern for every state) if asked.
    Eigen::VectorXd force(const Eigen::VectorXd &x, const Eigen::VectorXd &v, double theta,
                          Eigen::SparseMatrix<double> *df_dx = nullptr,
                          Eigen::SparseMatrix<double> *df_dv = nullptr) const;
    /// Full-length velocities at times t.
    Eigen::MatrixXd velocities_at(const Eigen::VectorXd &z, double omega, const std::vector<double> &t) const;
    const Eigen::VectorXd            &free_mass() const { return mass; }
    const std::vector<HarmonicForce> &harmonic_forces() const { return forces; }
    const std::vector<HarmonicDrive> &harmonic_drives() const { return drives; }
    const HarmonicBalanceSettings    &parameters() const { return settings; }
    /// Full-length positions from free values at phase theta = w t (fixed unknowns at their values,
    /// exactly driven ones on their prescribed motion).
    Eigen::VectorXd full(const Eigen::VectorXd &free_values, double theta = 0) const;
    /// Full-length velocities from free velocities (prescribed motion included).
    Eigen::VectorXd full_velocity(const Eigen::VectorXd &free_velocities, double theta, double omega) const;
    const std::vector<HarmonicDrive> &prescribed_drives() const { return prescribed; }
    /// Scales every forcing and drive amplitude (a load parameter for ramping the excitation up).
    void   set_excitation_scale(double scale) const { excitation = scale; }
    double excitation_scale() const { return excitation; }

    // Parameter derivatives for design (solvers/hbm/design.h): the residual h = A(w) z - F[f] is
    // linear in the lumped masses and in the sampled forces, so dh/dp at fixed z is the linear part
    // with the mass change and minus the coefficients of the sampled force change.

    /// The linear part A(w) z with the free masses replaced by `mass_change` (free length): the
    /// inertia and mass-proportional damping of a change of the masses.
    Eigen::VectorXd mass_residual(const Eigen::VectorXd &z, double omega,
                                  const Eigen::VectorXd &mass_change) const;
    /// Fourier coefficients (free-length harmonic blocks) of free-length samples (n_free x N_AFT).
    Eigen::VectorXd coefficients_of_samples(const Eigen::MatrixXd &free_samples) const;
    /// The samples' weights of lambda^T coefficients_of_samples(S) = sum_ij W_ij S_ij (n_free x N):
    /// an adjoint vector's view of the sampled forces, computed once for every parameter.
    Eigen::MatrixXd adjoint_sample_weights(const Eigen::VectorXd &lambda) const;
    /// Full-length velocities at the N samples (one column per sample), prescribed motion included.
    Eigen::MatrixXd sample_velocities(const Eigen::VectorXd &z, double omega) const;
    /// Position among the free unknowns of unknown i (-1: fixed or prescribed).
    long free_position(std::size_t i) const { return free_index[i]; }
    /// Coefficients of harmonic k (0..H) of free unknown i: (s_k, c_k); s_0 = 0.
    std::pair<double, double> coefficient(const Eigen::VectorXd &z, std::size_t free_index,
                                          unsigned int k) const;

  private:
    /// Forces on the free unknowns at the samples (n_free x N), with the per-sample tangents
    /// df/dx and df/dv (free x free, common pattern) when requested.
    Eigen::MatrixXd sample_forces(const Eigen::VectorXd &z, double omega,
                                  std::vector<Eigen::SparseMatrix<double>> *df_dx,
                                  std::vector<Eigen::SparseMatrix<double>> *df_dv) const;
    /// Fourier coefficients (free-length blocks) of sampled data (n_free x N) and back.
    Eigen::VectorXd to_frequency(const Eigen::MatrixXd &samples) const;
    Eigen::MatrixXd to_time(const Eigen::VectorXd &coefficients) const;
    Eigen::VectorXd linear_part(const Eigen::VectorXd &z, double omega, bool derivative) const;

    const Model                &system;
    HarmonicBalanceSettings     settings;
    unsigned int                H, N;
    std::vector<HarmonicForce>  forces;
    std::vector<HarmonicDrive>  drives, prescribed; // penalty drives, exact drives
    std::vector<std::size_t>    free_dofs;
    std::vector<long>           free_index;
    std::unique_ptr<FreeDofMap> restriction; // onto the free unknowns (not fixed, not prescribed)
    mutable double              excitation = 1;
    Eigen::VectorXd             base;                 // full-length template: fixed values
    Eigen::VectorXd             mass;                 // free lumped masses
    Eigen::MatrixXd             gamma, gamma_inverse; // dense DFT operators (2.A.17-18), N x (2H+1)
    struct FftPlans;
    std::unique_ptr<FftPlans> fft;
  };
} // namespace nlmech
