/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

struct MergedTriangulation : StageStatus
{
  Triangles triangles;
  /** \brief Edge flips that removed a chord two patches had both created. */
  std::size_t num_repair_flips = 0;
};

/** \brief Union of the patch triangulations along their shared paths (§3), with
  * the one repair the union can need: two patches whose parameterizations pushed
  * their interior away from a shared path may both join the same two path points
  * by a chord, an edge then used by four triangles. Such a chord is flipped inside
  * one of the two patches (which keeps that patch a disc with the same boundary),
  * provided the new diagonal is not an edge yet. The triangles come out in the
  * order of their smallest vertex index (ties in the patches' order): with the
  * points in a spatial order, later passes over the mesh walk memory in order.
  * \param[in] patches each patch's triangles (cloud indices), each patch a disc
  * \param[in] n number of points
  * \return fails if a chord cannot be repaired
  */
MergedTriangulation
mergePatches (const std::vector<Triangles>& patches, std::size_t n);

} // namespace meshless
} // namespace pcl
