// Scene "biphasic-sheet": a cloth or chainmail sheet that is soft until direction-dependent stretch
// limits, enforced exactly by projection onto second-order cones inside implicit time stepping (the
// SOCP paper; thesis ch. 3). Drapes, swinging sheets and sheets falling on a sphere, with any of
// the schemes IE, SAP, SAR, BDF2, BAP, BAR side by side (thesis Fig. 3.4). Its parameters:
// scenes/sheet/sheet_settings.h.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/exceptions.h>
#include <nlmech/base/plot.h>
#include <nlmech/base/progress.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/scenes/sheet/scheme_outcome.h>
#include <nlmech/scenes/sheet/sheet_settings.h>
#include <nlmech/solvers/time/cloth_simulation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class BiphasicSheetScene : public Scene
    {
    public:
      explicit BiphasicSheetScene(ParameterHandler &prm) { config.parse_parameters(prm); }

      void validate() const override { config.check(); }

      void run(RunContext &context) override
      {
        const auto                     &c               = config;
        const auto                     &directions      = c.directions;
        const auto                     &frames          = c.frames;
        const auto                     &curve_tolerance = c.curve_tolerance;
        const auto                     &end_time        = c.end_time;
        const auto                     &pin_offsets     = c.pin_offsets;
        const auto                     &material        = c.material;
        const auto                     &schemes         = c.schemes;
        const auto                     &settings        = c.settings;
        const auto                     &cone_settings   = c.cone_settings;
        const RawSimplexMesh<3>         mesh            = make_sheet_mesh(c.size, c.resolution);
        const std::vector<unsigned int> pinned          = c.pinned_vertices(mesh);
        const auto                      limit           = [&c](double alpha) { return c.limit_at(alpha); };
        const auto                      limits =
            make_strain_limits(mesh, {{1, 0, 0}}, {{0, 0, 1}}, directions, limit, curve_tolerance);
        context.pcout << "biphasic sheet: " << mesh.vertices.size() << " vertices, " << mesh.cells.size()
                      << " triangles, " << limits.size() << " stretch limits, " << pinned.size()
                      << " pinned vertices" << std::endl;
        {
          std::ostringstream polar;
          polar << "alpha,limit\n" << std::setprecision(12);
          for (int k = 0; k <= 360; ++k)
            {
              const double a = -numbers::PI / 2 + k * numbers::PI / 360;
              polar << a << "," << limit(a) << "\n";
            }
          polar << "#samples\n";
          for (unsigned int j = 0; j < directions; ++j)
            polar << limits.angle[j] << "," << limits.bound[j] << "\n";
          write_file_atomically(context.output.file("limits.csv"), polar.str());
        }
        const unsigned int steps = unsigned(std::llround(end_time / settings.time_step));
        // The schemes are independent runs: scheme k goes to rank k mod (number of ranks), and
        // rank 0 gathers their energy rows, figures and messages in scheme order (the same files
        // as a serial run). Frames come from the first scheme, always on rank 0.
        const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(context.comm);
        const unsigned int rank    = Utilities::MPI::this_mpi_process(context.comm);
        unsigned int       mine    = 0;
        for (std::size_t k = rank; k < schemes.size(); k += n_ranks)
          ++mine;
        ProgressReporter    progress("biphasic sheet", double(steps * mine), context.comm, std::cout);
        std::vector<double> frame_times;
        std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> frame_fields;
        std::string                                                       packed; // this rank's schemes
        unsigned int                                                      done = 0;
        for (std::size_t k = rank; k < schemes.size(); k += n_ranks, ++done)
          {
            ClothSettings s = settings;
            s.scheme        = schemes[k];
            std::ostringstream csv;
            csv << std::setprecision(12);
            SchemeOutcome         outcome;
            ClothSimulation       sim(mesh, material, pinned, limits, s, cone_settings, pin_offsets);
            const Eigen::VectorXd rest  = sim.shell().rest_positions;
            const double          e0    = sim.energy().total();
            double                worst = -1, newton = 0, projection = 0;
            double       worst_curve = -std::numeric_limits<double>::infinity(), worst_curve_time = 0;
            unsigned int iterations = 0, projections = 0;
            std::size_t  cuts = 0;
            outcome.reached   = largest_stretch_per_direction(limits, sim.positions());
            auto record       = [&](unsigned int step, const ClothStepStatistics &st) {
              const ClothEnergy e = sim.energy();
              csv << to_string(s.scheme) << "," << step << "," << sim.time() << "," << e.kinetic << ","
                  << e.elastic << "," << e.gravity << "," << e.contact << "," << e.total() << ","
                  << st.violation << "," << st.newton_seconds << "," << st.projection_seconds << ","
                  << st.projection_iterations << "\n";
            };
            auto frame = [&]() {
              frame_times.push_back(sim.time());
              frame_fields.push_back(
                  {{"displacement", sim.positions() - rest}, {"velocity", sim.velocities()}});
            };
            record(0, {});
            if (k == 0 && frames > 0)
              frame();
            for (unsigned int step = 1; step <= steps; ++step)
              {
                ClothStepStatistics st;
                try
                  {
                    st = sim.step();
                  }
                catch (const std::exception &e)
                  {
                    outcome.error = to_string(s.scheme) + " stopped at t = " + std::to_string(sim.time()) +
                                    " s: " + message_of(e);
                    break;
                  }
                record(step, st);
                worst = std::max(worst, st.violation);
                cuts += st.cuts;
                if (std::isfinite(st.curve_excess) && st.curve_excess > worst_curve)
                  worst_curve = st.curve_excess, worst_curve_time = sim.time();
                const std::vector<double> now = largest_stretch_per_direction(limits, sim.positions());
                for (std::size_t d = 0; d < now.size(); ++d)
                  outcome.reached[d] = std::max(outcome.reached[d], now[d]);
                newton += st.newton_seconds, projection += st.projection_seconds;
                iterations += st.projection_iterations, projections += st.projections;
                if (k == 0 && frames > 0 && step % std::max(1u, steps / frames) == 0)
                  frame();
                if (step % std::max(1u, steps / 20) == 0 || step == steps)
                  progress.report(double(done * steps + step),
                                  to_string(s.scheme) + " t = " + std::to_string(sim.time()) + " s");
              }
            outcome.index          = k;
            outcome.csv            = csv.str();
            const std::string name = to_string(s.scheme);
            if (uses_projection(s.scheme) && std::isfinite(worst_curve))
              {
                // How far any direction went past the curve (between the samples too), over the run.
                outcome.figures.push_back({"max_curve_excess_" + name, worst_curve, "1"});
                outcome.figures.push_back({"curve_cuts_" + name, double(cuts), "1"});
                char line[320];
                std::snprintf(line, sizeof line,
                              "%s: the largest stretch beyond the limit curve in any direction is %.3g of "
                              "the requested strain (at t = %.4g s; tolerance %.3g), %zu cutting planes",
                              name.c_str(), std::max(0.0, worst_curve), worst_curve_time, curve_tolerance,
                              cuts);
                outcome.message = line;
                if (curve_tolerance > 0 && worst_curve > curve_tolerance * (1 + 1e-6) + 1e-9)
                  outcome.check_failure =
                      name + " exceeded the limit curve by " + std::to_string(worst_curve) +
                      " of the requested strain (tolerance " + std::to_string(curve_tolerance) + ")";
              }
            if (outcome.error.empty())
              {
                outcome.figures.push_back({"energy_lost_" + name, e0 - sim.energy().total(), "J"});
                outcome.figures.push_back({"newton_seconds_per_step_" + name, newton / steps, "s"});
                if (uses_projection(s.scheme))
                  {
                    outcome.figures.push_back({"max_violation_" + name, worst, "1"});
                    outcome.figures.push_back(
                        {"projection_seconds_per_solve_" + name, projection / projections, "s"});
                    outcome.figures.push_back(
                        {"projection_iterations_per_solve_" + name, double(iterations) / projections, "1"});
                  }
                std::ostringstream message;
                if (!outcome.message.empty())
                  message << outcome.message << "\n";
                message << name << ": energy lost " << e0 - sim.energy().total() << " J over " << end_time
                        << " s, largest violation " << worst << ", " << newton / steps << " s Newton and "
                        << (projections ? projection / projections : 0.0) << " s per projection";
                outcome.message = message.str();
              }
            outcome.pack(packed);
          }
        // Rank 0: all schemes in order; everyone learns the first failure.
        const std::vector<std::string> parts = Utilities::MPI::gather(context.comm, packed, 0);
        std::vector<SchemeOutcome>     outcomes;
        for (const auto &part : parts)
          for (std::size_t pos = 0; pos < part.size();)
            outcomes.push_back(SchemeOutcome::unpack(part, pos));
        std::sort(outcomes.begin(), outcomes.end(),
                  [](const SchemeOutcome &a, const SchemeOutcome &b) { return a.index < b.index; });
        std::string all_csv =
            "scheme,step,time,kinetic,elastic,gravity,contact,total,violation,newton_seconds,projection_"
            "seconds,projection_iterations\n";
        std::string              error;
        std::vector<std::string> completed, failed;
        std::ostringstream       reached;
        reached << std::setprecision(12) << "alpha,limit";
        for (const auto &o : outcomes)
          reached << "," << to_string(schemes[o.index]);
        reached << "\n";
        for (std::size_t d = 0; d < limits.grid_angle.size() && !outcomes.empty(); ++d)
          {
            reached << limits.grid_angle[d] << "," << limits.grid_bound[d];
            for (const auto &o : outcomes)
              reached << "," << (d < o.reached.size() ? o.reached[d] : 0.0);
            reached << "\n";
          }
        for (const auto &o : outcomes)
          {
            all_csv += o.csv;
            // A scheme that stopped keeps its rows and figures up to there; the others are complete.
            for (const auto &f : o.figures)
              context.summary.add_figure(f.name, f.value, f.unit);
            if (!o.message.empty())
              context.pcout << o.message << std::endl;
            if (!o.check_failure.empty())
              context.fail_check(o.check_failure);
            if (!o.error.empty())
              {
                failed.push_back(to_string(schemes[o.index]));
                context.pcout << "nlmech: " << o.error << std::endl;
                if (error.empty())
                  error = o.error;
              }
            else
              completed.push_back(to_string(schemes[o.index]));
          }
        error = Utilities::MPI::broadcast(context.comm, error, 0);
        {
          // Every rank exits with the same status: the failed checks found on rank 0.
          std::string checks;
          for (const auto &c : context.failed_checks)
            checks += c + "\n";
          checks = Utilities::MPI::broadcast(context.comm, checks, 0);
          if (!context.is_root())
            for (const auto &c : Utilities::split_string_list(checks, '\n'))
              if (!c.empty())
                context.failed_checks.push_back(c);
        }
        if (context.is_root())
          write_file_atomically(context.output.file("stretch_reached.csv"), reached.str());
        context.summary.add_strings("completed_schemes", completed);
        context.summary.add_strings("failed_schemes", failed);
        if (!error.empty())
          context.partial_reason = error + (completed.empty() ? "" : " (the other schemes completed)");
        context.summary.add_number("mpi_ranks", n_ranks);
        context.summary.add_number("vertices", mesh.vertices.size());
        context.summary.add_number("triangles", mesh.cells.size());
        context.summary.add_number("stretch_limits", limits.size());
        context.summary.add_number("steps", steps);
        write_results(context, all_csv, frame_times, frame_fields, mesh);
      }

    private:
      void write_results(RunContext &context, const std::string &csv, const std::vector<double> &times,
                         const std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> &fields,
                         const RawSimplexMesh<3>                                                 &mesh) const
      {
        if (!context.is_root())
          return;
        write_file_atomically(context.output.file("energy.csv"), csv);
        if (!times.empty())
          write_vertex_fields_pvd(mesh, context.output.file(""), "sheet", times, fields);
        run_plot("biphasic.py", {context.output.file("energy.csv"), context.output.file("limits.csv"),
                                 context.output.file("energy.png"), context.output.file("limits.png"),
                                 context.output.file("stretch_reached.csv")});
      }

      BiphasicSheetSettings config;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(biphasic_sheet,
                        (SceneInfo{
                            "biphasic-sheet",
                            "Cloth and chainmail sheets with direction-dependent stretch limits enforced by "
                            "second-order cone projection (own interior-point solver) inside implicit time "
                            "stepping: IE, SAP, SAR, BDF2, BAP, BAR; drapes, swinging, sphere contact.",
                            &BiphasicSheetSettings::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<BiphasicSheetScene>(prm);
                            }}))
} // namespace nlmech
