// Sparse direct solvers on the neo-Hookean tangent of the cantilever bar (the ANM paper's bar, seed
// 003, Table 1), side by side in one run: CHOLMOD supernodal Cholesky and UMFPACK LU (the serial
// SparseFactorization the solvers use) against Trilinos Amesos MUMPS on an Epetra matrix whose rows
// are split over the ranks of MPI_COMM_WORLD. Each line: one factorisation and `solves` solves
// (an ANM step of order 20 does one and 20), medians of `repeats`.
//   mpirun -np 1|2 factorization_benchmark [repeats] [solves] [element sizes...]
#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

#include <Amesos.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>
#include <Epetra_Vector.h>
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

using namespace nlmech;

namespace
{
  double median(std::vector<double> v)
  {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  }

  double now()
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }

  struct Timing
  {
    double factorization = 0, solves = 0, error = 0;
  };

  /// Amesos MUMPS on the rows [begin, end) of A owned by this rank: symbolic + numeric, `solves`
  /// solves with b; the relative residual of the last one.
  Timing mumps(const Eigen::SparseMatrix<double, Eigen::RowMajor> &A, const Eigen::VectorXd &b,
               const unsigned solves, const Epetra_MpiComm &comm)
  {
    const Epetra_Map row_map(int(A.rows()), 0, comm);
    Epetra_CrsMatrix matrix(Copy, row_map, 0);
    for (int i = 0; i < row_map.NumMyElements(); ++i)
      {
        const int              row = row_map.GID(i);
        std::vector<int>       cols;
        std::vector<double>    vals;
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(A, row); it; ++it)
          cols.push_back(int(it.col())), vals.push_back(it.value());
        matrix.InsertGlobalValues(row, int(cols.size()), vals.data(), cols.data());
      }
    matrix.FillComplete();
    Epetra_Vector x(row_map), rhs(row_map);
    for (int i = 0; i < row_map.NumMyElements(); ++i)
      rhs[i] = b[row_map.GID(i)];
    Epetra_LinearProblem         problem(&matrix, &x, &rhs);
    Amesos                       factory;
    std::unique_ptr<Amesos_BaseSolver> solver(factory.Create("Amesos_Mumps", problem));
    Teuchos::ParameterList       list;
    list.set("MatrixProperty", "SPD");
    solver->SetParameters(list);
    comm.Barrier();
    Timing t;
    double start = now();
    solver->SymbolicFactorization();
    solver->NumericFactorization();
    comm.Barrier();
    t.factorization = now() - start;
    start           = now();
    for (unsigned s = 0; s < solves; ++s)
      solver->Solve();
    comm.Barrier();
    t.solves = now() - start;
    Epetra_Vector r(row_map);
    matrix.Multiply(false, x, r);
    r.Update(-1.0, rhs, 1.0);
    double rn = 0, bn = 0;
    r.Norm2(&rn);
    rhs.Norm2(&bn);
    t.error = rn / bn;
    return t;
  }

  Timing serial(const Eigen::SparseMatrix<double> &A, const Eigen::VectorXd &b, const unsigned solves,
                const bool symmetric)
  {
    SparseFactorization f;
    Timing              t;
    double              start = now();
    f.factorize(A, symmetric);
    t.factorization = now() - start;
    start           = now();
    Eigen::VectorXd x;
    for (unsigned s = 0; s < solves; ++s)
      x = f.solve(b);
    t.solves = now() - start;
    t.error  = (A * x - b).norm() / b.norm();
    return t;
  }
} // namespace

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  {
    const Epetra_MpiComm comm(MPI_COMM_WORLD);
    const unsigned       repeats = argc > 1 ? unsigned(std::atoi(argv[1])) : 3;
    const unsigned       solves  = argc > 2 ? unsigned(std::atoi(argv[2])) : 20;
    std::vector<double>  sizes;
    for (int a = 3; a < argc; ++a)
      sizes.push_back(std::atof(argv[a]));
    if (sizes.empty())
      sizes = {0.008, 0.004, 0.003, 0.0022};
    const bool root = comm.MyPID() == 0;
    if (root)
      std::printf("Neo-Hookean tangent of the bar (L 0.3 x 0.03 x 0.03 m, nu 0.45) at rest; %d rank(s); one "
                  "factorisation + %u solves, medians of %u [s]\n"
                  "| vertices | unknowns | CHOLMOD fact | CHOLMOD solves | UMFPACK fact | UMFPACK solves | "
                  "MUMPS fact | MUMPS solves | MUMPS / CHOLMOD (total) |\n|---|---|---|---|---|---|---|---|---|\n",
                  comm.NumProc(), solves, repeats);
    for (const double h : sizes)
      {
        MeshOptions options;
        options.file                  = std::string(NLMECH_SOURCE_DIR) + "/meshes/cantilever.geo";
        options.characteristic_length = h;
        options.constants             = {{"L", 0.3}, {"W", 0.03}, {"H", 0.03}};
        const auto mesh               = read_simplex_mesh<3>(options, 3);
        HyperelasticMaterial material;
        material.youngs_modulus = 1e6;
        material.poissons_ratio = 0.45;
        material.density        = 1100;
        HyperelasticBoundaryConditions conditions;
        conditions.clamped = {"clamped"};
        const HyperelasticProblem problem = make_hyperelastic_problem(mesh, material, conditions, {});
        const FreeDofMap          free(problem.internal);
        const Eigen::SparseMatrix<double> A = free.restrict(problem.internal.hessian(problem.rest_positions));
        const Eigen::SparseMatrix<double, Eigen::RowMajor> A_rows = A;
        const Eigen::VectorXd b = Eigen::VectorXd::Ones(A.rows());

        std::vector<double> cf, cs, uf, us, mf, ms;
        for (unsigned r = 0; r < repeats; ++r)
          {
            if (root) // the serial baselines run alone: the other ranks wait
              {
                const Timing c = serial(A, b, solves, true), u = serial(A, b, solves, false);
                cf.push_back(c.factorization), cs.push_back(c.solves);
                uf.push_back(u.factorization), us.push_back(u.solves);
              }
            comm.Barrier();
            const Timing m = mumps(A_rows, b, solves, comm);
            mf.push_back(m.factorization), ms.push_back(m.solves);
            if (root && m.error > 1e-8)
              std::printf("  MUMPS residual %.1e\n", m.error);
          }
        if (root)
          std::printf("| %zu | %ld | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f |\n", mesh.vertices.size(),
                      long(A.rows()), median(cf), median(cs), median(uf), median(us), median(mf), median(ms),
                      (median(mf) + median(ms)) / (median(cf) + median(cs)));
      }
  }
  MPI_Finalize();
  return 0;
}
