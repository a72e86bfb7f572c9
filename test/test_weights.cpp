// Convex-combination weights: positivity, partition of unity, linear precision.
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <meshless_tools/synthetic_clouds.h>
#include <pcl/surface/meshless/weights.h>

#include "test_support.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

using namespace pcl::meshless;

namespace {

constexpr double pi = 3.14159265358979323846;

/** A random ring around the origin: d points at sorted random angles whose
  * consecutive gaps stay below pi, at random radii. */
Points2
randomStarRing (std::mt19937& random, int d)
{
  std::uniform_real_distribution<double> u (0.0, 1.0);
  for (;;) {
    std::vector<double> angles (d);
    for (auto& a : angles)
      a = 2.0 * pi * u (random);
    std::sort (angles.begin (), angles.end ());
    double largest = 2.0 * pi - (angles.back () - angles.front ());
    for (int j = 1; j < d; ++j)
      largest = std::max (largest, angles[j] - angles[j - 1]);
    if (largest >= 0.95 * pi)
      continue;
    Points2 ring;
    for (double a : angles) {
      const double r = 0.1 + 2.0 * u (random);
      ring.emplace_back (r * std::cos (a), r * std::sin (a));
    }
    return ring;
  }
}


void
expectConvexCombination (const std::vector<double>& lambda, std::size_t d)
{
  ASSERT_EQ (lambda.size (), d);
  double sum = 0.0;
  for (double l : lambda) {
    EXPECT_GE (l, 0.0);
    sum += l;
  }
  EXPECT_NEAR (sum, 1.0, 1e-12);
}

} // namespace

TEST (Weights, MeanValueHasLinearPrecisionOnRandomStars)
{
  std::mt19937 random (3);
  for (int trial = 0; trial < 5000; ++trial) {
    const Points2 ring = randomStarRing (random, 3 + trial % 12);
    std::vector<double> lambda;
    ASSERT_TRUE (meanValueWeights (ring, lambda));
    expectConvexCombination (lambda, ring.size ());
    for (double l : lambda)
      EXPECT_GT (l, 0.0) << "mean value weights are strictly positive";
    Eigen::Vector2d reproduced = Eigen::Vector2d::Zero ();
    for (std::size_t j = 0; j < ring.size (); ++j)
      reproduced += lambda[j] * ring[j];
    EXPECT_LT (reproduced.norm (), 1e-12) << "trial " << trial;
  }
}

TEST (Weights, ShapePreservingHasLinearPrecisionOnRandomStars)
{
  std::mt19937 random (4);
  for (int trial = 0; trial < 5000; ++trial) {
    const Points2 ring = randomStarRing (random, 3 + trial % 12);
    std::vector<double> lambda;
    ASSERT_TRUE (shapePreservingWeights (ring, lambda)) << "trial " << trial;
    expectConvexCombination (lambda, ring.size ());
    Eigen::Vector2d reproduced = Eigen::Vector2d::Zero ();
    for (std::size_t j = 0; j < ring.size (); ++j)
      reproduced += lambda[j] * ring[j];
    EXPECT_LT (reproduced.norm (), 1e-12) << "trial " << trial;
  }
}

TEST (Weights, ShapePreservingOnATriangleAreBarycentricCoordinates)
{
  const Points2 ring = {{1.0, -0.5}, {0.2, 1.0}, {-1.5, -0.7}};
  std::vector<double> lambda;
  ASSERT_TRUE (shapePreservingWeights (ring, lambda));
  const double area = (ring[1] - ring[0]).x () * (ring[2] - ring[0]).y () -
                      (ring[1] - ring[0]).y () * (ring[2] - ring[0]).x ();
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector2d& b = ring[(j + 1) % 3];
    const Eigen::Vector2d& c = ring[(j + 2) % 3];
    EXPECT_NEAR (lambda[j], (b.x () * c.y () - b.y () * c.x ()) / area, 1e-14);
  }
}

TEST (Weights, RingsThatDoNotSurroundTheOriginAreRefused)
{
  const Points2 half = {{1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.1}}; // gap of more than pi
  std::vector<double> lambda = {42.0};
  EXPECT_FALSE (meanValueWeights (half, lambda));
  EXPECT_FALSE (shapePreservingWeights (half, lambda));
  EXPECT_EQ (lambda, std::vector<double>{42.0}) << "untouched on failure";
}

TEST (Weights, EveryTypeGivesConvexCombinationsOnASphere)
{
  const Points3 points = sampleShape (SyntheticShape::BumpySphere, {2000, 8, 0.0});
  const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
  const OrderedNeighbourhoods ordered = orderNeighbourhoods (points, graph);
  ASSERT_TRUE (ordered.success);
  for (WeightType type : {WeightType::Uniform, WeightType::ReciprocalDistance,
                          WeightType::ShapePreserving, WeightType::MeanValue}) {
    const Weights weights = computeWeights (points, ordered.rings, graph, ordered.normals, {type});
    ASSERT_TRUE (weights.success) << weights.message;
    EXPECT_EQ (weights.num_fallbacks, 0u) << "a closed, smooth surface is surrounded everywhere";
    for (std::size_t v = 0; v < points.size (); ++v) {
      const auto b = weights.values.begin () + weights.neighbours.offsets[v];
      const auto e = weights.values.begin () + weights.neighbours.offsets[v + 1];
      expectConvexCombination (std::vector<double> (b, e), e - b);
      if (type == WeightType::Uniform)
        for (auto it = b; it != e; ++it)
          EXPECT_DOUBLE_EQ (*it, 1.0 / static_cast<double> (e - b));
    }
  }
}

TEST (Weights, RingsAndWeightsDoNotDependOnTheThreadCount)
{
  const Points3 points = sampleShape (SyntheticShape::BumpySphere, {3000, 8, 0.0});
  const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
  OrderingOptions one_thread, three_threads;
  one_thread.num_threads = 1;
  three_threads.num_threads = 3;
  const OrderedNeighbourhoods ordered = orderNeighbourhoods (points, graph, one_thread);
  const OrderedNeighbourhoods again = orderNeighbourhoods (points, graph, three_threads);
  ASSERT_TRUE (ordered.success && again.success);
  EXPECT_EQ (ordered.rings.offsets, again.rings.offsets);
  EXPECT_EQ (ordered.rings.adjacency, again.rings.adjacency);
  EXPECT_EQ (ordered.normals, again.normals);
  WeightOptions serial, parallel;
  serial.num_threads = 1;
  parallel.num_threads = 3;
  const Weights weights = computeWeights (points, ordered.rings, graph, ordered.normals, serial);
  const Weights same = computeWeights (points, ordered.rings, graph, ordered.normals, parallel);
  ASSERT_TRUE (weights.success && same.success);
  EXPECT_EQ (weights.neighbours.adjacency, same.neighbours.adjacency);
  EXPECT_EQ (weights.values, same.values);
}

TEST (Weights, ReciprocalDistanceIsInverselyProportionalToDistance)
{
  const Points3 points = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 4}};
  const std::vector<pcl::index_t> nb = {1, 2, 3};
  std::vector<double> lambda;
  reciprocalDistanceWeights (points, 0, nb.data (), nb.data () + 3, lambda);
  ASSERT_EQ (lambda.size (), 3u);
  EXPECT_NEAR (lambda[0], 4.0 / 7.0, 1e-15);
  EXPECT_NEAR (lambda[1], 2.0 / 7.0, 1e-15);
  EXPECT_NEAR (lambda[2], 1.0 / 7.0, 1e-15);
}

TEST (Weights, LinearPrecisionOnATiltedPlanarCloudThroughTheWholeStage)
{
  // Points of a tilted plane, moved far from the origin and scaled: every point
  // whose ring surrounds it is reproduced exactly (up to rounding) by its
  // neighbours, in 3D, by mean value and shape-preserving weights.
  for (double scale : {1e-4, 1.0, 1e4}) {
    Points3 points = sampleShape (SyntheticShape::Disc, {1500, 6, 0.0});
    const Eigen::Matrix3d tilt =
        Eigen::AngleAxisd (0.6, Eigen::Vector3d (1, -1, 0.3).normalized ()).toRotationMatrix ();
    for (auto& p : points)
      p = scale * (tilt * p + Eigen::Vector3d (10, 20, -5));
    const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
    const OrderedNeighbourhoods ordered = orderNeighbourhoods (points, graph);
    for (WeightType type : {WeightType::MeanValue, WeightType::ShapePreserving}) {
      const Weights weights = computeWeights (points, ordered.rings, graph, ordered.normals, {type});
      ASSERT_TRUE (weights.success);
      std::size_t checked = 0;
      for (std::size_t v = 0; v < points.size (); ++v) {
        if (ordered.largest_gap[v] >= 0.999 * pi)
          continue; // on the rim: the fallback has no linear precision
        Eigen::Vector3d combination = Eigen::Vector3d::Zero ();
        for (auto k = weights.neighbours.offsets[v]; k < weights.neighbours.offsets[v + 1]; ++k)
          combination += weights.values[k] * (points[weights.neighbours.adjacency[k]] - points[v]);
        EXPECT_LT (combination.norm (), 1e-9 * scale) << "point " << v << " scale " << scale;
        ++checked;
      }
      EXPECT_GT (checked, 1300u);
    }
  }
}
