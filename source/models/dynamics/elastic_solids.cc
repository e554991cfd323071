#include <deal.II/base/exceptions.h>

#include <nlmech/models/dynamics/elastic_solids.h>
#include <nlmech/models/elastic_constants.h>
#include <nlmech/models/solid/hyperelastic_tet_energy.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace nlmech
{
  void SolidMaterial::check() const
  {
    AssertThrow(youngs_modulus > 0 && density > 0 && thickness > 0,
                dealii::ExcMessage("A solid material needs a positive Young's modulus, density and thickness "
                                   "(got E = " +
                                   std::to_string(youngs_modulus) + " Pa, rho = " + std::to_string(density) +
                                   " kg/m^3, t = " + std::to_string(thickness) + " m)."));
    AssertThrow(poissons_ratio > -1 && poissons_ratio < 0.5,
                dealii::ExcMessage("Poisson's ratio must lie in (-1, 0.5); it is " +
                                   std::to_string(poissons_ratio) + "."));
  }

  double PlaneTriangleElements::signed_area(const Eigen::VectorXd &x, const std::size_t e) const
  {
    const auto   d  = dofs(e);
    const double ax = x[d[2]] - x[d[0]], ay = x[d[3]] - x[d[1]];
    const double bx = x[d[4]] - x[d[0]], by = x[d[5]] - x[d[1]];
    return 0.5 * (ax * by - ay * bx);
  }

  bool PlaneTriangleTerm::is_valid(const Eigen::VectorXd &x) const
  {
    for (std::size_t e = 0; e < elements().n_elements(); ++e)
      if (!(elements().signed_area(x, e) > 0))
        return false;
    return true;
  }

  double PlaneTriangleTerm::max_safe_step(const Eigen::VectorXd &x, const Eigen::VectorXd &dx) const
  {
    // The signed area along x + t dx is a quadratic in t: its first positive root bounds the step.
    double step = 1.0;
    for (std::size_t e = 0; e < elements().n_elements(); ++e)
      {
        const auto   d  = elements().dofs(e);
        const double ax = x[d[2]] - x[d[0]], ay = x[d[3]] - x[d[1]];
        const double bx = x[d[4]] - x[d[0]], by = x[d[5]] - x[d[1]];
        const double dax = dx[d[2]] - dx[d[0]], day = dx[d[3]] - dx[d[1]];
        const double dbx = dx[d[4]] - dx[d[0]], dby = dx[d[5]] - dx[d[1]];
        const double c0 = ax * by - ay * bx, c1 = ax * dby + dax * by - ay * dbx - day * bx;
        const double c2 = dax * dby - day * dbx;
        step            = std::min(step, first_positive_root_of_cubic({{c0, c1, c2, 0.0}}, step));
      }
    return step;
  }

  namespace
  {
    std::vector<unsigned int> material_of_cells(const RawSimplexMesh<3>          &mesh,
                                                const std::vector<SolidMaterial> &materials,
                                                const std::vector<unsigned int>  &cell_material)
    {
      AssertThrow(!materials.empty(), dealii::ExcMessage("A solid needs at least one material."));
      for (const auto &m : materials)
        m.check();
      if (cell_material.empty())
        return std::vector<unsigned int>(mesh.cells.size(), 0);
      AssertThrow(cell_material.size() == mesh.cells.size(),
                  dealii::ExcMessage("One material index per cell is needed."));
      for (const unsigned int m : cell_material)
        AssertThrow(m < materials.size(),
                    dealii::ExcMessage("A cell refers to material " + std::to_string(m) + " of only " +
                                       std::to_string(materials.size()) + "."));
      return cell_material;
    }
  } // namespace

  SolidModel make_plane_model(const RawSimplexMesh<3> &mesh, const std::vector<SolidMaterial> &materials,
                              const std::vector<unsigned int> &cell_material_in)
  {
    const auto        cell_material = material_of_cells(mesh, materials, cell_material_in);
    const std::size_t n_vertices    = mesh.vertices.size();
    SolidModel        solid;
    solid.dim   = 2;
    solid.model = Model(2 * n_vertices);
    solid.rest_positions.resize(2 * n_vertices);
    for (std::size_t v = 0; v < n_vertices; ++v)
      {
        AssertThrow(std::abs(mesh.vertices[v][2]) < 1e-12 * (1 + mesh.vertices[v].norm()),
                    dealii::ExcMessage("A plane mesh must lie in z = 0."));
        for (int i = 0; i < 2; ++i)
          solid.rest_positions[2 * v + i] = mesh.vertices[v][i];
      }
    Eigen::VectorXd &mass = solid.model.lumped_mass();
    mass                  = Eigen::VectorXd::Zero(2 * n_vertices);
    PlaneTriangleElements elements;
    for (std::size_t c = 0; c < mesh.cells.size(); ++c)
      {
        AssertThrow(mesh.cells[c].size() == 3, dealii::ExcMessage("A plane mesh must consist of triangles."));
        std::array<unsigned int, 3> tri = {{mesh.cells[c][0], mesh.cells[c][1], mesh.cells[c][2]}};
        auto                        X   = [&](int v, int i) { return mesh.vertices[tri[v]][i]; };
        double a = X(1, 0) - X(0, 0), b = X(2, 0) - X(0, 0), cc = X(1, 1) - X(0, 1), d = X(2, 1) - X(0, 1);
        if (a * d - b * cc < 0) // orient every triangle counter-clockwise
          {
            std::swap(tri[1], tri[2]);
            std::swap(a, b), std::swap(cc, d);
          }
        const double det = a * d - b * cc;
        AssertThrow(
            det > 1e-14 * (a * a + cc * cc),
            dealii::ExcMessage("The plane mesh has a degenerate triangle " + std::to_string(c + 1) + "."));
        const SolidMaterial &m      = materials[cell_material[c]];
        const double         mu     = shear_modulus(m.youngs_modulus, m.poissons_ratio);
        const double         lambda = lame_lambda(m.youngs_modulus, m.poissons_ratio);
        elements.triangles.push_back(tri);
        elements.dm_inverse.push_back({{d / det, -b / det, -cc / det, a / det}});
        elements.measure.push_back(0.5 * det * m.thickness);
        elements.mu.push_back(mu);
        elements.lambda.push_back(2 * lambda * mu / (lambda + 2 * mu));
        for (int v = 0; v < 3; ++v)
          for (int i = 0; i < 2; ++i)
            mass[2 * tri[v] + i] += m.density * 0.5 * det * m.thickness / 3;
      }
    solid.model.add_term(std::make_shared<PlaneTriangleTerm>("plane StVK triangles", elements));
    return solid;
  }

  SolidModel make_tet_solid_model(const RawSimplexMesh<3> &mesh, const std::vector<SolidMaterial> &materials,
                                  const std::vector<unsigned int> &cell_material_in)
  {
    const auto        cell_material = material_of_cells(mesh, materials, cell_material_in);
    const std::size_t n_vertices    = mesh.vertices.size();
    SolidModel        solid;
    solid.dim   = 3;
    solid.model = Model(3 * n_vertices);
    solid.rest_positions.resize(3 * n_vertices);
    for (std::size_t v = 0; v < n_vertices; ++v)
      for (int i = 0; i < 3; ++i)
        solid.rest_positions[3 * v + i] = mesh.vertices[v][i];
    Eigen::VectorXd &mass = solid.model.lumped_mass();
    mass                  = Eigen::VectorXd::Zero(3 * n_vertices);
    std::vector<std::vector<std::vector<unsigned int>>> cells_of(materials.size());
    for (std::size_t c = 0; c < mesh.cells.size(); ++c)
      {
        AssertThrow(mesh.cells[c].size() == 4,
                    dealii::ExcMessage("A solid mesh must consist of tetrahedra."));
        const auto                &t = mesh.cells[c];
        const dealii::Tensor<1, 3> a = mesh.vertices[t[1]] - mesh.vertices[t[0]],
                                   b = mesh.vertices[t[2]] - mesh.vertices[t[0]],
                                   d = mesh.vertices[t[3]] - mesh.vertices[t[0]];
        const double volume          = std::abs(dealii::cross_product_3d(a, b) * d) / 6;
        for (const unsigned int v : t)
          for (int i = 0; i < 3; ++i)
            mass[3 * v + i] += materials[cell_material[c]].density * volume / 4;
        cells_of[cell_material[c]].push_back(t);
      }
    for (std::size_t m = 0; m < materials.size(); ++m)
      if (!cells_of[m].empty())
        {
          HyperelasticMaterial law;
          law.law            = HyperelasticLaw::saint_venant_kirchhoff;
          law.youngs_modulus = materials[m].youngs_modulus;
          law.poissons_ratio = materials[m].poissons_ratio;
          law.density        = materials[m].density;
          solid.model.add_term(std::make_shared<HyperelasticTetTerm>(mesh.vertices, cells_of[m], law));
        }
    return solid;
  }

  std::vector<unsigned int> cell_layers(const RawSimplexMesh<3> &mesh, const unsigned int axis,
                                        const unsigned int n_layers)
  {
    AssertThrow(axis < 3 && n_layers >= 1,
                dealii::ExcMessage("Layers need an axis 0-2 and at least one layer."));
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (const auto &p : mesh.vertices)
      lo = std::min(lo, p[axis]), hi = std::max(hi, p[axis]);
    std::vector<unsigned int> layer(mesh.cells.size(), 0);
    for (std::size_t c = 0; c < mesh.cells.size(); ++c)
      {
        double centroid = 0;
        for (const unsigned int v : mesh.cells[c])
          centroid += mesh.vertices[v][axis] / mesh.cells[c].size();
        const double s = hi > lo ? (centroid - lo) / (hi - lo) : 0;
        layer[c]       = std::min(n_layers - 1, unsigned(std::floor(s * n_layers)));
      }
    return layer;
  }

  template class ElementEnergyTerm<PlaneTriangleElements>;
} // namespace nlmech
