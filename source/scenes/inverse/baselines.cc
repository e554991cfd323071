// Newton and Levenberg-Marquardt baselines of inverse design (see baselines.h).
#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/json.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/stopwatch.h>
#include <nlmech/scenes/inverse/baselines.h>
#include <nlmech/solvers/relaxation/levenberg_marquardt.h>

#include <chrono>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  void InverseBaselineSettings::declare_parameters(ParameterHandler &prm)
  {
    const InverseBaselineSettings d;
    prm.declare_entry("Newton load steps", std::to_string(d.newton_load_steps), Patterns::Integer(1),
                      "The first load increment of Newton is 1 / this [-]; increments are adaptive: halved "
                      "after a failed step (down to 1/1024 of the first), doubled after one of at most four "
                      "iterations.");
    NewtonSettings newton;
    newton.max_iterations = 15; // per load step: a step that needs more is better cut
    NewtonSettings::declare_parameters(prm, newton);
    prm.declare_entry("Levenberg-Marquardt initial guesses", "target, reversed-load",
                      Patterns::MultipleSelection("target|reversed-load"),
                      "Initial rest shapes of Levenberg-Marquardt, each solved in turn (paper, Table 2): "
                      "target (X = x) and reversed-load (the equilibrium of x taken as rest shape under "
                      "the reversed load -g, by the forward ANM). The first gives the rest shape.");
    prm.declare_entry("Levenberg-Marquardt max iterations", std::to_string(d.lm_max_iterations),
                      Patterns::Integer(1), "Iteration cap per initial guess [-].");
    prm.declare_entry("Levenberg-Marquardt max time", "1800", Patterns::Double(0),
                      "Wall-time cap per initial guess [s]; a capped solve is reported as not converged.");
  }

  void InverseBaselineSettings::parse_parameters(const ParameterHandler &prm)
  {
    newton_load_steps = prm.get_integer("Newton load steps");
    newton.parse_parameters(prm);
    lm_initial_guesses = Utilities::split_string_list(prm.get("Levenberg-Marquardt initial guesses"), ',');
    lm_max_iterations  = prm.get_integer("Levenberg-Marquardt max iterations");
    lm_max_seconds     = prm.get_double("Levenberg-Marquardt max time");
  }

  namespace
  {
    std::string info_of(const ExceptionBase &e)
    {
      std::ostringstream message;
      e.print_info(message);
      std::string text = message.str();
      text.erase(0, text.find_first_not_of(" \n"));
      while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
        text.pop_back();
      return text;
    }
  } // namespace

  Eigen::VectorXd inverse_newton_baseline(RunContext &context, const InverseBaselineSettings &settings,
                                          const InverseBaselineProblem &p, const bool required)
  {
    Eigen::VectorXd rest = p.target;
    JsonObject      s;
    s.add_number("initial_load_steps", settings.newton_load_steps);
    s.add_number("max_iterations_per_step", settings.newton.max_iterations);
    const auto clock = std::chrono::steady_clock::now();
    try
      {
        const LoadSteppingResult result = solve_equilibrium_with_newton(
            p.system, p.load, rest, settings.newton_load_steps, p.tolerance, settings.newton);
        s.add_bool("completed", true);
        s.add_number("load_steps", result.load_steps);
        s.add_number("rejected_load_steps", result.rejected_steps);
        s.add_number("smallest_load_increment", result.smallest_increment);
        s.add_number("iterations", result.iterations);
        s.add_number("factorizations", result.factorizations);
        s.add_figure("wall_time", result.seconds, "s");
        context.pcout << "inverse Newton: " << result.load_steps << " load steps (" << result.rejected_steps
                      << " rejected, smallest increment " << result.smallest_increment << "), "
                      << result.iterations << " iterations, " << result.seconds << " s" << std::endl;
      }
    catch (const ExceptionBase &e)
      {
        // The baseline failing is a result, not an error of the run (unless it is the only method).
        const std::string why = info_of(e);
        AssertThrow(!required, ExcMessage("inverse Newton: " + why));
        s.add_bool("completed", false);
        s.add_string("failure", why);
        s.add_figure("wall_time", seconds_since(clock), "s");
        context.pcout << "inverse Newton failed: " << why << std::endl;
        rest.resize(0);
      }
    context.summary.add_object("newton", s);
    return rest;
  }

  Eigen::VectorXd inverse_levenberg_marquardt_baseline(RunContext                    &context,
                                                       const InverseBaselineSettings &settings,
                                                       const InverseBaselineProblem &p, const bool primary)
  {
    Eigen::VectorXd first;
    JsonObject      all;
    for (const std::string &guess : settings.lm_initial_guesses)
      {
        JsonObject      s;
        Eigen::VectorXd rest = p.target;
        if (guess == "reversed-load")
          {
            // x' with f(x, x') + g = 0: the target as rest shape, hanging the other way.
            const auto      clock = std::chrono::steady_clock::now();
            const AnmResult r     = AnmSolver(p.forward_from_target, -p.load, p.anm).solve(rest);
            s.add_figure("initial_guess_time", seconds_since(clock), "s");
            s.add_bool("initial_guess_completed", r.completed);
            if (!r.completed)
              {
                s.add_string("failure", "the reversed-load equilibrium was not reached: " + r.stop_reason);
                context.pcout << "Levenberg-Marquardt (" << guess << "): no initial guess (" << r.stop_reason
                              << ")" << std::endl;
                all.add_object(guess, s);
                if (first.size() == 0 && primary)
                  context.partial_reason = "Levenberg-Marquardt: no reversed-load initial guess";
                continue;
              }
          }
        LevenbergMarquardtSettings lm;
        lm.relative_tolerance              = p.tolerance;
        lm.max_iterations                  = settings.lm_max_iterations;
        lm.max_seconds                     = settings.lm_max_seconds;
        const LevenbergMarquardtResult res = solve_with_levenberg_marquardt(p.system, p.load, rest, lm);
        s.add_bool("converged", res.converged);
        s.add_bool("capped", res.capped);
        s.add_number("iterations", res.iterations);
        s.add_number("factorizations", res.factorizations);
        s.add_figure("wall_time", res.seconds, "s");
        s.add_number("final_relative_residual", res.residual);
        s.add_number("max_iterations", settings.lm_max_iterations);
        s.add_figure("max_time", settings.lm_max_seconds, "s");
        all.add_object(guess, s);
        context.pcout << "inverse Levenberg-Marquardt from " << guess << ": "
                      << (res.converged ? "converged"
                          : res.capped  ? "capped, NOT converged"
                                        : "NOT converged")
                      << " in " << res.iterations << " iterations, " << res.seconds
                      << " s (relative residual " << res.residual << ")" << std::endl;
        if (first.size() == 0)
          {
            first = rest;
            if (primary && !res.converged)
              context.partial_reason = "Levenberg-Marquardt from " + guess +
                                       " did not converge (relative residual " +
                                       std::to_string(res.residual) + (res.capped ? ", capped" : "") + ")";
          }
      }
    context.summary.add_object("levenberg_marquardt", all);
    return first.size() ? first : p.target;
  }
} // namespace nlmech
