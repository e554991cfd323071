// Harmonic-balance design: parameter derivatives, objectives, sensitivities and the adjoint
// gradient (design.h).
#include <deal.II/base/exceptions.h>

#include <nlmech/base/stopwatch.h>
#include <nlmech/solvers/hbm/design.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace nlmech
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// A free-length vector of a full-length one.
    Eigen::VectorXd free_part(const HarmonicBalance &hb, const Eigen::VectorXd &full)
    {
      Eigen::VectorXd out(Eigen::Index(hb.n_free()));
      for (std::size_t i = 0; i < hb.n_free(); ++i)
        out[Eigen::Index(i)] = full[Eigen::Index(hb.free()[i])];
      return out;
    }

    /// Samples of a parameter's force change (n_free x N) at the state's samples.
    Eigen::MatrixXd force_change_samples(const HarmonicBalance &hb, const DesignParameter &p,
                                         const Eigen::MatrixXd &x, const Eigen::MatrixXd &v,
                                         const double omega)
    {
      const unsigned int N = hb.n_samples();
      Eigen::MatrixXd    out(Eigen::Index(hb.n_free()), N);
      for (unsigned int j = 0; j < N; ++j)
        {
          Eigen::VectorXd df = Eigen::VectorXd::Zero(x.rows());
          p.add_force_change(hb, x.col(j), v.col(j), 2 * pi * j / N, omega, df);
          out.col(j) = free_part(hb, df);
        }
      return out;
    }
  } // namespace

  DesignParameter::DesignParameter(std::string name, const double lower_in, const double upper_in)
      : lower(lower_in)
      , upper(upper_in)
      , label(std::move(name))
  {
    AssertThrow(std::isfinite(lower) && std::isfinite(upper) && lower <= upper,
                dealii::ExcMessage("Design parameter <" + label +
                                   ">: the bounds are inverted or not finite (" + std::to_string(lower) +
                                   " > " + std::to_string(upper) + ")."));
  }

  Eigen::VectorXd DesignParameter::mass_change(std::size_t) const
  {
    return {};
  }

  void DesignParameter::add_force_change(const HarmonicBalance &, const Eigen::VectorXd &,
                                         const Eigen::VectorXd &, double, double, Eigen::VectorXd &) const
  {
  }

  Eigen::VectorXd parameter_derivative(const HarmonicBalance &hb, const DesignParameter &p,
                                       const Eigen::VectorXd &z, const double omega)
  {
    Eigen::VectorXd       dh = Eigen::VectorXd::Zero(z.size());
    const Eigen::VectorXd dm = p.mass_change(hb.model().n_unknowns());
    if (dm.size() > 0)
      dh += hb.mass_residual(z, omega, free_part(hb, dm));
    if (p.changes_force())
      dh -= hb.coefficients_of_samples(
          force_change_samples(hb, p, hb.sample_positions(z), hb.sample_velocities(z, omega), omega));
    return dh;
  }

  Eigen::VectorXd directional_parameter_derivative(
      const HarmonicBalance &hb, const std::vector<std::shared_ptr<DesignParameter>> &parameters,
      const Eigen::VectorXd &direction, const Eigen::VectorXd &z, const double omega)
  {
    AssertThrow(direction.size() == Eigen::Index(parameters.size()),
                dealii::ExcMessage("Design: a direction of the wrong size."));
    Eigen::VectorXd dm       = Eigen::VectorXd::Zero(Eigen::Index(hb.model().n_unknowns()));
    bool            any_mass = false, any_force = false;
    for (std::size_t k = 0; k < parameters.size(); ++k)
      {
        const double d = direction[Eigen::Index(k)];
        if (d == 0)
          continue;
        const Eigen::VectorXd m = parameters[k]->mass_change(hb.model().n_unknowns());
        if (m.size() > 0)
          dm += d * m, any_mass = true;
        any_force = any_force || parameters[k]->changes_force();
      }
    Eigen::VectorXd dh = Eigen::VectorXd::Zero(z.size());
    if (any_mass)
      dh += hb.mass_residual(z, omega, free_part(hb, dm));
    if (any_force)
      {
        const Eigen::MatrixXd x = hb.sample_positions(z), v = hb.sample_velocities(z, omega);
        Eigen::MatrixXd       f = Eigen::MatrixXd::Zero(Eigen::Index(hb.n_free()), hb.n_samples());
        for (std::size_t k = 0; k < parameters.size(); ++k)
          if (direction[Eigen::Index(k)] != 0 && parameters[k]->changes_force())
            f += direction[Eigen::Index(k)] * force_change_samples(hb, *parameters[k], x, v, omega);
        dh -= hb.coefficients_of_samples(f);
      }
    return dh;
  }

  Eigen::VectorXd adjoint_parameter_products(const HarmonicBalance                               &hb,
                                             const std::vector<std::shared_ptr<DesignParameter>> &parameters,
                                             const Eigen::VectorXd &z, const double omega,
                                             const Eigen::VectorXd &lambda)
  {
    Eigen::VectorXd out       = Eigen::VectorXd::Zero(Eigen::Index(parameters.size()));
    bool            any_force = false;
    for (const auto &p : parameters)
      any_force = any_force || p->changes_force();
    Eigen::MatrixXd x, v, W;
    if (any_force)
      x = hb.sample_positions(z), v = hb.sample_velocities(z, omega), W = hb.adjoint_sample_weights(lambda);
    for (std::size_t k = 0; k < parameters.size(); ++k)
      {
        const DesignParameter &p  = *parameters[k];
        const Eigen::VectorXd  dm = p.mass_change(hb.model().n_unknowns());
        if (dm.size() > 0)
          out[Eigen::Index(k)] += lambda.dot(hb.mass_residual(z, omega, free_part(hb, dm)));
        if (p.changes_force())
          out[Eigen::Index(k)] -= (W.array() * force_change_samples(hb, p, x, v, omega).array()).sum();
      }
    return out;
  }

  AmplitudeObjective::AmplitudeObjective(std::vector<std::size_t> dofs_in, const double target)
      : dofs(std::move(dofs_in))
      , target(target)
  {
    AssertThrow(!dofs.empty(), dealii::ExcMessage("Amplitude objective: no coordinates."));
  }

  double AmplitudeObjective::evaluate(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double omega,
                                      Eigen::VectorXd *gradient) const
  {
    Eigen::VectorXd dA;
    const double    A = hb.amplitude(z, omega, dofs, gradient ? &dA : nullptr);
    if (gradient)
      *gradient = 2 * (A - target) * dA;
    return (A - target) * (A - target);
  }

  TrajectoryObjective::TrajectoryObjective(std::vector<std::size_t> dofs_in, const Eigen::MatrixXd &samples,
                                           const unsigned int harmonics, const unsigned int phases_in,
                                           const double sharpness)
      : dofs(std::move(dofs_in))
      , phases(phases_in)
  {
    const Eigen::Index M = samples.cols();
    AssertThrow(!dofs.empty() && samples.rows() == Eigen::Index(dofs.size()),
                dealii::ExcMessage("Trajectory objective: one row of target samples per coordinate."));
    AssertThrow(harmonics >= 1 && M >= Eigen::Index(2 * harmonics + 1),
                dealii::ExcMessage("Trajectory objective: the target needs at least 2 N_H + 1 = " +
                                   std::to_string(2 * harmonics + 1) + " samples per period, it has " +
                                   std::to_string(M) + "."));
    AssertThrow(samples.allFinite(), dealii::ExcMessage("Trajectory objective: the target is not finite."));
    AssertThrow(phases >= 1, dealii::ExcMessage("Trajectory objective: at least one phase offset."));
    sine.setZero(samples.rows(), harmonics), cosine.setZero(samples.rows(), harmonics);
    for (Eigen::Index j = 0; j < samples.rows(); ++j)
      for (unsigned int k = 1; k <= harmonics; ++k)
        for (Eigen::Index i = 0; i < M; ++i)
          {
            const double theta = 2 * pi * double(i) / double(M);
            sine(j, k - 1) += 2.0 / double(M) * samples(j, i) * std::sin(k * theta);
            cosine(j, k - 1) += 2.0 / double(M) * samples(j, i) * std::cos(k * theta);
          }
    const double size2 = sine.squaredNorm() + cosine.squaredNorm();
    AssertThrow(size2 > 0, dealii::ExcMessage("Trajectory objective: the target does not move."));
    alpha = (sharpness > 0 ? sharpness : 50.0) / size2;
  }

  double TrajectoryObjective::evaluate(const HarmonicBalance &hb, const Eigen::VectorXd &z, const double,
                                       Eigen::VectorXd *gradient) const
  {
    const std::size_t  n = hb.n_free();
    const unsigned int H = std::min<unsigned int>(hb.n_harmonics(), unsigned(sine.cols()));
    std::vector<long>  index(dofs.size());
    for (std::size_t j = 0; j < dofs.size(); ++j)
      {
        index[j] = hb.free_position(dofs[j]);
        AssertThrow(index[j] >= 0,
                    dealii::ExcMessage("Trajectory objective: a tracked coordinate is not free."));
      }
    // d_i for every phase offset; target harmonic k shifted by phi: x(theta + phi).
    std::vector<double> d(phases, 0.0);
    auto                shifted = [&](std::size_t j, unsigned int k, double phi, double &s, double &c) {
      const double sk = sine(Eigen::Index(j), k - 1), ck = cosine(Eigen::Index(j), k - 1);
      s = sk * std::cos(k * phi) - ck * std::sin(k * phi),
      c = sk * std::sin(k * phi) + ck * std::cos(k * phi);
    };
    auto z_sine = [&](std::size_t j, unsigned int k) { return z[Eigen::Index((2 * k - 1) * n + index[j])]; };
    auto z_cosine = [&](std::size_t j, unsigned int k) { return z[Eigen::Index((2 * k) * n + index[j])]; };
    for (unsigned int i = 0; i < phases; ++i)
      {
        const double phi = 2 * pi * i / phases;
        for (std::size_t j = 0; j < dofs.size(); ++j)
          for (unsigned int k = 1; k <= unsigned(sine.cols()); ++k)
            {
              double s, c;
              shifted(j, k, phi, s, c);
              const double zs = k <= H ? z_sine(j, k) : 0.0, zc = k <= H ? z_cosine(j, k) : 0.0;
              d[i] += (zs - s) * (zs - s) + (zc - c) * (zc - c);
            }
      }
    // Smooth minimum (2.4.7), the exponentials relative to the smallest distance.
    const double        d_min = *std::min_element(d.begin(), d.end());
    std::vector<double> e(phases);
    double              sum = 0, weighted = 0;
    for (unsigned int i = 0; i < phases; ++i)
      e[i] = std::exp(-alpha * (d[i] - d_min)), sum += e[i], weighted += d[i] * e[i];
    const double f = weighted / sum;
    if (gradient)
      {
        gradient->setZero(z.size());
        for (unsigned int i = 0; i < phases; ++i)
          {
            // df/dd_i = w_i (1 - alpha (d_i - f)), w_i = e_i / sum.
            const double g   = e[i] / sum * (1 - alpha * (d[i] - f));
            const double phi = 2 * pi * i / phases;
            for (std::size_t j = 0; j < dofs.size(); ++j)
              for (unsigned int k = 1; k <= H; ++k)
                {
                  double s, c;
                  shifted(j, k, phi, s, c);
                  (*gradient)[Eigen::Index((2 * k - 1) * n + index[j])] += g * 2 * (z_sine(j, k) - s);
                  (*gradient)[Eigen::Index((2 * k) * n + index[j])] += g * 2 * (z_cosine(j, k) - c);
                }
          }
      }
    return f;
  }

  HarmonicDesign::HarmonicDesign(Rebuild                                       rebuild_in,
                                 std::vector<std::shared_ptr<DesignParameter>> parameters_in,
                                 std::vector<DesignCase> cases_in, std::vector<Eigen::VectorXd> states_in,
                                 DesignSettings settings_in)
      : rebuild(std::move(rebuild_in))
      , parameters(std::move(parameters_in))
      , cases(std::move(cases_in))
      , states(std::move(states_in))
      , settings(settings_in)
  {
    AssertThrow(!parameters.empty(), dealii::ExcMessage("Design: no parameters."));
    AssertThrow(!cases.empty() && cases.size() == states.size(),
                dealii::ExcMessage("Design: one periodic state per driving frequency."));
    for (const auto &c : cases)
      {
        AssertThrow(c.omega > 0 && !c.objectives.empty(),
                    dealii::ExcMessage("Design: every case needs a positive frequency and an objective."));
        AssertThrow(!c.peak || (c.omega_low > 0 && c.omega_low < c.omega && c.omega < c.omega_high &&
                                !c.peak_dofs.empty()),
                    dealii::ExcMessage("Design: a resonance peak's case needs its amplitude's unknowns and "
                                       "a frequency window around its start frequency " +
                                       std::to_string(c.omega) + " rad/s."));
        for (const auto &o : c.objectives)
          AssertThrow(
              c.peak || o->name() != "peak frequency",
              dealii::ExcMessage("Design: the peak frequency objective needs a resonance peak's case."));
      }
    start = values();
    for (std::size_t k = 0; k < parameters.size(); ++k)
      AssertThrow(start[Eigen::Index(k)] >= parameters[k]->lower &&
                      start[Eigen::Index(k)] <= parameters[k]->upper,
                  dealii::ExcMessage("Design parameter <" + parameters[k]->name() + ">: the initial value " +
                                     std::to_string(start[Eigen::Index(k)]) + " lies outside its bounds [" +
                                     std::to_string(parameters[k]->lower) + ", " +
                                     std::to_string(parameters[k]->upper) + "]."));
    hb = rebuild();
    for (std::size_t c = 0; c < cases.size(); ++c)
      if (cases[c].peak)
        {
          std::string why;
          AssertThrow(locate_peak(c, &why), dealii::ExcMessage("Design: the initial design: " + why + "."));
        }
  }

  Eigen::VectorXd HarmonicDesign::values() const
  {
    Eigen::VectorXd p(Eigen::Index(parameters.size()));
    for (std::size_t k = 0; k < parameters.size(); ++k)
      p[Eigen::Index(k)] = parameters[k]->value();
    return p;
  }

  std::vector<Eigen::VectorXd> HarmonicDesign::predicted_states(const Eigen::VectorXd &p)
  {
    std::vector<Eigen::VectorXd> out(cases.size());
    const long                   c = factorized_case;
    if (c < 0 || std::size_t(c) >= cases.size() || states[std::size_t(c)].size() != factorized_state.size() ||
        states[std::size_t(c)] != factorized_state || values() != factorized_parameters)
      return out;
    try
      {
        const Eigen::VectorXd &z = states[std::size_t(c)];
        const Eigen::VectorXd  dh =
            directional_parameter_derivative(*hb, parameters, p - values(), z, cases[std::size_t(c)].omega);
        Eigen::VectorXd y = z - lu.solve(dh);
        if (y.allFinite())
          out[std::size_t(c)] = std::move(y);
      }
    catch (const std::exception &)
      {
        // No prediction: the re-solve starts from the last state.
      }
    return out;
  }

  bool HarmonicDesign::solve_all(std::string *why, const std::vector<Eigen::VectorXd> &predicted)
  {
    try
      {
        hb = rebuild();
      }
    catch (const std::exception &e)
      {
        if (why)
          *why = std::string("the structure cannot be built with these parameters (") + e.what() + ")";
        return false;
      }
    for (std::size_t c = 0; c < cases.size(); ++c)
      {
        const bool          predict = c < predicted.size() && predicted[c].size() == states[c].size();
        Eigen::VectorXd     z       = predict ? predicted[c] : states[c];
        const auto          t0      = std::chrono::steady_clock::now();
        PeriodicSolveResult r       = solve_periodic_state(*hb, z, cases[c].omega, settings.solve);
        predicted_starts += predict;
        if (predict && !r.converged)
          {
            // The prediction left the basin of the state (a long step near a fold): the last state.
            ++failed_predictions, newton_iterations += r.iterations;
            z = states[c], r = solve_periodic_state(*hb, z, cases[c].omega, settings.solve);
          }
        solve_seconds += seconds_since(t0), newton_iterations += r.iterations;
        if (!r.converged || !z.allFinite())
          {
            if (why)
              *why =
                  "no periodic state at w = " + std::to_string(cases[c].omega) + " rad/s (" + r.message + ")";
            return false;
          }
        states[c] = z;
        if (cases[c].peak && !locate_peak(c, why))
          return false;
      }
    return true;
  }

  void HarmonicDesign::apply(const Eigen::VectorXd &p)
  {
    for (std::size_t k = 0; k < parameters.size(); ++k)
      parameters[k]->set(p[Eigen::Index(k)]);
  }

  bool HarmonicDesign::update(const Eigen::VectorXd &p, std::string *why)
  {
    AssertThrow(p.size() == Eigen::Index(parameters.size()) && p.allFinite(),
                dealii::ExcMessage("Design: parameter vector of the wrong size or not finite."));
    const Eigen::VectorXd              last        = values();
    const std::vector<Eigen::VectorXd> last_states = states;
    const std::vector<DesignCase>      last_cases  = cases; // peaks move
    const std::vector<Eigen::VectorXd> predicted   = predicted_states(p);
    apply(p);
    if (solve_all(why, predicted))
      return true;
    // A fold of some state over the parameters lies between: follow each case's solution curve
    // from the last solved design (states, parameters) to p.
    states = last_states, cases = last_cases;
    apply(last);
    return continue_to(p, why);
  }

  bool HarmonicDesign::continue_to(const Eigen::VectorXd &p, std::string *why)
  {
    AssertThrow(p.size() == Eigen::Index(parameters.size()) && p.allFinite(),
                dealii::ExcMessage("Design: parameter vector of the wrong size or not finite."));
    const Eigen::VectorXd              last        = values();
    const std::vector<Eigen::VectorXd> last_states = states;
    const std::vector<DesignCase>      last_cases  = cases;
    ++continued_updates;
    bool ok = true;
    for (std::size_t c = 0; c < cases.size() && ok; ++c)
      try
        {
          ok = continue_case(c, last, p, why);
        }
      catch (const std::exception &e)
        {
          ok = false;
          if (why)
            *why = std::string("the parameter continuation failed (") + e.what() + ")";
        }
    if (ok)
      {
        apply(p);
        hb = rebuild();
        // Each peak's state followed at its last frequency; the peak itself has moved.
        for (std::size_t c = 0; c < cases.size() && ok; ++c)
          ok = !cases[c].peak || locate_peak(c, why);
        if (ok)
          return true;
      }
    ++failed_updates;
    last_failure = why ? *why : "";
    apply(last);
    states = last_states, cases = last_cases;
    hb = rebuild();
    return false;
  }

  double HarmonicDesign::objective(Eigen::VectorXd *gradient)
  {
    const auto      t0 = std::chrono::steady_clock::now();
    const auto      p  = values();
    double          f  = 0;
    Eigen::VectorXd g  = Eigen::VectorXd::Zero(p.size());
    for (std::size_t c = 0; c < cases.size(); ++c)
      {
        Eigen::VectorXd df_dz = Eigen::VectorXd::Zero(states[c].size());
        double          df_dw = 0;
        for (const auto &objective : cases[c].objectives)
          {
            Eigen::VectorXd part;
            f += objective->evaluate(*hb, states[c], cases[c].omega, gradient ? &part : nullptr);
            if (gradient)
              df_dz += part, df_dw += objective->omega_derivative(*hb, states[c], cases[c].omega);
          }
        if (gradient && (df_dz.squaredNorm() > 0 || df_dw != 0))
          {
            // (2.4.5): df/dp = -lambda^T dh/dp with (dh/dz)^T lambda = df/dz.
            lu.factorize(hb->jacobian(states[c], cases[c].omega));
            factorized_case = long(c), factorized_state = states[c], factorized_parameters = p;
            if (cases[c].peak)
              g += peak_gradient(c, df_dz, df_dw);
            else
              {
                const Eigen::VectorXd lambda = lu.solve(df_dz, true);
                g -= adjoint_parameter_products(*hb, parameters, states[c], cases[c].omega, lambda);
              }
          }
      }
    if (settings.change_penalty > 0)
      for (std::size_t k = 0; k < parameters.size(); ++k)
        {
          const double range = std::max(parameters[k]->upper - parameters[k]->lower, 1e-300);
          const double r     = (p[Eigen::Index(k)] - start[Eigen::Index(k)]) / range;
          f += settings.change_penalty * r * r;
          g[Eigen::Index(k)] += 2 * settings.change_penalty * r / range;
        }
    if (gradient)
      *gradient = g, ++gradients, gradient_seconds += seconds_since(t0);
    AssertThrow(std::isfinite(f) && g.allFinite(),
                dealii::ExcMessage("Design: the objective or its gradient is not finite."));
    return f;
  }

  Eigen::MatrixXd HarmonicDesign::sensitivity(const std::size_t c)
  {
    lu.factorize(hb->jacobian(states[c], cases[c].omega));
    factorized_case = long(c), factorized_state = states[c], factorized_parameters = values();
    Eigen::MatrixXd S(states[c].size(), Eigen::Index(parameters.size()));
    for (std::size_t k = 0; k < parameters.size(); ++k)
      S.col(Eigen::Index(k)) =
          -lu.solve(parameter_derivative(*hb, *parameters[k], states[c], cases[c].omega));
    return S;
  }
} // namespace nlmech
