/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "half_edges.h"

namespace pcl {
namespace meshless {

HalfEdgeGroups
groupHalfEdges (const Triangles& triangles, std::size_t n)
{
  return groupHalfEdges (triangles, n, [] (std::size_t) { return true; });
}

std::vector<std::int32_t>
halfEdgeTwins (const Triangles& triangles, std::size_t n)
{
  // The twin of a -> b is among the half-edges leaving b, listed per vertex in
  // ascending order.
  const auto T = static_cast<std::int32_t> (triangles.size ());
  std::vector<std::int32_t> twin (3 * triangles.size (), -1);
  std::vector<std::int32_t> first (n + 1, 0);
  for (const Triangle& t : triangles)
    for (const pcl::index_t v : t)
      ++first[v + 1];
  for (std::size_t v = 0; v < n; ++v)
    first[v + 1] += first[v];
  std::vector<std::int32_t> leaving (3 * triangles.size ());
  {
    std::vector<std::int32_t> fill (first.begin (), first.end () - 1);
    for (std::int32_t h = 0; h < 3 * T; ++h)
      leaving[fill[triangles[h / 3][h % 3]]++] = h;
  }
  for (std::int32_t h = 0; h < 3 * T; ++h) {
    const pcl::index_t a = triangles[h / 3][h % 3], b = triangles[h / 3][(h + 1) % 3];
    for (std::int32_t k = first[b]; k < first[b + 1]; ++k) {
      const std::int32_t g = leaving[k];
      if (triangles[g / 3][(g + 1) % 3] == a) {
        twin[h] = g;
        break;
      }
    }
  }
  return twin;
}

} // namespace meshless
} // namespace pcl
