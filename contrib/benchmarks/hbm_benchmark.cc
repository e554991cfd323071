// Benchmark: harmonic balance against Newmark time stepping to the periodic steady state, at equal
// trajectory error, and the AFT by FFTW against dense DFT matrices. Prints medians of repeated
// runs side by side, and the cost of one Newton iteration (residual, Jacobian, sparse LU, solve)
// against N_H and the number of unknowns on the fork shell of prm/fork-shell.prm.
//   build/contrib/benchmarks/hbm_benchmark [repeats]
// Model: the forced, damped, hardening Duffing oscillator of prm/duffing.prm (m = k = k3 = 1,
// c = 0.1, F = 0.5) off resonance; reference trajectory: HBM with N_H = 25 (converged to round-off).
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/dynamics/spring_network.h>
#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

using namespace nlmech;

namespace
{
  constexpr double pi = 3.14159265358979323846;
  using Clock         = std::chrono::steady_clock;

  double median_seconds(unsigned int repeats, const std::function<void()> &f)
  {
    std::vector<double> t;
    for (unsigned int r = 0; r < repeats; ++r)
      {
        const auto start = Clock::now();
        f();
        t.push_back(std::chrono::duration<double>(Clock::now() - start).count());
      }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
  }

  /// A chain of n masses with cubic springs between them (and to a wall), forced at the last one.
  Model chain(unsigned int n)
  {
    Model             model(n + 1);
    SpringElements<1> springs;
    for (unsigned int i = 0; i < n; ++i)
      {
        Spring<1> s;
        s.a = i, s.b = i + 1, s.stiffness = 1, s.cubic = 0.5, s.axial = true, s.direction = {{1.0}};
        springs.springs.push_back(s);
      }
    model.add_term(std::make_shared<SpringTerm<1>>("chain", springs));
    model.lumped_mass() = Eigen::VectorXd::Constant(n + 1, 1.0);
    model.fix(0, 0.0);
    return model;
  }
} // namespace

int main(int argc, char **argv)
{
  const unsigned int repeats = argc > 1 ? unsigned(std::atoi(argv[1])) : 5;
  // `hbm_benchmark 3 --skip-newmark`: only the AFT and Newton-iteration tables (minutes less).
  const bool skip_newmark = argc > 2 && std::string(argv[2]) == "--skip-newmark";
  std::printf("# HBM benchmark (median of %u)\n\n", repeats);
  const Model             model = make_duffing_model(1, 1, 1);
  HarmonicBalanceSettings settings;
  settings.rayleigh_mass = 0.1;
  std::printf("## Duffing steady state: HBM vs Newmark from rest, equal trajectory error\n\n");
  std::printf(
      "| w [rad/s] | N_H | HBM error | HBM [ms] | Newmark steps/period | Newmark error | Newmark periods "
      "| Newmark [ms] | Newmark/HBM |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const double omega : skip_newmark ? std::vector<double>{} : std::vector<double>{0.6, 2.5})
    {
      settings.n_harmonics = 25;
      const HarmonicBalance reference(model, settings, {{1, 0.5, 0.0}});
      Eigen::VectorXd       z_ref = Eigen::VectorXd::Zero(reference.n_unknowns());
      solve_periodic_state(reference, z_ref, omega);
      auto error_of = [&](const Eigen::MatrixXd &x, const std::vector<double> &t) {
        const Eigen::MatrixXd xr   = reference.positions_at(z_ref, omega, t);
        const double          size = reference.half_range(z_ref, omega, 1);
        return (x.row(1) - xr.row(1)).lpNorm<Eigen::Infinity>() / size;
      };
      for (const unsigned int H : {3u, 5u})
        {
          settings.n_harmonics = H;
          const HarmonicBalance hb(model, settings, {{1, 0.5, 0.0}});
          Eigen::VectorXd       z;
          const double          t_hbm = median_seconds(repeats, [&] {
            z = Eigen::VectorXd::Zero(hb.n_unknowns());
            solve_periodic_state(hb, z, omega);
          });
          std::vector<double>   t(512);
          for (unsigned int i = 0; i < t.size(); ++i)
            t[i] = 2 * pi / omega * i / t.size();
          const double e_hbm = error_of(hb.positions_at(z, omega, t), t);
          // Newmark: the coarsest steps per period (powers of two) reaching the same error.
          NewmarkSettings ns;
          ns.period_tolerance = std::max(1e-12, 0.1 * e_hbm);
          NewmarkResult nm;
          unsigned int  S    = 16;
          double        e_nm = 1;
          for (; S <= 8192; S *= 2)
            {
              ns.steps_per_period = S;
              nm = newmark_steady_state(hb, omega, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), ns);
              std::vector<double> tn(S);
              for (unsigned int i = 0; i < S; ++i)
                tn[i] = 2 * pi / omega * i / S;
              e_nm = error_of(nm.last_period, tn);
              if (e_nm <= e_hbm)
                break;
            }
          const double t_nm = median_seconds(1, [&] {
            newmark_steady_state(hb, omega, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), ns);
          });
          std::printf("| %.1f | %u | %.1e | %.2f | %u%s | %.1e | %u | %.1f | %.0fx |\n", omega, H, e_hbm,
                      1e3 * t_hbm, std::min(S, 8192u), S > 8192 ? " (cap)" : "", e_nm, nm.periods, 1e3 * t_nm,
                      t_nm / t_hbm);
          std::fflush(stdout);
        }
    }

  std::fflush(stdout);
  std::printf("\n## AFT: FFTW vs dense DFT, residual + Jacobian of a chain of cubic springs\n\n");
  std::printf("| unknowns n | N_H | N_AFT | FFT [ms] | dense DFT [ms] | dense/FFT | same result |\n"
              "|---|---|---|---|---|---|---|\n");
  for (const unsigned int n : {10u, 200u})
    for (const unsigned int H : {5u, 20u, 60u})
      {
        const Model             m = chain(n);
        HarmonicBalanceSettings fft, dense;
        fft.n_harmonics = dense.n_harmonics = H;
        fft.rayleigh_mass = dense.rayleigh_mass = 0.05;
        dense.use_fft                           = false;
        const HarmonicBalance a(m, fft, {{n, 0.3, 0.0}}), b(m, dense, {{n, 0.3, 0.0}});
        std::srand(1);
        const Eigen::VectorXd z = 0.1 * Eigen::VectorXd::Random(a.n_unknowns());
        Eigen::VectorXd       ra, rb;
        const double          ta   = median_seconds(repeats, [&] { ra = a.residual(z, 1.3); });
        const double          tb   = median_seconds(repeats, [&] { rb = b.residual(z, 1.3); });
        const double          diff = (ra - rb).norm();
        std::printf("| %u | %u | %u | %.3f | %.3f | %.1fx | %s |\n", n, H, a.n_samples(), 1e3 * ta, 1e3 * tb,
                    tb / ta, diff < 1e-9 * (1 + ra.norm()) ? "yes" : "NO");
      }
  std::printf(
      "\n(residual only: the AFT is what differs; the Jacobian assembly uses the dense products in both.)\n");

  std::printf("\n## Cost of one Newton iteration on the fork shell (prm/fork-shell.prm), medians\n\n");
  std::printf(
      "| vertices | free dofs | N_H | unknowns | residual [ms] | Jacobian [ms] | LU [ms] | solve [ms] | "
      "iteration [ms] | Jacobian nonzeros |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (const double size : {0.02, 0.012, 0.008})
    {
      MeshOptions options;
      options.file                  = NLMECH_SOURCE_DIR "/meshes/fork.geo";
      options.characteristic_length = size;
      const RawSimplexMesh<3> mesh  = read_simplex_mesh<3>(options, 2);
      ShellMaterial           material;
      material.youngs_modulus = 1e7, material.poissons_ratio = 0.4, material.density = 1100;
      const ShellModel           shell = make_shell_model(mesh, material);
      std::vector<HarmonicDrive> drives;
      const unsigned int         handle = mesh.groups.material_ids.at("handle");
      std::vector<bool>          driven(mesh.vertices.size(), false);
      for (std::size_t c = 0; c < mesh.cells.size(); ++c)
        if (mesh.cell_material[c] == handle)
          for (const unsigned int v : mesh.cells[c])
            driven[v] = true;
      for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        if (driven[v])
          for (unsigned int i = 0; i < 3; ++i)
            drives.push_back(
                {3 * v + i, i == 2 ? 5e-4 : 0.0, 0.0, 0.0, shell.rest_positions[3 * v + i], {}, {}});
      for (const unsigned int H : {1u, 3u, 5u, 7u})
        {
          HarmonicBalanceSettings settings;
          settings.n_harmonics   = H;
          settings.rayleigh_mass = 1;
          const HarmonicBalance hb(shell.model, settings, {}, drives);
          Eigen::VectorXd       z = hb.static_coefficients(shell.rest_positions);
          solve_with_excitation_ramp(hb, z, 4.0); // a genuine state (the fork's scene at 4 rad/s)
          Eigen::SparseMatrix<double> J;
          Eigen::VectorXd             h;
          SparseFactorization         lu;
          const double                tr = median_seconds(repeats, [&] { h = hb.residual(z, 4.0); });
          const double                tj = median_seconds(repeats, [&] { J = hb.jacobian(z, 4.0); });
          const double                tf = median_seconds(repeats, [&] { lu.factorize(J, false); });
          Eigen::VectorXd             dz;
          const double                ts = median_seconds(repeats, [&] { dz = lu.solve(h); });
          std::printf("| %zu | %zu | %u | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %ld |\n",
                      mesh.vertices.size(), hb.n_free(), H, hb.n_unknowns(), 1e3 * tr, 1e3 * tj, 1e3 * tf,
                      1e3 * ts, 1e3 * (tr + tj + tf + ts), long(J.nonZeros()));
          std::fflush(stdout);
        }
    }
  return 0;
}
