#pragma once
// Per-element storage for the ANM's auxiliary-variable recurrences (ANM paper, section 4.2.2):
// the Taylor coefficients of a few quantities per element, kept from one order to the next along
// one series, so that order k costs O(k) instead of recomputing orders 0..k-1.

#include <cstddef>
#include <vector>

namespace nlmech
{
  class SeriesCache
  {
  public:
    /// Makes room for orders 0..k of `n_quantities` series per element. Keeps the cached orders
    /// when the layout is already large enough; otherwise reallocates (at least 21 orders, the ANM
    /// default order 20) and forgets them. Call on one thread before a loop over the elements.
    void prepare(std::size_t n_elements, std::size_t n_quantities, unsigned int k);

    /// Coefficients 0..capacity()-1 of quantity q of element e.
    double     *quantity(std::size_t e, std::size_t q) { return &data[(e * n_quantities + q) * stride]; }
    std::size_t capacity() const { return stride; }

    /// For coefficient k of the series whose origin (coefficient 0 of the path) is `origin`: the
    /// first order element e must compute. Orders 0..k-2 are exact if the last call for this
    /// element was coefficient k-1 of the same path, so the answer is k-1 (order k-1 was computed
    /// with the then unknown path coefficient k-1 taken as zero); otherwise 0. Records that the
    /// element will hold orders 0..k-1 of this path. Safe for different elements on different threads.
    int first_order(std::size_t e, unsigned int k, const void *origin);

    std::size_t bytes() const { return data.capacity() * sizeof(double); }

  private:
    std::size_t               n_elements   = 0;
    std::size_t               n_quantities = 0;
    std::size_t               stride       = 0;
    std::vector<double>       data;   // element-major: [e][quantity][order]
    std::vector<int>          cached; // per element: highest order computed, -1: none
    std::vector<const void *> origin; // per element: the path it was computed for
  };
} // namespace nlmech
