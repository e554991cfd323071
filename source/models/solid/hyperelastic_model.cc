#include <nlmech/models/solid/hyperelastic_model.h>

#include <deal.II/base/exceptions.h>

#include <nlmech/base/nearest_point.h>

#include <limits>

namespace nlmech
{
  HyperelasticProblem make_hyperelastic_problem(const RawSimplexMesh<3>              &mesh,
                                                const HyperelasticMaterial           &material,
                                                const HyperelasticBoundaryConditions &conditions,
                                                const HyperelasticLoads              &loads)
  {
    check_simplex_mesh(mesh, 3);
    const std::size_t   n = 3 * mesh.vertices.size();
    HyperelasticProblem problem;
    problem.internal = Model(n);
    problem.rest_positions.resize(n);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int i = 0; i < 3; ++i)
        problem.rest_positions[3 * v + i] = mesh.vertices[v][i];
    problem.elastic = std::make_shared<HyperelasticTetTerm>(mesh.vertices, mesh.cells, material);
    problem.internal.add_term(problem.elastic);

    problem.load   = Eigen::VectorXd::Zero(n);
    const auto &el = problem.elastic->elements();
    for (std::size_t e = 0; e < mesh.cells.size(); ++e)
      for (unsigned int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i)
          {
            const double m = material.density * el.volume[e] / 4; // lumped mass [kg]
            problem.internal.lumped_mass()[3 * mesh.cells[e][a] + i] += m;
            problem.load[3 * mesh.cells[e][a] + i] += m * loads.gravity[i];
          }
    for (const auto &t : loads.tractions)
      {
        const unsigned int id = mesh.groups.boundary_id(t.first);
        for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f)
          if (mesh.boundary_face_id[f] == id)
            {
              const auto  &v    = mesh.boundary_faces[f];
              const double area = 0.5 * dealii::cross_product_3d(mesh.vertices[v[1]] - mesh.vertices[v[0]],
                                                                 mesh.vertices[v[2]] - mesh.vertices[v[0]])
                                            .norm();
              for (unsigned int a = 0; a < 3; ++a)
                for (int i = 0; i < 3; ++i)
                  problem.load[3 * v[a] + i] += t.second[i] * area / 3; // exact for linear triangles
            }
      }
    for (const auto &p : loads.point_loads)
      {
        const std::size_t nearest = nearest_point(mesh.vertices, p.first);
        for (int i = 0; i < 3; ++i)
          problem.load[3 * nearest + i] += p.second[i];
      }

    auto fix_group = [&](const std::string &group, int component) {
      const unsigned int id = mesh.groups.boundary_id(group);
      for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f)
        if (mesh.boundary_face_id[f] == id)
          for (unsigned int v : mesh.boundary_faces[f])
            for (int i = 0; i < 3; ++i)
              if (component < 0 || component == i)
                problem.internal.fix(3 * std::size_t(v) + i, mesh.vertices[v][i]);
    };
    for (const auto &g : conditions.clamped)
      fix_group(g, -1);
    for (const auto &r : conditions.rollers)
      {
        AssertThrow(r.second < 3,
                    dealii::ExcMessage("A roller condition fixes component 0, 1 or 2 (x, y, z)."));
        fix_group(r.first, r.second);
      }
    AssertThrow(!problem.internal.fixed().empty(),
                dealii::ExcMessage("No boundary conditions: the structure is free to move as a rigid body."));
    return problem;
  }

  Eigen::Vector3d resultant_force(const Eigen::VectorXd &nodal_loads)
  {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Eigen::Index i = 0; i + 2 < nodal_loads.size(); i += 3)
      sum += nodal_loads.segment<3>(i);
    return sum;
  }
} // namespace nlmech
