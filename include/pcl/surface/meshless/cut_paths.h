/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/base_mesh.h>
#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

/** \brief One shortest path in G per edge of the base mesh D (§3), and the regions
  * they cut the surface into. */
struct CutPaths : StageStatus
{
  /** \brief The edges of D (baseMeshEdges), positions into BaseMesh::vertices. */
  std::vector<std::array<int, 2>> edges;
  /** \brief Per edge: the cloud points of its path, from the edge's first vertex to
    * its second, end points included. */
  std::vector<std::vector<pcl::index_t>> paths;
  /** \brief Per point: the face of D whose region holds it, or -1 on a path or where
    * the graph did not reach (a part joined to the rest only by other edges). */
  std::vector<int> face_of;
  /** \brief Points next to a path that its two sides both claimed (a sign of paths
    * running close to each other); distance decided them. */
  std::size_t num_side_conflicts = 0;
};

/** \brief Shortest paths (Euclidean edge lengths, Dijkstra) for the edges of D that
  * meet only at D's vertices and cut the surface into one region per face of D.
  *
  * The edges are routed in turn: first a spanning tree of D (shortest edges first),
  * then the others by length. The paths routed so far cut the surface into regions,
  * one per face of the part of D routed so far; every point carries its region.
  * A path may only run through the region its edge lies in (never through another
  * path's points or another vertex of D), and at each of its corners c it must
  * leave c between the paths that D puts before and after it around c, read in c's
  * oriented ring. When a path closes a loop, it splits its region in two: the ring
  * members left and right of the path seed the two new regions, which grow by a
  * multi-source Dijkstra inside the old one. Such paths cannot cross and a corner
  * cannot be shut out of the region it must be reached in; the stage fails (and the
  * caller retries with another D) only when a region is too thin to hold its path.
  * \param[in] graph the graph to route in (the mutual ring graph, whose edges are
  *            ring edges, so that every step has a side in the rings)
  * \param[in] rings rings counter-clockwise around outward-oriented normals
  */
CutPaths
computeCutPaths (const Points3& points,
                 const CsrGraph& graph,
                 const CsrGraph& rings,
                 const BaseMesh& base);

} // namespace meshless
} // namespace pcl
