/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/base_mesh.h>
#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

/** \brief One shortest path in G per edge of the base mesh D (§3). */
struct CutPaths : StageStatus
{
  /** \brief The edges of D (baseMeshEdges), positions into BaseMesh::vertices. */
  std::vector<std::array<int, 2>> edges;
  /** \brief Per edge: the cloud points of its path, from the edge's first vertex to
    * its second, end points included. */
  std::vector<std::vector<pcl::index_t>> paths;
};

/** \brief Shortest paths (Euclidean edge lengths, Dijkstra) for the edges of D,
  * shortest edges first. A path may not use another path's points nor any other
  * vertex of D, so that paths are simple and meet only at D's vertices. Then, at
  * every vertex c of D, the first steps of its paths must appear in c's oriented
  * ring in the cyclic order that D's faces prescribe around c; otherwise the
  * patches would overlap, and the stage fails (the caller retries with another D).
  * \param[in] graph the graph to route in (the mutual ring graph, whose edges are
  *            ring edges, so that every first step is in the ring)
  * \param[in] rings rings counter-clockwise around outward-oriented normals
  */
CutPaths
computeCutPaths (const Points3& points,
                 const CsrGraph& graph,
                 const CsrGraph& rings,
                 const BaseMesh& base);

} // namespace meshless
} // namespace pcl
