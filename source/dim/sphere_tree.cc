#include <deal.II/base/exceptions.h>

#include <nlmech/dim/sphere_tree.h>

#include <algorithm>
#include <numeric>

namespace nlmech::dim
{
  SphereTree::SphereTree(const std::vector<Eigen::Vector3d> &centres, const std::vector<double> &radii,
                         const unsigned int leaf_size)
      : item_centre(centres)
      , item_radius(radii)
  {
    AssertThrow(centres.size() == radii.size() && leaf_size >= 1,
                dealii::ExcMessage("Sphere tree: one radius per centre, leaves of at least one item."));
    if (centres.empty())
      return;
    order.resize(centres.size());
    std::iota(order.begin(), order.end(), 0u);
    nodes.reserve(2 * centres.size() / leaf_size + 2);
    build(0, unsigned(centres.size()), leaf_size);
  }

  int SphereTree::build(const unsigned int first, const unsigned int count, const unsigned int leaf_size)
  {
    // The node's sphere: centred at the mean of its items' centres, enclosing every item's sphere.
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (unsigned int k = first; k < first + count; ++k)
      {
        const Eigen::Vector3d &x = item_centre[order[k]];
        c += x, lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
      }
    c /= double(count);
    double r = 0;
    for (unsigned int k = first; k < first + count; ++k)
      r = std::max(r, (item_centre[order[k]] - c).norm() + item_radius[order[k]]);
    const int index = int(nodes.size());
    nodes.push_back({c, r, first, count, -1, -1});
    if (count <= leaf_size)
      return index;
    // Split at the median along the axis of largest spread.
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    const unsigned int half = count / 2;
    std::nth_element(
        order.begin() + first, order.begin() + first + half, order.begin() + first + count,
        [&](const unsigned i, const unsigned j) { return item_centre[i][axis] < item_centre[j][axis]; });
    const int left                 = build(first, half, leaf_size);
    const int right                = build(first + half, count - half, leaf_size);
    nodes[std::size_t(index)].left = left, nodes[std::size_t(index)].right = right;
    return index;
  }
} // namespace nlmech::dim
