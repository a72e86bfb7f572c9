/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/types.h>
#include <pcl/surface/meshless/weights.h>

#include <functional>

namespace pcl {
namespace meshless {

/** \brief What every pipeline builds from the neighbourhoods before it cuts: the
  * graph G, rings oriented counter-clockwise around consistent outward normals,
  * the mutual ring graph and the weights (paper §2). */
struct SurfaceGraphs : StageStatus
{
  /** \brief The symmetric connectivity graph G. */
  CsrGraph graph;
  /** \brief Rings and normals, oriented (orientNormals). */
  OrderedNeighbourhoods ordered;
  /** \brief Edges both end points' rings agree on (mutualRingGraph). */
  CsrGraph mutual;
  std::size_t normals_flipped = 0;
  Weights weights;
};

/** \brief Called after "graph", "rings" and "weights" with a short detail line;
  * return false to cancel. */
using SurfaceStageDone = std::function<bool (const std::string& stage, const std::string& detail)>;

/** \brief Symmetric graph, Delaunay rings, orientation, mutual graph, weights.
  * \param[in] neighbourhoods directed neighbourhoods N(v) of the points
  * \return fails if the graph is disconnected (several objects, outliers, too few
  *         neighbours), a stage fails, or `done` cancels (message "cancelled by
  *         the progress callback")
  */
SurfaceGraphs
buildSurfaceGraphs (const Points3& points,
                    const CsrGraph& neighbourhoods,
                    WeightType weights,
                    const SurfaceStageDone& done = {});

} // namespace meshless
} // namespace pcl
