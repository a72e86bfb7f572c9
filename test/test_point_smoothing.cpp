/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/point_smoothing.h>
#include <meshless_tools/synthetic_clouds.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using meshless_test::bruteForceKnn;
using pcl::meshless::Points3;

Points3
sphereSample (std::size_t n, double noise, std::uint32_t seed)
{
  pcl::meshless::SyntheticCloudOptions options{n, seed, noise};
  Points3 points;
  for (const auto& p : pcl::meshless::sampleShape (pcl::meshless::SyntheticShape::Sphere, options))
    points.push_back (p.cast<double> ());
  return points;
}

double
meanDistanceToUnitSphere (const Points3& points)
{
  double sum = 0.0;
  for (const auto& p : points)
    sum += std::abs (p.norm () - 1.0);
  return sum / static_cast<double> (points.size ());
}

} // namespace

TEST (PointSmoothing, QuadraticSurfacesKeepTheirPoints)
{
  // Points on a tilted plane are their own projections; on a paraboloid (a quadratic
  // over the plane fitted to each neighbourhood, not exactly over its own axes) they
  // move by a hundredth of the spacing at most. Neither measures noise.
  std::mt19937 random (5);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  Points3 paraboloid, plane;
  for (int i = 0; i < 2000; ++i) {
    const double x = u (random), y = u (random);
    paraboloid.emplace_back (x, y, 0.3 * x * x - 0.2 * x * y + 0.1 * y * y);
    plane.emplace_back (x, y, 0.5 * x - 0.25 * y + 2.0);
  }
  for (const Points3* points : {&paraboloid, &plane}) {
    const auto smoothed = pcl::meshless::projectOntoFittedSurfaces (
        *points, bruteForceKnn (*points, 48));
    ASSERT_EQ (smoothed.points.size (), points->size ());
    const double bound = points == &plane ? 1e-5 : 0.01 * smoothed.noise.median_spacing;
    for (std::size_t i = 0; i < points->size (); ++i)
      ASSERT_LT ((smoothed.points[i] - (*points)[i]).norm (), bound) << "point " << i;
    EXPECT_LT (smoothed.noise.noise_ratio, 1e-3);
    EXPECT_GT (smoothed.noise.median_spacing, 0.0);
  }
}

TEST (PointSmoothing, NoiseAtTheSpacingIsMeasuredAndHalved)
{
  // A clean sphere measures far below the bound that calls a cloud noisy; Gaussian
  // noise of 0.7 spacings far above it, and its projections lie at most half as far
  // from the sphere as the points, every one of them finite.
  for (const std::uint32_t seed : {1u, 2u}) {
    const Points3 clean = sphereSample (5000, 0.0, seed);
    const auto clean_fit =
        pcl::meshless::projectOntoFittedSurfaces (clean, bruteForceKnn (clean, 48));
    EXPECT_LT (clean_fit.noise.noise_ratio, 0.05);

    const Points3 noisy = sphereSample (5000, 0.014, seed);
    const auto fit = pcl::meshless::projectOntoFittedSurfaces (noisy, bruteForceKnn (noisy, 48));
    EXPECT_GT (fit.noise.noise_ratio, pcl::meshless::min_noise_ratio);
    EXPECT_GT (fit.noise.max_offset, fit.noise.median_offset);
    for (const auto& p : fit.points)
      ASSERT_TRUE (p.allFinite ());
    EXPECT_LT (meanDistanceToUnitSphere (fit.points), 0.5 * meanDistanceToUnitSphere (noisy));
  }
}

TEST (PointSmoothing, PointsWithoutNeighboursStay)
{
  const Points3 points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  pcl::meshless::CsrGraph none;
  none.offsets.assign (4, 0);
  const auto smoothed = pcl::meshless::projectOntoFittedSurfaces (points, none);
  ASSERT_EQ (smoothed.points.size (), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_EQ (smoothed.points[i], points[i]);
  EXPECT_EQ (smoothed.noise.noise_ratio, 0.0);
}
