#include <deal.II/base/exceptions.h>

#include <nlmech/base/nearest_point.h>
#include <nlmech/base/run_context.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/scenes/hbm/mesh_structure.h>

#include <filesystem>
#include <set>

namespace nlmech
{
  using namespace dealii;

  void MeshStructureSettings::declare_parameters(ParameterHandler &prm)
  {
    MeshParameters::declare_parameters(prm, NLMECH_SOURCE_DIR "/meshes/fork.geo", 0.012);
    prm.enter_subsection("Structure");
    prm.declare_entry("Clamped groups", "", Patterns::Anything(),
                      "Boundary or cell groups held at rest, comma-separated.");
    prm.declare_entry("Driven groups", "handle", Patterns::Anything(),
                      "Boundary or cell groups moved harmonically (Drive kind), comma-separated. Vertices "
                      "along one straight edge alone leave a shell free to rotate about it.");
    prm.declare_entry("Drive kind", "translation", Patterns::Selection("translation|rotation"),
                      "translation: x = X + a d cos(w t); rotation: x = c + R(phi_0 cos(w t)) (X - c) about "
                      "Rotation axis through Rotation center, exact up to the harmonics kept.");
    prm.declare_entry("Rotation axis", "1, 0, 0", Patterns::Anything(), "[-].");
    prm.declare_entry("Rotation center", "0, 0, 0", Patterns::Anything(), "c [m].");
    prm.declare_entry("Rotation amplitude", "0.1", Patterns::Double(0), "phi_0 [rad].");
    prm.declare_entry("Drive stiffness factor", "0", Patterns::Double(0),
                      "0: the driven vertices follow their motion exactly (eliminated); > 0: a penalty "
                      "(thesis 2.A.5) of this multiple of the largest diagonal entry of the stiffness "
                      "matrix at rest, whose forces limit the attainable residual [-].");
    prm.declare_entry("Tracked point", "0.16, 0.0275, 0", Patterns::Anything(),
                      "The vertex nearest to this point is the one whose amplitude (2.3.14) is traced [m].");
    prm.leave_subsection();
  }

  void MeshStructureSettings::parse_parameters(ParameterHandler &prm)
  {
    mesh.parse_parameters(prm);
    prm.enter_subsection("Structure");
    for (const auto &g : Utilities::split_string_list(prm.get("Clamped groups"), ','))
      if (!g.empty())
        clamped_groups.push_back(g);
    for (const auto &g : Utilities::split_string_list(prm.get("Driven groups"), ','))
      if (!g.empty())
        driven_groups.push_back(g);
    rotation_drive     = prm.get("Drive kind") == "rotation";
    rotation_axis      = parse_vector<3>(prm.get("Rotation axis"), "Rotation axis");
    rotation_center    = parse_vector<3>(prm.get("Rotation center"), "Rotation center");
    rotation_amplitude = prm.get_double("Rotation amplitude");
    AssertThrow(!rotation_drive || rotation_axis.norm() > 0, ExcMessage("Rotation axis must not be zero."));
    drive_stiffness_factor = prm.get_double("Drive stiffness factor");
    tracked_point          = Point<3>(parse_vector<3>(prm.get("Tracked point"), "Tracked point"));
    prm.leave_subsection();
  }

  namespace
  {
    /// Vertices of a boundary group or a cell group of the mesh.
    std::set<unsigned int> group_vertices(const RawSimplexMesh<3> &m, const std::string &group)
    {
      std::set<unsigned int> vertices;
      if (m.groups.material_ids.count(group))
        {
          const unsigned int id = m.groups.material_ids.at(group);
          for (std::size_t c = 0; c < m.cells.size(); ++c)
            if (m.cell_material[c] == id)
              vertices.insert(m.cells[c].begin(), m.cells[c].end());
        }
      else
        {
          const unsigned int id = m.groups.boundary_id(group); // clear error if missing
          for (std::size_t f = 0; f < m.boundary_faces.size(); ++f)
            if (m.boundary_face_id[f] == id)
              vertices.insert(m.boundary_faces[f].begin(), m.boundary_faces[f].end());
        }
      AssertThrow(!vertices.empty(), ExcMessage("The group <" + group + "> has no vertices."));
      return vertices;
    }
  } // namespace

  MeshStructure::MeshStructure(ParameterHandler &prm, std::string kind, const int cell_dim)
      : kind(std::move(kind))
      , cell_dim(cell_dim)
  {
    settings.parse_parameters(prm);
  }

  void MeshStructure::validate() const
  {
    settings.mesh.check_exists();
  }

  PeriodicStructure MeshStructure::build(RunContext &context, const HarmonicBalanceSettings &hb_settings,
                                         const ExcitationSettings &excitation)
  {
    mesh = read_simplex_mesh<3>(settings.mesh.options(settings.mesh.element_size), cell_dim);
    check_simplex_mesh(mesh, cell_dim);
    MeshModel         made = make_model(mesh);
    PeriodicStructure s;
    s.model = std::move(made.model), s.rest = made.rest, dofs_per_vertex = made.dofs_per_vertex;
    const unsigned int d = dofs_per_vertex;
    s.layer_terms = made.layer_terms, s.element_moduli = made.element_moduli;
    {
      const auto vertices = std::make_shared<std::vector<Point<3>>>(mesh.vertices);
      s.point_dofs        = [vertices, d](const Point<3> &p) {
        std::vector<std::size_t> dofs;
        const std::size_t        v = nearest_point(*vertices, p);
        for (unsigned int i = 0; i < d; ++i)
          dofs.push_back(d * v + i);
        return dofs;
      };
      s.point_distance = [vertices](const Point<3> &p) {
        return (*vertices)[nearest_point(*vertices, p)].distance(p);
      };
    }
    for (const auto &g : settings.clamped_groups)
      for (const unsigned int v : group_vertices(mesh, g))
        for (unsigned int i = 0; i < d; ++i)
          s.model.fix(d * v + i, s.rest[d * v + i]);
    AssertThrow(!settings.driven_groups.empty() || !excitation.point_forces.empty(),
                ExcMessage("The structure needs driven groups or point forces: nothing excites it."));
    double largest_diagonal = 0;
    {
      const Eigen::SparseMatrix<double> K = s.model.hessian(s.rest);
      for (Eigen::Index i = 0; i < K.rows(); ++i)
        largest_diagonal = std::max(largest_diagonal, K.coeff(i, i));
    }
    std::set<unsigned int> driven;
    for (const auto &g : settings.driven_groups)
      for (const unsigned int v : group_vertices(mesh, g))
        {
          AssertThrow(!s.model.is_fixed(d * v),
                      ExcMessage("A driven vertex is also clamped (group <" + g + ">)."));
          driven.insert(v);
        }
    const double penalty = settings.drive_stiffness_factor * largest_diagonal;
    if (settings.rotation_drive)
      {
        std::vector<std::array<double, 3>>      points;
        std::vector<std::array<std::size_t, 3>> dofs;
        for (const unsigned int v : driven)
          {
            points.push_back({{mesh.vertices[v][0], mesh.vertices[v][1], mesh.vertices[v][2]}});
            dofs.push_back({{d * v, d * v + 1, d * v + 2}});
          }
        AssertThrow(d == 3,
                    ExcMessage("Rotation drives need a 3D model (shell or solid); a plane structure is "
                               "driven by translation."));
        const auto &axis = settings.rotation_axis, &center = settings.rotation_center;
        s.drives =
            rotation_drives(points, dofs, {{axis[0], axis[1], axis[2]}}, {{center[0], center[1], center[2]}},
                            settings.rotation_amplitude, hb_settings.n_harmonics, penalty);
        // Start from the whole structure turning with the drive: the quasi-static limit.
        std::vector<std::array<double, 3>>      all_points;
        std::vector<std::array<std::size_t, 3>> all_dofs;
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
          if (!driven.count(unsigned(v)) && !s.model.is_fixed(d * v))
            {
              all_points.push_back({{mesh.vertices[v][0], mesh.vertices[v][1], mesh.vertices[v][2]}});
              all_dofs.push_back({{d * v, d * v + 1, d * v + 2}});
            }
        s.start_motion = rotation_drives(all_points, all_dofs, {{axis[0], axis[1], axis[2]}},
                                         {{center[0], center[1], center[2]}}, settings.rotation_amplitude,
                                         hb_settings.n_harmonics);
        for (HarmonicDrive &m : s.start_motion)
          m.center -= mesh.vertices[m.dof / d][m.dof % d];
      }
    else
      for (const unsigned int v : driven)
        for (unsigned int i = 0; i < d; ++i)
          s.drives.push_back({d * v + i,
                              excitation.drive_amplitude * excitation.drive_direction[i],
                              0.0,
                              penalty,
                              s.rest[d * v + i],
                              {},
                              {}});
    for (const auto &pf : excitation.point_forces)
      {
        const std::size_t v = nearest_point(mesh.vertices, pf.first);
        for (unsigned int i = 0; i < d; ++i)
          if (pf.second[i] != 0)
            s.forces.push_back({d * v + i, pf.second[i], 0.0});
      }
    const std::size_t t = nearest_point(mesh.vertices, settings.tracked_point);
    for (unsigned int i = 0; i < d; ++i)
      s.tracked_dofs.push_back(d * t + i);
    AssertThrow(excitation.tracked_direction < d,
                ExcMessage("Tracked direction z does not exist in a plane model."));
    s.tracked = d * t + excitation.tracked_direction;
    AssertThrow(!s.model.is_fixed(s.tracked), ExcMessage("The tracked vertex is clamped."));
    context.pcout << kind << ": " << mesh.vertices.size() << " vertices, " << mesh.cells.size() << " cells, "
                  << made.material_layers << " material layer(s), " << driven.size()
                  << " driven vertices, tracked vertex " << t << " at " << mesh.vertices[t] << std::endl;
    context.summary.add_number("n_vertices", mesh.vertices.size());
    context.summary.add_number("n_cells", mesh.cells.size());
    return s;
  }

  void MeshStructure::write_period(RunContext                &context, const PeriodicStructure &,
                                   const std::vector<double> &times, const Eigen::MatrixXd &x) const
  {
    const unsigned int                                                d = dofs_per_vertex;
    std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> frames;
    for (std::size_t f = 0; f < times.size(); ++f)
      {
        Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * mesh.vertices.size());
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
          for (unsigned int i = 0; i < d; ++i)
            u[3 * v + i] = x(d * v + i, f) - mesh.vertices[v][i];
        frames.push_back({{"displacement", u}});
      }
    write_vertex_fields_pvd(mesh, std::filesystem::path(context.output.file("period.pvd")).parent_path(),
                            "period", times, frames);
  }
} // namespace nlmech
