#include <nlmech/scenes/elastic_statics_study.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>
#include <deal.II/distributed/shared_tria.h>

#include <nlmech/base/progress.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  template <int dim>
  MeshStudyTable ElasticStaticsStudy<dim>::run(RunContext &context) const
  {
    const std::vector<double> sizes   = study.sizes(mesh.element_size);
    std::vector<std::string>  columns = extra_columns;
    columns.insert(columns.end(), {"solve_time_s", "solver_iterations", "peak_memory_MiB"});
    MeshStudyTable table(error_name, columns);

    double total_work = 0;
    for (double h : sizes)
      total_work += std::pow(h > 0 ? h : 1.0, -double(dim));
    ProgressReporter                            progress(title, total_work, context.comm, std::cout);
    double                                      work_done = 0;
    std::vector<std::pair<double, std::string>> pvd_entries;

    for (unsigned int level = 0; level < sizes.size(); ++level)
      {
        Timer                                level_timer(context.comm, true);
        parallel::shared::Triangulation<dim> tria(context.comm, Triangulation<dim>::none, false,
                                                  parallel::shared::Triangulation<dim>::partition_metis);
        MeshGroups                           groups;
        {
          TimerOutput::Scope t(context.timer, "mesh (gmsh + checks)");
          groups = load_gmsh_mesh(mesh.options(sizes[level]), tria);
        }
        LinearElasticity<dim> problem(tria, material.material, discretization.degree);
        configure(problem, groups);
        {
          TimerOutput::Scope t(context.timer, "setup (DoFs, constraints, sparsity)");
          problem.setup();
        }
        {
          TimerOutput::Scope t(context.timer, "assembly");
          problem.assemble();
        }
        LinearSolveStatistics stats;
        {
          TimerOutput::Scope t(context.timer, "solve (" + solver.settings.method + ")");
          stats = problem.solve(solver.settings);
        }
        std::pair<double, std::vector<double>> figures;
        {
          TimerOutput::Scope t(context.timer, "evaluation");
          figures = evaluate(problem, groups);
        }
        const double wall = level_timer.wall_time();

        if (study.write_fields)
          {
            TimerOutput::Scope t(context.timer, "output (VTU)");
            char               name[64];
            std::snprintf(name, sizeof(name), "solution-%02u", level);
            const std::string record = problem.write_vtu(context.output.file(""), name);
            pvd_entries.emplace_back(level, record);
          }

        if (study.write_vertex_displacements && level + 1 == sizes.size())
          {
            const auto rows = problem.vertex_displacements();
            if (context.is_root())
              {
                std::ostringstream csv;
                csv.precision(17);
                const char *axis[] = {"x", "y", "z"};
                for (unsigned int d = 0; d < dim; ++d)
                  csv << axis[d] << "_m,";
                for (unsigned int d = 0; d < dim; ++d)
                  csv << "u_" << axis[d] << "_m" << (d + 1 < dim ? "," : "\n");
                for (const auto &r : rows)
                  {
                    for (unsigned int d = 0; d < dim; ++d)
                      csv << r.first[d] << ",";
                    for (unsigned int d = 0; d < dim; ++d)
                      csv << r.second[d] << (d + 1 < dim ? "," : "\n");
                  }
                write_file_atomically(context.output.file("vertex_displacements.csv"), csv.str());
              }
          }

        MeshStudyTable::Row row;
        row.level        = level;
        row.element_size = sizes[level];
        row.n_cells      = tria.n_active_cells();
        row.n_dofs       = problem.n_dofs();
        row.error        = figures.first;
        row.wall_seconds = wall;
        row.extra        = figures.second;
        Utilities::System::MemoryStats memory_stats;
        Utilities::System::get_memory_stats(memory_stats);
        const double memory = Utilities::MPI::max(double(memory_stats.VmHWM) / 1024.0, context.comm); // MiB
        row.extra.insert(row.extra.end(), {stats.solve_seconds, double(stats.iterations), memory});
        table.add(row);

        work_done += std::pow(sizes[level] > 0 ? sizes[level] : 1.0, -double(dim));
        char label[160];
        if (finish) // the error is measured after the last level (against all of them)
          std::snprintf(label, sizeof(label), "level %u: h = %g m, %llu DOFs", level, sizes[level],
                        row.n_dofs);
        else
          std::snprintf(label, sizeof(label), "level %u: h = %g m, %llu DOFs, %s = %.4g", level, sizes[level],
                        row.n_dofs, error_name.c_str(), row.error);
        progress.report(work_done, label);
      }

    if (finish)
      finish(table);
    if (context.is_root())
      {
        table.write_csv(context.output.file("mesh_study.csv"));
        if (!pvd_entries.empty())
          {
            AtomicFile pvd(context.output.file("solution.pvd"));
            DataOutBase::write_pvd_record(pvd.stream(), pvd_entries);
            pvd.commit();
          }
        if (table.rows().size() >= 2)
          {
            const std::string problem_with_plot =
                MeshStudyTable::plot(context.output.file("mesh_study.csv"),
                                     context.output.file("mesh_study.png"), title, context_column);
            // (run_plot has warned on stderr when it failed)
            context.summary.add_bool("mesh_study_plot_written", problem_with_plot.empty());
          }
      }

    const auto &finest = table.rows().back();
    context.summary.add_number("mesh_levels", table.rows().size());
    context.summary.add_figure("finest_element_size", finest.element_size, "m");
    context.summary.add_number("finest_n_dofs", finest.n_dofs);
    context.summary.add_number("finest_n_cells", finest.n_cells);
    context.summary.add_figure("finest_wall_time", finest.wall_seconds, "s");
    context.summary.add_number("mpi_ranks", Utilities::MPI::n_mpi_processes(context.comm));
    return table;
  }

  template struct ElasticStaticsStudy<2>;
  template struct ElasticStaticsStudy<3>;
} // namespace nlmech
