// Structure "mechanism": a planar compliant mechanism of rigid links, rigid joints and springs
// (subsection Mechanism), driven at joints, with its joint positions over one period as CSV and PNG.

#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/gravity_parameter.h>
#include <nlmech/base/json.h>
#include <nlmech/base/nearest_point.h>
#include <nlmech/base/parse.h>
#include <nlmech/base/plot.h>
#include <nlmech/base/run_context.h>
#include <nlmech/models/dynamics/mechanism.h>
#include <nlmech/scenes/hbm/structure.h>

#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// subsection Mechanism
    struct MechanismSettings
    {
      MechanismDescription      mechanism;
      std::vector<unsigned int> fixed_joints, driven_joints;
      unsigned int              tracked_joint = 0;

      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Mechanism");
        prm.declare_entry("Joints", "", Patterns::Anything(),
                          "`x, y, m; ...` position [m] and mass [kg] per joint.");
        prm.declare_entry("Links", "", Patterns::Anything(),
                          "`a, b; ...` rigid links between joints (0-based).");
        prm.declare_entry("Rigid joints", "", Patterns::Anything(),
                          "`a, b, c; ...` the angle at b between links (a, b) and (b, c) is kept.");
        prm.declare_entry(
            "Springs", "", Patterns::Anything(),
            "`link_a, u_a, w_a, link_b, u_b, w_b, k, L0; ...`: a linear spring of stiffness k "
            "[N/m] and rest length L0 [m] (negative: its initial length) between points given in "
            "the local frames of two links (origin at the link's first joint, axes the link "
            "vector and its left normal).");
        prm.declare_entry("Fixed joints", "", Patterns::Anything(), "Joints held at rest, comma-separated.");
        prm.declare_entry(
            "Driven joints", "", Patterns::Anything(),
            "Joints moved by x = X + a d cos(w t) (Structure: Drive direction and amplitude, first "
            "two components), comma-separated.");
        prm.declare_entry("Tracked joint", "0", Patterns::Integer(0), "[-].");
        prm.declare_entry("Link stiffness", "1e5", Patterns::Double(0), "Rigid-link penalty k_l [N/m].");
        prm.declare_entry("Angle stiffness", "100", Patterns::Double(0),
                          "Rigid-joint penalty k_t [N m/rad^2].");
        GravityParameter::declare_parameters(prm, 1, "along -y");
        prm.leave_subsection();
      }

      void parse_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Mechanism");
        MechanismDescription &m = mechanism;
        for (const auto &row : parse_number_rows(prm.get("Joints"), "Joints", 3))
          m.joints.push_back({{row[0], row[1]}}), m.masses.push_back(row[2]);
        for (const auto &row : parse_number_rows(prm.get("Links"), "Links", 2))
          m.links.push_back({{parse_index(row[0], "Links"), parse_index(row[1], "Links")}});
        for (const auto &row : parse_number_rows(prm.get("Rigid joints"), "Rigid joints", 3))
          m.rigid_angles.push_back({{parse_index(row[0], "Rigid joints"), parse_index(row[1], "Rigid joints"),
                                     parse_index(row[2], "Rigid joints")}});
        for (const auto &row : parse_number_rows(prm.get("Springs"), "Springs", 8))
          {
            MechanismSpring sp;
            sp.link_a = parse_index(row[0], "Springs"), sp.u_a = row[1], sp.w_a = row[2];
            sp.link_b = parse_index(row[3], "Springs"), sp.u_b = row[4], sp.w_b = row[5];
            sp.stiffness = row[6], sp.rest_length = row[7];
            m.springs.push_back(sp);
          }
        for (const double j : parse_number_list(prm.get("Fixed joints"), "Fixed joints"))
          fixed_joints.push_back(parse_index(j, "Fixed joints"));
        for (const double j : parse_number_list(prm.get("Driven joints"), "Driven joints"))
          driven_joints.push_back(parse_index(j, "Driven joints"));
        tracked_joint     = unsigned(prm.get_integer("Tracked joint"));
        m.link_stiffness  = prm.get_double("Link stiffness");
        m.angle_stiffness = prm.get_double("Angle stiffness");
        m.gravity         = GravityParameter::parse_parameters(prm, 1)[0];
        prm.leave_subsection();
        AssertThrow(!m.joints.empty() && !m.links.empty(),
                    ExcMessage("Mechanism: Joints and Links are needed."));
        for (const unsigned int j : fixed_joints)
          AssertThrow(j < m.joints.size(),
                      ExcMessage("Mechanism: fixed joint " + std::to_string(j) + " is missing."));
        for (const unsigned int j : driven_joints)
          AssertThrow(j < m.joints.size(),
                      ExcMessage("Mechanism: driven joint " + std::to_string(j) + " is missing."));
        AssertThrow(tracked_joint < m.joints.size(), ExcMessage("Mechanism: the tracked joint is missing."));
      }
    };

    class MechanismStructure : public StructurePlugin
    {
    public:
      explicit MechanismStructure(ParameterHandler &prm) { settings.parse_parameters(prm); }

      PeriodicStructure build(RunContext               &context, const HarmonicBalanceSettings &,
                              const ExcitationSettings &excitation) override
      {
        const MechanismDescription &mechanism = settings.mechanism;
        MechanismModel              mech      = make_mechanism_model(mechanism);
        PeriodicStructure           s;
        s.model = std::move(mech.model), s.rest = mech.rest_positions;
        for (const unsigned int j : settings.fixed_joints)
          for (unsigned int i = 0; i < 2; ++i)
            s.model.fix(2 * j + i, s.rest[2 * j + i]);
        AssertThrow(!settings.driven_joints.empty() || !excitation.point_forces.empty(),
                    ExcMessage("The mechanism needs driven joints or point forces: nothing excites it."));
        for (const unsigned int j : settings.driven_joints)
          {
            AssertThrow(!s.model.is_fixed(2 * j), ExcMessage("A driven joint is also fixed."));
            for (unsigned int i = 0; i < 2; ++i)
              s.drives.push_back({2 * j + i,
                                  excitation.drive_amplitude * excitation.drive_direction[i],
                                  0.0,
                                  0.0,
                                  s.rest[2 * j + i],
                                  {},
                                  {}});
          }
        for (const auto &pf : excitation.point_forces)
          {
            const std::size_t best = nearest_point(mechanism.joints, pf.first, 2);
            for (unsigned int i = 0; i < 2; ++i)
              if (pf.second[i] != 0)
                s.forces.push_back({2 * best + i, pf.second[i], 0.0});
          }
        const unsigned int t = settings.tracked_joint;
        s.tracked_dofs       = {2 * t, 2 * t + 1};
        {
          const auto joints = std::make_shared<std::vector<std::array<double, 2>>>(mechanism.joints);
          s.point_dofs      = [joints](const Point<3> &p) {
            const std::size_t j = nearest_point(*joints, p, 2);
            return std::vector<std::size_t>{2 * j, 2 * j + 1};
          };
          s.point_distance = [joints](const Point<3> &p) {
            const auto &j = (*joints)[nearest_point(*joints, p, 2)];
            return std::hypot(j[0] - p[0], j[1] - p[1]);
          };
          s.gravity = Eigen::VectorXd::Zero(s.model.n_unknowns());
          for (std::size_t j = 0; j < mechanism.joints.size(); ++j)
            s.gravity[Eigen::Index(2 * j + 1)] = -mechanism.gravity;
        }
        AssertThrow(excitation.tracked_direction < 2,
                    ExcMessage("Tracked direction z does not exist in a planar mechanism."));
        s.tracked = 2 * t + excitation.tracked_direction;
        AssertThrow(!s.model.is_fixed(s.tracked), ExcMessage("The tracked joint is fixed."));
        context.pcout << "mechanism: " << mechanism.joints.size() << " joints, " << mechanism.links.size()
                      << " rigid links, " << mechanism.rigid_angles.size() << " rigid joints, "
                      << mechanism.springs.size() << " springs" << std::endl;
        return s;
      }

      /// mechanism_period.csv and .png: the joints over one period, with the constraint violations.
      void write_period(RunContext &context, const PeriodicStructure &, const std::vector<double> &times,
                        const Eigen::MatrixXd &x) const override
      {
        const MechanismDescription &mechanism = settings.mechanism;
        std::ostringstream          csv;
        std::array<double, 2>       worst = {{0, 0}};
        csv << "t";
        for (std::size_t j = 0; j < mechanism.joints.size(); ++j)
          csv << ",x" << j << ",y" << j;
        csv << "\n";
        for (std::size_t f = 0; f < times.size(); ++f)
          {
            csv << json_number(times[f]);
            for (Eigen::Index i = 0; i < x.rows(); ++i)
              csv << "," << json_number(x(i, Eigen::Index(f)));
            csv << "\n";
            const auto v = mechanism_constraint_violation(mechanism, x.col(Eigen::Index(f)));
            worst[0] = std::max(worst[0], v[0]), worst[1] = std::max(worst[1], v[1]);
          }
        std::ostringstream links;
        for (const auto &l : mechanism.links)
          links << l[0] << "-" << l[1] << " ";
        write_file_atomically(context.output.file("mechanism_period.csv"), csv.str());
        run_plot("mechanism.py", {context.output.file("mechanism_period.csv"),
                                  context.output.file("mechanism_period.png"), links.str()});
        context.summary.add_figure("max_link_length_change_relative", worst[0], "1");
        context.summary.add_figure("max_rigid_angle_change", worst[1], "rad");
      }

    private:
      MechanismSettings settings;
    };
  } // namespace

  NLMECH_REGISTER_STRUCTURE(mechanism,
                            StructureInfo{"mechanism",
                                          "a planar compliant mechanism of rigid links, rigid joints and "
                                          "springs (subsection Mechanism)",
                                          {&MechanismSettings::declare_parameters},
                                          [](ParameterHandler &prm) -> std::unique_ptr<StructurePlugin> {
                                            return std::make_unique<MechanismStructure>(prm);
                                          }})
} // namespace nlmech
