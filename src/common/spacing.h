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

/** \brief A point's spacing: its mean distance to its six nearest among the row
  * [begin, end) of a neighbourhood graph (all of them if fewer; 0 if none). Fewer
  * than six see noise pull pairs of points together.
  * \param[out] distances scratch, left holding the row's distances in some order */
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

} // namespace meshless
} // namespace pcl
