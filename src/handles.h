/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

// The sphere topology's check for handles, on grown base meshes (not installed:
// conductor policy, not API).

#include <pcl/surface/meshless/grown_base_mesh.h>

#include <string>

namespace pcl {
namespace meshless {

/** \brief Why a closed genus-0 mesh is refused for a cloud of genus g > 0. */
std::string
handlesRefusal (int genus);

/** \brief Seeds and rounds a sphere run grows D with at most to look for handles:
  * a cloud that needs more has no clear handles at its sampling. */
constexpr std::size_t max_seeds_for_handles = 512;
constexpr std::size_t max_rounds_for_handles = 32;

/** \brief The genus of a cloud if it clearly has handles: of up to three D grown
  * from different starts with at most max_seeds_for_handles seeds and
  * max_rounds_for_handles rounds, two find it and
  * none finds another. \return the genus, or 0. */
int
clearHandles (const Points3& points,
              const CsrGraph& graph,
              const CsrGraph& rings,
              const std::vector<char>& eligible = {});

} // namespace meshless
} // namespace pcl
