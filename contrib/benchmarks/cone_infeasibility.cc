// Near-infeasible cone problems: the two intervals |x| <= 1 and |x - (2 + g)| <= 1 (infeasible by a
// gap g), min x^2 / 2, by our interior-point solver, direct method with the embedding as fallback
// (automatic) and the embedding alone. Prints one CSV row per gap and method:
//   gap,method,status,iterations,seconds,h_dot_z,Gt_z
// contrib/benchmarks/cone_infeasibility.py puts CVXOPT beside it.
#include <nlmech/solvers/socp/conic_qp.h>

#include <chrono>
#include <cstdio>

using namespace nlmech;

int main()
{
  std::printf("gap,method,status,iterations,seconds,h_dot_z,Gt_z\n");
  for (const double g : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9})
    for (const ConicMethod method : {ConicMethod::automatic, ConicMethod::embedded})
      {
        ConicQP p;
        p.P_diagonal = Eigen::VectorXd::Ones(1);
        p.q          = Eigen::VectorXd::Zero(1);
        p.G.resize(4, 1);
        p.G.insert(1, 0) = -1;
        p.G.insert(3, 0) = -1;
        p.G.makeCompressed();
        p.h     = (Eigen::VectorXd(4) << 1, 0, 1, -(2 + g)).finished();
        p.cones = {2, 2};
        ConicSettings settings;
        settings.method = method;
        ConicQPSolver     solver;
        const auto        t0 = std::chrono::steady_clock::now();
        const ConicResult r  = solver.solve(p, settings);
        const double      s  = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const bool        certified = r.status == ConicStatus::primal_infeasible;
        std::printf("%.0e,%s,%s,%u,%.2e,%.6g,%.2e\n", g,
                    method == ConicMethod::embedded ? "embedded" : "automatic", to_string(r.status).c_str(),
                    r.iterations, s, certified ? p.h.dot(r.z) : 0.0,
                    certified ? (p.G.transpose() * r.z).norm() : 0.0);
      }
}
