#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/mesh/vertex_field_output.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>
#include <deal.II/numerics/data_out.h>

#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// Tetrahedra (dim 3) or surface triangles in 3D (dim 2, a Triangulation<2, 3>).
    template <int dim>
    void write_fields(const RawSimplexMesh<3>                                    &mesh,
                      const std::vector<std::pair<std::string, Eigen::VectorXd>> &fields,
                      const std::vector<std::pair<std::string, Eigen::VectorXd>> &cell_fields,
                      const std::string                                          &path)
    {
      Triangulation<dim, 3>      tria;
      std::vector<CellData<dim>> cells(mesh.cells.size());
      for (std::size_t c = 0; c < cells.size(); ++c)
        cells[c].vertices = mesh.cells[c];
      tria.create_triangulation(mesh.vertices, cells, SubCellData());
      AssertThrow(tria.n_vertices() == mesh.vertices.size(), ExcMessage("The mesh has unused vertices."));

      const FESystem<dim, 3>  fe(FE_SimplexP<dim, 3>(1), 3);
      const MappingFE<dim, 3> mapping(FE_SimplexP<dim, 3>(1));
      DoFHandler<dim, 3>      dofs(tria);
      dofs.distribute_dofs(fe);
      std::vector<Vector<double>> values;
      for (const auto &f : fields)
        {
          AssertThrow(std::size_t(f.second.size()) == 3 * mesh.vertices.size() && f.second.allFinite(),
                      ExcMessage("Field <" + f.first + "> is not a finite vertex vector field."));
          values.emplace_back(dofs.n_dofs());
          for (const auto &cell : dofs.active_cell_iterators())
            for (const unsigned int v : cell->vertex_indices())
              for (unsigned int i = 0; i < 3; ++i)
                values.back()[cell->vertex_dof_index(v, i)] = f.second[3 * cell->vertex_index(v) + i];
        }
      DataOut<dim, 3> data_out;
      data_out.attach_dof_handler(dofs);
      const std::vector<DataComponentInterpretation::DataComponentInterpretation> vector_field(
          3, DataComponentInterpretation::component_is_part_of_vector);
      for (std::size_t k = 0; k < fields.size(); ++k)
        data_out.add_data_vector(values[k], std::vector<std::string>(3, fields[k].first),
                                 DataOut<dim, 3>::type_dof_data, vector_field);
      std::vector<Vector<float>> cell_values;
      for (const auto &f : cell_fields)
        {
          AssertThrow(std::size_t(f.second.size()) == mesh.cells.size() && f.second.allFinite(),
                      ExcMessage("Cell field <" + f.first + "> is not finite or has the wrong size."));
          cell_values.emplace_back(f.second.size());
          for (std::size_t c = 0; c < mesh.cells.size(); ++c)
            cell_values.back()[c] = f.second[c];
        }
      for (std::size_t k = 0; k < cell_fields.size(); ++k)
        data_out.add_data_vector(cell_values[k], cell_fields[k].first, DataOut<dim, 3>::type_cell_data);
      data_out.build_patches(mapping, 1);
      AtomicFile file(path);
      data_out.write_vtu(file.stream());
      file.commit();
    }
  } // namespace

  void write_vertex_fields_vtu(const RawSimplexMesh<3>                                    &mesh,
                               const std::vector<std::pair<std::string, Eigen::VectorXd>> &fields,
                               const std::vector<std::pair<std::string, Eigen::VectorXd>> &cell_fields,
                               const std::string                                          &path)
  {
    AssertThrow(!mesh.cells.empty(), ExcMessage("Cannot write fields on an empty mesh."));
    if (mesh.cells.front().size() == 3)
      write_fields<2>(mesh, fields, cell_fields, path);
    else
      write_fields<3>(mesh, fields, cell_fields, path);
  }

  void
  write_vertex_fields_pvd(const RawSimplexMesh<3> &mesh, const std::string &directory,
                          const std::string &basename, const std::vector<double> &times,
                          const std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> &frames)
  {
    AssertThrow(times.size() == frames.size(), ExcMessage("One time per frame is needed."));
    std::vector<std::pair<double, std::string>> records;
    for (std::size_t f = 0; f < frames.size(); ++f)
      {
        const std::string name = basename + "-" + Utilities::int_to_string(f, 4) + ".vtu";
        write_vertex_fields_vtu(mesh, frames[f], {}, directory + "/" + name);
        records.emplace_back(times[f], name);
      }
    AtomicFile file(directory + "/" + basename + ".pvd");
    DataOutBase::write_pvd_record(file.stream(), records);
    file.commit();
  }
} // namespace nlmech

namespace nlmech
{
  void write_vertex_displacements_csv(const RawSimplexMesh<3> &mesh, const Eigen::VectorXd &displacement,
                                      const std::string &path)
  {
    AssertThrow(std::size_t(displacement.size()) == 3 * mesh.vertices.size() && displacement.allFinite(),
                ExcMessage("The displacement is not a finite vertex vector field."));
    std::ostringstream csv;
    csv << "x,y,z,u_x,u_y,u_z\n";
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      csv << json_number(mesh.vertices[v][0]) << "," << json_number(mesh.vertices[v][1]) << ","
          << json_number(mesh.vertices[v][2]) << "," << json_number(displacement[3 * v]) << ","
          << json_number(displacement[3 * v + 1]) << "," << json_number(displacement[3 * v + 2]) << "\n";
    write_file_atomically(path, csv.str());
  }
} // namespace nlmech
