/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/base_mesh.h>
#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

struct GrownBaseMeshOptions
{
  /** \brief Farthest-point seeds to start from; 0 chooses from the number of points
    * (one per thousand, 12 to 64). */
  std::size_t initial_seeds = 0;
  /** \brief Seeds the growth may reach while the conditions fail; 0 chooses from the
    * number of points (a region keeps at least a few dozen points on average). */
  std::size_t max_seeds = 0;
  /** \brief Which point the first seed is: 0 the eligible point farthest from the
    * centroid; any other number picks another eligible point deterministically, for
    * a different D of the same genus. */
  std::uint32_t start = 0;
  /** \brief Rounds of added seeds after which the growth gives up; 0: no limit but
    * max_seeds. */
  std::size_t max_rounds = 0;
  /** \brief Regions of fewer points merge, once D is valid, into a neighbour across
    * one edge where D stays valid (mergeSmallRegions): the growth needs small regions
    * to see the topology, the paths need room. 0 chooses a quarter of the points per
    * initial seed; 1 keeps every region. */
  std::size_t merge_regions_below = 0;
  /** \brief Default: true. Where the regions fail to make a valid D, they grow once
    * more with every length counted in local point spacings: where the density varies,
    * regions of equal extent hold few points in the sparse parts, whose rings then
    * read no clean dual, and many in the dense ones. Lengths in the cloud's units come
    * first: on clouds they suit, their regions leave thin parts more room. */
  bool retry_in_local_spacings = true;
};

/** \brief A base mesh D grown from the cloud, whatever its genus. */
struct GrownBaseMesh : StageStatus
{
  /** \brief D: a vertex per place where three regions meet, a polygonal face per
    * region, counter-clockwise seen from outside. */
  BaseMesh mesh;
  /** \brief The seed of each region, in the order of mesh.faces. */
  std::vector<pcl::index_t> seeds;
  /** \brief Genus of D, hence of the surface the cloud samples (-1 on failure). */
  int genus = -1;
  /** \brief Per point: the region (face of mesh) that holds it, -1 where the graph
    * does not reach. */
  std::vector<int> region_of;
  /** \brief Rounds of adding seeds where a condition failed. */
  std::size_t rounds = 0;
};

/** \brief The base complex of §5 grown from the cloud instead of picked from a list.
  *
  * Farthest-point seeds (geodesic along the graph); regions grown from them by one
  * multi-source Dijkstra; their dual triangulation (a vertex per seed, an edge per two
  * regions that touch, a face per place where three regions meet, read from the
  * triangles of the oriented rings) is a closed surface of the cloud's topology when
  * every region is a disc, two regions share at most one boundary arc and three meet
  * at most once (Eck et al.; the closed-ball property). Where the dual is not a closed
  * manifold, or three regions meet in two places, or two regions touch without a
  * face, each region concerned gets a further seed at its farthest point and the
  * regions grow again. D is then the regions themselves as polygonal faces (§5),
  * cornered where three meet, and the genus follows from its Euler characteristic.
  * Small regions then merge into neighbours (GrownBaseMeshOptions::
  * merge_regions_below): every face stays a disc and D a closed polygon mesh of the
  * same genus, but two merged faces may share more than one edge.
  * \param[in] graph the graph to grow in (the mutual ring graph)
  * \param[in] rings rings counter-clockwise around outward-oriented normals
  * \param[in] eligible optional per-point mask of points that may be seeds (empty:
  *            any point)
  * \return D and its genus, or the reason no valid D was found within the seeds
  *         allowed (the cloud's topology is ambiguous at its sampling: a handle
  *         thinner than the point spacing, heavy noise, several objects).
  */
GrownBaseMesh
growBaseMesh (const Points3& points,
              const CsrGraph& graph,
              const CsrGraph& rings,
              const std::vector<char>& eligible = {},
              const GrownBaseMeshOptions& options = {});

} // namespace meshless
} // namespace pcl
