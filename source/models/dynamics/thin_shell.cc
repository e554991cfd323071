#include <deal.II/base/exceptions.h>

#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/models/elastic_constants.h>

#include <map>

namespace nlmech
{
  ShellModel make_shell_model(const RawSimplexMesh<3> &mesh, const ShellMaterial &material)
  {
    AssertThrow(material.youngs_modulus > 0 && material.thickness > 0 && material.density > 0,
                dealii::ExcMessage("The shell needs a positive Young's modulus, thickness and density."));
    AssertThrow(material.poissons_ratio > -1 && material.poissons_ratio < 0.5,
                dealii::ExcMessage("Poisson's ratio must lie in (-1, 0.5)."));
    const std::size_t n_vertices = mesh.vertices.size();
    ShellModel        shell;
    shell.model = Model(3 * n_vertices);
    shell.rest_positions.resize(3 * n_vertices);
    for (std::size_t v = 0; v < n_vertices; ++v)
      for (int i = 0; i < 3; ++i)
        shell.rest_positions[3 * v + i] = mesh.vertices[v][i];

    const double     E = material.youngs_modulus, nu = material.poissons_ratio, t = material.thickness;
    const double     mu = shear_modulus(E, nu), lambda = lame_lambda(E, nu);
    MembraneElements membrane;
    membrane.mu = mu, membrane.lambda = 2 * lambda * mu / (lambda + 2 * mu), membrane.thickness = t;
    Eigen::VectorXd &mass = shell.model.lumped_mass();
    mass                  = Eigen::VectorXd::Zero(3 * n_vertices);
    // edge (min, max) -> (triangle, position of the edge's first vertex in the triangle)
    std::map<std::pair<unsigned int, unsigned int>, std::vector<std::pair<std::size_t, int>>> edges;
    for (std::size_t c = 0; c < mesh.cells.size(); ++c)
      {
        AssertThrow(mesh.cells[c].size() == 3,
                    dealii::ExcMessage("The shell mesh must consist of triangles."));
        const std::array<unsigned int, 3> tri = {{mesh.cells[c][0], mesh.cells[c][1], mesh.cells[c][2]}};
        const auto &X0 = mesh.vertices[tri[0]], &X1 = mesh.vertices[tri[1]], &X2 = mesh.vertices[tri[2]];
        const dealii::Tensor<1, 3> d1 = X1 - X0, d2 = X2 - X0;
        const dealii::Tensor<1, 3> normal = dealii::cross_product_3d(d1, d2);
        const double               area   = 0.5 * normal.norm();
        AssertThrow(
            area > 1e-14 * d1.norm_square(),
            dealii::ExcMessage("The shell mesh has a degenerate triangle " + std::to_string(c + 1) + "."));
        const dealii::Tensor<1, 3> e1 = d1 / d1.norm();
        const dealii::Tensor<1, 3> e2 = dealii::cross_product_3d(normal / normal.norm(), e1);
        const double a = d1 * e1, b = d2 * e1, cc = d1 * e2, d = d2 * e2; // D_m = [[a, b], [cc, d]]
        const double det = a * d - b * cc;
        membrane.triangles.push_back(tri);
        membrane.dm_inverse.push_back({{d / det, -b / det, -cc / det, a / det}});
        membrane.area.push_back(area);
        for (int v = 0; v < 3; ++v)
          {
            for (int i = 0; i < 3; ++i)
              mass[3 * tri[v] + i] += material.density * t * area / 3;
            const unsigned int p = tri[v], q = tri[(v + 1) % 3];
            edges[{std::min(p, q), std::max(p, q)}].emplace_back(c, v);
          }
      }
    HingeElements hinges;
    const double  bending_stiffness = E * t * t * t / (12 * (1 - nu * nu)) / 6;
    for (const auto &edge : edges)
      {
        AssertThrow(edge.second.size() <= 2,
                    dealii::ExcMessage("An edge of the shell mesh is shared by more than two triangles."));
        if (edge.second.size() < 2)
          continue;
        const auto &[c1, v1]                  = edge.second[0];
        const auto &[c2, v2]                  = edge.second[1];
        const std::array<unsigned int, 3> &t1 = membrane.triangles[c1], &t2 = membrane.triangles[c2];
        const unsigned int a = t1[v1], b = t1[(v1 + 1) % 3], c = t1[(v1 + 2) % 3], d = t2[(v2 + 2) % 3];
        hinges.hinges.push_back({{a, b, c, d}});
        std::array<double, 12> X;
        for (int v = 0; v < 4; ++v)
          for (int i = 0; i < 3; ++i)
            X[3 * v + i] = mesh.vertices[hinges.hinges.back()[v]][i];
        hinges.rest_angle.push_back(HingeElements::dihedral_angle(X));
        const double length2 = (mesh.vertices[b] - mesh.vertices[a]).norm_square();
        hinges.weight.push_back(bending_stiffness * 3 * length2 / (membrane.area[c1] + membrane.area[c2]));
      }
    shell.membrane = std::make_shared<ElementEnergyTerm<MembraneElements>>("CST membrane", membrane);
    shell.bending  = std::make_shared<ElementEnergyTerm<HingeElements>>("hinge bending", hinges);
    shell.model.add_term(shell.membrane);
    shell.model.add_term(shell.bending);
    return shell;
  }

  template class ElementEnergyTerm<MembraneElements>;
  template class ElementEnergyTerm<HingeElements>;
} // namespace nlmech
