#include <nlmech/base/parse.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <cmath>
#include <cstdlib>

namespace nlmech
{
  using namespace dealii;

  std::vector<double> parse_number_list(const std::string &text, const std::string &entry)
  {
    std::vector<double> values;
    for (const auto &piece : Utilities::split_string_list(text, ','))
      {
        if (piece.empty())
          continue;
        char        *end   = nullptr;
        const double value = std::strtod(piece.c_str(), &end);
        AssertThrow(end && *end == '\0' && std::isfinite(value),
                    ExcMessage("The entry <" + entry + "> must be a comma-separated list of numbers; <" +
                               piece + "> is not a number."));
        values.push_back(value);
      }
    return values;
  }

  template <int dim>
  Tensor<1, dim> parse_vector(const std::string &text, const std::string &entry)
  {
    const auto values = parse_number_list(text, entry);
    AssertThrow(values.size() == dim,
                ExcMessage("The entry <" + entry + "> needs " + std::to_string(dim) + " components; it has " +
                           std::to_string(values.size()) + "."));
    Tensor<1, dim> v;
    for (unsigned int d = 0; d < dim; ++d)
      v[d] = values[d];
    return v;
  }
  template Tensor<1, 2> parse_vector<2>(const std::string &, const std::string &);
  template Tensor<1, 3> parse_vector<3>(const std::string &, const std::string &);

  std::vector<std::pair<std::string, Tensor<1, 3>>> parse_group_vectors(const std::string &text,
                                                                        const std::string &entry)
  {
    std::vector<std::pair<std::string, Tensor<1, 3>>> out;
    for (const auto &item : Utilities::split_string_list(text, ';'))
      if (!item.empty())
        {
          const auto parts = Utilities::split_string_list(item, ':');
          AssertThrow(parts.size() == 2 && !parts[0].empty(),
                      ExcMessage("The entry <" + entry + "> must read `group: v_x, v_y, v_z; ...`; <" + item +
                                 "> does not."));
          out.emplace_back(parts[0], parse_vector<3>(parts[1], entry));
        }
    return out;
  }

  std::vector<std::pair<Point<3>, Tensor<1, 3>>> parse_point_vectors(const std::string &text,
                                                                     const std::string &entry)
  {
    std::vector<std::pair<Point<3>, Tensor<1, 3>>> out;
    for (const auto &item : Utilities::split_string_list(text, ';'))
      if (!item.empty())
        {
          const auto parts = Utilities::split_string_list(item, ':');
          AssertThrow(parts.size() == 2, ExcMessage("The entry <" + entry +
                                                    "> must read `x, y, z: f_x, f_y, f_z; "
                                                    "...`; <" +
                                                    item + "> does not."));
          out.emplace_back(Point<3>(parse_vector<3>(parts[0], entry)), parse_vector<3>(parts[1], entry));
        }
    return out;
  }

  std::vector<std::vector<double>> parse_number_rows(const std::string &text, const std::string &entry,
                                                     const std::size_t width)
  {
    std::vector<std::vector<double>> rows;
    for (const auto &row : Utilities::split_string_list(text, ';'))
      if (!row.empty())
        {
          rows.push_back(parse_number_list(row, entry));
          AssertThrow(width == 0 || rows.back().size() == width,
                      ExcMessage(entry + ": every `;`-separated entry needs " + std::to_string(width) +
                                 " numbers (got <" + row + ">)."));
        }
    return rows;
  }

  unsigned int parse_index(const double value, const std::string &entry)
  {
    AssertThrow(value >= 0 && value == std::floor(value) && value < 1e9,
                ExcMessage(entry + ": <" + std::to_string(value) + "> is not an index."));
    return unsigned(value);
  }
} // namespace nlmech
