// Scene "harmonic-balance": periodic steady states of forced nonlinear structures by the harmonic
// balance method (thesis ch. 2). The structure is a registered plugin (scenes/hbm: duffing,
// two-spring-mass, shell, solid, plane, mechanism, rods); the scene solves its static state under
// constant loads, traces the frequency-response curve by continuation with folds, stability and
// resonance peaks, adds the linear modal analysis response for comparison, writes one period, and
// runs the optional evaluation frequencies, backbone and Newmark check.

#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/exceptions.h>
#include <nlmech/base/json.h>
#include <nlmech/base/plot.h>
#include <nlmech/base/progress.h>
#include <nlmech/base/rank_sharing.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/scenes/hbm/design_study.h>
#include <nlmech/scenes/hbm/response_output.h>
#include <nlmech/scenes/hbm/scene_settings.h>
#include <nlmech/scenes/hbm/structure.h>
#include <nlmech/solvers/hbm/linear_modal.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class HarmonicBalanceScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        const auto &registry = StructureRegistry::instance();
        std::string descriptions;
        for (const auto &p : registry.plugins())
          descriptions += (descriptions.empty() ? "" : "; ") + p.name + ": " + p.description;
        HarmonicBalanceSceneSettings::declare_parameters(prm, registry.names_separated_by("|"), descriptions);
        ExcitationSettings::declare_parameters(prm);
        DesignStudySettings::declare_parameters(prm);
        registry.declare_parameters(prm);
      }

      explicit HarmonicBalanceScene(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        model_name = prm.get("Model");
        prm.leave_subsection();
        structure = StructureRegistry::instance().get(model_name).create(prm);
        excitation.parse_parameters(prm);
        settings.parse_parameters(prm);
        design.parse_parameters(prm);
        if (design.enabled())
          {
            std::ostringstream text;
            prm.print_parameters(
                text, ParameterHandler::OutputStyle(ParameterHandler::PRM | ParameterHandler::Short));
            prm_text         = text.str();
            source_directory = std::filesystem::absolute(current_parameter_directory()).string();
          }
      }

      void validate() const override { structure->validate(); }

      void run(RunContext &context) override
      {
        // Under mpirun every rank evaluates its block of the elements; the solvers see the sums.
        const ShareElementsOverRanks sharing(context.comm);
        context.summary.add_number("element_sharing_ranks", element_sharing_ranks());
        PeriodicStructure s;
        DesignOutcome     designed;
        {
          TimerOutput::Scope t(context.timer, "model");
          s = structure->build(context, settings.harmonic_balance, excitation);
          solve_static_state(context, s);
        }
        HarmonicBalanceSettings &hb_settings  = settings.harmonic_balance;
        ContinuationSettings    &continuation = settings.continuation;
        if (settings.adaptive_threshold > 0)
          {
            TimerOutput::Scope t(context.timer, "adaptive number of harmonics");
            const double       w =
                settings.adaptive_frequency > 0 ? settings.adaptive_frequency : continuation.omega_start;
            const HarmonicsChoice choice =
                choose_harmonics(s.model, hb_settings, s.forces, s.drives, s.rest, w,
                                 settings.adaptive_threshold, hb_settings.n_harmonics, 25, 2);
            std::ostringstream changes;
            for (const auto &c : choice.changes)
              changes << " N_H " << c.first << ": " << c.second << ";";
            context.pcout << "adaptive harmonics at w = " << w << " rad/s:" << changes.str()
                          << " -> N_H = " << choice.n_harmonics
                          << (choice.converged ? "" : " (threshold not met at N_H = 25)") << std::endl;
            context.summary.add_number("adaptive_harmonics_converged", choice.converged);
            if (!choice.changes.empty())
              context.summary.add_figure("adaptive_last_trajectory_change", choice.changes.back().second,
                                         "1");
            hb_settings.n_harmonics = choice.n_harmonics;
            if (hb_settings.n_samples != 0)
              hb_settings.n_samples = std::max(hb_settings.n_samples, 2 * hb_settings.n_harmonics + 1);
          }
        if (design.enabled())
          {
            designed = run_design(context, s);
            // Added masses carry weight and links change length: the designed structure hangs
            // differently. Its static state is sought from the mean of its periodic state (near it
            // when the motion is small; the old static state may be far from it).
            if (s.gravity.size() > 0)
              {
                if (!designed.states.empty())
                  {
                    const HarmonicBalance at(s.model, hb_settings, s.forces, s.drives);
                    Eigen::VectorXd start = at.full(designed.states.front().head(Eigen::Index(at.n_free())));
                    for (const auto &d : s.drives)
                      start[Eigen::Index(d.dof)] = d.center;
                    if (start.allFinite())
                      s.rest = start;
                  }
                solve_static_state(context, s, true);
              }
          }
        const HarmonicBalance hb(s.model, hb_settings, s.forces, s.drives);
        context.summary.add_string("model", model_name);
        context.summary.add_number("harmonics", hb_settings.n_harmonics);
        context.summary.add_number("time_samples", hb.n_samples());
        context.summary.add_number("unknowns", hb.n_unknowns());
        context.summary.add_number("free_unknowns", hb.n_free());

        ProgressReporter progress("frequency response", 1.0, context.comm, context.pcout.get_stream());
        continuation.tracked_dofs = s.tracked_dofs;
        double reported           = 0;
        continuation.progress     = [&](double done) {
          if (done >= reported + 0.1)
            progress.report(done), reported = done;
        };
        FrequencyResponse frc;
        frc.completed = true;
        if (settings.trace_curve)
          {
            TimerOutput::Scope t(context.timer, "frequency response (HBM continuation)");
            frc = trace_frequency_response(hb, start_coefficients(hb, s), continuation);
          }
        // Linear modal analysis at the static state, at the same frequencies.
        std::vector<std::pair<double, double>> lma; // (amplitude A, half range) per point
        if (settings.linear_reference && hb.n_free() <= 3000 && !frc.points.empty())
          {
            TimerOutput::Scope       t(context.timer, "linear modal analysis");
            const LinearModes        modes = linear_modes(hb, s.rest);
            std::vector<std::size_t> tracked_free;
            long                     half_index = -1;
            for (const std::size_t d : s.tracked_dofs)
              {
                const auto it = std::find(hb.free().begin(), hb.free().end(), d);
                if (it != hb.free().end())
                  tracked_free.push_back(std::size_t(it - hb.free().begin()));
                if (it != hb.free().end() && d == s.tracked)
                  half_index = long(it - hb.free().begin());
              }
            for (const auto &p : frc.points)
              {
                const Eigen::VectorXcd U = linear_modal_response(hb, modes, p.omega);
                lma.emplace_back(linear_amplitude(U, p.omega, tracked_free),
                                 half_index >= 0 ? std::abs(U[half_index]) : 0.0);
              }
            for (Eigen::Index m = 0; m < std::min<Eigen::Index>(3, modes.frequencies.size()); ++m)
              context.summary.add_figure("natural_frequency_" + std::to_string(m + 1), modes.frequencies[m],
                                         "rad/s");
            context.pcout << "linear modes: lowest natural frequencies";
            for (Eigen::Index m = 0; m < std::min<Eigen::Index>(4, modes.frequencies.size()); ++m)
              context.pcout << " " << modes.frequencies[m];
            context.pcout << " rad/s" << std::endl;
          }
        write_response(context, hb, s, frc, lma, model_name);
        if (design.enabled() && settings.trace_curve && design.initial_curve && context.is_root())
          run_plot("design.py", {"curves", context.output.file("frequency_response_initial.csv"),
                                 context.output.file("frequency_response.csv"),
                                 context.output.file("design_frequency_response.png"),
                                 json_number(designed.frequencies.empty() ? design.frequencies.front()
                                                                          : designed.frequencies.front())});
        if (excitation.period_frames > 0 && context.is_root() && !frc.points.empty())
          {
            TimerOutput::Scope t(context.timer, "output (one period)");
            // The design's state at its first driving frequency (the motion designed for); else the
            // first resonance peak, or the curve's end.
            const bool             at_design = !designed.states.empty();
            const Eigen::VectorXd &z         = at_design           ? designed.states.front()
                                               : frc.peaks.empty() ? frc.points.back().z
                                                                   : frc.peaks.front().z;
            const double           w         = at_design           ? designed.frequencies.front()
                                               : frc.peaks.empty() ? frc.points.back().omega
                                                                   : frc.peaks.front().omega;
            write_period(context, hb, s, *structure, z, w, excitation.period_frames);
          }
        evaluate_frequencies(context, hb, s, frc, settings);
        trace_backbone_curve(context, s, settings);
        if (!frc.completed)
          {
            context.partial_reason = "frequency response stopped: " + frc.stop_reason;
            return;
          }
        newmark_checks(context, hb, s, settings);
      }

    private:
      /// The design study (subsection Design): the initial design's curve first, then the study,
      /// which leaves `s` at the design found.
      DesignOutcome run_design(RunContext &context, PeriodicStructure &s)
      {
        // The initial design is the structure with the parameters' initial values on it (an added
        // mass of the file's initial value, not none).
        const auto initial_curve = [&](const PeriodicStructure &s) {
          if (!settings.trace_curve || !design.initial_curve)
            return;
          {
            TimerOutput::Scope    t(context.timer, "frequency response of the initial design");
            const HarmonicBalance hb(s.model, settings.harmonic_balance, s.forces, s.drives);
            ContinuationSettings  cs    = settings.continuation;
            cs.tracked_dofs             = s.tracked_dofs;
            cs.stability                = StabilityMethod::none;
            cs.progress                 = {};
            const FrequencyResponse frc = trace_frequency_response(hb, start_coefficients(hb, s), cs);
            std::ostringstream      csv;
            csv << "omega,amplitude_A,half_range,fold\n";
            for (const auto &p : frc.points)
              csv << json_number(p.omega) << "," << json_number(p.amplitude) << ","
                  << json_number(hb.half_range(p.z, p.omega, s.tracked)) << "," << p.fold << "\n";
            std::ostringstream peaks;
            peaks << "omega,amplitude_A,half_range\n";
            for (const auto &p : frc.peaks)
              peaks << json_number(p.omega) << "," << json_number(p.amplitude) << ","
                    << json_number(hb.half_range(p.z, p.omega, s.tracked)) << "\n";
            if (!frc.peaks.empty())
              context.summary.add_figure("initial_first_peak_frequency", frc.peaks.front().omega, "rad/s");
            if (context.is_root())
              {
                write_file_atomically(context.output.file("frequency_response_initial.csv"), csv.str());
                write_file_atomically(context.output.file("resonance_peaks_initial.csv"), peaks.str());
              }
            context.pcout << "initial design: " << frc.points.size() << " points on the frequency response"
                          << (frc.completed ? "" : " (stopped: " + frc.stop_reason + ")") << std::endl;
          }
        };
        TimerOutput::Scope t(context.timer, "design");
        return run_design_study(context, s, settings.harmonic_balance, settings.continuation, design,
                                prm_text, source_directory, initial_curve);
      }

      /// The static state under constant loads (gravity) with the drives at their centres: the
      /// start of the curve.
      static void solve_static_state(RunContext &context, PeriodicStructure &s, const bool designed = false)
      {
        bool constant_loads = designed;
        for (const auto &t : s.model.terms())
          constant_loads = constant_loads || dynamic_cast<const ConstantForceTerm *>(t.get()) != nullptr;
        if (!constant_loads)
          return;
        Model held = s.model;
        for (const auto &d : s.drives)
          held.fix(d.dof, d.center);
        NewtonResult r;
        if (designed)
          {
            // Already at rest when the design's values are those the state was settled for (apply):
            // Newton then cannot improve on a zero gradient, and the state is kept.
            try
              {
                r = minimize_with_newton(held, s.rest);
              }
            catch (const std::exception &e)
              {
                context.pcout << "static state of the design: kept (" << message_of(e) << ")" << std::endl;
                context.summary.add_string("design_static_state", "kept (" + message_of(e) + ")");
                return;
              }
          }
        else
          r = minimize_with_newton(held, s.rest);
        context.pcout << "static state under gravity" << (designed ? " of the design: " : ": ")
                      << r.iterations << " Newton iterations" << std::endl;
        context.summary.add_number(designed ? "design_static_newton_iterations" : "static_newton_iterations",
                                   r.iterations);
      }

      std::string                      model_name;
      std::unique_ptr<StructurePlugin> structure;
      ExcitationSettings               excitation;
      HarmonicBalanceSceneSettings     settings;
      DesignStudySettings              design;
      std::string                      prm_text, source_directory;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(harmonic_balance,
                        (SceneInfo{
                            "harmonic-balance",
                            "Periodic steady states of forced nonlinear structures (oscillators, shells, "
                            "solids, plane structures, compliant mechanisms, rods) by harmonic balance: "
                            "frequency-response curve, folds, stability, resonance peaks, linear modal "
                            "reference, Newmark check.",
                            &HarmonicBalanceScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<HarmonicBalanceScene>(prm);
                            }}))
} // namespace nlmech
