#include <nlmech/base/mesh_study.h>

#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/plot.h>

#include <algorithm>
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

  void MeshStudyTable::set_errors(const std::vector<double> &errors)
  {
    AssertThrow(errors.size() == table.size(),
                dealii::ExcMessage("Mesh study: one error per row is needed to replace them."));
    for (std::size_t i = 0; i < table.size(); ++i)
      table[i].error = errors[i];
  }

  std::size_t MeshStudyTable::extra_index(const std::string &name) const
  {
    const auto it = std::find(extra_columns.begin(), extra_columns.end(), name);
    AssertThrow(it != extra_columns.end(), dealii::ExcMessage("Mesh study: no column <" + name + ">."));
    return std::size_t(it - extra_columns.begin());
  }

  Extrapolation richardson_extrapolation(const std::vector<double> &h, const std::vector<double> &u,
                                         const double assumed_order)
  {
    AssertThrow(h.size() == u.size() && h.size() >= 2,
                dealii::ExcMessage("Richardson extrapolation needs at least two levels."));
    const std::size_t n = h.size();
    Extrapolation     e;
    e.order = assumed_order;
    if (n >= 3)
      {
        // (u1 - u2) / (u2 - u3) = (h1^p - h2^p) / (h2^p - h3^p) for the three finest, solved for p
        // by bisection on [0.5, 8] when it brackets a root.
        const double h1 = h[n - 3], h2 = h[n - 2], h3 = h[n - 1];
        const double d1 = u[n - 3] - u[n - 2], d2 = u[n - 2] - u[n - 1];
        if (d1 * d2 > 0 && std::abs(d2) < std::abs(d1) && h1 > h2 && h2 > h3 && h3 > 0)
          {
            const double target = d1 / d2;
            auto         f      = [&](double p) {
              return (std::pow(h1, p) - std::pow(h2, p)) / (std::pow(h2, p) - std::pow(h3, p)) - target;
            };
            double lo = 0.5, hi = 8;
            if (f(lo) * f(hi) < 0)
              {
                for (int it = 0; it < 200; ++it)
                  {
                    const double mid                = 0.5 * (lo + hi);
                    (f(lo) * f(mid) <= 0 ? hi : lo) = mid;
                  }
                e.order        = 0.5 * (lo + hi);
                e.order_fitted = true;
              }
          }
      }
    // u_0 from the two finest levels and the order.
    const double r = std::pow(h[n - 1] / h[n - 2], e.order);
    e.value        = (u[n - 1] - r * u[n - 2]) / (1 - r);
    return e;
  }

  std::string MeshStudyTable::plot(const std::string &csv_path, const std::string &png_path,
                                   const std::string &title, const std::string &context_column)
  {
    std::vector<std::string> arguments = {csv_path, png_path, title};
    if (!context_column.empty())
      arguments.push_back(context_column);
    return run_plot("mesh_study.py", arguments) ? "" : "python3/matplotlib failed";
  }
} // namespace nlmech
