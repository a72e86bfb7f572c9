// The points' Z-order: a permutation that puts neighbours in space near in memory.
#include "common/spatial_order.h"
#include <meshless_tools/synthetic_clouds.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

using namespace pcl::meshless;

namespace {

bool
isPermutation (std::vector<pcl::index_t> order, std::size_t n)
{
  std::sort (order.begin (), order.end ());
  for (std::size_t k = 0; k < order.size (); ++k)
    if (order[k] != static_cast<pcl::index_t> (k))
      return false;
  return order.size () == n;
}

double
meanStep (const Points3& points, const std::vector<pcl::index_t>& order)
{
  double sum = 0.0;
  for (std::size_t k = 1; k < order.size (); ++k)
    sum += (points[order[k]] - points[order[k - 1]]).norm ();
  return sum / static_cast<double> (order.size () - 1);
}

} // namespace

TEST (SpatialOrder, ConsecutivePointsAreNeighboursOnAShuffledSphere)
{
  SyntheticCloudOptions options;
  options.num_points = 20000;
  Points3 points = sampleShape (SyntheticShape::Sphere, options);
  std::shuffle (points.begin (), points.end (), std::mt19937 (7));
  const std::vector<pcl::index_t> order = mortonOrder (points);
  ASSERT_TRUE (isPermutation (order, points.size ()));

  std::vector<pcl::index_t> input (points.size ());
  std::iota (input.begin (), input.end (), 0);
  const double spacing = std::sqrt (4.0 * M_PI / static_cast<double> (points.size ()));
  const double shuffled = meanStep (points, input), ordered = meanStep (points, order);
  // A random order steps across the sphere (mean chord 4/3); the curve mostly
  // steps to a neighbour and jumps only at the boundaries of its cells.
  EXPECT_GT (shuffled, 1.0);
  EXPECT_LT (ordered, 3.0 * spacing) << "shuffled " << shuffled << ", spacing " << spacing;
}

TEST (SpatialOrder, PointsInOneCellKeepTheirInputOrder)
{
  // Points 0, 2, 4 coincide, as do 1 and 3: the sort must not reorder equals, so
  // that the result does not depend on the sort's implementation.
  const Points3 points = {{1, 1, 1}, {0, 0, 0}, {1, 1, 1}, {0, 0, 0}, {1, 1, 1}};
  const std::vector<pcl::index_t> order = mortonOrder (points);
  EXPECT_EQ (order, (std::vector<pcl::index_t> {1, 3, 0, 2, 4}));
}

TEST (SpatialOrder, DegenerateInputsGiveAPermutation)
{
  EXPECT_TRUE (mortonOrder ({}).empty ());
  EXPECT_TRUE (isPermutation (mortonOrder ({{2, 3, 4}}), 1));
  const double nan = std::numeric_limits<double>::quiet_NaN ();
  const double inf = std::numeric_limits<double>::infinity ();
  EXPECT_TRUE (isPermutation (mortonOrder ({{0, 0, 0}, {nan, 1, 2}, {inf, 0, 0}, {1, 1, 1}}), 4));
  // NaN counts as the lowest cell, +inf as the highest: tied with the finite corners.
  EXPECT_EQ (mortonOrder ({{0, 0, 0}, {1, 1, 1}, {nan, nan, nan}, {inf, inf, inf}}),
             (std::vector<pcl::index_t> {0, 2, 1, 3}));
  // All points equal (zero extent) and points on one line.
  EXPECT_TRUE (isPermutation (mortonOrder ({{5, 5, 5}, {5, 5, 5}, {5, 5, 5}}), 3));
  const std::vector<pcl::index_t> line = mortonOrder ({{3, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 0}});
  EXPECT_EQ (line, (std::vector<pcl::index_t> {3, 1, 2, 0}));
}

TEST (SpatialOrder, MortonKeysInterleaveTheAxes)
{
  EXPECT_EQ (mortonKey (1, 0, 0), 1u);
  EXPECT_EQ (mortonKey (0, 1, 0), 2u);
  EXPECT_EQ (mortonKey (0, 0, 1), 4u);
  EXPECT_EQ (mortonKey (3, 0, 0), 9u);  // x bits at 0 and 3
  EXPECT_EQ (mortonKey (0, 2, 1), 20u); // y bit at 4, z bit at 2
  const std::uint64_t top = (std::uint64_t {1} << 21) - 1;
  EXPECT_EQ (mortonKey (top, top, top), (std::uint64_t {1} << 63) - 1);
  // Only the low 21 bits count.
  EXPECT_EQ (mortonKey (top + 2, 0, 0), 1u);
}
