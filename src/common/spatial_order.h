/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <cstdint>
#include <vector>

/** \file
  * An order of the points in which neighbours in space are mostly neighbours in
  * memory.
  *
  * Every stage walks the points' neighbourhoods: kNN queries, rings, weights, the
  * patches' sparse systems, the mesh checks. In the order a scanner or a file
  * delivers them, a point's neighbours lie anywhere in memory, and on a million
  * points each visit misses the cache; in this order the queries, the rings and the
  * solves run several times faster, and the fill-reducing ordering finds less fill
  * (doc/benchmarks.md).
  */
namespace pcl {
namespace meshless {

/** \brief The Morton (Z-order) key of a cell: the low 21 bits of x, y and z
  * interleaved, x in the lowest bit. */
std::uint64_t
mortonKey (std::uint64_t x, std::uint64_t y, std::uint64_t z);

/** \brief The points' indices sorted along a Morton (Z-order) curve over their
  * bounding cube, 21 bits per axis; points in the same cell keep their input order.
  * \param[in] points positions; a NaN or -inf coordinate counts as the cube's lowest
  *            cell along its axis, +inf as the highest (only finite points bound the
  *            cube)
  * \return a permutation of 0 .. points.size () - 1: the k-th point of the new
  *         order is points[order[k]]
  */
std::vector<pcl::index_t>
mortonOrder (const Points3& points);

} // namespace meshless
} // namespace pcl
