#include <nlmech/models/solid/linear_elastic_tet_energy.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/tensor.h>

namespace nlmech
{
  template class ElementEnergyTerm<LinearElasticTetElements>;

  LinearElasticTetElements::LinearElasticTetElements(const std::vector<dealii::Point<3>>          &vertices,
                                                     const std::vector<std::vector<unsigned int>> &cells,
                                                     const IsotropicMaterial                      &material)
      : lambda(material.lame_lambda())
      , mu(material.shear_modulus())
  {
    material.check();
    for (const auto &c : cells)
      {
        AssertThrow(c.size() == 4, dealii::ExcMessage("Linear-elastic tetrahedra need 4 vertices per cell."));
        // D = [X1-X0, X2-X0, X3-X0]; grad phi_a (a = 1..3) are the rows of D^-1, grad phi_0 = -sum.
        dealii::Tensor<2, 3> D;
        for (int a = 0; a < 3; ++a)
          for (int d = 0; d < 3; ++d)
            D[d][a] = vertices[c[a + 1]][d] - vertices[c[0]][d];
        const double det = dealii::determinant(D);
        AssertThrow(det > 0, dealii::ExcMessage("Inverted or degenerate tetrahedron in the elastic term."));
        const dealii::Tensor<2, 3>           Dinv = dealii::invert(D);
        std::array<std::array<double, 3>, 4> g{};
        for (int a = 0; a < 3; ++a)
          for (int d = 0; d < 3; ++d)
            {
              g[a + 1][d] = Dinv[a][d];
              g[0][d] -= Dinv[a][d];
            }
        tets.push_back({{c[0], c[1], c[2], c[3]}});
        shape_gradients.push_back(g);
        volume.push_back(det / 6);
      }
  }

  std::array<std::size_t, 12> LinearElasticTetElements::dofs(const std::size_t e) const
  {
    std::array<std::size_t, 12> d;
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i)
        d[3 * a + i] = 3 * std::size_t(tets[e][a]) + i;
    return d;
  }

  Model make_linear_elastic_tet_model(const RawSimplexMesh<3> &mesh, const IsotropicMaterial &material,
                                      const dealii::Tensor<1, 3>     &gravity,
                                      const std::vector<std::string> &clamped_groups)
  {
    check_simplex_mesh(mesh, 3);
    const std::size_t n = 3 * mesh.vertices.size();
    Model             model(n);
    auto              term = std::make_shared<LinearElasticTetTerm>(
        "linear elastic tetrahedra", LinearElasticTetElements(mesh.vertices, mesh.cells, material));
    Eigen::VectorXd weight = Eigen::VectorXd::Zero(n);
    for (std::size_t e = 0; e < mesh.cells.size(); ++e)
      for (unsigned int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i)
          {
            const double m = material.density * term->elements().volume[e] / 4; // lumped mass [kg]
            model.lumped_mass()[3 * mesh.cells[e][a] + i] += m;
            weight[3 * mesh.cells[e][a] + i] += m * gravity[i];
          }
    model.add_term(term);
    model.add_term(std::make_shared<ConstantForceTerm>("gravity", weight));
    for (const auto &group : clamped_groups)
      {
        const unsigned int id = mesh.groups.boundary_id(group);
        for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f)
          if (mesh.boundary_face_id[f] == id)
            for (unsigned int v : mesh.boundary_faces[f])
              for (int i = 0; i < 3; ++i)
                model.fix(3 * std::size_t(v) + i, 0.0);
      }
    return model;
  }
} // namespace nlmech
