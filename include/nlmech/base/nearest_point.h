#pragma once
// The index of the point nearest to a query: one search for every "the vertex nearest to" entry.

#include <deal.II/base/exceptions.h>

#include <cstddef>
#include <limits>

namespace nlmech
{
  /// Points and query are anything indexable as p[i][k] and q[k], k < dim (deal.II points,
  /// std::array, std::vector). The first of equally near points wins; throws on no points.
  template <typename Points, typename Query>
  std::size_t nearest_point(const Points &points, const Query &query, const unsigned int dim = 3)
  {
    AssertThrow(!points.empty(), dealii::ExcMessage("There is no point to search the nearest one in."));
    std::size_t best          = 0;
    double      best_distance = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < points.size(); ++i)
      {
        double d2 = 0;
        for (unsigned int k = 0; k < dim; ++k)
          d2 += (points[i][k] - query[k]) * (points[i][k] - query[k]);
        if (d2 < best_distance)
          best_distance = d2, best = i;
      }
    return best;
  }
} // namespace nlmech
