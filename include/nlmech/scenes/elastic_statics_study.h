#pragma once
// The run loop shared by the linear-elastic statics scenes: for each element size of the mesh study,
// mesh with gmsh, set up, assemble, solve, evaluate the scene's figures and write fields; then the
// study table (CSV), a PNG plot of error against DOFs and time, the PVD record and the summary.

#include <nlmech/base/mesh_study.h>
#include <nlmech/base/run_context.h>
#include <nlmech/scenes/elastic_statics_parameters.h>

#include <functional>
#include <string>
#include <vector>

namespace nlmech
{
  template <int dim>
  struct ElasticStaticsStudy
  {
    MeshParameters           mesh;
    MeshStudyParameters      study;
    MaterialParameters       material;
    DiscretizationParameters discretization;
    LinearSolverParameters   solver;

    std::string              title;
    std::string              error_name; // CSV column, with unit
    std::vector<std::string> extra_columns;

    /// Boundary conditions and loads for one mesh (groups by name).
    std::function<void(LinearElasticity<dim> &, const MeshGroups &)> configure;
    /// Error against the scene's reference and the extra columns, for one solved mesh.
    std::function<std::pair<double, std::vector<double>>(const LinearElasticity<dim> &, const MeshGroups &)>
        evaluate;

    /// Optional: after all levels, before the table is written, e.g. to measure the errors against
    /// a reference extrapolated from the levels themselves (MeshStudyTable::set_errors).
    std::function<void(MeshStudyTable &)> finish;
    /// An extra column drawn beside the error in mesh_study.png (e.g. the error against beam
    /// theory, as context); empty: none.
    std::string context_column;

    /// Runs all levels; writes mesh_study.csv/.png, solution.pvd and per-level VTU into the context.
    MeshStudyTable run(RunContext &context) const;
  };
} // namespace nlmech
