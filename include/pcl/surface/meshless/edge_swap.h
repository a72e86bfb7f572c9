/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief What the edge swaps minimise (Dyn, Hormann, Kim and Levin 2001).
  *
  * The discrete curvatures of a vertex v, with A the area of its triangles,
  * alpha_j their angles at v and beta_j the angle between the normals of the two
  * triangles at the j-th edge e_j of v:
  * K = 3 (2 pi - sum alpha_j) / A (pi instead of 2 pi on the boundary),
  * |H| = (3/4) sum |e_j| beta_j / A (interior edges only), and
  * |k1| + |k2| = 2 |H| if K >= 0, else 2 sqrt (H^2 - K).
  * The per-vertex costs are summed over the vertices, ABN over the interior edges. */
enum class SwapCost
{
  /** Sum over the interior edges of the angle between the normals of their two
    * triangles (Dyn, Levin and Rippa's data-dependent triangulations). */
  AngleBetweenNormals,
  /** Sum over the vertices of |H| A. */
  IntegratedMeanCurvature,
  /** Sum over the vertices of H^2 A. */
  SquaredMeanCurvature,
  /** Sum over the vertices of (|k1| + |k2|) A. */
  TotalAbsoluteCurvature
};

/** \brief The rules of the edge swaps that a user chooses (the class's
  * setOptimizationOptions). */
struct SwapRules
{
  /** \brief Default: IntegratedMeanCurvature. With TotalAbsoluteCurvature it leaves
    * the fewest self-intersecting pairs and the best angles; of the two it has the
    * lower normal deviation, and being a sum over edges, (3/2) |e| beta_e, it is
    * priced as fast as ABN and in parallel, where the other vertex costs need whole
    * fans per candidate swap. ABN keeps the most slivers. */
  SwapCost cost = SwapCost::IntegratedMeanCurvature;
  /** \brief Default: 90. Fold bound, in degrees. Swapping edge a-b of the triangles
    * (a, b, c), (b, a, d) gives (a, d, c), (d, b, c); the swap is rejected when the
    * normals of the two new triangles turn against each other by more than the bound,
    * or when a new normal turns by more than the bound against both old normals. Where
    * the old pair already turns by more (a fold), its turn is the bound instead: a
    * swap may open a fold or leave it, never deepen it. */
  double max_fold_angle_deg = 90.0;
  /** \brief Default: true. Counts the self-intersecting triangle pairs exactly (the
    * semantics of checkMesh) with a hashed grid that follows the swaps (candidates
    * first separated by certified floating-point plane tests, the exact test only
    * where those cannot decide; the first count in parallel), and
    * - never accepts a cost-lowering swap whose two new triangles take part in more
    *   intersecting pairs than the two old ones did;
    * - then targets the remaining pairs: for each triangle in a pair it tries its three
    *   edges and makes the admissible swap (fold bound, no duplicate edge, no
    *   degenerate triangle) that lowers the number of pairs the quad takes part in
    *   most, if any does (the cost may rise; the total count strictly drops, so no swap
    *   trades one intersection for more), revisiting the new triangles while they
    *   still intersect something;
    * - then resumes the cost descent under the first rule. */
  bool remove_self_intersections = true;
  /** \brief Default: 0, meaning unlimited (the descent ends anyway: every swap lowers
    * the cost by more than rounding, and there are finitely many triangulations).
    * Limits all swaps of all passes (the look-ahead's tried and undone ones among
    * them). */
  std::size_t max_swaps = 0;
  /** \brief Default: 10. The descent only swaps edges whose two triangles turn by at
    * least this angle (degrees), or that belong to a triangle of an intersecting pair
    * (any swap that lowers the cost there may take part in removing it); flatter edges
    * are left to the angle pass. On nearly flat parts the curvature cost is tiny and
    * rewards slivers along the least curved direction, which the angle pass would
    * then flip back: the bound saves most of both passes' swaps at the same quality. */
  double descent_min_dihedral_deg = 10.0;
  /** \brief Default: 25. Noisy input: when the median angle between the normals of
    * adjacent triangles of the input exceeds this (degrees), the points scatter about
    * the surface by about their spacing, and lowering the curvature pulls the surface
    * off them. The descent then only makes swaps that bring the new edge's midpoint no
    * farther from the local average of the points (each vertex's mean with its
    * neighbours, measured along the quad's normal) than the old edge's midpoint.
    * Clean clouds stay well below the default. 180 turns the rule off. */
  double noisy_median_dihedral_deg = 25.0;
  /** \brief Default: true. A last pass that makes the mesh locally Delaunay: an edge
    * whose two opposite angles sum to more than pi (decided on the sine and cosine of
    * the sum) is swapped when its quad turns by less than
    * `angle_pass_max_dihedral_deg`, the swap is admissible as above, and it adds no
    * intersecting pair. It runs last because the curvature descent prefers slivers
    * along the directions of least curvature on smooth, curved parts and would undo
    * it; it removes most triangles with an angle below 10 degrees, and the slivers'
    * chords, which lie off the surface. */
  bool improve_angles = true;
  /** \brief Default: true. The descent makes no swap whose new edge is longer than
    * every edge of its quad (the four sides and the old diagonal). A surface departs
    * from a chord by about the square of its length times the curvature, and the
    * curvature cost, summed over edges, sometimes prefers one long edge across a
    * region the points do not support (a web between two parts); the rule keeps the
    * largest distance to the surface down and the angles up. Applies to the cost
    * descent only. */
  bool descent_keeps_longest_edge = true;
  /** \brief Default: 4 (0 or 1: off). After the descent, sequences of up to this
    * many swaps, each on an outer edge of the two triangles the one before made,
    * that lower the cost together although their first swap alone does not. The
    * greedy descent stops where a few swaps must change together: a crease crossed
    * by fans of triangles instead of followed by an edge, whose chords lie off the
    * surface. In rounds, each followed by the descent: the first starts from every
    * edge turning by descent_min_dihedral_deg or more, later ones from those among
    * them at the triangles the last round and the descent rewrote, until a round
    * keeps none. A first swap that lowers the cost alone is no start (the descent
    * would have made it but for one of its rules); each step must be admissible;
    * with remove_self_intersections, a sequence is kept only if it leaves no more
    * intersecting pairs than before.
    * The steps are not held to descent_keeps_longest_edge (an edge along a crease is
    * often longer than the quads it crosses). Per-edge costs only; not on noisy
    * input (noisy_median_dihedral_deg), where the descent itself is held back. */
  std::size_t look_ahead_depth = 4;
  /** \brief Default: 8 (0 or 1: off). After the rounds of look_ahead_depth, rounds
    * of the same kind with sequences up to this many swaps, starting only from
    * edges that turn by 45 degrees or more: a fan across a sharp crease changes over
    * more swaps than the first depth reaches, and that depth from every edge would
    * cost several times more. Independent of look_ahead_depth (set both to 0 to
    * turn the look-ahead off); per-edge costs only, not on noisy input. */
  std::size_t crease_look_ahead_depth = 8;
  /** \brief Default: 60. Quads turning more than this (degrees) are left alone by
    * the angle pass, but for angle_pass_unfolds_steep_quads. A low bound leaves the
    * descent's slivers on curved parts, whose chords lie off the surface; much above
    * 60 the pass pulls a noisy sample's mesh off its points and flattens the folds by
    * which a closed mesh through an open surface shows that it turns back. */
  double angle_pass_max_dihedral_deg = 60.0;
  /** \brief Default: true. On input that is not noisy (noisy_median_dihedral_deg),
    * the angle pass also swaps a steeper quad's edge where the two new triangles
    * turn less against each other than the old ones did: triangles folded across a
    * part, off the surface, open out. The quad's own turn only drops (the fold
    * bound still limits how far the new triangles tilt); its four sides are not
    * looked at. */
  bool angle_pass_unfolds_steep_quads = true;
};

/** \brief The swaps' rules and what the caller knows of its mesh and machine. */
struct EdgeSwapOptions : SwapRules
{
  /** \brief Default: false. True where the caller knows that the input has no
    * intersecting pair (checkMesh listed every pair and a repair removed them all):
    * the first count, a full check of the mesh, is skipped and taken as 0. A wrong
    * true cannot break the mesh's structure, but pairs the optimizer would have
    * counted are then neither avoided nor removed: the caller's own check must still
    * look at the result. */
  bool input_free_of_intersections = false;
  /** \brief Default: true. Renumbers the vertices in the order the triangles first
    * use them, on a copy of the points, so that neighbours sit close in memory
    * (every step reads the points of a neighbourhood); this pays on points in random
    * order. False where the points are in a spatially coherent order already (the
    * class numbers them along a Z-order curve): the copies of the points and the
    * triangles are skipped, and the swaps work on the caller's triangles. A mesh that
    * leaves vertices unused is renumbered all the same. The result depends on the
    * numbering only in which of equally good swaps comes first. */
  bool renumber_vertices = true;
  /** \brief Default: 0, meaning all cores. Threads for the parts that run in
    * parallel (pricing every edge, the first intersection count); the result is the
    * same for every thread count. */
  int num_threads = 0;
  /** \brief Default: none. Optional, one entry per triangle: each slot a swap
    * writes is set to 1 (the others are left as they are), as
    * FoldRepairOptions::rewritten. Ignored if its size differs. */
  std::vector<char>* rewritten = nullptr;
};

struct EdgeSwapResult : StageStatus
{
  /** \brief Swaps performed (all passes). */
  std::size_t swaps = 0;
  /** \brief Of those, made by the cost descent, by the look-ahead's sequences
    * (SwapRules::look_ahead_depth and crease_look_ahead_depth; their swaps made
    * again under the intersection
    * bookkeeping and those undone because they added pairs counted too), by the
    * targeted removal of intersections and by the angle pass. */
  std::size_t descent_swaps = 0, look_ahead_swaps = 0, intersection_swaps = 0, angle_swaps = 0;
  /** \brief Total cost (options.cost) of the input and of the output. */
  double cost_before = 0.0, cost_after = 0.0;
  /** \brief Self-intersecting triangle pairs (as checkMesh counts them) of the input
    * and of the output; counted only with remove_self_intersections, zero otherwise. */
  std::size_t self_intersections_before = 0, self_intersections_after = 0;
  /** \brief Median angle (degrees) between the normals of adjacent triangles of the
    * input, and whether it made the input count as noisy
    * (EdgeSwapOptions::noisy_median_dihedral_deg). */
  double median_dihedral_deg = 0.0;
  bool noisy = false;
};

/** \brief Improves a triangle mesh by edge swaps only: greedy descent of a discrete
  * curvature cost with a heap of interior edges keyed by the cost change of swapping
  * (lazily invalidated), optionally removing self-intersections.
  *
  * The input must be a manifold, consistently oriented mesh (closed or with boundary)
  * whose indices are in range and pairwise distinct within each triangle; otherwise
  * the stage fails and leaves the triangles untouched (as it does when memory runs
  * out, except with renumber_vertices = false: then the triangles hold the valid
  * triangulation of the swaps made so far). A swap never touches a boundary
  * edge, never creates an edge that already exists, a degenerate triangle (twice its
  * area below 1e-8 times its longest edge squared) or a fold (see max_fold_angle_deg);
  * so the vertex set, the number of triangles, orientation, manifoldness, the Euler
  * characteristic and the boundary are kept. Deterministic.
  *
  * The passes: the descent (edges that turn by at least descent_min_dihedral_deg),
  * then rounds of the look-ahead each followed by the descent (first from every
  * edge the descent looks at, then deeper from sharp creases), then rounds of
  * targeted intersection removal each followed by the descent, then the angle
  * pass. Angles are computed with a polynomial arctangent (within 4e-8
  * radians), costs before a swap are cached per edge. Memory: about 180 bytes per
  * triangle without renumbering.
  * \param[in] points the vertex positions
  * \param[in,out] triangles the mesh, counter-clockwise seen from outside
  * \param[in] options cost and passes
  */
EdgeSwapResult
optimizeBySwaps (const Points3& points,
                 Triangles& triangles,
                 const EdgeSwapOptions& options = {});

} // namespace meshless
} // namespace pcl
