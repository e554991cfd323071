#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <nlmech/solvers/newton/nox_newton.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_Import.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>
#include <Epetra_Vector.h>
#include <NOX.H>
#include <NOX_Epetra.H>
#include <NOX_Epetra_LinearSystem_Amesos.H>
#include <NOX_MeritFunction_Generic.H>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numeric>

namespace nlmech
{
  namespace
  {
    /// The system seen by NOX: residual and tangent on the free unknowns at load factor lambda.
    class NoxInterface : public NOX::Epetra::Interface::Required, public NOX::Epetra::Interface::Jacobian
    {
    public:
      NoxInterface(const EquilibriumSystem &system, const FreeDofMap &free, const Eigen::VectorXd &g,
                   const Epetra_Map &row_map, const Epetra_Map &replicated_map)
          : system(system)
          , free(free)
          , g(g)
          , row_map(row_map)
          , importer(replicated_map, row_map)
          , replicated(replicated_map)
      {
      }

      double               lambda      = 0;
      mutable unsigned int n_residuals = 0, n_jacobians = 0;

      /// Full-length state from a distributed vector of free values (fixed values from the template).
      Eigen::VectorXd full_state(const Epetra_Vector &x) const
      {
        Epetra_Vector &all = const_cast<Epetra_Vector &>(replicated);
        AssertThrow(all.Import(x, importer, Insert) == 0,
                    dealii::ExcMessage("NOX: gathering the state failed."));
        Eigen::VectorXd free_values(free.n_free());
        for (std::size_t i = 0; i < free.n_free(); ++i)
          free_values[i] = all[i];
        Eigen::VectorXd q = free.expand(free_values);
        for (const auto &f : system.fixed())
          q[f.first] = f.second;
        return q;
      }

      bool computeF(const Epetra_Vector &x, Epetra_Vector &F, const FillType) override
      {
        ++n_residuals;
        const Eigen::VectorXd q = full_state(x);
        if (!system.is_valid(q))
          {
            // An inverted element: a residual far above any admissible one makes the line search
            // shorten the step (NOX has no notion of a domain of definition).
            F.PutScalar(1e100 / std::sqrt(double(std::max<std::size_t>(1, free.n_free()))));
            return true;
          }
        const Eigen::VectorXd R = free.restrict(system.internal_force(q)) - lambda * g;
        for (int i = 0; i < row_map.NumMyElements(); ++i)
          F[i] = R[row_map.GID(i)];
        return true;
      }

      bool computeJacobian(const Epetra_Vector &x, Epetra_Operator &Jac) override
      {
        ++n_jacobians;
        auto &A = dynamic_cast<Epetra_CrsMatrix &>(Jac);
        fill(A, full_state(x), false);
        return true;
      }

      /// Writes the tangent's owned rows into A: inserting (pattern set-up) or summing into it.
      void fill(Epetra_CrsMatrix &A, const Eigen::VectorXd &q, const bool insert) const
      {
        const Eigen::SparseMatrix<double, Eigen::RowMajor> K = free.restrict(system.tangent(q));
        if (!insert)
          A.PutScalar(0.0);
        std::vector<int>    columns;
        std::vector<double> values;
        for (int i = 0; i < row_map.NumMyElements(); ++i)
          {
            const int row = row_map.GID(i);
            columns.clear(), values.clear();
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(K, row); it; ++it)
              columns.push_back(int(it.col())), values.push_back(it.value());
            const int error =
                insert ? A.InsertGlobalValues(row, int(values.size()), values.data(), columns.data())
                       : A.SumIntoGlobalValues(row, int(values.size()), values.data(), columns.data());
            AssertThrow(error == 0,
                        dealii::ExcMessage("NOX: the tangent's sparsity changed between evaluations (row " +
                                           std::to_string(row) + ", Epetra error " + std::to_string(error) +
                                           ")."));
          }
      }

    private:
      const EquilibriumSystem &system;
      const FreeDofMap        &free;
      const Eigen::VectorXd   &g;
      const Epetra_Map        &row_map;
      Epetra_Import            importer;
      Epetra_Vector            replicated;
    };
    /// Merit function phi(q) = E(q) - lambda g.q, whose gradient is the residual F. Near
    /// convergence the decrease a Newton step promises, -F.d, falls below what the energy sum can
    /// resolve (about 1e-14 |E|): there this line search switches to 0.5 |F|^2 (slope -|F|^2 for a
    /// Newton direction), the standard remedy for energy line searches at the round-off floor.
    class EnergyMerit : public NOX::MeritFunction::Generic
    {
    public:
      EnergyMerit(const NoxInterface &interface, const EnergyFunction &energy, const Eigen::VectorXd &g,
                  const FreeDofMap &free)
          : interface(interface)
          , energy(energy)
          , g(g)
          , free(free)
      {
      }
      double computef(const NOX::Abstract::Group &group) const override
      {
        if (use_residual)
          return 0.5 * std::pow(group.getNormF(), 2);
        return energy_merit(group);
      }
      void computeGradient(const NOX::Abstract::Group &group, NOX::Abstract::Vector &result) const override
      {
        result = group.getF();
      }
      /// Called on the line search's base point first: picks the merit for this line search.
      double computeSlope(const NOX::Abstract::Vector &direction,
                          const NOX::Abstract::Group  &group) const override
      {
        const double slope = group.getF().innerProduct(direction);
        use_residual       = std::abs(slope) < 1e-8 * std::abs(energy_merit(group));
        return use_residual ? -std::pow(group.getNormF(), 2) : slope;
      }
      double computeQuadraticModel(const NOX::Abstract::Vector &direction,
                                   const NOX::Abstract::Group  &group) const override
      {
        auto Jd = direction.clone(NOX::ShapeCopy);
        group.applyJacobian(direction, *Jd);
        return energy_merit(group) + group.getF().innerProduct(direction) + 0.5 * direction.innerProduct(*Jd);
      }
      /// The Cauchy point of the quadratic model along -F.
      void computeQuadraticMinimizer(const NOX::Abstract::Group &group,
                                     NOX::Abstract::Vector      &result) const override
      {
        const NOX::Abstract::Vector &F  = group.getF();
        auto                         JF = F.clone(NOX::ShapeCopy);
        group.applyJacobian(F, *JF);
        const double curvature = F.innerProduct(*JF);
        result.update(curvature > 0 ? -F.innerProduct(F) / curvature : -1.0, F, 0.0);
      }
      const std::string &name() const override { return merit_name; }

    private:
      double energy_merit(const NOX::Abstract::Group &group) const
      {
        const auto           &x = dynamic_cast<const NOX::Epetra::Vector &>(group.getX()).getEpetraVector();
        const Eigen::VectorXd q = interface.full_state(x);
        const double          e = energy(q) - interface.lambda * g.dot(free.restrict(q));
        return std::isfinite(e) ? e : 1e300;
      }

      const NoxInterface    &interface;
      const EnergyFunction  &energy;
      const Eigen::VectorXd &g;
      const FreeDofMap      &free;
      mutable bool           use_residual = false;
      const std::string      merit_name   = "nlmech potential energy";
    };
  } // namespace

  NoxNewtonResult solve_equilibrium_with_nox(const EquilibriumSystem &system, const Eigen::VectorXd &load,
                                             Eigen::VectorXd &q, const NoxNewtonSettings &settings,
                                             MPI_Comm comm, const EnergyFunction &energy)
  {
    const auto       start = std::chrono::steady_clock::now();
    const FreeDofMap free(system.n_unknowns(), system.fixed());
    const int        n_free = int(free.n_free());
    AssertThrow(n_free > 0, dealii::ExcMessage("NOX Newton: every unknown is fixed."));
    for (const auto &f : system.fixed())
      q[f.first] = f.second;
    const Eigen::VectorXd g = free.restrict(load);

    const Epetra_MpiComm epetra_comm(comm);
    const Epetra_Map     row_map(n_free, 0, epetra_comm);
    std::vector<int>     all(n_free);
    std::iota(all.begin(), all.end(), 0);
    const Epetra_Map replicated_map(-1, n_free, all.data(), 0, epetra_comm);
    auto             interface = Teuchos::rcp(new NoxInterface(system, free, g, row_map, replicated_map));

    // The tangent's pattern, fixed for the whole solve.
    auto matrix = Teuchos::rcp(new Epetra_CrsMatrix(Copy, row_map, 0));
    interface->fill(*matrix, q, true);
    AssertThrow(matrix->FillComplete() == 0, dealii::ExcMessage("NOX: assembling the tangent failed."));

    Epetra_Vector         x(row_map);
    const Eigen::VectorXd q_free = free.restrict(q);
    for (int i = 0; i < row_map.NumMyElements(); ++i)
      x[i] = q_free[row_map.GID(i)];

    NoxNewtonResult result;
    result.direct_solver = epetra_comm.NumProc() > 1 ? "Amesos_Mumps" : "Amesos_Klu";
    if (!settings.direct_solver.empty())
      result.direct_solver = settings.direct_solver;
    auto params = Teuchos::rcp(new Teuchos::ParameterList);
    params->set("Nonlinear Solver", "Line Search Based");
    params->sublist("Printing")
        .set("Output Information", std::getenv("NLMECH_NOX_VERBOSE")
                                       ? NOX::Utils::Error + NOX::Utils::OuterIteration +
                                             NOX::Utils::InnerIteration + NOX::Utils::Warning
                                       : NOX::Utils::Error);
    if (energy)
      {
        params->sublist("Line Search").set("Method", "Polynomial");
        params->sublist("Solver Options")
            .set<Teuchos::RCP<NOX::MeritFunction::Generic>>(
                "User Defined Merit Function", Teuchos::rcp(new EnergyMerit(*interface, energy, g, free)));
      }
    else
      params->sublist("Line Search").set("Method", settings.line_search);
    params->sublist("Direction").set("Method", "Newton");
    Teuchos::ParameterList &linear = params->sublist("Direction").sublist("Newton").sublist("Linear Solver");
    linear.set("Amesos Solver", result.direct_solver);

    Teuchos::RCP<NOX::Epetra::Interface::Required> required = interface;
    Teuchos::RCP<NOX::Epetra::Interface::Jacobian> jacobian = interface;
    const NOX::Epetra::Vector                      clone(x, NOX::DeepCopy);
    auto linear_system = Teuchos::rcp(new NOX::Epetra::LinearSystemAmesos(params->sublist("Printing"), linear,
                                                                          required, jacobian, matrix, clone));
    auto group =
        Teuchos::rcp(new NOX::Epetra::Group(params->sublist("Printing"), required, clone, linear_system));

    const double tolerance = settings.relative_tolerance * g.norm();
    for (unsigned int step = 1; step <= settings.load_steps; ++step)
      {
        interface->lambda = double(step) / settings.load_steps;
        group->setX(NOX::Epetra::Vector(x, NOX::DeepCopy));
        auto converged =
            Teuchos::rcp(new NOX::StatusTest::NormF(tolerance, NOX::StatusTest::NormF::Unscaled));
        auto iterations = Teuchos::rcp(new NOX::StatusTest::MaxIters(int(settings.max_iterations)));
        auto finite     = Teuchos::rcp(new NOX::StatusTest::FiniteValue);
        auto test       = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR));
        test->addStatusTest(converged);
        test->addStatusTest(iterations);
        test->addStatusTest(finite);
        auto                              solver = NOX::Solver::buildSolver(group, test, params);
        const NOX::StatusTest::StatusType status = solver->solve();
        result.iterations += unsigned(solver->getNumIterations());
        const auto  &solution = dynamic_cast<const NOX::Epetra::Group &>(solver->getSolutionGroup());
        const double residual = solution.getNormF();
        // Stagnation at the round-off floor, far below any useful accuracy, is accepted as converged.
        AssertThrow(status == NOX::StatusTest::Converged ||
                        (std::isfinite(residual) && residual <= 1e-6 * g.norm()),
                    dealii::ExcMessage("NOX Newton did not converge at load factor " +
                                       std::to_string(interface->lambda) + " (relative residual " +
                                       std::to_string(residual / g.norm()) + " after " +
                                       std::to_string(solver->getNumIterations()) + " iterations)."));
        x = dynamic_cast<const NOX::Epetra::Vector &>(solution.getX()).getEpetraVector();
      }
    q                     = interface->full_state(x);
    result.factorizations = interface->n_jacobians;
    result.residuals      = interface->n_residuals;
    result.seconds        = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
} // namespace nlmech
