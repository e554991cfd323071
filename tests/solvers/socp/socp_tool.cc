// Test helper for the comparison with CVXOPT (tests/solvers/socp/compare_cvxopt.py):
//   socp_tool solve <problem> <solution>           solves a cone QP given as text
//   socp_tool cloth <n> <limit> <seed> <problem>   writes the projection problem of an n x n sheet
// Problem text: "n rows cones", then P diagonal (n), q (n), h (rows), the cone sizes, the number
// of nonzeros of G and one "row column value" line each. Solution text: status, iterations,
// objective, then x (n values).
#include <nlmech/models/cloth/strain_limits.h>
#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/solvers/socp/conic_qp.h>
#include <nlmech/solvers/socp/strain_projection.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <string>

using namespace nlmech;

namespace
{
  void write(const ConicQP &p, const std::string &file)
  {
    std::ofstream out(file);
    out << std::setprecision(17) << p.q.size() << " " << p.h.size() << " " << p.cones.size() << "\n";
    for (const Eigen::VectorXd *v : {&p.P_diagonal, &p.q, &p.h})
      {
        for (Eigen::Index i = 0; i < v->size(); ++i)
          out << (*v)[i] << " ";
        out << "\n";
      }
    for (const unsigned int c : p.cones)
      out << c << " ";
    out << "\n" << p.G.nonZeros() << "\n";
    for (Eigen::Index c = 0; c < p.G.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(p.G, c); it; ++it)
        out << it.row() << " " << it.col() << " " << it.value() << "\n";
  }

  ConicQP read(const std::string &file)
  {
    std::ifstream in(file);
    long          n = 0, rows = 0, cones = 0, nnz = 0;
    in >> n >> rows >> cones;
    ConicQP p;
    p.P_diagonal.resize(n), p.q.resize(n), p.h.resize(rows);
    for (Eigen::VectorXd *v : {&p.P_diagonal, &p.q, &p.h})
      for (Eigen::Index i = 0; i < v->size(); ++i)
        in >> (*v)[i];
    p.cones.resize(std::size_t(cones));
    for (auto &c : p.cones)
      in >> c;
    in >> nnz;
    std::vector<Eigen::Triplet<double>> t;
    for (long k = 0; k < nnz; ++k)
      {
        long   r = 0, c = 0;
        double v = 0;
        in >> r >> c >> v;
        t.emplace_back(r, c, v);
      }
    if (!in)
      throw std::runtime_error("cannot read the problem " + file);
    p.G.resize(rows, n);
    p.G.setFromTriplets(t.begin(), t.end());
    p.G.makeCompressed();
    return p;
  }
} // namespace

int main(int argc, char **argv)
{
  try
    {
      const std::string mode = argc > 1 ? argv[1] : "";
      if (mode == "solve" && argc == 4)
        {
          const ConicQP     p = read(argv[2]);
          ConicQPSolver     solver;
          const ConicResult r = solver.solve(p);
          std::ofstream     out(argv[3]);
          std::string       status = to_string(r.status);
          std::replace(status.begin(), status.end(), ' ', '_');
          out << std::setprecision(17) << status << "\n" << r.iterations << "\n" << r.objective << "\n";
          for (Eigen::Index i = 0; i < r.x.size(); ++i)
            out << r.x[i] << "\n";
          return 0;
        }
      if (mode == "cloth" && argc == 6)
        {
          const unsigned int n     = unsigned(std::stoi(argv[2]));
          const double       limit = std::stod(argv[3]);
          const auto         mesh  = make_sheet_mesh(0.5, n);
          const auto         limits =
              make_strain_limits(mesh, {{1, 0, 0}}, {{0, 0, 1}}, 4, [&](double) { return limit; });
          ShellMaterial material;
          material.thickness = 5e-4, material.density = 200;
          const ShellModel              shell = make_shell_model(mesh, material);
          std::map<std::size_t, double> fixed;
          for (const unsigned int v : {0u, n})
            for (unsigned int d = 0; d < 3; ++d)
              fixed[3 * v + d] = shell.rest_positions[3 * v + d];
          std::mt19937                     rng(unsigned(std::stoi(argv[4])));
          std::normal_distribution<double> normal(0, 0.01);
          Eigen::VectorXd                  x_hat = shell.rest_positions;
          for (Eigen::Index v = 0; v < x_hat.size() / 3; ++v)
            {
              x_hat[3 * v] *= 1.06;
              x_hat[3 * v + 1] -= 0.3 * std::pow(shell.rest_positions[3 * v + 2], 2);
              for (int d = 0; d < 3; ++d)
                x_hat[3 * v + d] += normal(rng);
            }
          StrainLimitProjector projector(limits, shell.model.lumped_mass(), fixed);
          write(projector.problem(x_hat), argv[5]);
          return 0;
        }
      std::cerr << "usage: socp_tool solve <problem> <solution> | cloth <n> <limit> <seed> <problem>\n";
      return 2;
    }
  catch (const std::exception &e)
    {
      std::cerr << "socp_tool: " << e.what() << "\n";
      return 1;
    }
}
