/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <Eigen/Core>

#include <algorithm>

namespace pcl {
namespace meshless {

/** \file
  * The predicates the edge swaps and the patches' flips decide with, so that both
  * stages decide alike. */

/** \brief Whether a triangle with (unnormalised) normal n and corners x, y, z is
  * degenerate for the swaps: the sine of its smallest angle below about 1e-8. Also
  * used by flipFlatEdgesInPatch. */
inline bool
nearlyDegenerateTriangle (const Eigen::Vector3d& n,
                          const Eigen::Vector3d& x,
                          const Eigen::Vector3d& y,
                          const Eigen::Vector3d& z)
{
  const double longest =
      std::max ({(x - y).squaredNorm (), (y - z).squaredNorm (), (z - x).squaredNorm ()});
  return !(n.norm () > 1e-8 * longest);
}

/** \brief Whether the (unnormalised) normals u and v turn by at most the angle whose
  * cosine is `cosine` (the swaps' fold bound; also flipFlatEdgesInPatch's). */
inline bool
normalsWithin (const Eigen::Vector3d& u, const Eigen::Vector3d& v, double cosine)
{
  return u.dot (v) >= cosine * u.norm () * v.norm ();
}

/** \brief Whether the angles at c and d opposite edge a-b of the triangles (a, b, c)
  * and (b, a, d) sum to more than pi + 1e-9: then a-b is not locally Delaunay (the
  * angle pass's test, also used by flipFlatEdgesInPatch). */
bool
oppositeAnglesExceedPi (const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c,
                        const Eigen::Vector3d& d);

} // namespace meshless
} // namespace pcl
