/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/base_mesh.h>
#include <pcl/surface/meshless/cut_paths.h>
#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

/** \brief The points V^i of one face of D: its boundary loop and all its points. */
struct Patch
{
  /** \brief The face's three (or more) paths in sequence, counter-clockwise seen
    * from outside, each corner once. */
  std::vector<pcl::index_t> loop;
  /** \brief Every point of the patch: the loop's points first, then the interior. */
  std::vector<pcl::index_t> points;
};

struct PatchSplit : StageStatus
{
  /** \brief One patch per face of D, in the order of BaseMesh::faces. */
  std::vector<Patch> patches;
  /** \brief Per point: the face whose interior it belongs to, or -1 on a path. */
  std::vector<int> face_of;
  /** \brief Points next to a path claimed by both its sides (a sign of paths
    * running close to each other; CutPaths::num_side_conflicts). */
  std::size_t num_side_conflicts = 0;
  /** \brief Interior points moved to a neighbouring face because their own face's
    * region did not connect them to its boundary. */
  std::size_t num_reassigned = 0;
};

/** \brief Split the points not on a path among the faces of D (§4).
  *
  * The paper grows the paths by rings until the rest falls apart into one component
  * per face; on a kNN graph, whose edges jump across paths, that count may never
  * settle. Here the cut paths already carry the regions they cut the surface into
  * (CutPaths::face_of, seeded from the oriented rings on both sides of each path
  * and grown inside the region the path split). Points those regions did not reach
  * (parts joined to the rest only by edges of the fallback graph) join the nearest
  * region by a multi-source Dijkstra, first in `graph`, then in `fallback_graph`.
  * A point that cannot reach its face's loop through the neighbours its parameter
  * point depends on (the weights' neighbourhoods, within the face) is moved to a
  * face it can reach, so that every patch's linear system is non-singular.
  * \param[in] graph the graph regions grow in (the mutual ring graph)
  * \param[in] fallback_graph a graph for points the first does not reach (G)
  * \param[in] dependencies each point's weight neighbourhood (Weights::neighbours)
  * \param[in] paths cut paths with their regions (computeCutPaths)
  * \return fails if some point cannot be reached from any path (disconnected cloud)
  */
PatchSplit
splitIntoPatches (const Points3& points,
                  const CsrGraph& graph,
                  const CsrGraph& fallback_graph,
                  const CsrGraph& dependencies,
                  const BaseMesh& base,
                  const CutPaths& paths);

/** \brief The rows of `candidates` (the graph G) that the patches' systems can
  * read, the others empty: a point's candidates are needed only where its weight
  * neighbourhood reaches outside its patch (see PatchRingContext), next to a cut.
  * Rows are kept for every interior point with a weight neighbour that is not an
  * interior point of the same patch (a superset of those). All of G then need not
  * live through the patch solves, which set the peak memory of large clouds.
  * \param[in] candidates n rows
  * \param[in] dependencies each point's weight neighbourhood (Weights::neighbours)
  * \param[in] split the patches (splitIntoPatches) */
CsrGraph
candidatesNearCuts (const CsrGraph& candidates,
                    const CsrGraph& dependencies,
                    const PatchSplit& split);

} // namespace meshless
} // namespace pcl
