// Discrete interlocking materials at native scale: time per quasi-static test against the number
// of elements, in one run.
//   - bending tests (positive curvature along x, thesis eq. 4.3.4) on disk patches of 7, 19, 37 and
//     61 elements of the threefold chainmail;
//   - in-plane stretch and compression tests (eq. 4.3.3) on the periodic cells of all four
//     materials.
// Each test is run `repeats` times; medians are printed with Newton iterations and the limit found.
// Samples per minute on 1 and 2 ranks come from the dim-characterization scene (see README.md).
// Last, the contact queries between triangulated elements (sphere trees against all primitive
// pairs, same placement, same answers).
// usage: dim_benchmark [repeats] [largest patch]
#include <nlmech/dim/characterization.h>
#include <nlmech/dim/element_shape.h>
#include <nlmech/dim/rigid_assembly.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace nlmech::dim;

namespace
{
  double median(std::vector<double> v)
  {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  }
} // namespace

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  const unsigned      repeats = argc > 1 ? std::atoi(argv[1]) : 3;
  const unsigned      largest = argc > 2 ? std::atoi(argv[2]) : 61;
  const double        density = 1.24e-6;
  NativeSolveSettings settings;
  settings.contact.dhat   = 0.01;
  settings.contact.kappa  = 0.01;
  settings.max_iterations = 2000;

  std::printf(
      "Bending test (kappa target +0.5 /mm along x, gravity), threefold chainmail disk patches; medians "
      "of %u runs\n",
      repeats);
  std::printf(
      "| elements | unknowns | time per test | Newton iterations | kappa_p [1/mm] | kappa_o [1/mm] |\n");
  std::printf("|---|---|---|---|---|---|\n");
  const Pattern threefold = threefold_pattern({}, density);
  for (const unsigned n : {7u, 19u, 37u, 61u})
    {
      if (n > largest)
        continue;
      std::vector<double> t;
      TestOutcome         out;
      for (unsigned r = 0; r < repeats; ++r)
        {
          BendingTest test(threefold, n, 0.0, settings);
          out = test.solve(0.5, settings.target_weight, 0.0, 0.0);
          t.push_back(out.seconds);
        }
      std::printf("| %u | %u | %.2f s | %u | %.4f | %.4f |\n", n, 6 * n + 2, median(t), out.iterations,
                  out.principal, out.orthogonal);
      std::fflush(stdout);
    }

  std::printf("\nIn-plane tests on periodic cells (theta = 0, orthogonal strain free); medians of %u runs\n",
              repeats);
  std::printf(
      "| material | elements per cell | stretch test | iterations | eps_s | compression test | iterations | "
      "eps_c | c (eq. 4.4.1) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const Pattern &p : {four_in_one_pattern({}, density), threefold, torus_knot_pattern({}, density),
                           scale_mail_pattern({}, density)})
    {
      std::vector<double> ts, tc;
      TestOutcome         s, c;
      for (unsigned r = 0; r < repeats; ++r)
        {
          InPlaneTest test(p, 0.0, settings);
          s = test.solve(0.9, settings.target_weight, 0, 0);
          c = test.solve(-0.9, settings.target_weight, 0, 0);
          ts.push_back(s.seconds), tc.push_back(c.seconds);
        }
      std::printf("| %s | %zu | %.3f s | %u | %.4f | %.3f s | %u | %.4f | %.4f |\n", p.name.c_str(),
                  p.centres.size(), median(ts), s.iterations, s.principal, median(tc), c.iterations,
                  c.principal, travel_metric(s.principal, c.principal));
      std::fflush(stdout);
    }

  // Contact queries between triangulated elements: the sphere trees against every primitive pair.
  std::printf(
      "\nContact queries between two triangulated tori (meshes/dim-torus.geo, R = 3, r = 1 mm, skin 0.05 "
      "mm), ring B through A's hole near contact; sphere trees against all primitive pairs, medians of "
      "%u x 5 queries\n",
      repeats);
  std::printf(
      "| mesh size h | triangles per element | smallest gap [mm] | gap, trees | gap, all pairs | all pairs / "
      "trees | pairs within 0.05 mm | pair list, trees | pair list, all pairs | all pairs / trees | same "
      "result |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const double h : {0.8, 0.5, 0.35})
    {
      const ElementShape shape =
          triangle_mesh_element(std::string(NLMECH_SOURCE_DIR) + "/meshes/dim-torus.geo", 0.05, density, h);
      const RigidAssembly assembly({shape}, {0, 0});
      Eigen::VectorXd     q = Eigen::VectorXd::Zero(12);
      q.segment<6>(6) << 3.88, 0.02, 0.01, M_PI / 2 + 0.01, 0.005, 0.0;
      const double                   reach = 0.05;
      std::vector<double>            t_gap, t_brute, t_pairs;
      double                         gap   = 0;
      std::size_t                    pairs = 0;
      std::pair<double, std::size_t> brute;
      auto                           time = [](const auto &f) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      };
      for (unsigned r = 0; r < 5 * repeats; ++r)
        {
          t_gap.push_back(time([&] { gap = assembly.exact_gap(q, 0, 1, {{0, 0}}); }));
          t_pairs.push_back(time([&] { pairs = assembly.contact_pairs(q, reach).size(); }));
          if (r < repeats) // the all-pairs reference answers both questions in one pass
            t_brute.push_back(time([&] { brute = assembly.all_pairs_gap(q, 0, 1, {{0, 0}}, reach); }));
        }
      std::printf(
          "| %.2f | %zu | %.4f | %.3f ms | %.1f ms | %.0fx | %zu | %.3f ms | %.1f ms | %.0fx | %s |\n", h,
          shape.triangles.size(), gap, 1e3 * median(t_gap), 1e3 * median(t_brute),
          median(t_brute) / median(t_gap), pairs, 1e3 * median(t_pairs), 1e3 * median(t_brute),
          median(t_brute) / median(t_pairs),
          std::abs(gap - brute.first) < 1e-12 && pairs == brute.second ? "yes" : "NO");
      std::fflush(stdout);
    }
  MPI_Finalize();
}
