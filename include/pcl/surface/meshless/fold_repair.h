/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

/** \file
  * Local folds removed by re-meshing small discs.
  *
  * Where a triangulation folds locally (a vertex whose fan overlaps itself or its
  * neighbours' triangles, a pleat of two or three triangles: the pairs left after
  * the edge swaps are typically at most two edges apart), no single edge swap may
  * lower the number of intersecting pairs. The fold is gone once its vertices are
  * taken out and put back: the disc of their triangles is projected onto the plane of its boundary (Newell's normal), the
  * boundary polygon, if simple there, is triangulated by ear clipping, the inner
  * vertices are inserted one by one into the triangles they fall in, and Lawson
  * flips make the disc Delaunay in that plane. The disc keeps its boundary and
  * number of triangles, so the mesh keeps its vertices, edges, faces, orientation
  * and genus; a re-meshing is kept only if it lowers the number of intersecting
  * pairs (counted exactly, as checkMesh counts them). Discs tried around each
  * vertex of an intersecting triangle: its star, then with one ring, then two.
  * A disc with no simple projection (too curved, or folded over a part thinner
  * than the point spacing) is re-meshed in a map instead when the cloud's
  * neighbourhoods and oriented normals are given: its loop on a circle, each inner
  * vertex at the mean of its neighbours on its own side. A disc's rings can
  * reach a vertex from two sides (around a thin spike or ear rim) or surround a
  * few triangles they do not cover: the region then takes in that vertex or hole
  * until its boundary is one simple loop (otherwise such folds stay). Folds whose
  * discs mix the two sides of a thin part along their boundary are left to the
  * swaps, in longer runs where only a few pairs are left.
  */
namespace pcl {
namespace meshless {

/** \brief Options of repairFoldsByReinsertion(). */
struct FoldRepairOptions
{
  /** \brief Rounds over the vertices of intersecting triangles (a round looks
    * again only where the last one re-meshed). Default 4. */
  int max_rounds = 4;
  /** \brief After the discs, swap edges through the vertices of triangles that
    * still intersect, up to max_swaps_in_a_row in a row (max_swaps_in_a_row_when_few
    * where few pairs are left), where that lowers the number of intersecting pairs.
    * Default true. */
  bool swaps = true;
  /** \brief Swaps tried in a row before giving up on an edge; each more removes a
    * few more pairs at many times the cost. Default 2. */
  int max_swaps_in_a_row = 2;
  /** \brief Where at most max_pairs_for_longer_runs pairs are left after the
    * passes, swaps up to this many in a row around them, one more at a time: a pleat
    * on the rim of a part thinner than the point spacing, whose discs mix its two
    * sides, may open only then. Each swap more in a row multiplies the cost, which
    * is affordable around a few folds only. Default 4; at most max_swaps_in_a_row
    * turns it off. */
  int max_swaps_in_a_row_when_few = 4;
  /** \brief See max_swaps_in_a_row_when_few. Default 8. */
  std::size_t max_pairs_for_longer_runs = 8;
  /** \brief The runs longer than max_swaps_in_a_row (all their lengths
    * together) stop after trying this many swaps: a run branches at every step,
    * and around folds that no run opens the search would otherwise go on long.
    * In a run, the second swap is tried on every edge through the first's four
    * vertices, each later one on the outer edges of the two triangles the one
    * before made. 0 turns the longer runs off; the runs up to max_swaps_in_a_row
    * are not limited. Default 20000. */
  std::size_t max_swaps_tried_in_longer_runs = 20000;
  /** \brief Nothing is tried where the pairs number more than this many times
    * the triangles: a tangle rather than local folds, where no disc or swap around
    * one fold lowers the count and every test meets many triangles. The measure is
    * over the whole mesh. Default 0.5 (the densities the repair serves are in
    * doc/benchmarks.md). */
  double max_pairs_per_triangle = 0.5;
  /** \brief Passes of discs then swaps (a pass after the first starts from the
    * triangles still intersecting); they stop at the first pass that lowers nothing.
    * Default 4: more passes rarely lower anything further. */
  int max_passes = 4;
  /** \brief Larger discs are not tried. Default 300 triangles. */
  std::size_t max_region_triangles = 300;
  /** \brief Optional: the cloud's neighbourhoods (e.g. the kNN graph) and oriented
    * normals, one per vertex. With both, a disc that has no simple projection (a
    * fold over a part thinner than the point spacing) is re-meshed in a map built
    * from each inner vertex's neighbours on its own side (normals agreeing). */
  const CsrGraph* neighbours = nullptr;
  const std::vector<Eigen::Vector3f>* normals = nullptr;
  /** \brief Default: none. Optional, one entry per triangle: each slot the repair
    * writes is set to 1 (the others are left as they are), so that a later check
    * knows which triangles are still those an earlier one saw
    * (MeshCheckOptions::known_apart). Ignored if its size differs. */
  std::vector<char>* rewritten = nullptr;
  /** \brief Threads for setting up the repair's grid (0 = all cores). The result
    * does not depend on it. Default 0. */
  int num_threads = 0;
};

/** \brief What repairFoldsByReinsertion() did. */
struct FoldRepairResult : StageStatus
{
  /** \brief Intersecting pairs before and after (exact counts). */
  std::size_t pairs_before = 0, pairs_after = 0;
  /** \brief Discs re-meshed. */
  std::size_t regions_remeshed = 0;
  /** \brief Runs of edge swaps (one to max_swaps_in_a_row_when_few long) that
    * lowered the pair count. */
  std::size_t swaps = 0;
  /** \brief Swaps tried in the runs longer than max_swaps_in_a_row, and whether
    * FoldRepairOptions::max_swaps_tried_in_longer_runs stopped them. */
  std::size_t longer_run_swaps_tried = 0;
  bool longer_runs_cut_short = false;
  /** \brief Nothing was tried: more pairs than
    * FoldRepairOptions::max_pairs_per_triangle per triangle. */
  bool tangle = false;
};

/** \brief The region repairFoldsByReinsertion re-meshes around the vertices
  * `inner`: the triangles through them, grown until the region's boundary is one
  * simple loop (a disc on a genus-0 mesh; tryRemesh checks the Euler count). Where
  * its boundary passes a vertex twice (the stars of `inner` reach it from two
  * sides, as around a thin spike or an ear's rim) that vertex joins `inner`; where
  * the boundary has several loops, the vertices of every loop but the longest do
  * (the region surrounded triangles it did not cover; `inner` is meant to be
  * connected, as a vertex with its rings is). Repeated until the boundary is one
  * simple loop, at most 16 times.
  * \param[in] triangles a manifold mesh (closed or with boundary)
  * \param[in] star the slots (positions in `triangles`) of the triangles through a
  *            vertex
  * \param[in,out] inner the vertices whose triangles form the region; on return
  *                also the vertices taken in
  * \param[in] max_triangles the largest region accepted
  * \return the region's slots, sorted; empty if it grew beyond max_triangles, has
  *         fewer than 4 triangles, covers the whole mesh, or did not close up (a
  *         boundary that is no set of loops, or nothing left to take in)
  */
std::vector<std::int32_t>
closedDiscRegion (const Triangles& triangles,
                  const std::function<std::vector<std::int32_t> (pcl::index_t)>& star,
                  std::vector<pcl::index_t>& inner,
                  std::size_t max_triangles);

/** \brief Re-mesh small discs around the vertices of intersecting triangles
  * while that lowers the number of intersecting pairs.
  * \param[in] points the vertices
  * \param[in,out] triangles a closed, manifold, consistently oriented mesh
  *   (counter-clockwise seen from outside), or a disc; changed only by
  *   re-meshings, each in the slots of the triangles it replaces
  * \param[in] pairs every intersecting pair of the mesh (checkMesh's
  *   intersecting_pairs, listed in full)
  * \param[in] options see FoldRepairOptions
  * \return fails (leaving the triangles untouched) if the mesh is not closed and
  *   manifold where a re-meshing would act, or an option is invalid; succeeds
  *   with the triangles untouched and `tangle` set where the pairs exceed
  *   FoldRepairOptions::max_pairs_per_triangle
  */
FoldRepairResult
repairFoldsByReinsertion (const Points3& points,
                          Triangles& triangles,
                          const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                          const FoldRepairOptions& options = {});

} // namespace meshless
} // namespace pcl
