/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/parameterization.h>
#include <pcl/surface/meshless/patch_flips.h>
#include <pcl/surface/meshless/patch_split.h>
#include <pcl/surface/meshless/types.h>
#include <pcl/surface/meshless/weights.h>

namespace pcl {
namespace meshless {

/** \brief Triangulation of one disc patch (Floater-Reimers). */
struct PatchTriangulation : StageStatus
{
  /** \brief Triangles over cloud indices, oriented so that the loop runs
    * counter-clockwise around them (outward for a loop counter-clockwise seen
    * from outside). A disc: 2m - 2 - h triangles for m points, h on the loop. */
  Triangles triangles;
  /** \brief Parameter point of each patch point (order of Patch::points). */
  Points2 uv;
  /** \brief Smallest distance between two parameter points joined by a triangle
    * edge: how strongly the map compresses (diagnostic). */
  double smallest_edge = 0.0;
  /** \brief Edges flipped by flipFlatEdgesInPatch (0 unless asked for). */
  std::size_t flips = 0;
};

/** \brief Parameterize a patch with its loop on the unit circle (chord length),
  * triangulate the parameter points (exact Delaunay), map the triangles back.
  * \param[in] rings optional context to recompute the rings of points next to the
  *            loop inside the patch (see PatchRingContext); used for patches cut
  *            out of a larger surface
  * \param[in] flips the edge swaps' angle pass in the plane (flipFlatEdgesInPatch),
  *            after the Delaunay triangulation, if enabled
  * \return fails (with a message) if the system is singular, parameter points
  *         coincide, or the convex hull of the parameter points is not exactly
  *         the loop (an interior point landed on the boundary), so that a
  *         returned patch is always a disc bounded by its loop.
  */
PatchTriangulation
triangulatePatch (const Points3& points,
                  const Weights& weights,
                  const Patch& patch,
                  const SolveOptions& options = {},
                  const PatchRingContext* rings = nullptr,
                  const PatchFlipOptions& flips = {});

} // namespace meshless
} // namespace pcl
