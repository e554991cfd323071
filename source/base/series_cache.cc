#include <nlmech/base/series_cache.h>

#include <algorithm>

namespace nlmech
{
  void SeriesCache::prepare(const std::size_t elements, const std::size_t quantities, const unsigned int k)
  {
    if (elements == n_elements && quantities == n_quantities && std::size_t(k) < stride)
      return;
    n_elements   = elements;
    n_quantities = quantities;
    stride       = std::max<std::size_t>({stride, std::size_t(k) + 1, 21});
    data.assign(n_elements * n_quantities * stride, 0.0);
    cached.assign(n_elements, -1);
    origin.assign(n_elements, nullptr);
  }

  int SeriesCache::first_order(const std::size_t e, const unsigned int k, const void *path_origin)
  {
    const int first = (k > 2 && origin[e] == path_origin && cached[e] == int(k) - 2) ? int(k) - 1 : 0;
    cached[e]       = int(k) - 1;
    origin[e]       = path_origin;
    return first;
  }
} // namespace nlmech
