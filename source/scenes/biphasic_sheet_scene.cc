// Scene "biphasic-sheet": a cloth or chainmail sheet that is soft until direction-dependent stretch
// limits, enforced exactly by projection onto second-order cones inside implicit time stepping (the
// SOCP paper; thesis ch. 3). Drapes, swinging sheets and sheets falling on a sphere, with any of
// the schemes IE, SAP, SAR, BDF2, BAP, BAR side by side (thesis Fig. 3.4).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>

#include <nlmech/base/exceptions.h>
#include <nlmech/base/plot.h>
#include <nlmech/base/progress.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/solvers/time/cloth_simulation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// One scheme's run, packed into a string (length-prefixed fields) for the gather to rank 0.
    struct SchemeOutcome
    {
      struct Figure
      {
        std::string name;
        double      value;
        std::string unit;
      };
      std::size_t         index = 0;
      std::string         csv, message, error;
      std::vector<Figure> figures;
      std::vector<double> reached;       // largest stretch per grid direction over the run
      std::string         check_failure; // the curve was not held to its tolerance

      static void put(std::string &out, const std::string &field)
      {
        out += std::to_string(field.size()) + ":" + field;
      }
      static std::string take(const std::string &in, std::size_t &pos)
      {
        const std::size_t colon = in.find(':', pos);
        const std::size_t n     = std::stoul(in.substr(pos, colon - pos));
        std::string       field = in.substr(colon + 1, n);
        pos                     = colon + 1 + n;
        return field;
      }
      void pack(std::string &out) const
      {
        put(out, std::to_string(index)), put(out, csv), put(out, message), put(out, error);
        put(out, check_failure);
        char value[64];
        put(out, std::to_string(reached.size()));
        for (const double r : reached)
          {
            std::snprintf(value, sizeof value, "%.17g", r);
            put(out, value);
          }
        put(out, std::to_string(figures.size()));
        for (const auto &f : figures)
          {
            std::snprintf(value, sizeof value, "%.17g", f.value);
            put(out, f.name), put(out, value), put(out, f.unit);
          }
      }
      static SchemeOutcome unpack(const std::string &in, std::size_t &pos)
      {
        SchemeOutcome o;
        o.index             = std::stoul(take(in, pos));
        o.csv               = take(in, pos);
        o.message           = take(in, pos);
        o.error             = take(in, pos);
        o.check_failure     = take(in, pos);
        const std::size_t m = std::stoul(take(in, pos));
        for (std::size_t k = 0; k < m; ++k)
          o.reached.push_back(std::strtod(take(in, pos).c_str(), nullptr));
        const std::size_t n = std::stoul(take(in, pos));
        for (std::size_t k = 0; k < n; ++k)
          {
            Figure f;
            f.name  = take(in, pos);
            f.value = std::strtod(take(in, pos).c_str(), nullptr);
            f.unit  = take(in, pos);
            o.figures.push_back(f);
          }
        return o;
      }
    };

    class BiphasicSheetScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Sheet");
        prm.declare_entry("Size", "0.5", Patterns::Double(0),
                          "Side of the square sheet [m] (xz-plane, y up).");
        prm.declare_entry("Resolution", "20", Patterns::Integer(1), "Quads per side (2 triangles each) [-].");
        prm.declare_entry("Pinned points", "0, 0, 0; 0.5, 0, 0", Patterns::Anything(),
                          "Points (x, y, z) [m], separated by ';', whose nearest vertices stay fixed.");
        prm.declare_entry("Pin offsets", "", Patterns::Anything(),
                          "Empty, or one displacement (x, y, z) [m] per pinned point, separated by ';': "
                          "grips moved before the first step (limits they cannot meet are reported as "
                          "infeasible).");
        prm.declare_entry("Thickness", "0.0005", Patterns::Double(0), "[m]");
        prm.declare_entry("Density", "200", Patterns::Double(0), "[kg/m^3]");
        prm.declare_entry("Young's modulus", "1800", Patterns::Double(0), "[Pa]");
        prm.declare_entry("Poisson's ratio", "0.41", Patterns::Double(-1, 0.5), "[-]");
        prm.leave_subsection();
        prm.enter_subsection("Strain limits");
        prm.declare_entry("Limit", "1.01", Patterns::Anything(),
                          "Largest stretch |F d| >= 1 in the material direction d = (cos alpha, sin alpha) "
                          "(alpha from the warp axis x towards the weft axis z), a formula in alpha [rad] "
                          "(e.g. 1.01, or 1/sqrt(cos(alpha)^2/1.02^2 + sin(alpha)^2/1.2^2) for an "
                          "orthotropic ellipse) [-].");
        prm.declare_entry("Limit samples", "", Patterns::Anything(),
                          "Instead of the formula: measured samples 'angle:limit; ...' with the angle in "
                          "degrees from the warp axis (e.g. 0:1.02; 45:1.08; 90:1.2), interpolated "
                          "linearly and periodically over 180 degrees (d and -d are one direction).");
        prm.declare_entry("Directions", "4", Patterns::Integer(1),
                          "Sampled directions per triangle, alpha_j = -pi/2 + (j + 1/2) pi / n [-].");
        prm.declare_entry("Curve tolerance", "0.1", Patterns::Double(0),
                          "The limit curve is held between the sampled directions too: a triangle "
                          "stretched beyond b(alpha) + tol (b(alpha) - 1) in any direction gets a further "
                          "cone in that direction (cutting planes) and is projected again. A fraction of "
                          "the requested strain; 0: only the sampled directions are held (with lateral "
                          "contraction a 1 % limit sampled at 4 directions then allows 9.3 % along x) [-].");
        prm.leave_subsection();
        prm.enter_subsection("Time stepping");
        prm.declare_entry("Schemes", "SAR", Patterns::Anything(),
                          "One or more of IE, SAP, SAR, BDF2, BAP, BAR, each run from the same start; "
                          "the first one's frames go to VTU.");
        prm.declare_entry("Time step", "0.0166666666667", Patterns::Double(0), "[s]");
        prm.declare_entry("End time", "2", Patterns::Double(0), "[s]");
        prm.declare_entry("Frames", "40", Patterns::Integer(0), "VTU frames of the first scheme [-].");
        prm.declare_entry("Newton tolerance", "1e-8", Patterns::Double(0),
                          "Relative gradient norm of the implicit steps [-].");
        prm.declare_entry("Newton velocity tolerance", "1e-4", Patterns::Double(0),
                          "Also converged when a full Newton step moves no vertex faster than this "
                          "(|dx|_inf / time step); 0: the gradient criterion only [m/s].");
        prm.declare_entry("Area barrier", "0.1", Patterns::Double(0, 0.99),
                          "Triangles crushed below this fraction of their rest area meet a log "
                          "barrier (St.Venant-Kirchhoff alone lets a soft sheet collapse triangles, "
                          "which stalls Newton); 0: none [-].");
        prm.declare_entry("Newton Hessian", "projected", Patterns::Selection("projected|exact"),
                          "projected: every element's Hessian block is projected to positive "
                          "semi-definite (robust when the sheet wrinkles under compression); exact: "
                          "the true Hessian, shifted by a multiple of the identity where indefinite.");
        prm.declare_entry("Projection tolerance", "1e-9", Patterns::Double(0),
                          "Residuals and gap of the interior-point projection (relative) [-].");
        prm.declare_entry("Projection iterations", "100", Patterns::Integer(1),
                          "Interior-point iterations per cone problem before the projection (and its "
                          "scheme) is given up [-].");
        prm.leave_subsection();
        prm.enter_subsection("Collisions");
        prm.declare_entry("Sphere stiffness", "0", Patterns::Double(0),
                          "Penalty k/2 depth^2 per vertex against the sphere; 0: no sphere [N/m].");
        prm.declare_entry("Sphere center", "0.25, -0.2, 0.25", Patterns::Anything(), "[m]");
        prm.declare_entry("Sphere radius", "0.12", Patterns::Double(0), "[m]");
        prm.declare_entry("Ground stiffness", "0", Patterns::Double(0), "0: no ground [N/m].");
        prm.declare_entry("Ground height", "-1", Patterns::Double(), "[m]");
        prm.leave_subsection();
      }

      explicit BiphasicSheetScene(ParameterHandler &prm)
      {
        prm.enter_subsection("Sheet");
        size       = prm.get_double("Size");
        resolution = unsigned(prm.get_integer("Resolution"));
        for (const auto &point : Utilities::split_string_list(prm.get("Pinned points"), ';'))
          {
            const auto p = parse_number_list(point, "Pinned points");
            AssertThrow(p.size() == 3, ExcMessage("Pinned points: each point needs three coordinates."));
            pinned_points.push_back({{p[0], p[1], p[2]}});
          }
        for (const auto &offset : Utilities::split_string_list(prm.get("Pin offsets"), ';'))
          {
            const auto p = parse_number_list(offset, "Pin offsets");
            AssertThrow(p.size() == 3, ExcMessage("Pin offsets: each offset needs three coordinates."));
            pin_offsets.push_back({{p[0], p[1], p[2]}});
          }
        AssertThrow(pin_offsets.empty() || pin_offsets.size() == pinned_points.size(),
                    ExcMessage("Pin offsets: give one offset per pinned point, or none."));
        material.thickness      = prm.get_double("Thickness");
        material.density        = prm.get_double("Density");
        material.youngs_modulus = prm.get_double("Young's modulus");
        material.poissons_ratio = prm.get_double("Poisson's ratio");
        AssertThrow(size > 0 && material.thickness > 0 && material.density > 0 && material.youngs_modulus > 0,
                    ExcMessage("Sheet: size, thickness, density and Young's modulus must be positive."));
        prm.leave_subsection();
        prm.enter_subsection("Strain limits");
        limit_expression = prm.get("Limit");
        directions       = unsigned(prm.get_integer("Directions"));
        curve_tolerance  = prm.get_double("Curve tolerance");
        for (const auto &sample : Utilities::split_string_list(prm.get("Limit samples"), ';'))
          {
            const auto parts = Utilities::split_string_list(sample, ':');
            AssertThrow(parts.size() == 2 && !parts[0].empty() && !parts[1].empty(),
                        ExcMessage("Limit samples: <" + sample + "> is not of the form angle:limit."));
            const double angle = parse_number_list(parts[0], "Limit samples")[0];
            const double value = parse_number_list(parts[1], "Limit samples")[0];
            // The direction's angle in [0, 180) degrees, in radians.
            limit_samples.emplace_back(std::fmod(std::fmod(angle, 180.0) + 180.0, 180.0) * numbers::PI / 180,
                                       value);
          }
        std::sort(limit_samples.begin(), limit_samples.end());
        prm.leave_subsection();
        prm.enter_subsection("Time stepping");
        for (const auto &name : Utilities::split_string_list(prm.get("Schemes"), ','))
          schemes.push_back(parse_cloth_scheme(name));
        AssertThrow(!schemes.empty(), ExcMessage("Time stepping: name at least one scheme."));
        settings.time_step                  = prm.get_double("Time step");
        end_time                            = prm.get_double("End time");
        frames                              = unsigned(prm.get_integer("Frames"));
        settings.newton_tolerance           = prm.get_double("Newton tolerance");
        settings.project_element_hessians   = prm.get("Newton Hessian") == "projected";
        settings.newton_velocity_tolerance  = prm.get_double("Newton velocity tolerance");
        settings.area_barrier               = prm.get_double("Area barrier");
        cone_settings.feasibility_tolerance = cone_settings.gap_tolerance =
            prm.get_double("Projection tolerance");
        cone_settings.max_iterations = unsigned(prm.get_integer("Projection iterations"));
        AssertThrow(settings.time_step > 0 && end_time >= settings.time_step,
                    ExcMessage("Time stepping: needs a positive time step no longer than the end time."));
        prm.leave_subsection();
        prm.enter_subsection("Collisions");
        settings.sphere_stiffness = prm.get_double("Sphere stiffness");
        settings.sphere           = settings.sphere_stiffness > 0;
        const auto c              = parse_number_list(prm.get("Sphere center"), "Sphere center");
        AssertThrow(c.size() == 3, ExcMessage("Sphere center needs three coordinates."));
        settings.sphere_center    = {{c[0], c[1], c[2]}};
        settings.sphere_radius    = prm.get_double("Sphere radius");
        settings.ground_stiffness = prm.get_double("Ground stiffness");
        settings.ground           = settings.ground_stiffness > 0;
        settings.ground_height    = prm.get_double("Ground height");
        prm.leave_subsection();
        // The limit formula, checked once here (b >= 1 and finite at every sampled direction).
        // deal.II's parser parses on first use and reports to std::cerr: silenced, one clear error.
        limit_function = std::make_shared<FunctionParser<1>>(1);
        std::ostringstream    silenced;
        std::streambuf *const saved = std::cerr.rdbuf(silenced.rdbuf());
        bool                  ok    = true;
        try
          {
            limit_function->initialize("alpha", limit_expression, {{"pi", numbers::PI}});
            limit_function->value(Point<1>(0.0));
          }
        catch (...)
          {
            ok = false;
          }
        std::cerr.rdbuf(saved);
        AssertThrow(ok, ExcMessage("Strain limits: cannot parse the limit formula <" + limit_expression +
                                   "> (a function of alpha)."));
      }

      void run(RunContext &context) override
      {
        const RawSimplexMesh<3>         mesh   = make_sheet_mesh(size, resolution);
        const std::vector<unsigned int> pinned = pinned_vertices(mesh);
        const auto                      limit  = [this](double alpha) { return limit_at(alpha); };
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
      /// b(alpha): the formula, or the samples interpolated linearly and periodically over pi.
      double limit_at(const double alpha) const
      {
        if (limit_samples.empty())
          return limit_function->value(Point<1>(alpha));
        const double a = std::fmod(std::fmod(alpha, numbers::PI) + numbers::PI, numbers::PI);
        const auto   n = limit_samples.size();
        for (std::size_t k = 0; k < n; ++k)
          {
            const auto  &lo = limit_samples[k];
            const auto  &hi = limit_samples[(k + 1) % n];
            const double a0 = lo.first, a1 = k + 1 < n ? hi.first : hi.first + numbers::PI;
            const double aa = a < a0 ? a + numbers::PI : a;
            if (n == 1 || (aa >= a0 && aa <= a1))
              return n == 1 ? lo.second : lo.second + (hi.second - lo.second) * (aa - a0) / (a1 - a0);
          }
        return limit_samples.front().second;
      }

      /// The sheet's vertices nearest to the pinned points (each within half a cell of one).
      std::vector<unsigned int> pinned_vertices(const RawSimplexMesh<3> &mesh) const
      {
        std::vector<unsigned int> pinned;
        const double              cell = size / resolution;
        for (const auto &p : pinned_points)
          {
            unsigned int best = 0;
            double       d    = 1e300;
            for (unsigned int v = 0; v < mesh.vertices.size(); ++v)
              {
                const double dv = mesh.vertices[v].distance(Point<3>(p[0], p[1], p[2]));
                if (dv < d)
                  d = dv, best = v;
              }
            AssertThrow(d <= 0.5 * cell,
                        ExcMessage("Pinned points: (" + std::to_string(p[0]) + ", " + std::to_string(p[1]) +
                                   ", " + std::to_string(p[2]) + ") is not on the sheet."));
            pinned.push_back(best);
          }
        return pinned;
      }

      /// Refused before any step: a limit curve below 1 or not finite anywhere (a fine grid, not only
      /// the sampled directions), and pins moved farther apart than any state within the limits
      /// allows (no triangle stretches beyond the largest limit, plus the curve tolerance, or
      /// b_max / cos(pi / 2n) when only the n sampled directions are held).
      void validate() const override
      {
        const auto limit = [this](double alpha) { return limit_at(alpha); };
        check_limit_curve(limit);
        const RawSimplexMesh<3>         mesh   = make_sheet_mesh(size, resolution);
        const std::vector<unsigned int> pinned = pinned_vertices(mesh);
        double                          b_max  = 1;
        for (int k = 0; k < 3600; ++k)
          b_max = std::max(b_max, limit(-numbers::PI / 2 + k * numbers::PI / 3600));
        const double allowed = curve_tolerance > 0 ? b_max + curve_tolerance * (b_max - 1)
                                                   : b_max / std::cos(numbers::PI / (2 * directions));
        for (std::size_t a = 0; a < pinned.size() && !pin_offsets.empty(); ++a)
          for (std::size_t b = a + 1; b < pinned.size(); ++b)
            {
              const Point<3> pa = mesh.vertices[pinned[a]], pb = mesh.vertices[pinned[b]];
              const double   rest = pa.distance(pb);
              Point<3>       qa = pa, qb = pb;
              for (unsigned int d = 0; d < 3; ++d)
                qa[d] += pin_offsets[a][d], qb[d] += pin_offsets[b][d];
              const double       ratio = qa.distance(qb) / rest;
              std::ostringstream what;
              what << "Strain limits cannot hold: the pins are farther apart than the limits allow (pins "
                   << a + 1 << " and " << b + 1 << " are moved to " << ratio
                   << " times their rest distance; no state within the limits stretches the sheet beyond "
                   << allowed << ").";
              AssertThrow(rest == 0 || ratio <= allowed, ExcMessage(what.str()));
            }
      }

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

      double                                 size       = 0.5;
      unsigned int                           resolution = 20, directions = 4, frames = 40;
      std::vector<std::array<double, 3>>     pinned_points, pin_offsets;
      ShellMaterial                          material;
      std::string                            limit_expression;
      std::shared_ptr<FunctionParser<1>>     limit_function;
      std::vector<std::pair<double, double>> limit_samples; // (angle in [0, pi), limit)
      std::vector<ClothScheme>               schemes;
      ClothSettings                          settings;
      ConicSettings                          cone_settings;
      double                                 end_time        = 2;
      double                                 curve_tolerance = 0.1;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(biphasic_sheet,
                        (SceneInfo{
                            "biphasic-sheet",
                            "Cloth and chainmail sheets with direction-dependent stretch limits enforced by "
                            "second-order cone projection (own interior-point solver) inside implicit time "
                            "stepping: IE, SAP, SAR, BDF2, BAP, BAR; drapes, swinging, sphere contact.",
                            &BiphasicSheetScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<BiphasicSheetScene>(prm);
                            }}))
} // namespace nlmech
