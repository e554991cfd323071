#pragma once
// A refinement study table: one row per mesh (level, element size, DOFs, error against the scene's
// reference, wall time), written as CSV, with fitted convergence orders and a PNG plot of error
// against DOFs and against time. Every solver reuses it to report run time against error.

#include <mpi.h>

#include <string>
#include <vector>

namespace nlmech
{
  class MeshStudyTable
  {
  public:
    struct Row
    {
      unsigned int        level        = 0;
      double              element_size = 0; // m
      unsigned long long  n_cells      = 0;
      unsigned long long  n_dofs       = 0;
      double              error        = 0; // in the unit given by error_name
      double              wall_seconds = 0;
      std::vector<double> extra; // values of the extra columns
    };

    MeshStudyTable(const std::string &error_name, const std::vector<std::string> &extra_columns = {});

    void                    add(const Row &row);
    const std::vector<Row> &rows() const { return table; }
    /// Replaces the error of every row (one value per row).
    void set_errors(const std::vector<double> &errors);
    /// The index of an extra column by name (throws if there is none).
    std::size_t extra_index(const std::string &name) const;

    /// Least-squares slope of log(error) against log(element size): the order in h.
    double fitted_order_in_h() const;
    /// -dim * slope of log(error) against log(DOFs): the order in h_eff = DOFs^(-1/dim).
    double fitted_order_in_dofs(unsigned int dim) const;

    std::string to_csv() const;
    /// Writes the CSV atomically (call on one rank).
    void write_csv(const std::string &path) const;
    /// Runs contrib/plot/mesh_study.py on a written CSV; returns an empty string or the reason it
    /// could not plot.
    /// `context_column` (optional): an extra column drawn beside the error, dashed.
    static std::string plot(const std::string &csv_path, const std::string &png_path,
                            const std::string &title, const std::string &context_column = "");

  private:
    std::string              error_name;
    std::vector<std::string> extra_columns;
    std::vector<Row>         table;
  };

  /// Least-squares slope of y against x.
  double fitted_slope(const std::vector<double> &x, const std::vector<double> &y);

  /// Richardson extrapolation of a quantity computed on meshes of sizes h (any ratios) to h = 0:
  /// u(h) = u_0 + C h^p fitted to the three finest levels (p from them when the differences keep
  /// their sign and shrink, else `assumed_order`), or to the two finest with p = `assumed_order`.
  struct Extrapolation
  {
    double value = 0, order = 0;
    bool   order_fitted = false;
  };
  Extrapolation richardson_extrapolation(const std::vector<double> &h, const std::vector<double> &u,
                                         double assumed_order);
} // namespace nlmech
