// The project's own generated clouds: deterministic, on their shapes, evenly spread.
#include <meshless_tools/synthetic_clouds.h>

#include "test_support.h"

#include <cmath>

using namespace pcl::meshless;

TEST (SyntheticClouds, SameSeedSameCloudOtherSeedOtherCloud)
{
  const Points3 a = sampleShape (SyntheticShape::BumpySphere, {500, 1, 0.0});
  const Points3 b = sampleShape (SyntheticShape::BumpySphere, {500, 1, 0.0});
  const Points3 c = sampleShape (SyntheticShape::BumpySphere, {500, 2, 0.0});
  ASSERT_EQ (a.size (), 500u);
  EXPECT_EQ (a, b);
  EXPECT_NE (a, c);
}

TEST (SyntheticClouds, PointsLieOnTheirShapes)
{
  for (const auto& p : sampleShape (SyntheticShape::Sphere, {1000, 1, 0.0}))
    EXPECT_NEAR (p.norm (), 1.0, 1e-12);
  for (const auto& p : sampleShape (SyntheticShape::Ellipsoid, {1000, 1, 0.0}))
    EXPECT_NEAR (p.x () * p.x () + p.y () * p.y () + p.z () * p.z () / 36.0, 1.0, 1e-12);
  for (const auto& p : sampleShape (SyntheticShape::Torus, {1000, 1, 0.0})) {
    const double ring = std::hypot (p.x (), p.y ()) - 1.0;
    EXPECT_NEAR (std::hypot (ring, p.z ()), 0.35, 1e-12);
  }
  for (const auto& p : sampleShape (SyntheticShape::Disc, {1000, 1, 0.0})) {
    EXPECT_EQ (p.z (), 0.0);
    EXPECT_LE (p.head<2> ().norm (), 1.0);
  }
  for (const auto& p : sampleShape (SyntheticShape::BumpySphere, {1000, 1, 0.0})) {
    EXPECT_GT (p.norm (), 0.74);
    EXPECT_LT (p.norm (), 1.26);
  }
}

TEST (SyntheticClouds, SpacingIsEvenOnTheSphere)
{
  const std::size_t n = 2000;
  const Points3 points = sampleShape (SyntheticShape::Sphere, {n, 4, 0.0});
  const double expected = std::sqrt (4.0 * 3.14159265358979 / static_cast<double> (n));
  for (std::size_t i = 0; i < n; ++i) {
    double nearest = 1e9;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i)
        nearest = std::min (nearest, (points[i] - points[j]).norm ());
    EXPECT_GT (nearest, 0.2 * expected) << "point " << i;
    EXPECT_LT (nearest, 1.5 * expected) << "point " << i;
  }
}

TEST (SyntheticClouds, NoiseMovesPointsOffTheShape)
{
  const Points3 points = sampleShape (SyntheticShape::Sphere, {2000, 1, 0.01});
  double sum_sq = 0.0;
  for (const auto& p : points)
    sum_sq += (p.norm () - 1.0) * (p.norm () - 1.0);
  const double rms = std::sqrt (sum_sq / 2000.0);
  // sigma = 1% of the diagonal (2 sqrt 3) in each coordinate: radial rms ~ sigma.
  EXPECT_NEAR (rms, 0.01 * 2.0 * std::sqrt (3.0), 0.01);
  std::string bad = "cube";
  SyntheticShape shape;
  EXPECT_FALSE (parseSyntheticShape (bad, shape));
  EXPECT_TRUE (parseSyntheticShape ("bumpy_sphere", shape));
  EXPECT_EQ (shape, SyntheticShape::BumpySphere);
}
