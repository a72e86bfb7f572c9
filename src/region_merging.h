/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

// Coarsening a grown D (not installed: a step of growBaseMesh).

#include <pcl/surface/meshless/grown_base_mesh.h>

#include <cstddef>

namespace pcl {
namespace meshless {

/** \brief Merges regions of a grown D smaller than `min_points` into a neighbour
  * across one edge of D, smallest first, while D stays a closed polygon mesh of the
  * same genus whose faces are discs: two faces merge only where they share exactly
  * one edge and no other corner (two discs glued along one arc make a disc), a
  * corner left between two faces stops being one, and no two edges may join the
  * same corners. The growth needs small regions to see the topology; the router
  * needs room, which every corner's guarded ring takes from it.
  * \return the number of merges (grown is unchanged where none was possible). */
std::size_t
mergeSmallRegions (GrownBaseMesh& grown, std::size_t min_points);

} // namespace meshless
} // namespace pcl
