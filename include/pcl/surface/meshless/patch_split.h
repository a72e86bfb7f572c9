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
  /** \brief Points next to a path claimed by two faces' sides (a sign of paths
    * running close to each other); each went to the first. */
  std::size_t num_side_conflicts = 0;
  /** \brief Interior points moved to a neighbouring face because their own face's
    * region did not connect them to its boundary. */
  std::size_t num_reassigned = 0;
};

/** \brief Split the points not on a path among the faces of D (§4).
  *
  * The paper grows the paths by rings until the rest falls apart into one component
  * per face; on a kNN graph, whose edges jump across paths, that count may never
  * settle. Here each face is seeded directly instead: at every inner point of a
  * path, the oriented ring says which neighbours lie left of the path (inside the
  * face the path bounds counter-clockwise) and which lie right. From all seeds at
  * once a multi-source Dijkstra assigns every other point to its nearest face (the
  * paper's second step). A point that cannot reach its face's loop through the
  * neighbours its parameter point depends on (the weights' neighbourhoods, within
  * the face) is moved to a face it can reach, so that every patch's linear system
  * is non-singular.
  * \param[in] graph the graph regions grow in (the mutual ring graph)
  * \param[in] fallback_graph a graph for points the first does not reach (G)
  * \param[in] rings rings counter-clockwise around outward-oriented normals
  * \param[in] dependencies each point's weight neighbourhood (Weights::neighbours)
  * \return fails if some point cannot be reached from any path (disconnected cloud)
  */
PatchSplit
splitIntoPatches (const Points3& points,
                  const CsrGraph& graph,
                  const CsrGraph& fallback_graph,
                  const CsrGraph& rings,
                  const CsrGraph& dependencies,
                  const BaseMesh& base,
                  const CutPaths& paths);

} // namespace meshless
} // namespace pcl
