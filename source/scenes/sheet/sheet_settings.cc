#include <deal.II/base/exceptions.h>

#include <nlmech/base/nearest_point.h>
#include <nlmech/base/parse.h>
#include <nlmech/models/cloth/strain_limits.h>
#include <nlmech/scenes/sheet/sheet_settings.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  void BiphasicSheetSettings::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Sheet");
    prm.declare_entry("Size", "0.5", Patterns::Double(0), "Side of the square sheet [m] (xz-plane, y up).");
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
    prm.declare_entry("End time", "2", Patterns::Double(0), "[s]");
    prm.declare_entry("Frames", "40", Patterns::Integer(0), "VTU frames of the first scheme [-].");
    ConicSettings::declare_parameters(prm);
    prm.leave_subsection();
    ClothSettings::declare_parameters(prm);
  }

  void BiphasicSheetSettings::parse_parameters(ParameterHandler &prm)
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
    end_time = prm.get_double("End time");
    frames   = unsigned(prm.get_integer("Frames"));
    cone_settings.parse_parameters(prm);
    prm.leave_subsection();
    settings.parse_parameters(prm);
    AssertThrow(settings.time_step > 0 && end_time >= settings.time_step,
                ExcMessage("Time stepping: needs a positive time step no longer than the end time."));
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

  double BiphasicSheetSettings::limit_at(const double alpha) const
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

  std::vector<unsigned int> BiphasicSheetSettings::pinned_vertices(const RawSimplexMesh<3> &mesh) const
  {
    std::vector<unsigned int> pinned;
    const double              cell = size / resolution;
    for (const auto &p : pinned_points)
      {
        const Point<3>     q(p[0], p[1], p[2]);
        const unsigned int best = unsigned(nearest_point(mesh.vertices, q));
        const double       d    = mesh.vertices[best].distance(q);
        AssertThrow(d <= 0.5 * cell,
                    ExcMessage("Pinned points: (" + std::to_string(p[0]) + ", " + std::to_string(p[1]) +
                               ", " + std::to_string(p[2]) + ") is not on the sheet."));
        pinned.push_back(best);
      }
    return pinned;
  }

  void BiphasicSheetSettings::check() const
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

} // namespace nlmech
