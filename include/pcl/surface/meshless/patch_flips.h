/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

/** \brief Options of flipFlatEdgesInPatch. */
struct PatchFlipOptions
{
  /** \brief Default: false. Whether triangulatePatch flips at all (the pipelines turn
    * it on when the edge swaps' angle pass will run: without optimization the
    * paper's triangulation is returned as it is). */
  bool enabled = false;
  /** \brief Default: 60. The largest angle (degrees) between the normals of a quad's
    * two triangles, before and after the flip (EdgeSwapOptions::
    * angle_pass_max_dihedral_deg, whose rule this is). */
  double max_dihedral_deg = 60.0;
  /** \brief Default: 90. A new triangle turns by at most this (degrees) against one
    * of the old ones, or by the old quad's own turn if that is larger
    * (EdgeSwapOptions::max_fold_angle_deg, the swaps' fold bound). */
  double max_fold_angle_deg = 90.0;
  /** \brief Default: 10. At most this many flips per triangle (a curved quad can
    * flip back and forth). */
  std::size_t flips_per_triangle = 10;
};

/** \brief The edge swaps' angle pass (EdgeSwapOptions::improve_angles) on one patch,
  * in the patch stage, where the patches are triangulated in parallel: interior
  * edges that are not locally Delaunay in space (their opposite angles sum to more
  * than pi) in quads turning less than the bound are flipped, but only where the quad is strictly
  * convex in the parameter plane, so that the triangulation stays an embedding of
  * the parameter points (a disc bounded by the same loop, no fold in the plane).
  *
  * The swaps then find most of that work done: their angle pass runs on one thread
  * and checks each swap for intersections against the whole mesh, while these
  * flips run in parallel and leave it a few percent. The intersections the flips
  * could make with other
  * parts of the surface are found by the check of the raw mesh like those of the
  * Delaunay triangulation itself.
  *
  * Contract: `triangles` index `uv` (and through `global_of` the 3D `points`), all
  * turn the same way in the plane and form a disc: every edge in one triangle (on
  * the boundary) or two. On return the same holds, with the same boundary edges, the
  * same number of triangles and the same vertices.
  * \param[in] points 3D points (cloud indices)
  * \param[in] global_of the cloud index of each parameter point
  * \param[in] uv parameter points
  * \param[in,out] triangles over positions into uv
  * \return the number of flips (0, the triangles untouched, if an index is out of
  *         range or global_of does not match uv)
  */
std::size_t
flipFlatEdgesInPatch (const Points3& points,
                      const std::vector<pcl::index_t>& global_of,
                      const Points2& uv,
                      Triangles& triangles,
                      const PatchFlipOptions& options = {});

} // namespace meshless
} // namespace pcl
