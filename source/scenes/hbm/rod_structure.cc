// Structure "rods": a network of discrete elastic rods with rigid junctions (subsection Rods; the
// thesis's wire characters), driven at points, with added point masses; its vertices over one
// period as CSV and PNG.

#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/nearest_point.h>
#include <nlmech/base/parse.h>
#include <nlmech/base/plot.h>
#include <nlmech/base/run_context.h>
#include <nlmech/models/dynamics/rod_network.h>
#include <nlmech/scenes/hbm/structure.h>

#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// subsection Rods
    struct RodSettings
    {
      std::vector<std::vector<std::array<double, 3>>> polylines;
      unsigned int                                    segments = 8;
      RodMaterial                                     material;
      std::vector<std::vector<double>>                masses, driven; // (x, y, z, m), (x, y, z)
      Point<3>                                        tracked;

      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Rods");
        prm.declare_entry(
            "Polylines", "", Patterns::Anything(),
            "`x, y, z, x, y, z, ...; ...`: one rod per polyline [m], resampled to equal edges; a "
            "polyline whose ends coincide is a closed loop; rod ends that meet form a rigid "
            "junction.");
        prm.declare_entry("Segments per rod", "8", Patterns::Integer(1), "[-].");
        prm.declare_entry("Radius", "0.00055", Patterns::Double(0), "Wire radius [m].");
        prm.declare_entry("Young's modulus", "69e9", Patterns::Double(0), "[Pa].");
        prm.declare_entry("Poisson's ratio", "0.33", Patterns::Double(-1, 0.5), "[-].");
        prm.declare_entry("Density", "2700", Patterns::Double(0), "[kg/m^3].");
        prm.declare_entry("Added masses", "", Patterns::Anything(),
                          "`x, y, z, m; ...`: point masses [kg] at the vertices nearest to the points [m].");
        prm.declare_entry(
            "Driven points", "", Patterns::Anything(),
            "`x, y, z; ...`: the nearest vertices move by x = X + a d cos(w t) (Structure: Drive "
            "direction and amplitude); a driven junction is also held from turning (a clamp).");
        prm.declare_entry("Tracked point", "0, 0, 0", Patterns::Anything(), "[m].");
        prm.leave_subsection();
      }

      void parse_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Rods");
        for (const auto &row : parse_number_rows(prm.get("Polylines"), "Polylines", 0))
          {
            AssertThrow(
                row.size() >= 6 && row.size() % 3 == 0,
                ExcMessage("Polylines: each polyline needs at least two points of three coordinates."));
            std::vector<std::array<double, 3>> line;
            for (std::size_t i = 0; i < row.size(); i += 3)
              line.push_back({{row[i], row[i + 1], row[i + 2]}});
            polylines.push_back(line);
          }
        AssertThrow(!polylines.empty(), ExcMessage("Rods: Polylines are needed."));
        segments                = unsigned(prm.get_integer("Segments per rod"));
        material.radius         = prm.get_double("Radius");
        material.youngs_modulus = prm.get_double("Young's modulus");
        material.poissons_ratio = prm.get_double("Poisson's ratio");
        material.density        = prm.get_double("Density");
        masses                  = parse_number_rows(prm.get("Added masses"), "Added masses", 4);
        driven                  = parse_number_rows(prm.get("Driven points"), "Driven points", 3);
        tracked                 = Point<3>(parse_vector<3>(prm.get("Tracked point"), "Tracked point"));
        for (const auto &m : masses)
          AssertThrow(m[3] >= 0, ExcMessage("Added masses must not be negative."));
        prm.leave_subsection();
      }
    };

    class RodStructure : public StructurePlugin
    {
    public:
      explicit RodStructure(ParameterHandler &prm) { settings.parse_parameters(prm); }

      PeriodicStructure build(RunContext               &context, const HarmonicBalanceSettings &,
                              const ExcitationSettings &excitation) override
      {
        RodNetworkDescription d = rods_from_polylines(settings.polylines, settings.segments, 1e-9);
        d.material              = settings.material;
        RodNetwork        net   = make_rod_network(d);
        PeriodicStructure s;
        s.model = std::move(net.model), s.rest = net.rest_positions;
        n_vertices = d.vertices.size(), edges = net.edges;
        for (const auto &m : settings.masses)
          for (int i = 0; i < 3; ++i)
            s.model.lumped_mass()[3 * nearest_point(d.vertices, m) + i] += m[3];
        AssertThrow(!settings.driven.empty() || !excitation.point_forces.empty(),
                    ExcMessage("The rods need driven points or point forces: nothing excites them."));
        for (const auto &p : settings.driven)
          {
            const std::size_t v = nearest_point(d.vertices, p);
            for (unsigned int i = 0; i < 3; ++i)
              s.drives.push_back({3 * v + i,
                                  excitation.drive_amplitude * excitation.drive_direction[i],
                                  0.0,
                                  0.0,
                                  s.rest[3 * v + i],
                                  {},
                                  {}});
            for (std::size_t j = 0; j < net.junction_vertices.size(); ++j)
              if (net.junction_vertices[j] == v)
                for (unsigned int i = 0; i < 3; ++i)
                  s.model.fix(net.rotation_offset + 3 * j + i, 0.0);
          }
        for (const auto &pf : excitation.point_forces)
          {
            const std::size_t v = nearest_point(d.vertices, pf.first);
            for (unsigned int i = 0; i < 3; ++i)
              if (pf.second[i] != 0)
                s.forces.push_back({3 * v + i, pf.second[i], 0.0});
          }
        const std::size_t t = nearest_point(d.vertices, settings.tracked);
        s.tracked_dofs      = {3 * t, 3 * t + 1, 3 * t + 2};
        {
          const auto vertices = std::make_shared<decltype(d.vertices)>(d.vertices);
          s.point_dofs        = [vertices](const Point<3> &p) {
            const std::size_t v = nearest_point(*vertices, p);
            return std::vector<std::size_t>{3 * v, 3 * v + 1, 3 * v + 2};
          };
          s.point_distance = [vertices](const Point<3> &p) {
            const auto &v = (*vertices)[nearest_point(*vertices, p)];
            return std::sqrt(std::pow(v[0] - p[0], 2) + std::pow(v[1] - p[1], 2) + std::pow(v[2] - p[2], 2));
          };
        }
        s.tracked = 3 * t + excitation.tracked_direction;
        AssertThrow(!s.model.is_fixed(s.tracked), ExcMessage("The tracked vertex is held."));
        context.pcout << "rods: " << d.rods.size() << " rods, " << d.vertices.size() << " vertices, "
                      << net.edges.size() << " edges, " << net.junction_vertices.size() << " junctions, "
                      << settings.masses.size() << " added masses, tracked vertex " << t << std::endl;
        context.summary.add_number("n_vertices", d.vertices.size());
        context.summary.add_number("n_junctions", net.junction_vertices.size());
        return s;
      }

      /// rod_period.csv and .png: every vertex over one period.
      void write_period(RunContext &context, const PeriodicStructure &, const std::vector<double> &times,
                        const Eigen::MatrixXd &x) const override
      {
        std::ostringstream csv;
        csv << "t";
        for (std::size_t v = 0; v < n_vertices; ++v)
          csv << ",x" << v << ",y" << v << ",z" << v;
        csv << "\n";
        for (std::size_t f = 0; f < times.size(); ++f)
          {
            csv << json_number(times[f]);
            for (std::size_t i = 0; i < 3 * n_vertices; ++i)
              csv << "," << json_number(x(Eigen::Index(i), Eigen::Index(f)));
            csv << "\n";
          }
        std::ostringstream edge_list;
        for (const auto &e : edges)
          edge_list << e[0] << "-" << e[1] << " ";
        write_file_atomically(context.output.file("rod_period.csv"), csv.str());
        run_plot("rods.py", {context.output.file("rod_period.csv"), context.output.file("rod_period.png"),
                             edge_list.str()});
      }

    private:
      RodSettings                              settings;
      std::size_t                              n_vertices = 0;
      std::vector<std::array<unsigned int, 2>> edges;
    };
  } // namespace

  NLMECH_REGISTER_STRUCTURE(rods, StructureInfo{
                                      "rods",
                                      "a network of discrete elastic rods with rigid junctions (subsection "
                                      "Rods)",
                                      {&RodSettings::declare_parameters},
                                      [](ParameterHandler &prm) -> std::unique_ptr<StructurePlugin> {
                                        return std::make_unique<RodStructure>(prm);
                                      }})
} // namespace nlmech
