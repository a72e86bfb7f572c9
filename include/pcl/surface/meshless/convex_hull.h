/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <cstddef>

/** \file
  * The convex hull of a small cloud whose points all lie on it.
  *
  * Below a few dozen points the meshless pipeline has too little to work with: the
  * neighbourhoods of four to a few dozen points span much of the cloud, and no base
  * mesh finds room for its paths. Yet such a cloud often has an obvious closed
  * surface through every point: when every point is a vertex of the convex hull
  * (four points of a tetrahedron, six of an octahedron, a sparse sample of a round
  * object), the hull is a closed genus-0 triangulation with exactly 2n - 4
  * triangles, oriented outward and free of self-intersections.
  */
namespace pcl {
namespace meshless {

/** \brief The hull's triangles if every point is a vertex of the convex hull and no
  * four points on the hull are coplanar (then its faces are triangles, unique);
  * empty otherwise, or for more than `max_points` points (the search tests every
  * triple against every point, O(n^4), exact predicates).
  * \return triangles counter-clockwise seen from outside, 2n - 4 of them, or none
  */
Triangles
convexHullThroughAll (const Points3& points, std::size_t max_points = 100);

} // namespace meshless
} // namespace pcl
