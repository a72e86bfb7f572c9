/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

/** \brief Result of orienting the unoriented least-squares normals. */
struct NormalOrientation : StageStatus
{
  /** \brief Normals flipped to agree with their neighbours. */
  std::size_t num_flipped = 0;
  /** \brief Graph components oriented (each from its own outermost point). */
  std::size_t num_components = 0;
};

/** \brief Give neighbouring normals the same sign (after Hoppe et al. 1992):
  * propagate the orientation along a maximum spanning tree, starting in each
  * component from the point v maximising |n_v . (v - c)|, c the component's
  * centroid, whose normal is made to point away from c (outward on a closed
  * surface).
  *
  * The tree runs over the mutual ring graph, whose edges lie in the local tangent
  * planes, and an edge's weight |n_v . n_w| is lowered by how much the edge runs
  * along either normal: a kNN edge across a thin part joins two sides of the
  * surface whose outward normals are opposite, and |n_v . n_w| alone would rate it
  * best. Points the mutual graph does not reach are oriented afterwards through
  * `graph`.
  *
  * One edge of the tree decides everything beyond it, and on a limb a few points
  * around even a confident edge may cross the limb, turning a leg inwards. So the
  * tree's signs are then revised
  * by regions: points joined by confident mutual edges (confidence above 0.3)
  * whose signs agree form a region; between two regions all graph edges vote for
  * the same or the opposite sign, each weighted by its confidence (at least 0.05);
  * a spanning tree over the regions, strongest sums first and from each
  * component's largest region, settles each region's sign.
  *
  * The seed alone may sit in a thin part whose propagation goes astray (a seed on
  * a hoof can turn the whole body inwards), so each component's sign is finally
  * settled by a vote: outward normals satisfy sum n_v . (v - c) A_v =
  * 3 volume > 0 (divergence theorem), A_v estimated by the squared distance to the
  * nearest neighbour. Each ring whose normal is flipped is reversed, so that rings
  * stay counter-clockwise around their (now consistent) normals.
  * \param[in] points n points
  * \param[in] graph the symmetric neighbourhood graph G
  * \param[in] mutual the mutual ring graph (mutualRingGraph of the rings)
  * \param[in,out] ordered rings and normals from orderNeighbourhoods
  */
NormalOrientation
orientNormals (const Points3& points,
               const CsrGraph& graph,
               const CsrGraph& mutual,
               OrderedNeighbourhoods& ordered);

/** \brief The graph of edges both end points agree on: [v,w] with w in ring(v) and
  * v in ring(w). Close to a planar local triangulation, so that paths in it cut
  * the surface (a kNN graph's edges jump across paths). Rows sorted ascending. */
CsrGraph
mutualRingGraph (const CsrGraph& rings);

} // namespace meshless
} // namespace pcl
