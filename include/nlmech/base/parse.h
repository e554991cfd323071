#pragma once
// Parsing the list-valued entries of parameter files, with errors that name the entry: numbers,
// vectors, `;`-separated rows, `point: vector` and `group: vector` pairs, indices.

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <string>
#include <utility>
#include <vector>

namespace nlmech
{
  /// "a, b, c" -> {a, b, c} with a clear error naming the entry.
  std::vector<double> parse_number_list(const std::string &text, const std::string &entry);
  /// "a, b, c" -> a vector of exactly dim components.
  template <int dim>
  dealii::Tensor<1, dim> parse_vector(const std::string &text, const std::string &entry);
  /// "a, b, c; d, e, f" -> rows of numbers, each with `width` entries (0: any).
  std::vector<std::vector<double>> parse_number_rows(const std::string &text, const std::string &entry,
                                                     std::size_t width);
  /// A number that must be a non-negative integer (a joint, a link).
  unsigned int parse_index(double value, const std::string &entry);
  /// "group: t_x, t_y, t_z; ..." -> (group, vector) pairs.
  std::vector<std::pair<std::string, dealii::Tensor<1, 3>>> parse_group_vectors(const std::string &text,
                                                                                const std::string &entry);
  /// "x, y, z: f_x, f_y, f_z; ..." -> (point, vector) pairs.
  std::vector<std::pair<dealii::Point<3>, dealii::Tensor<1, 3>>>
  parse_point_vectors(const std::string &text, const std::string &entry);
} // namespace nlmech
