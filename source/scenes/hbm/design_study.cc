// subsection Design of the harmonic-balance scene (design_study.h).
#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/parse.h>
#include <nlmech/base/plot.h>
#include <nlmech/base/progress.h>
#include <nlmech/base/run_context.h>
#include <nlmech/scenes/hbm/design_study.h>
#include <nlmech/solvers/hbm/design.h>
#include <nlmech/solvers/hbm/design_parameters.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    std::string trim(const std::string &s)
    {
      const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
      return a == std::string::npos ? "" : s.substr(a, b - a + 1);
    }

    /// One `KIND [SELECTION] = INITIAL in LOWER, UPPER`.
    struct ParameterSpec
    {
      std::string kind, selection, text;
      double      initial = 0, lower = 0, upper = 0;
    };

    ParameterSpec parse_spec(const std::string &text)
    {
      static const std::regex form(
          R"(^\s*([a-z ]+?)\s*(?:(at(?=\s)|[0-9]+)\s*([^=]*))?=\s*(\S+)\s+in\s+(\S+)\s*,\s*(\S+)\s*$)");
      std::smatch m;
      AssertThrow(
          std::regex_match(text, m, form),
          ExcMessage("Design: cannot read the parameter <" + trim(text) +
                     ">: expected `KIND [SELECTION] = INITIAL in LOWER, UPPER`, e.g. `mass at 0.1, 0, 0 = "
                     "0.01 in 0, 0.05`."));
      ParameterSpec p;
      p.text            = trim(text);
      p.kind            = trim(m[1].str());
      p.selection       = m[2].str() == "at" ? trim(m[3].str()) : trim(m[2].str() + m[3].str());
      const auto number = [&](const std::string &v, const std::string &what) {
        const auto values = parse_number_list(v, "Design parameter <" + p.text + "> " + what);
        AssertThrow(values.size() == 1, ExcMessage("Design parameter <" + p.text + ">: one " + what + "."));
        return values[0];
      };
      static const std::vector<std::string> kinds = {"mass",
                                                     "force amplitude",
                                                     "force phase",
                                                     "drive amplitude",
                                                     "layer modulus",
                                                     "element modulus",
                                                     "spring stiffness",
                                                     "spring rest length",
                                                     "spring attachment",
                                                     "link length"};
      AssertThrow(
          std::find(kinds.begin(), kinds.end(), p.kind) != kinds.end(),
          ExcMessage("Design parameter <" + p.text + ">: unknown kind <" + p.kind +
                     "> (mass at, force amplitude, force phase, drive amplitude, layer modulus, element "
                     "modulus, spring stiffness, spring rest length, spring attachment, link length)."));
      p.initial = number(m[4].str(), "initial value"), p.lower = number(m[5].str(), "lower bound");
      p.upper = number(m[6].str(), "upper bound");
      AssertThrow(p.lower <= p.upper,
                  ExcMessage("Design parameter <" + p.text + ">: the bounds are inverted (" + m[5].str() +
                             " > " + m[6].str() + ")."));
      return p;
    }

    /// The largest |coordinate| of the rest shape: a point farther than 10 % of it from every
    /// vertex is outside the model.
    double model_extent(const PeriodicStructure &s)
    {
      double extent = 0;
      for (Eigen::Index i = 0; i < s.rest.size(); ++i)
        extent = std::max(extent, std::abs(s.rest[i]));
      return extent;
    }

    /// The parameters of the specs on the structure's parts.
    std::vector<std::shared_ptr<DesignParameter>> make_parameters(PeriodicStructure                &s,
                                                                  const std::vector<ParameterSpec> &specs)
    {
      std::vector<std::shared_ptr<DesignParameter>> out;
      for (const auto &p : specs)
        {
          const std::size_t first = out.size();
          if (p.kind == "mass")
            {
              AssertThrow(s.point_dofs,
                          ExcMessage("Design: this structure has no vertices for point masses."));
              const auto xyz = parse_number_list(p.selection, "Design parameter <" + p.text + "> point");
              AssertThrow(xyz.size() == 2 || xyz.size() == 3,
                          ExcMessage("Design parameter <" + p.text + ">: `mass at X, Y[, Z]`."));
              const Point<3> point(xyz[0], xyz[1], xyz.size() > 2 ? xyz[2] : 0.0);
              // A point far from every vertex is a mistake, not a selection: refuse beyond 10 % of
              // the model's extent (or 1 cm for a point model).
              const double distance = s.point_distance(point);
              AssertThrow(distance <= std::max(0.1 * model_extent(s), 1e-2),
                          ExcMessage("Design parameter <" + p.text + ">: the point lies " +
                                     std::to_string(distance) +
                                     " m from the nearest vertex, outside the model."));
              auto dofs = s.point_dofs(point);
              dofs.erase(std::remove_if(dofs.begin(), dofs.end(),
                                        [&](std::size_t d) { return s.model.is_fixed(d); }),
                         dofs.end());
              AssertThrow(!dofs.empty(),
                          ExcMessage("Design parameter <" + p.text + ">: the vertex is clamped."));
              out.push_back(make_point_mass_parameter("mass_" + std::to_string(out.size()), s.model, dofs,
                                                      p.initial, p.lower, p.upper, s.gravity));
            }
          else if (p.kind == "force amplitude" || p.kind == "force phase")
            {
              AssertThrow(!s.forces.empty(),
                          ExcMessage("Design parameter <" + p.text + ">: no point forces."));
              std::vector<std::size_t> all(s.forces.size());
              for (std::size_t i = 0; i < all.size(); ++i)
                all[i] = i;
              out.push_back(
                  p.kind == "force amplitude"
                      ? make_force_amplitude_parameter("force_amplitude", s.forces, all, p.lower, p.upper)
                      : make_force_phase_parameter("force_phase", s.forces, all, p.lower, p.upper));
            }
          else if (p.kind == "drive amplitude")
            {
              AssertThrow(!s.drives.empty(), ExcMessage("Design parameter <" + p.text + ">: no drives."));
              out.push_back(make_drive_amplitude_parameter("drive_amplitude", s.drives, p.lower, p.upper));
            }
          else if (p.kind == "layer modulus")
            {
              const auto index = parse_number_list(p.selection, "Design parameter <" + p.text + "> layer");
              AssertThrow(index.size() == 1 && index[0] >= 0 && index[0] < double(s.layer_terms.size()) &&
                              index[0] == std::floor(index[0]),
                          ExcMessage("Design parameter <" + p.text +
                                     ">: no such material layer (the structure has " +
                                     std::to_string(s.layer_terms.size()) + ")."));
              const auto &layer = s.layer_terms[std::size_t(index[0])];
              AssertThrow(layer.first >= 0,
                          ExcMessage("Design parameter <" + p.text +
                                     ">: the layer has no elements, or the model is not a solid."));
              out.push_back(make_term_modulus_parameter("E_layer_" + std::to_string(std::size_t(index[0])),
                                                        s.model, std::size_t(layer.first), layer.second,
                                                        p.lower, p.upper));
            }
          else if (p.kind == "spring stiffness" || p.kind == "spring rest length" ||
                   p.kind == "spring attachment")
            {
              // `spring stiffness S`, `spring rest length S`, `spring attachment S u_a|w_a|u_b|w_b`.
              std::istringstream in(p.selection);
              double             spring = -1;
              std::string        key;
              in >> spring >> key;
              AssertThrow(
                  spring >= 0 && spring == std::floor(spring),
                  ExcMessage("Design parameter <" + p.text + ">: give the spring's index (0-based)."));
              static const std::vector<std::string> keys  = {"u_a", "w_a", "u_b", "w_b"};
              unsigned int                          datum = p.kind == "spring stiffness" ? 5 : 4;
              if (p.kind == "spring attachment")
                {
                  const auto k = std::find(keys.begin(), keys.end(), key);
                  AssertThrow(k != keys.end(),
                              ExcMessage("Design parameter <" + p.text +
                                         ">: the attachment coordinate is u_a, w_a, u_b or w_b."));
                  datum = unsigned(k - keys.begin());
                }
              const std::string label = p.kind == "spring stiffness"     ? "k"
                                        : p.kind == "spring rest length" ? "L0"
                                                                         : keys[datum];
              out.push_back(make_spring_parameter(label + "_spring_" + std::to_string(std::size_t(spring)),
                                                  s.model, std::size_t(spring), datum, p.initial, p.lower,
                                                  p.upper));
            }
          else if (p.kind == "link length")
            {
              const auto index = parse_number_list(p.selection, "Design parameter <" + p.text + "> link");
              AssertThrow(index.size() == 1 && index[0] >= 0 && index[0] == std::floor(index[0]),
                          ExcMessage("Design parameter <" + p.text + ">: give the link's index (0-based)."));
              out.push_back(make_link_length_parameter("L_link_" + std::to_string(std::size_t(index[0])),
                                                       s.model, std::size_t(index[0]), p.initial, p.lower,
                                                       p.upper));
            }
          else if (p.kind == "element modulus")
            {
              AssertThrow(!s.element_moduli.empty(),
                          ExcMessage("Design parameter <" + p.text +
                                     ">: a modulus per element needs a plane model."));
              AssertThrow(p.lower > 0,
                          ExcMessage("Design parameter <" + p.text +
                                     ">: the bounds are factors on the modulus and must be positive."));
              std::vector<std::vector<std::size_t>> groups;
              for (std::size_t e = 0; e < s.element_moduli.size(); ++e)
                groups.push_back({e});
              for (auto &q : make_element_modulus_parameters("E_element", s.model, groups, s.element_moduli,
                                                             p.lower, p.upper))
                out.push_back(q);
            }
          else
            AssertThrow(false, ExcMessage("Design parameter <" + p.text + ">: unknown kind <" + p.kind +
                                          "> (mass at, force amplitude, force phase, drive amplitude, layer "
                                          "modulus, element modulus, spring stiffness, spring rest length, "
                                          "spring attachment, link length)."));
          if (p.kind != "element modulus")
            for (std::size_t k = first; k < out.size(); ++k)
              out[k]->set(p.initial);
        }
      return out;
    }

    /// The target trajectory: a CSV with a header, the first column time over one period, then one
    /// column per tracked coordinate (the mean is free). Samples must be equally spaced.
    Eigen::MatrixXd read_target(const std::string &file, const std::size_t coordinates)
    {
      std::ifstream in(file);
      AssertThrow(in, ExcMessage("Design: cannot read the target trajectory <" + file + ">."));
      std::string                      line;
      std::vector<std::vector<double>> rows;
      std::getline(in, line); // header
      unsigned int number = 1;
      while (std::getline(in, line))
        {
          ++number;
          if (trim(line).empty())
            continue;
          std::vector<double> row;
          std::stringstream   ss(line);
          std::string         cell;
          while (std::getline(ss, cell, ','))
            {
              char        *end   = nullptr;
              const double value = std::strtod(cell.c_str(), &end);
              AssertThrow(end != cell.c_str() && trim(end).empty() && std::isfinite(value),
                          ExcMessage("Design: the target trajectory <" + file + "> has a malformed value <" +
                                     cell + "> in line " + std::to_string(number) + "."));
              row.push_back(value);
            }
          AssertThrow(row.size() == coordinates + 1,
                      ExcMessage("Design: line " + std::to_string(number) + " of the target trajectory <" +
                                 file + "> has " + std::to_string(row.size()) + " columns, expected t and " +
                                 std::to_string(coordinates) + " coordinates."));
          rows.push_back(row);
        }
      Eigen::MatrixXd x(Eigen::Index(coordinates), Eigen::Index(rows.size()));
      for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t j = 0; j < coordinates; ++j)
          x(Eigen::Index(j), Eigen::Index(i)) = rows[i][j + 1];
      if (rows.size() >= 3)
        {
          const double dt = rows[1][0] - rows[0][0];
          for (std::size_t i = 1; i < rows.size(); ++i)
            AssertThrow(dt > 0 &&
                            std::abs(rows[i][0] - rows[i - 1][0] - dt) <= 1e-6 * dt * double(rows.size()),
                        ExcMessage("Design: the target trajectory <" + file +
                                   "> needs equally spaced times over one period."));
        }
      return x; // too few samples: TrajectoryObjective refuses it with the count it needs
    }

    /// An element moduli CSV: a header, then `element,modulus` with elements 0, 1, 2, ... in order.
    std::vector<double> read_element_moduli(const std::string &file)
    {
      std::ifstream in(file);
      AssertThrow(in, ExcMessage("Design: cannot read the element moduli <" + file + ">."));
      std::string         line;
      std::vector<double> moduli;
      std::getline(in, line);
      unsigned int number = 1;
      while (std::getline(in, line))
        {
          ++number;
          if (trim(line).empty())
            continue;
          const auto row = parse_number_list(line, "Design: line " + std::to_string(number) +
                                                       " of the element moduli <" + file + ">");
          AssertThrow(
              row.size() == 2 && row[0] == double(moduli.size()) && std::isfinite(row[1]) && row[1] > 0,
              ExcMessage("Design: line " + std::to_string(number) + " of the element moduli <" + file +
                         "> is not `" + std::to_string(moduli.size()) + ",MODULUS` with MODULUS > 0."));
          moduli.push_back(row[1]);
        }
      return moduli;
    }

    /// Sets the element modulus parameters (E_element_*, in order) to `moduli`, within their bounds.
    void set_element_moduli(const std::vector<std::shared_ptr<DesignParameter>> &parameters,
                            const std::vector<double>                           &moduli)
    {
      std::size_t e = 0;
      for (const auto &p : parameters)
        if (p->name().rfind("E_element", 0) == 0)
          {
            AssertThrow(e < moduli.size(),
                        ExcMessage("Design: the element moduli file has " + std::to_string(moduli.size()) +
                                   " rows, fewer than the structure's elements."));
            AssertThrow(moduli[e] >= p->lower && moduli[e] <= p->upper,
                        ExcMessage("Design: element " + std::to_string(e) + "'s modulus " +
                                   std::to_string(moduli[e]) + " lies outside its bounds."));
            p->set(moduli[e++]);
          }
      AssertThrow(e == moduli.size(),
                  ExcMessage("Design: the element moduli file has " + std::to_string(moduli.size()) +
                             " rows for " + std::to_string(e) + " elements with a modulus parameter."));
    }

    /// Writes `text` with every value that names an existing file relative to `directory` made absolute.
    std::string absolute_paths(const std::string &text, const std::string &directory)
    {
      std::stringstream       in(text);
      std::ostringstream      out;
      std::string             line;
      static const std::regex set(R"(^(\s*set\s+[^=]+=\s*)(\S[^#]*?)(\s*(#.*)?)$)");
      while (std::getline(in, line))
        {
          std::smatch m;
          if (std::regex_match(line, m, set))
            {
              // Any value may be tested (a long parameter list is no file name: the error_code
              // overload reports instead of throwing).
              const std::filesystem::path value = trim(m[2].str());
              std::error_code             ec;
              if (!value.is_absolute() && !value.empty() &&
                  std::filesystem::is_regular_file(std::filesystem::path(directory) / value, ec))
                line =
                    m[1].str() + std::filesystem::absolute(std::filesystem::path(directory) / value).string();
            }
          out << line << "\n";
        }
      return out.str();
    }
  } // namespace

  void DesignStudySettings::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Design");
    prm.declare_entry("Mode", "off", Patterns::Selection("off|apply|explore|optimize"),
                      "off; apply: set the parameters' values and analyse that design; explore: first-order "
                      "predictions z + S dp against re-solved states along the objective's descent direction "
                      "(sensitivity_sweep.csv); optimize: bound-constrained L-BFGS (NLopt) from the values.");
    prm.declare_entry(
        "Parameters", "", Patterns::Anything(),
        "`;`-separated `KIND [SELECTION] = INITIAL in LOWER, UPPER`: mass at X, Y, Z [kg]; force "
        "amplitude [-]; force phase [rad]; drive amplitude [-]; layer modulus L [Pa]; element modulus "
        "(every plane element, bounds as factors) [Pa]; mechanisms: spring stiffness S [N/m], spring rest "
        "length S [m], spring attachment S u_a|w_a|u_b|w_b (link-frame coordinates of spring S, 0-based) "
        "[-]; link length L (rigid link L's length, 0-based) [m].");
    prm.declare_entry("Element moduli", "", Patterns::Anything(),
                      "element modulus: a CSV `element,modulus` (header, one row per element, as "
                      "design_element_moduli.csv) with the initial moduli; empty: the structure's own [Pa].");
    prm.declare_entry("Frequencies", "", Patterns::Anything(),
                      "Driving frequencies of the objective [rad/s].");
    prm.declare_entry(
        "Objective", "amplitude", Patterns::Selection("amplitude|trajectory|peak amplitude|peak frequency"),
        "amplitude: (A - target)^2 of the tracked point (2.4.8); trajectory: the phase-free distance "
        "to Target trajectory (2.4.6-2.4.7); peak amplitude: (A* - target)^2 with A* the resonance "
        "peak's amplitude, the largest over the frequency near each of Frequencies (found again after "
        "every change, inside Peak window); peak frequency: (w* - Target frequency)^2, the peak placed "
        "at a frequency.");
    prm.declare_entry("Target amplitude", "1", Patterns::Double(0),
                      "A (2.3.14) aimed at; a large value maximises the amplitude [m].");
    prm.declare_entry("Peak window", "", Patterns::Anything(),
                      "peak objectives: LOW, HIGH, the frequencies the peak must stay between (each of "
                      "Frequencies inside) [rad/s].");
    prm.declare_entry("Target frequency", "0", Patterns::Double(0),
                      "peak frequency: where the resonance peak should lie [rad/s].");
    prm.declare_entry("Amplitude axes", "", Patterns::Anything(),
                      "Coordinates of the tracked point in A (x, y, z; empty: all).");
    prm.declare_entry("Objective points", "", Patterns::Anything(),
                      "`;`-separated points `X, Y[, Z]` whose motion the objective follows (vertices or "
                      "joints nearest to them); empty: the scene's tracked point. Amplitude: the sum of "
                      "one objective per point; trajectory: one target over all their coordinates [m].");
    prm.declare_entry(
        "Target trajectory", "", Patterns::Anything(),
        "CSV: header, then t and one column per objective coordinate (per point, its Amplitude axes "
        "or all), equally spaced over one period (the same target at every frequency) [s, m].");
    prm.declare_entry("Phase offsets", "64", Patterns::Integer(1), "N of the smooth minimum (2.4.7) [-].");
    prm.declare_entry("Smooth minimum sharpness", "50", Patterns::Double(0),
                      "alpha times the target's squared size [-].");
    prm.declare_entry("Change penalty", "0", Patterns::Double(0),
                      "Weight of sum ((p - p0) / (upper - lower))^2 added to the objective [-].");
    prm.declare_entry("Maximum evaluations", "200", Patterns::Integer(1),
                      "Objective evaluations of L-BFGS [-].");
    prm.declare_entry("Tolerance", "1e-8", Patterns::Double(0),
                      "Relative change of the objective at the end [-].");
    prm.declare_entry("Time limit", "0", Patterns::Double(0),
                      "[s]; 0: none. Stopped by it: partial, best kept.");
    prm.declare_entry("Exploration steps", "0.4, 0.2, 0.1, 0.05, 0.025", Patterns::Anything(),
                      "explore: steps along the descent direction, relative to the parameters' ranges [-].");
    prm.declare_entry(
        "Initial curve", "true", Patterns::Bool(),
        "Trace the frequency response of the initial design too (frequency_response_initial.csv).");
    prm.leave_subsection();
  }

  void DesignStudySettings::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Design");
    mode = prm.get("Mode");
    parameters.clear();
    for (const auto &p : Utilities::split_string_list(prm.get("Parameters"), ';'))
      if (!trim(p).empty())
        parameters.push_back(p);
    frequencies = parse_number_list(prm.get("Frequencies"), "Design: Frequencies");
    objective = prm.get("Objective"), target_amplitude = prm.get_double("Target amplitude");
    const auto window = parse_number_list(prm.get("Peak window"), "Design: Peak window");
    target_frequency  = prm.get_double("Target frequency");
    axes.clear();
    for (const auto &a : Utilities::split_string_list(prm.get("Amplitude axes"), ','))
      {
        AssertThrow(a == "x" || a == "y" || a == "z",
                    ExcMessage("Design: Amplitude axes takes x, y and z, not <" + a + ">."));
        axes.push_back(a == "x" ? 0u : a == "y" ? 1u : 2u);
      }
    objective_points.clear();
    for (const auto &p : Utilities::split_string_list(prm.get("Objective points"), ';'))
      if (!trim(p).empty())
        objective_points.push_back(p);
    target_file     = prm.get("Target trajectory");
    moduli_file     = prm.get("Element moduli");
    phases          = unsigned(prm.get_integer("Phase offsets"));
    sharpness       = prm.get_double("Smooth minimum sharpness");
    change_penalty  = prm.get_double("Change penalty");
    max_evaluations = unsigned(prm.get_integer("Maximum evaluations"));
    tolerance = prm.get_double("Tolerance"), time_limit = prm.get_double("Time limit");
    exploration_steps = parse_number_list(prm.get("Exploration steps"), "Design: Exploration steps");
    initial_curve     = prm.get_bool("Initial curve");
    prm.leave_subsection();
    if (!enabled())
      return;
    AssertThrow(!parameters.empty(),
                ExcMessage("Design: Mode is " + mode + " but no Parameters are declared."));
    for (const auto &p : parameters)
      parse_spec(p); // every spec readable before anything runs
    AssertThrow(!frequencies.empty(), ExcMessage("Design: give the driving Frequencies of the objective."));
    for (const double w : frequencies)
      AssertThrow(w > 0, ExcMessage("Design: driving frequencies must be positive."));
    AssertThrow(objective != "trajectory" || !target_file.empty(),
                ExcMessage("Design: the trajectory objective needs a Target trajectory file."));
    AssertThrow(!peak() || mode != "explore",
                ExcMessage("Design: explore predicts states at fixed frequencies; with a peak objective use "
                           "apply or optimize."));
    if (peak())
      {
        AssertThrow(window.size() == 2 && window[0] > 0 && window[0] < window[1],
                    ExcMessage("Design: the " + objective +
                               " objective needs Peak window = LOW, HIGH with 0 < LOW < HIGH [rad/s]."));
        peak_low = window[0], peak_high = window[1];
        for (const double w : frequencies)
          AssertThrow(w > peak_low && w < peak_high,
                      ExcMessage("Design: the frequency " + std::to_string(w) +
                                 " rad/s lies outside the Peak window; the peak is sought from it."));
        AssertThrow(objective != "peak frequency" || target_frequency > 0,
                    ExcMessage("Design: the peak frequency objective needs a positive Target frequency."));
      }
    if (!target_file.empty())
      target_file = resolve_input_path(target_file, current_parameter_directory());
    if (!moduli_file.empty())
      moduli_file = resolve_input_path(moduli_file, current_parameter_directory());
  }

  DesignOutcome run_design_study(RunContext &context, PeriodicStructure &s,
                                 const HarmonicBalanceSettings &hb_settings,
                                 const ContinuationSettings    &continuation,
                                 const DesignStudySettings &settings, const std::string &prm_text,
                                 const std::string                                    &source_directory,
                                 const std::function<void(const PeriodicStructure &)> &initial_design)
  {
    DesignOutcome              outcome;
    std::vector<ParameterSpec> specs;
    for (const auto &p : settings.parameters)
      specs.push_back(parse_spec(p));
    auto parameters = make_parameters(s, specs);
    if (!settings.moduli_file.empty())
      set_element_moduli(parameters, read_element_moduli(settings.moduli_file));
    if (s.gravity.size() > 0)
      {
        // The initial values' added weights move the static state the periodic states start from.
        Model held = s.model;
        for (const auto &d : s.drives)
          held.fix(d.dof, d.center);
        const NewtonResult r = minimize_with_newton(held, s.rest);
        context.summary.add_number("design_initial_static_newton_iterations", r.iterations);
      }
    if (initial_design)
      initial_design(s);
    // The coordinates of the objective: per point (the scene's tracked one, or those listed) its
    // Amplitude axes, free ones only.
    std::vector<std::vector<std::size_t>> point_coordinates;
    const auto                            select = [&](const std::vector<std::size_t> &dofs) {
      std::vector<std::size_t> out;
      for (std::size_t i = 0; i < dofs.size(); ++i)
        if ((settings.axes.empty() || std::count(settings.axes.begin(), settings.axes.end(), unsigned(i))) &&
            !s.model.is_fixed(dofs[i]))
          out.push_back(dofs[i]);
      AssertThrow(
                                     !out.empty(),
                                     ExcMessage("Design: the Amplitude axes select none of a tracked point's free coordinates."));
      return out;
    };
    if (settings.objective_points.empty())
      point_coordinates.push_back(select(s.tracked_dofs));
    else
      for (const auto &text : settings.objective_points)
        {
          const auto xyz = parse_number_list(text, "Design: Objective points");
          AssertThrow(
              xyz.size() == 2 || xyz.size() == 3,
              ExcMessage("Design: Objective points takes `X, Y[, Z]` per point, not <" + text + ">."));
          const Point<3> point(xyz[0], xyz[1], xyz.size() > 2 ? xyz[2] : 0.0);
          AssertThrow(s.point_distance(point) <= std::max(0.1 * model_extent(s), 1e-2),
                      ExcMessage("Design: the objective point <" + text + "> lies " +
                                 std::to_string(s.point_distance(point)) +
                                 " m from the nearest vertex, outside the model."));
          point_coordinates.push_back(select(s.point_dofs(point)));
        }
    std::vector<std::size_t> tracked;
    for (const auto &c : point_coordinates)
      tracked.insert(tracked.end(), c.begin(), c.end());
    std::vector<std::shared_ptr<const DesignObjective>> objectives;
    std::string                                         objective_name = settings.objective;
    Eigen::MatrixXd                                     target;
    if (settings.objective == "trajectory")
      {
        target = read_target(settings.target_file, tracked.size());
        objectives.push_back(std::make_shared<TrajectoryObjective>(tracked, target, hb_settings.n_harmonics,
                                                                   settings.phases, settings.sharpness));
      }
    else if (settings.objective == "peak frequency")
      objectives.push_back(std::make_shared<PeakFrequencyObjective>(settings.target_frequency));
    else
      for (const auto &c : point_coordinates)
        objectives.push_back(std::make_shared<AmplitudeObjective>(c, settings.target_amplitude));

    HarmonicDesign::Rebuild rebuild = [&]() {
      return std::make_unique<HarmonicBalance>(s.model, hb_settings, s.forces, s.drives);
    };
    std::vector<DesignCase>      cases;
    std::vector<Eigen::VectorXd> states;
    for (const double w : settings.frequencies)
      {
        const auto      hb = rebuild();
        Eigen::VectorXd z  = start_coefficients(*hb, s);
        const auto      r  = solve_with_excitation_ramp(*hb, z, w);
        if (!r.converged)
          {
            // Inside a hysteresis band a start from rest may not reach any state: follow the curve
            // from the scene's start frequency to w instead (the branch connected to it).
            ContinuationSettings cs = continuation;
            cs.omega_end = w, cs.tracked_dofs = s.tracked_dofs, cs.stability = StabilityMethod::none;
            cs.progress                 = {};
            const FrequencyResponse frc = trace_frequency_response(*hb, start_coefficients(*hb, s), cs);
            AssertThrow(
                frc.completed && !frc.points.empty(),
                ExcMessage("Design: no periodic state of the initial design at w = " + std::to_string(w) +
                           " rad/s (a start from rest: " + r.message + "; the curve from " +
                           std::to_string(continuation.omega_start) + " rad/s: " + frc.stop_reason + ")."));
            z = frc.points.back().z;
          }
        DesignCase dc;
        dc.omega = w, dc.objectives = objectives;
        if (settings.peak())
          {
            // The peak of the (first) objective point's amplitude, sought from w inside the window.
            dc.peak = true, dc.omega_low = settings.peak_low, dc.omega_high = settings.peak_high;
            dc.peak_dofs = point_coordinates.front();
          }
        cases.push_back(dc);
        states.push_back(z);
      }
    DesignSettings ds;
    ds.change_penalty   = settings.change_penalty;
    ds.peak_search_step = continuation.max_step;
    HarmonicDesign      design(rebuild, parameters, cases, states, ds);
    std::vector<double> initial_omegas;
    for (std::size_t c = 0; c < cases.size(); ++c)
      initial_omegas.push_back(design.omega(c));
    if (settings.peak())
      {
        context.summary.add_numbers("design_peak_frequency_initial", initial_omegas);
        for (std::size_t c = 0; c < cases.size(); ++c)
          context.pcout << "design: resonance peak of the initial design at " << design.omega(c)
                        << " rad/s (sought from " << cases[c].omega << ")" << std::endl;
      }
    const auto amplitudes = [&]() {
      std::vector<double> a;
      for (std::size_t c = 0; c < cases.size(); ++c)
        for (const auto &coordinates : point_coordinates)
          a.push_back(design.balance().amplitude(design.state(c), design.omega(c), coordinates));
      return a;
    };
    std::vector<Eigen::VectorXd> initial_states;
    for (std::size_t c = 0; c < cases.size(); ++c)
      initial_states.push_back(design.state(c));
    const std::vector<double> initial_amplitude = amplitudes();
    const double              initial_objective = design.objective();
    context.pcout << "design: " << parameters.size() << " parameters, " << cases.size() << " frequencies, "
                  << objective_name << " objective " << initial_objective << std::endl;
    context.summary.add_number("design_parameters", parameters.size());
    context.summary.add_number("design_initial_objective", initial_objective);

    std::ostringstream history;
    history << "iteration,objective,gradient_norm,seconds";
    for (const auto &p : parameters)
      history << "," << p->name();
    history << "\n";
    const auto history_row = [&](const DesignIterate &it) {
      history << it.iteration << "," << json_number(it.objective) << "," << json_number(it.gradient_norm)
              << "," << json_number(it.seconds);
      for (Eigen::Index k = 0; k < it.parameters.size(); ++k)
        history << "," << json_number(it.parameters[k]);
      history << "\n";
    };
    if (settings.mode == "optimize")
      {
        ProgressReporter     progress("design (L-BFGS evaluations)", settings.max_evaluations, context.comm,
                                      context.pcout.get_stream());
        OptimizationSettings os;
        os.max_iterations = settings.max_evaluations, os.relative_tolerance = settings.tolerance;
        os.time_limit = settings.time_limit;
        os.progress   = [&](const DesignIterate &it) {
          if (it.iteration % 5 == 0)
            progress.report(it.iteration, "objective " + json_number(it.objective));
        };
        const auto               t0 = std::chrono::steady_clock::now();
        const OptimizationResult r  = optimize_design(design, os);
        context.summary.add_figure(
            "design_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
            "s");
        for (const auto &it : r.history)
          history_row(it);
        context.pcout << "design: " << r.evaluations << " evaluations, objective " << initial_objective
                      << " -> " << r.best.objective << " (" << r.stop_reason << ")" << std::endl;
        context.summary.add_number("design_evaluations", r.evaluations);
        context.summary.add_number("design_objective", r.best.objective);
        context.summary.add_string("design_stop_reason", r.stop_reason);
        context.summary.add_string("design_optimizer", "NLopt LD_LBFGS (bound-constrained)");
        context.summary.add_figure("design_gradient_seconds",
                                   design.gradients > 0 ? design.gradient_seconds / design.gradients : 0.0,
                                   "s");
        context.summary.add_number("design_newton_iterations", design.newton_iterations);
        context.summary.add_number("design_predicted_starts", design.predicted_starts);
        context.summary.add_number("design_failed_predictions", design.failed_predictions);
        // One gradient against one Newton iteration of the periodic solve (residual, Jacobian,
        // factorisation and solve): the adjoint's cost does not grow with the parameters.
        const double newton =
            design.newton_iterations > 0 ? design.solve_seconds / design.newton_iterations : 0.0;
        context.summary.add_figure("design_newton_iteration_seconds", newton, "s");
        context.summary.add_figure(
            "design_gradient_over_newton_iteration",
            newton > 0 && design.gradients > 0 ? design.gradient_seconds / design.gradients / newton : 0.0,
            "1");
        context.summary.add_number("design_gradients", design.gradients);
        context.summary.add_number("design_continued_updates", design.continued_updates);
        context.summary.add_number("design_continuation_folds", design.continuation_folds);
        context.summary.add_number("design_failed_updates", design.failed_updates);
        if (design.failed_updates > 0)
          context.summary.add_string("design_last_failed_update", design.last_failure);
        if (!r.converged)
          context.partial_reason =
              "the design optimiser stopped early (" + r.stop_reason + "); the best design is kept";
      }
    else
      {
        Eigen::VectorXd g;
        DesignIterate   it;
        it.objective = design.objective(&g), it.gradient_norm = g.norm(), it.parameters = design.values();
        history_row(it);
      }
    if (settings.mode == "explore")
      {
        // Predictions z + S dp along the descent direction -g scaled to the parameters' ranges.
        Eigen::VectorXd g;
        design.objective(&g);
        const Eigen::VectorXd p0 = design.values();
        Eigen::VectorXd       range(p0.size());
        for (Eigen::Index k = 0; k < p0.size(); ++k)
          range[k] = parameters[std::size_t(k)]->upper - parameters[std::size_t(k)]->lower;
        // Steepest descent in the coordinates u = (p - lower) / range: dp = -range^2 g, of unit
        // length in u (steps are fractions of the ranges).
        Eigen::VectorXd direction = -(range.array().square() * g.array()).matrix();
        AssertThrow(direction.norm() > 0,
                    ExcMessage("Design: the objective's gradient is zero; nothing to explore."));
        direction /= (direction.array() / range.array()).matrix().norm();
        std::vector<Eigen::MatrixXd> S;
        for (std::size_t c = 0; c < cases.size(); ++c)
          S.push_back(design.sensitivity(c));
        const std::vector<Eigen::VectorXd> z0 = {initial_states};
        std::ostringstream                 sweep;
        sweep << "step,dp_norm,frequency,prediction_error,motion_size\n";
        for (const double t : settings.exploration_steps)
          {
            Eigen::VectorXd dp = t * direction;
            for (Eigen::Index k = 0; k < dp.size(); ++k)
              dp[k] = std::clamp(p0[k] + dp[k], parameters[std::size_t(k)]->lower,
                                 parameters[std::size_t(k)]->upper) -
                      p0[k];
            std::string why;
            if (!design.update(p0 + dp, &why))
              {
                context.pcout << "design: no state at exploration step " << t << " (" << why << ")"
                              << std::endl;
                continue;
              }
            for (std::size_t c = 0; c < cases.size(); ++c)
              {
                const Eigen::VectorXd &z = z0[c];
                const double size        = z.tail(z.size() - Eigen::Index(design.balance().n_free())).norm();
                const double err         = (design.state(c) - z - S[c] * dp).norm() / size;
                sweep << json_number(t) << "," << json_number(dp.norm()) << ","
                      << json_number(design.omega(c)) << "," << json_number(err) << "," << json_number(size)
                      << "\n";
              }
          }
        AssertThrow(design.update(p0), ExcMessage("Design: the explored design no longer solves."));
        if (context.is_root())
          {
            write_file_atomically(context.output.file("sensitivity_sweep.csv"), sweep.str());
            run_plot("design.py", {"sweep", context.output.file("sensitivity_sweep.csv"),
                                   context.output.file("sensitivity_sweep.png")});
          }
      }
    // The design's figures: objective, amplitude gains, Hill stability of each state.
    const std::vector<double> final_amplitude = amplitudes();
    std::vector<double>       gains;
    bool                      unstable = false;
    for (std::size_t c = 0; c < cases.size(); ++c)
      {
        gains.push_back(final_amplitude[c] / std::max(initial_amplitude[c], 1e-300));
        const HillResult h = hill_stability(design.balance(), design.state(c), design.omega(c));
        context.pcout << "design at w = " << design.omega(c) << " rad/s: amplitude " << initial_amplitude[c]
                      << " -> " << final_amplitude[c] << " (" << gains.back()
                      << "x), Hill: " << (h.determined ? (h.stable ? "stable" : "UNSTABLE") : "undetermined")
                      << ", max multiplier " << h.max_multiplier << std::endl;
        unstable = unstable || (h.determined && !h.stable);
        context.summary.add_figure("design_max_multiplier_" + std::to_string(c), h.max_multiplier, "1");
      }
    if (settings.peak())
      {
        std::vector<double> omegas;
        for (std::size_t c = 0; c < cases.size(); ++c)
          omegas.push_back(design.omega(c));
        context.summary.add_numbers("design_peak_frequency_final", omegas);
        context.summary.add_number("design_peak_searches", design.peak_searches);
      }
    context.summary.add_numbers("design_amplitude_initial", initial_amplitude);
    context.summary.add_numbers("design_amplitude_final", final_amplitude);
    context.summary.add_numbers("design_amplitude_gain", gains);
    context.summary.add_bool("design_state_unstable", unstable);
    if (unstable)
      context.pcout
          << "design: WARNING: the design's periodic state is unstable (Hill); it would not be observed"
          << std::endl;

    if (context.is_root())
      {
        // Parameters, trajectories before / after / target, the optimised parameter file.
        std::ostringstream values;
        values << "name,initial,final,lower,upper\n";
        const Eigen::VectorXd p = design.values();
        for (std::size_t k = 0; k < parameters.size(); ++k)
          values << parameters[k]->name() << "," << json_number(design.initial_values()[Eigen::Index(k)])
                 << "," << json_number(p[Eigen::Index(k)]) << "," << json_number(parameters[k]->lower) << ","
                 << json_number(parameters[k]->upper) << "\n";
        write_file_atomically(context.output.file("design_parameters.csv"), values.str());
        write_file_atomically(context.output.file("design_history.csv"), history.str());
        std::ostringstream traj;
        traj << "frequency,phase";
        for (std::size_t j = 0; j < tracked.size(); ++j)
          traj << ",before_" << j << ",after_" << j << (target.size() ? ",target_" + std::to_string(j) : "");
        traj << "\n";
        const unsigned int M = 96;
        for (std::size_t c = 0; c < cases.size(); ++c)
          {
            std::vector<double> t(M);
            for (unsigned int i = 0; i < M; ++i)
              t[i] = 2 * pi / initial_omegas[c] * i / M;
            std::vector<double> ta(M);
            for (unsigned int i = 0; i < M; ++i)
              ta[i] = 2 * pi / design.omega(c) * i / M;
            const Eigen::MatrixXd xb = design.balance().positions_at(initial_states[c], initial_omegas[c], t);
            const Eigen::MatrixXd xa = design.balance().positions_at(design.state(c), design.omega(c), ta);
            for (unsigned int i = 0; i < M; ++i)
              {
                traj << json_number(design.omega(c)) << "," << json_number(2 * pi * i / M);
                for (std::size_t j = 0; j < tracked.size(); ++j)
                  {
                    traj << "," << json_number(xb(Eigen::Index(tracked[j]), i)) << ","
                         << json_number(xa(Eigen::Index(tracked[j]), i));
                    if (target.size())
                      traj << ","
                           << json_number(target(Eigen::Index(j), Eigen::Index(i * target.cols() / M)));
                  }
                traj << "\n";
              }
          }
        write_file_atomically(context.output.file("design_trajectories.csv"), traj.str());
        run_plot("design.py", {"history", context.output.file("design_history.csv"),
                               context.output.file("design_history.png")});
        run_plot("design.py", {"trajectories", context.output.file("design_trajectories.csv"),
                               context.output.file("design_trajectories.png"),
                               std::to_string(point_coordinates.front().size())});
        // optimized.prm: this run's parameters with the design's values applied.
        std::ostringstream prm;
        prm << "# The design found by nlmech from " << source_directory
            << " (every parameter; Design: Mode = apply with the values found).\n"
            << absolute_paths(prm_text, source_directory) << "\nsubsection Design\n  set Mode = apply\n"
            << "  set Parameters = ";
        std::size_t        k = 0;
        std::ostringstream moduli;
        for (std::size_t i = 0; i < specs.size(); ++i)
          {
            const auto &sp = specs[i];
            if (sp.kind == "element modulus")
              {
                // One parameter per element: the spec stays, the values go to a CSV it reads.
                prm << (i ? "; " : "") << sp.text;
                moduli << "element,modulus\n";
                for (std::size_t e = 0; e < s.element_moduli.size(); ++e)
                  moduli << e << "," << json_number(p[Eigen::Index(k + e)]) << "\n";
                k += s.element_moduli.size();
                continue;
              }
            prm << (i ? "; " : "") << sp.kind << (sp.kind == "mass" ? " at " : " ") << sp.selection << " = "
                << json_number(p[Eigen::Index(k)]) << " in " << json_number(sp.lower) << ", "
                << json_number(sp.upper);
            ++k;
          }
        if (!moduli.str().empty())
          {
            write_file_atomically(context.output.file("design_element_moduli.csv"), moduli.str());
            prm << "\n  set Element moduli = "
                << (std::filesystem::absolute(context.output.final_path()) / "design_element_moduli.csv")
                       .string();
          }
        prm << "\nend\n\nsubsection Output\n  set Output directory = "
            << (std::filesystem::absolute(context.output.final_path()) / "optimized").string() << "\nend\n";
        write_file_atomically(context.output.file("optimized.prm"), prm.str());
      }
    outcome.ran = true;
    for (std::size_t c = 0; c < cases.size(); ++c)
      outcome.frequencies.push_back(design.omega(c)), outcome.states.push_back(design.state(c));
    return outcome;
  }
} // namespace nlmech
