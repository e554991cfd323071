// Scene "dim-characterization": a discrete interlocking material characterised at native scale
// (thesis ch. 4): periodic-cell in-plane tests and paraboloid bending tests on a disk patch sampled
// over directions (section 4.3.3), spread over MPI ranks with a checkpoint per sample; the
// strain-space boundaries as closed meshes (.ssb and VTU), directional limits (CSV, polar PNGs with
// the metric c of eq. 4.4.1) and VTU of the elements at rest and at the stretch limit.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <nlmech/base/plot.h>
#include <nlmech/base/progress.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/dim/characterization.h>
#include <nlmech/dim/element_output.h>
#include <nlmech/scenes/dim/dim_output.h>
#include <nlmech/scenes/dim/pattern_plugin.h>
#include <nlmech/scenes/elastic_statics_parameters.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace nlmech
{
  using namespace dealii;
  using namespace nlmech::dim;

  namespace
  {
    class DimCharacterizationScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Material");
        const auto &patterns = PatternRegistry::instance();
        std::string descriptions;
        for (const auto &p : patterns.plugins())
          descriptions += (descriptions.empty() ? "" : "; ") + p.name + ": " + p.description;
        prm.declare_entry("Pattern", "threefold", Patterns::Selection(patterns.names_separated_by("|")),
                          "The interlocking pattern, its dimensions in the subsection of its name (" +
                              descriptions + ").");
        prm.declare_entry("Density", "1.24e-6", Patterns::Double(0),
                          "Element material density [kg/mm^3] (PLA).");
        patterns.declare_parameters(prm);
        prm.leave_subsection();

        prm.enter_subsection("Contact");
        prm.declare_entry("Barrier gap", "0.01", Patterns::Double(0), "dhat, where the barrier starts [mm].");
        prm.declare_entry("Barrier stiffness", "0.01", Patterns::Double(0), "kappa [N mm].");
        prm.declare_entry("Minimum separation", "0", Patterns::Double(0),
                          "Gap always kept between elements, e.g. the printer's clearance [mm].");
        prm.declare_entry("Newton iterations", "600", Patterns::Integer(1), "Per test, at most.");
        prm.leave_subsection();

        prm.enter_subsection("Sampling");
        prm.declare_entry("Tests", "in-plane, bending", Patterns::MultipleSelection("in-plane|bending"),
                          "Which strain spaces to sample.");
        prm.declare_entry(
            "Directions", "12", Patterns::Integer(1),
            "theta_i = i 180 / n deg, i < n (at least 3 for a boundary, so that the samples span "
            "the strain space).");
        prm.declare_entry("Bending directions", "0", Patterns::Integer(0),
                          "Directions of the bending test, when it should sample fewer than the in-plane "
                          "test (its samples cost seconds to minutes, in-plane ones milliseconds); 0: as "
                          "Directions. limits.csv has a row per direction of either test, the fields of "
                          "a test not sampled at that angle left empty.");
        prm.declare_entry("Levels", "2", Patterns::Integer(0),
                          "Principal values per direction at which the orthogonal limits are sought.");
        prm.declare_entry("Far strain", "0.9", Patterns::Double(0, 0.99),
                          "|target| of a driven strain: far outside the feasible set [-].");
        prm.declare_entry("Far curvature", "0.5", Patterns::Double(0),
                          "|target| of a driven curvature [1/mm].");
        prm.declare_entry("Target weight", "0.01", Patterns::Double(0),
                          "w of the driven component [N mm]. Bending tests raise it (and the hold weight, "
                          "in proportion) where gravity could hold a driven curvature back by more than "
                          "0.5 % of the far curvature (2 G / w, G the gravity load); the log says so.");
        prm.declare_entry("Hold weight", "1", Patterns::Double(0),
                          "w of a component held at a level [N mm].");
        prm.declare_entry("Patch elements", "19", Patterns::Integer(2),
                          "Elements of the bending disk patch.");
        prm.declare_entry("Checkpoint directory", "", Patterns::Anything(),
                          "Finished samples are kept here and skipped when the run is repeated (empty: "
                          "'<output directory>.checkpoint').");
        prm.declare_entry(
            "Positive only", "false", Patterns::Bool(),
            "Only the uniaxial stretch (and positive bending) limits, no boundary: validation runs.");
        prm.declare_entry("Stop after", "0", Patterns::Integer(0),
                          "Stop (with an error) after this many new samples, as if killed: 0 never.");
        prm.leave_subsection();
      }

      explicit DimCharacterizationScene(ParameterHandler &prm)
      {
        prm.enter_subsection("Material");
        material_name = prm.get("Pattern");
        density       = prm.get_double("Density");
        // The pattern's dimensions are read and checked here, so a bad file fails before any work.
        pattern = PatternRegistry::instance().get(material_name).create(prm)->pattern(density);
        prm.leave_subsection();

        prm.enter_subsection("Contact");
        settings.contact.dhat       = prm.get_double("Barrier gap");
        settings.contact.kappa      = prm.get_double("Barrier stiffness");
        settings.contact.separation = prm.get_double("Minimum separation");
        settings.max_iterations     = prm.get_integer("Newton iterations");
        AssertThrow(settings.contact.dhat > 0 && settings.contact.kappa > 0,
                    ExcMessage("Contact: the barrier gap and stiffness must be positive."));
        prm.leave_subsection();

        prm.enter_subsection("Sampling");
        for (const auto &t : Utilities::split_string_list(prm.get("Tests"), ','))
          tests.push_back(t);
        AssertThrow(!tests.empty(), ExcMessage("Sampling: name at least one test (in-plane, bending)."));
        plan.directions         = prm.get_integer("Directions");
        plan.bending_directions = prm.get_integer("Bending directions");
        plan.levels             = prm.get_integer("Levels");
        plan.far_strain         = prm.get_double("Far strain");
        plan.far_curvature      = prm.get_double("Far curvature");
        settings.target_weight  = prm.get_double("Target weight");
        settings.hold_weight    = prm.get_double("Hold weight");
        plan.patch_elements     = prm.get_integer("Patch elements");
        checkpoint_directory    = prm.get("Checkpoint directory");
        plan.stop_after         = prm.get_integer("Stop after");
        plan.positive_only      = prm.get_bool("Positive only");
        const bool bending      = std::find(tests.begin(), tests.end(), "bending") != tests.end();
        AssertThrow(plan.positive_only ||
                        (plan.directions >= 3 && (!bending || plan.directions_of("bending") >= 3)),
                    ExcMessage("Sampling: a boundary needs at least 3 directions (or set Positive only)."));
        prm.leave_subsection();
        // What the samples depend on, for the checkpoint: every parameter but the output places.
        std::ostringstream all;
        prm.print_parameters(all, ParameterHandler::ShortPRM);
        std::istringstream lines(all.str());
        for (std::string line; std::getline(lines, line);)
          if (line.find("Output directory") == std::string::npos &&
              line.find("Stop after") == std::string::npos &&
              line.find("Checkpoint directory") == std::string::npos)
            plan.fingerprint += line + "\n";
        prm.enter_subsection("Sampling");
        AssertThrow(settings.target_weight > 0 && settings.hold_weight > 0,
                    ExcMessage("Sampling: the target and hold weights must be positive."));
        prm.leave_subsection();
      }

      void validate() const override
      {
        // The starting states: intersection-free (names the pair otherwise).
        const auto cell = periodic_cell(pattern, {});
        check_initial_state(*cell.assembly, cell.q, settings.contact.separation);
        if (pattern.neighbours == 0)
          return; // elements without centrelines (triangle meshes): links cannot be counted
        const auto links = find_links(*cell.assembly, cell.q);
        for (unsigned b = 0; b < links.per_element.size(); ++b)
          AssertThrow(links.per_element[b] == pattern.neighbours,
                      ExcMessage("Pattern " + pattern.name + ": element " + std::to_string(b) + " links " +
                                 std::to_string(links.per_element[b]) + " neighbours instead of " +
                                 std::to_string(pattern.neighbours) + "; the dimensions do not interlock."));
      }

      void run(RunContext &context) override
      {
        validate();
        const std::string checkpoint =
            checkpoint_directory.empty() ? context.output.final_path() + ".checkpoint" : checkpoint_directory;
        const unsigned n_ranks = Utilities::MPI::n_mpi_processes(context.comm);
        context.pcout << "DIM characterisation of " << pattern.name << " on " << n_ranks
                      << " rank(s); checkpoint in " << checkpoint << std::endl;
        std::vector<DirectionalLimits> stretch, bend; // of the tests that ran
        Eigen::VectorXd                limit_state;   // of the in-plane sample at theta = 0, if solved here
        Eigen::VectorXd bending_state; // of the positive bending sample at theta = 0, if solved here
        // Bending: weights strong enough that gravity cannot hold a driven curvature back (the
        // prm's weights are a floor); they are part of the checkpoint's fingerprint (one plan, and
        // so one fingerprint, for both tests: they share the checkpoint directory).
        NativeSolveSettings bending_settings = settings;
        SamplingPlan        sampling_plan    = plan;
        if (std::find(tests.begin(), tests.end(), "bending") != tests.end())
          {
            const double factor = raise_bending_weights(pattern, plan, bending_settings);
            if (factor > 1)
              context.pcout << "Bending: target and hold weights raised " << factor << "x to "
                            << bending_settings.target_weight << " and " << bending_settings.hold_weight
                            << " N mm, so that gravity moves a driven curvature by at most 1 % of "
                            << plan.far_curvature << " /mm" << std::endl;
            context.summary.add_number("bending_target_weight", bending_settings.target_weight);
            sampling_plan.fingerprint += "bending weights " + std::to_string(bending_settings.target_weight) +
                                         " " + std::to_string(bending_settings.hold_weight) + "\n";
          }
        // One progress line for the whole run: every job of both tests and phases, a bending job
        // weighted as 40 in-plane ones (the DIM benchmark: about 3600 in-plane against 90 bending
        // samples per minute), this rank's share counted for every rank.
        const auto jobs_of = [&](const std::string &test) {
          const double d = plan.directions_of(test);
          return (plan.positive_only ? d : 2 * d + 2 * d * plan.levels) * (test == "bending" ? 40.0 : 1.0);
        };
        double total_work = 0, work_before = 0;
        for (const auto &test : tests)
          total_work += jobs_of(test);
        ProgressReporter progress("characterisation", total_work, context.comm, std::cout);
        for (const auto &test : tests)
          {
            const auto         start    = std::chrono::steady_clock::now();
            unsigned           new_here = 0; // samples solved by this rank in this run (not resumed)
            SamplingStatistics checkpoint_counts;
            const auto         samples = sample_strain_space(
                        pattern, test, sampling_plan, test == "bending" ? bending_settings : settings, checkpoint,
                        context.comm,
                        [&](const unsigned done, const unsigned mine, const Sample &s) {
                  ++new_here;
                  // The stretch limit along x, for the VTU (no second solve).
                  if (s.test == "in-plane" && s.direction == 0 && s.level == 0 &&
                      s.kind == SampleKind::positive)
                    limit_state = s.outcome.state;
                  if (s.test == "bending" && s.direction == 0 && s.level == 0 &&
                      s.kind == SampleKind::positive)
                    bending_state = s.outcome.state;
                  std::ostringstream label;
                  label << s.key() << ": " << s.outcome.principal << ", " << s.outcome.orthogonal << " ("
                        << s.outcome.iterations << " its, " << s.outcome.seconds << " s)";
                  (void)done, (void)mine;
                  const double weight = test == "bending" ? 40.0 : 1.0;
                  progress.report(
                              std::min(work_before + jobs_of(test), work_before + weight * new_here * n_ranks),
                              test + " " + label.str());
                },
                        &checkpoint_counts);
            work_before += jobs_of(test);
            {
              const unsigned computed = Utilities::MPI::sum(checkpoint_counts.computed, context.comm);
              JsonObject     c;
              c.add_number("resumed", checkpoint_counts.resumed);
              c.add_number("computed", computed);
              c.add_number("recomputed_other_code_version", checkpoint_counts.stale);
              c.add_number("recomputed_damaged_or_edited", checkpoint_counts.damaged);
              context.summary.add_object(test == "in-plane" ? "checkpoint_in_plane" : "checkpoint_bending",
                                         c);
              context.pcout << test << " samples: " << checkpoint_counts.resumed << " resumed from "
                            << checkpoint << ", " << computed << " computed";
              if (checkpoint_counts.stale > 0)
                context.pcout << " (" << checkpoint_counts.stale
                              << " of them because an older build of the code wrote them)";
              if (checkpoint_counts.damaged > 0)
                context.pcout << " (" << checkpoint_counts.damaged
                              << " of them because their file was unreadable, edited or invalid)";
              context.pcout << std::endl;
            }
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            write_samples_csv(context, test, samples);
            if (!checkpoint_counts.failure.empty())
              {
                // Keep what was computed: the finished samples (also in the checkpoint, where a rerun
                // resumes them); no boundary or limits from an incomplete set.
                context.summary.add_number(test == "in-plane" ? "stretch_samples_finished"
                                                              : "bending_samples_finished",
                                           samples.size());
                context.partial_reason =
                    checkpoint_counts.failure + " (" + std::to_string(samples.size()) + " " + test +
                    " samples finished and kept; a rerun resumes them from " + checkpoint + ")";
                return;
              }
            (test == "in-plane" ? stretch : bend) = directional_limits(samples, plan.directions_of(test));
            if (plan.positive_only)
              continue; // no boundary from one-sided samples
            // The boundary: samples plus the rest state inside; axes scaled by their sample ranges.
            std::vector<Eigen::Vector3d> points;
            Eigen::Vector3d              lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
            std::vector<double>          times;
            unsigned                     at_target = 0;
            for (const auto &s : samples)
              {
                // A sample that reaches its far target found no limit: the set extends farther there.
                if (reached_far_target(s))
                  ++at_target;
                points.push_back(s.point);
                lo = lo.cwiseMin(s.point), hi = hi.cwiseMax(s.point);
                times.push_back(s.outcome.seconds);
              }
            const Eigen::Vector3d scale    = (hi - lo).cwiseMax(1e-9);
            StrainSpaceBoundary   boundary = star_shaped_boundary(points, Eigen::Vector3d::Zero(), scale);
            boundary.kind                  = test == "in-plane" ? "stretch" : "bending";
            if (test == "bending")
              boundary.axes = {{"kappa_xx", "kappa_yy", "kappa_xy"}};
            const BoundaryCheck checked = check(boundary);
            AssertThrow(checked.closed && checked.contains_rest,
                        ExcMessage("The " + boundary.kind +
                                   " boundary is not a closed surface around the rest state "
                                   "(closed: " +
                                   std::to_string(checked.closed) +
                                   ", contains rest: " + std::to_string(checked.contains_rest) + ")."));
            std::sort(times.begin(), times.end());
            const std::string prefix = test == "in-plane" ? "stretch" : "bending";
            context.summary.add_number(prefix + "_samples", samples.size());
            context.summary.add_number(prefix + "_samples_at_far_target", at_target);
            context.summary.add_figure(prefix + "_median_seconds_per_sample", times[times.size() / 2], "s");
            // The rate counts only the samples solved in this run (resumed ones cost nothing).
            const unsigned new_samples = Utilities::MPI::sum(new_here, context.comm);
            context.summary.add_number(prefix + "_new_samples", new_samples);
            if (new_samples > 0)
              context.summary.add_figure(prefix + "_samples_per_minute", 60.0 * new_samples / seconds,
                                         "1/min");
            context.summary.add_number(prefix + "_boundary_vertices", checked.vertices);
            context.summary.add_number(prefix + "_boundary_triangles", checked.triangles);
            context.summary.add_number(prefix + "_boundary_closed", checked.closed ? 1 : 0);
            context.summary.add_number(prefix + "_boundary_contains_rest", checked.contains_rest ? 1 : 0);
            context.summary.add_number(prefix + "_boundary_flipped_triangles", checked.flipped);
            context.summary.add_figure(prefix + "_boundary_volume", checked.volume, "");
            if (context.is_root())
              {
                std::ostringstream comment;
                comment << boundary.kind << " boundary of " << pattern.name << " from " << samples.size()
                        << " native-scale samples (nlmech dim-characterization)\n"
                        << (test == "in-plane"
                                ? "Green strain components, tensor E_xy"
                                : "curvature tensor components [1/mm], z = 1/2 kappa_ij x_i x_j");
                write_boundary(context.output.file("boundary-" + prefix + ".ssb"), boundary, comment.str());
                write_boundary_vtu(boundary, context.output.file("boundary-" + prefix + ".vtu"));
              }
            context.pcout << test << ": " << samples.size() << " samples in " << seconds << " s; boundary "
                          << checked.vertices << " vertices, " << checked.triangles << " triangles, closed, "
                          << checked.flipped << " flipped" << std::endl;
            if (at_target > 0)
              context.pcout << test << ": " << at_target << " of " << samples.size()
                            << " samples reached their far target (within 1 %): no limit there up to "
                            << (test == "in-plane" ? "the far strain" : "the far curvature")
                            << "; the boundary there is the target, not a limit" << std::endl;
          }
        report_directional_limits(context, stretch, bend);
        context.summary.add_number("mpi_ranks", n_ranks);
        context.summary.add_number("elements_per_cell", pattern.centres.size());
        if (context.is_root())
          {
            write_file_atomically(context.output.file("limits.csv"), limits_table(stretch, bend));
            write_cell_states(context, pattern, settings, plan.far_strain, limit_state);
            // The bent patch at its positive limit along x (only when this rank solved that sample:
            // the checkpoint keeps figures, not states).
            if (bending_state.size() > 0)
              {
                BendingTest test(pattern, plan.patch_elements, 0.0, bending_settings);
                if (bending_state.size() == test.state().size())
                  write_elements_vtu(test.assembly(), bending_state, {{{0, 0}}},
                                     context.output.file("patch-bending-limit.vtu"));
              }
            run_plot("dim_limits.py",
                     {context.output.file("limits.csv"), context.output.file("limits-stretch.png"),
                      context.output.file("limits-bending.png"), pattern.name});
          }
      }

    private:
      std::string              material_name;
      double                   density = 1.24e-6;
      Pattern                  pattern;
      NativeSolveSettings      settings;
      SamplingPlan             plan;
      std::vector<std::string> tests;
      std::string              checkpoint_directory;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(dim_characterization,
                        (SceneInfo{
                            "dim-characterization",
                            "Discrete interlocking materials at native scale: rigid elements with "
                            "intersection-free barrier contact, periodic in-plane and paraboloid bending "
                            "tests sampled over directions (MPI, checkpointed), strain-space boundaries "
                            "(CGAL) and polar limit plots.",
                            &DimCharacterizationScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<DimCharacterizationScene>(prm);
                            }}))
} // namespace nlmech
