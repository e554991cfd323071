#include <nlmech/base/mesh_study.h>

#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace nlmech
{
  double fitted_slope(const std::vector<double> &x, const std::vector<double> &y)
  {
    AssertThrow(x.size() == y.size() && x.size() >= 2,
                dealii::ExcMessage("A fit needs at least two points."));
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      mx += x[i] / x.size(), my += y[i] / y.size();
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
    return sxy / sxx;
  }

  MeshStudyTable::MeshStudyTable(const std::string &error_name, const std::vector<std::string> &extra_columns)
      : error_name(error_name)
      , extra_columns(extra_columns)
  {
  }

  void MeshStudyTable::add(const Row &row)
  {
    AssertThrow(row.extra.size() == extra_columns.size(), dealii::ExcInternalError());
    table.push_back(row);
  }

  double MeshStudyTable::fitted_order_in_h() const
  {
    std::vector<double> x, y;
    for (const auto &r : table)
      if (r.error > 0)
        x.push_back(std::log(r.element_size)), y.push_back(std::log(r.error));
    return x.size() >= 2 ? fitted_slope(x, y) : std::nan("");
  }

  double MeshStudyTable::fitted_order_in_dofs(const unsigned int dim) const
  {
    std::vector<double> x, y;
    for (const auto &r : table)
      if (r.error > 0)
        x.push_back(std::log(double(r.n_dofs))), y.push_back(std::log(r.error));
    return x.size() >= 2 ? -double(dim) * fitted_slope(x, y) : std::nan("");
  }

  std::string MeshStudyTable::to_csv() const
  {
    std::ostringstream out;
    out.precision(10);
    out << "level,element_size_m,n_cells,n_dofs," << error_name << ",wall_time_s";
    for (const auto &c : extra_columns)
      out << "," << c;
    out << "\n";
    for (const auto &r : table)
      {
        out << r.level << "," << json_number(r.element_size) << "," << r.n_cells << "," << r.n_dofs << ","
            << json_number(r.error) << "," << json_number(r.wall_seconds);
        for (double v : r.extra)
          out << "," << json_number(v);
        out << "\n";
      }
    return out.str();
  }

  void MeshStudyTable::write_csv(const std::string &path) const
  {
    write_file_atomically(path, to_csv());
  }

  std::string MeshStudyTable::plot(const std::string &csv_path, const std::string &png_path,
                                   const std::string &title)
  {
    const std::string script = std::string(NLMECH_SOURCE_DIR) + "/contrib/plot/mesh_study.py";
    if (!std::filesystem::exists(script))
      return "plot script " + script + " not found";
    const std::string command = std::string(NLMECH_PYTHON) + " '" + script + "' '" + csv_path + "' '" +
                                png_path + "' '" + title + "'";
    const int status = std::system(command.c_str());
    return status == 0 ? "" : "python3/matplotlib failed (exit status " + std::to_string(status) + ")";
  }
} // namespace nlmech
