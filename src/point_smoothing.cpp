/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/point_smoothing.h>

#include "common/spacing.h"
#include "common/threads.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/mls.h>
// MLSResult::computeMLSSurface for PointXYZ; GCC reads PCL's centroid as possibly
// uninitialized through an SSE load, which it is not.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <pcl/surface/impl/mls.hpp>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <cmath>

namespace pcl {
namespace meshless {

SmoothedPoints
projectOntoFittedSurfaces (const Points3& points, const CsrGraph& neighbours, int num_threads)
{
  const std::size_t n = points.size ();
  SmoothedPoints result;
  result.points = points;
  // PCL's fit reads float points; the pipeline's are centred, so float keeps them.
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.resize (n);
  for (std::size_t i = 0; i < n; ++i)
    cloud[i].getVector3fMap () = points[i].cast<float> ();
  std::vector<double> offsets (n, 0.0), spacings (n, 0.0);
  // A quadratic has six coefficients: with fewer points PCL leaves them unset.
  const std::size_t min_fit = 6;
#pragma omp parallel num_threads(threadCount (num_threads))
  {
    pcl::Indices fit;
    std::vector<double> distances;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t ii = 0; ii < static_cast<std::ptrdiff_t> (n); ++ii) {
      const auto i = static_cast<pcl::index_t> (ii);
      fit.assign (1, i);
      fit.insert (fit.end (), neighbours.begin (i), neighbours.end (i));
      spacings[i] = nearestSpacing (points, i, neighbours.begin (i), neighbours.end (i), distances);
      if (distances.empty ())
        continue;
      if (fit.size () < min_fit)
        continue;
      const double reach = *std::max_element (distances.begin (), distances.end ());
      pcl::MLSResult surface;
      surface.computeMLSSurface (cloud, i, fit, reach, 2);
      if (!surface.valid)
        continue;
      const Eigen::Vector3d moved =
          surface.projectQueryPoint (pcl::MLSResult::SIMPLE, static_cast<int> (min_fit)).point;
      // A fit that throws a point beyond its own neighbours is no surface of theirs.
      if (!moved.allFinite () || !((moved - points[i]).norm () <= reach))
        continue;
      result.points[i] = moved;
      offsets[i] = (moved - points[i]).norm ();
    }
  }
  PointNoise& noise = result.noise;
  noise.max_offset = offsets.empty () ? 0.0 : *std::max_element (offsets.begin (), offsets.end ());
  noise.median_offset = median (offsets);
  noise.median_spacing = median (spacings);
  noise.noise_ratio = noise.median_spacing > 0.0 ? noise.median_offset / noise.median_spacing : 0.0;
  return result;
}

} // namespace meshless
} // namespace pcl
