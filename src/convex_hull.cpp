/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/convex_hull.h>
#include <pcl/surface/meshless/triangle_intersection.h>

#include <vector>

namespace pcl {
namespace meshless {

Triangles
convexHullThroughAll (const Points3& points, std::size_t max_points)
{
  const std::size_t n = points.size ();
  if (n < 4 || n > max_points)
    return {};
  for (const auto& p : points)
    if (!p.allFinite ())
      return {};
  // A triple is a face when every other point lies strictly on one side of its
  // plane; a point on the plane of a face candidate means four coplanar points on
  // the hull (or a point inside a face), where faces would not be unique.
  Triangles faces;
  std::vector<char> on_hull (n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        int side = 0;
        bool face = true, coplanar = false;
        for (std::size_t l = 0; l < n && face; ++l) {
          if (l == i || l == j || l == k)
            continue;
          const int s = orient3d (points[i], points[j], points[k], points[l]);
          if (s == 0)
            coplanar = true;
          else if (side == 0)
            side = s;
          else if (s != side)
            face = false;
        }
        if (!face)
          continue;
        if (coplanar || side == 0)
          return {}; // a flat hull face with four points or more, or a flat cloud
        // The others lie behind a face seen from outside: counter-clockwise when
        // they are on the negative side.
        if (side < 0)
          faces.push_back ({static_cast<pcl::index_t> (i), static_cast<pcl::index_t> (j),
                            static_cast<pcl::index_t> (k)});
        else
          faces.push_back ({static_cast<pcl::index_t> (i), static_cast<pcl::index_t> (k),
                            static_cast<pcl::index_t> (j)});
        on_hull[i] = on_hull[j] = on_hull[k] = 1;
      }
  for (const char used : on_hull)
    if (!used)
      return {}; // a point inside the hull: the hull does not pass through it
  if (faces.size () != 2 * n - 4)
    return {};
  return faces;
}

} // namespace meshless
} // namespace pcl
