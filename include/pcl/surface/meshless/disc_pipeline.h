/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/parameterization.h>
#include <pcl/surface/meshless/sphere_pipeline.h> // ProgressCallback
#include <pcl/surface/meshless/types.h>
#include <pcl/surface/meshless/weights.h>

namespace pcl {
namespace meshless {

/** \brief The boundary loops of an open surface sampled by points. */
struct BoundaryLoops : StageStatus
{
  /** \brief Each loop in cyclic order, the surface on its left (counter-clockwise
    * around the oriented normals); the longest (in 3D) first: the outer boundary.
    */
  std::vector<std::vector<pcl::index_t>> loops;
};

/** \brief Find the boundary loops of an open surface.
  *
  * A point is on the boundary when its Delaunay ring leaves an angular gap of at
  * least `min_gap` (radians; the ring does not surround it). From each such point
  * the loop is walked along the mutual ring graph with the outer-face rule: having
  * arrived at w from v, go on to the first neighbour of w counter-clockwise after
  * v. The walk follows the boundary with the surface on its left, also through
  * boundary points whose gap is smaller (concave corners). A walk that meets a
  * point twice stops; only where no walk closes a loop do they run again and cut
  * off the shorter of the two loops through such a point (a notch pinched by
  * noise), if it has fewer than `min_loop` points. Once the outline is found (and
  * is not refused as a gap of the sample), walks also start, without cutting
  * notches, from points whose gap is at least `min_rim_gap`: a round hole a few
  * spacings wide has a concave rim, on which every gap stays below `min_gap`.
  * \param[in] normals the consistently oriented normals the rings turn around
  * \param[in] rings rings counter-clockwise around `normals`
  * \param[in] mutual the mutual ring graph
  * \param[in] largest_gap per point (OrderedNeighbourhoods::largest_gap)
  * \param[in] min_loop loops with fewer points are noise and dropped (default 8)
  * \param[in] spacing optional, a distance per point (ignored unless there is one
  *            per point), the typical gap of the sample around it: an inner loop
  *            is a hole only if its half-width (twice its area over its length;
  *            the area is its vector area's norm, the largest of its
  *            projections) is at least 2.05 times its points' median spacing; without spacings,
  *            1.5 times its median edge, a coarser yardstick (a walked rim's edges
  *            run long, and where a sample comes in small dense clusters, a gap's
  *            edges run short)
  * \param[in] min_rim_gap the least gap (radians) of a point that starts a walk
  *            after the outline is found (default 2 pi / 3; no effect unless
  *            below min_gap)
  */
BoundaryLoops
findBoundaryLoops (const Points3& points,
                   const std::vector<Eigen::Vector3f>& normals,
                   const CsrGraph& rings,
                   const CsrGraph& mutual,
                   const std::vector<float>& largest_gap,
                   double min_gap = 3.14159265358979323846,
                   std::size_t min_loop = 8,
                   const std::vector<double>& spacing = {},
                   double min_rim_gap = 2.0 * 3.14159265358979323846 / 3.0);

/** \brief An edge longer than this many times the spacing of its end points (a
  * point's mean distance to its six nearest, or past its cluster where those are
  * a small dense cluster's own) spans a hole: a sample's own edges stay well
  * below it (doc/benchmarks.md). */
constexpr double max_edge_over_spacing = 4.0;

/** \brief Cut open the holes the boundary walk missed: removes the triangles with an
  * edge longer than `max_span` (positive) times the larger spacing of its end
  * points (each point's mean distance to its six nearest in `neighbourhoods`,
  * or, where the twelfth lies much farther, as in a sample of small dense
  * clusters, the twelfth's distance scaled to what it is on even samples; with
  * fewer neighbours the spacing is smaller and more triangles look long).
  * Edge-connected regions of such triangles that reach the boundary stay. Run it
  * on a finished (edge-swapped) mesh: in the raw parameter-space triangulation,
  * long triangles near the outline are the map's, until the swaps shorten them.
  * \return the number of regions removed (0: triangles unchanged) */
std::size_t
openMissedHoles (const Points3& points, const CsrGraph& neighbourhoods, Triangles& triangles,
                 double max_span = max_edge_over_spacing);

struct DiscPipelineOptions
{
  /** \brief Default: WeightType::MeanValue. The rim points of holes get mean value
    * weights over their rings closed by the hole's centre whatever the type,
    * unless the map is made without centres (see triangulateDisc). */
  WeightType weights = WeightType::MeanValue;
  SolveOptions solve;
  /** \brief Threads for the graphs (0 = all cores). */
  int num_threads = 0;
  ProgressCallback progress;
};

struct DiscTriangulation : StageStatus
{
  /** \brief Triangles over the point indices, oriented with the loops (normals
    * on the side the oriented point normals point to). */
  Triangles triangles;
  /** \brief The outer boundary loop used for the parameterization. */
  std::vector<pcl::index_t> outer_loop;
  /** \brief Inner boundary loops (holes) kept open. */
  std::size_t holes = 0;
  /** \brief The consistently oriented normals the rings turn around, one per
    * point; the triangles are oriented with them. */
  std::vector<Eigen::Vector3f> normals;
  /** \brief Connected components of the neighbourhood graph (more than one: the
    * run failed before any boundary was looked for; 0 if it stopped earlier). */
  std::size_t graph_pieces = 0;
};

/** \brief Floater-Reimers for an open surface with one outer boundary: graph,
  * oriented rings, weights, the outer loop on the unit circle, one sparse solve,
  * exact Delaunay of the parameter points, triangles back to 3D. Inner boundary
  * loops (holes, depth-camera shadows) stay open: the triangles whose parameter
  * centroid lies inside a hole's loop are removed. In the map each hole gets one
  * more point at its rim's centroid, on which the rim points' rings close (else
  * they are open towards the hole); where the holes cannot be cut out cleanly
  * so (a bent hole's centroid can lie off it), the map is made without them.
  * \param[in] neighbourhoods directed neighbourhoods N(v)
  * \return fails if no boundary loop is found (a closed surface: use the
  *         spherical pipeline) or a stage fails
  */
DiscTriangulation
triangulateDisc (const Points3& points,
                 const CsrGraph& neighbourhoods,
                 const DiscPipelineOptions& options = {});

} // namespace meshless
} // namespace pcl
