/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

/** \brief Convex-combination weights lambda_vw of the meshless parameterization. */
enum class WeightType
{
  /** lambda = 1/d on an unordered neighbourhood (Floater-Reimers' simplest). */
  Uniform,
  /** lambda ~ 1/|v - w| (Floater-Reimers: best with 10-20 neighbours). */
  ReciprocalDistance,
  /** Floater's shape-preserving weights on the Delaunay ring (1997). */
  ShapePreserving,
  /** Floater's mean value coordinates on the Delaunay ring (2003). */
  MeanValue
};

struct WeightOptions
{
  /** \brief Default: WeightType::MeanValue (linear precision, cheap, positive on
    * every ring whose angles are all below pi). */
  WeightType type = WeightType::MeanValue;
  /** \brief How rings were brought into their plane; must match the ordering. */
  LocalPlane plane = LocalPlane::ProjectOntoFit;
  /** \brief Threads computing the weights (0 = all cores). The weights do not
    * depend on it. Default 0. */
  int num_threads = 0;
};

/** \brief Weights per point, laid out like the neighbourhood they were computed on:
  * weight `values[k]` belongs to neighbour `neighbours.adjacency[k]`. */
struct Weights : StageStatus
{
  CsrGraph neighbours;
  std::vector<double> values;
  /** \brief Points whose ring does not surround them (an angle of at least pi
    * between consecutive neighbours, or fewer than two ring members) so that
    * shape-preserving or mean value weights do not exist; they got
    * reciprocal-distance weights over their unordered neighbourhood instead. */
  std::size_t num_fallbacks = 0;
};

/** \brief Mean value coordinates of the origin with respect to a ring.
  * \param[in] ring d >= 2 points counter-clockwise around the origin
  * \param[out] lambda d weights, positive and summing to 1
  * \return false (lambda untouched) if some angle between consecutive ring points
  *         is pi or more, or a ring point sits at the origin
  */
bool
meanValueWeights (const Points2& ring, std::vector<double>& lambda);

/** \brief Floater's shape-preserving weights of the origin with respect to a ring.
  * \param[in] ring d >= 3 points counter-clockwise around the origin
  * \param[out] lambda d weights, non-negative and summing to 1
  * \return false (lambda untouched) if the origin is not strictly inside the ring's
  *         star (some angle between consecutive ring points is pi or more)
  */
bool
shapePreservingWeights (const Points2& ring, std::vector<double>& lambda);

/** \brief Reciprocal-distance weights of v with respect to its neighbours. */
void
reciprocalDistanceWeights (const Points3& points,
                           pcl::index_t v,
                           const pcl::index_t* begin,
                           const pcl::index_t* end,
                           std::vector<double>& lambda);

/** \brief Weights for every point.
  * \param[in] points n points
  * \param[in] rings the Delaunay rings of orderNeighbourhoods (ShapePreserving and
  *            MeanValue use them)
  * \param[in] graph unordered neighbourhoods, usually G (Uniform and
  *            ReciprocalDistance use them, and every point whose ring does not
  *            surround it falls back to reciprocal-distance weights over them)
  * \param[in] normals the plane normal each ring was ordered around
  *            (OrderedNeighbourhoods::normals)
  */
Weights
computeWeights (const Points3& points,
                const CsrGraph& rings,
                const CsrGraph& graph,
                const std::vector<Eigen::Vector3f>& normals,
                const WeightOptions& options = {});

} // namespace meshless
} // namespace pcl
