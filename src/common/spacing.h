/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <algorithm>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief The upper median of `values` (0 if empty). */
inline double
median (std::vector<double> values)
{
  if (values.empty ())
    return 0.0;
  const auto middle = values.begin () + values.size () / 2;
  std::nth_element (values.begin (), middle, values.end ());
  return *middle;
}

/** \brief A point's spacing: its mean distance to its six nearest among the row
  * [begin, end) of a neighbourhood graph (all of them if fewer; 0 if none). Fewer
  * than six see noise pull pairs of points together.
  * \param[out] distances scratch, left holding the row's distances with the six
  *             smallest (all if fewer) first, in some order (sampleSpacing needs it) */
inline double
nearestSpacing (const Points3& points,
                pcl::index_t v,
                const pcl::index_t* begin,
                const pcl::index_t* end,
                std::vector<double>& distances)
{
  distances.clear ();
  for (const pcl::index_t* w = begin; w != end; ++w)
    distances.push_back ((points[*w] - points[v]).norm ());
  if (distances.empty ())
    return 0.0;
  const std::size_t nearest = std::min<std::size_t> (6, distances.size ());
  std::nth_element (distances.begin (), distances.begin () + (nearest - 1), distances.end ());
  double sum = 0.0;
  for (std::size_t j = 0; j < nearest; ++j)
    sum += distances[j];
  return sum / static_cast<double> (nearest);
}

/** \brief The spacing of a sample's gaps around a point: nearestSpacing, except
  * where the twelfth nearest in the row lies more than `cluster_ratio` times
  * farther than that (the six nearest are the point's own small dense cluster, as
  * at a mesh's vertices around long thin triangles): there the twelfth nearest's
  * distance over that ratio on even samples. Rows of six or fewer
  * give nearestSpacing; in rows of seven to eleven the farthest stands in for
  * the twelfth (fewer neighbours than the default k). */
inline double
sampleSpacing (const Points3& points,
               pcl::index_t v,
               const pcl::index_t* begin,
               const pcl::index_t* end,
               std::vector<double>& distances)
{
  // Between the ratio's largest on even, noisy and lattice samples and its usual
  // value on clusters (doc/benchmarks.md).
  constexpr double cluster_ratio = 2.6;
  constexpr double twelfth_over_nearest_on_even_samples = 1.8;
  const double nearest = nearestSpacing (points, v, begin, end, distances);
  if (distances.size () <= 6)
    return nearest;
  const std::size_t twelfth = std::min<std::size_t> (12, distances.size ()) - 1;
  std::nth_element (distances.begin () + 6, distances.begin () + twelfth, distances.end ());
  const double far = distances[twelfth];
  return far > cluster_ratio * nearest ? far / twelfth_over_nearest_on_even_samples : nearest;
}

} // namespace meshless
} // namespace pcl
