// Paper §2: neighbourhoods through PCL's search and the symmetric graph G.
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/neighbourhood_search.h>

#include "test_support.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <set>

using namespace pcl::meshless;

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr
randomCloud (std::size_t n, double scale, std::uint32_t seed)
{
  std::mt19937 random (seed);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (std::size_t i = 0; i < n; ++i)
    cloud->push_back (pcl::PointXYZ (static_cast<float> (scale * u (random)),
                                     static_cast<float> (scale * u (random)),
                                     static_cast<float> (scale * u (random))));
  return cloud;
}

pcl::Indices
allIndices (std::size_t n)
{
  pcl::Indices indices (n);
  std::iota (indices.begin (), indices.end (), 0);
  return indices;
}

double
sqrDistance (const pcl::PointXYZ& a, const pcl::PointXYZ& b)
{
  return (a.getVector3fMap () - b.getVector3fMap ()).cast<double> ().squaredNorm ();
}

/** Brute force: the sorted squared distances of the k nearest other points of
  * `cloud[query]` among `members`. Comparing distances, not indices, makes the
  * check independent of how ties are broken. */
std::vector<double>
bruteForceKnnDistances (const pcl::PointCloud<pcl::PointXYZ>& cloud,
                        const pcl::Indices& members,
                        pcl::index_t query,
                        int k)
{
  std::vector<double> d;
  for (auto m : members)
    if (m != query)
      d.push_back (sqrDistance (cloud[query], cloud[m]));
  std::sort (d.begin (), d.end ());
  d.resize (std::min<std::size_t> (d.size (), k));
  return d;
}

Neighbourhoods
searchAll (const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
           const pcl::Indices& members,
           const NeighbourhoodOptions& options)
{
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud (cloud, pcl::make_shared<pcl::Indices> (members));
  return searchNeighbourhoods (tree, members, options);
}

} // namespace

TEST (NeighbourhoodGraph, KNearestAgreesWithBruteForce)
{
  const auto cloud = randomCloud (2000, 1.0, 7);
  const auto members = allIndices (cloud->size ());
  // 12: the rows share one array; 300: beyond its stride cap, a vector per row.
  for (const int k : {12, 300}) {
    NeighbourhoodOptions options;
    options.k = k;
    const Neighbourhoods result = searchAll (cloud, members, options);
    ASSERT_TRUE (result.success) << result.message;
    ASSERT_EQ (result.neighbours.size (), cloud->size ());
    for (std::size_t v = 0; v < cloud->size (); ++v) {
      ASSERT_EQ (result.neighbours.degree (v), k);
      std::vector<double> got;
      for (auto w = result.neighbours.begin (v); w != result.neighbours.end (v); ++w) {
        ASSERT_NE (static_cast<std::size_t> (*w), v) << "a point is its own neighbour";
        got.push_back (sqrDistance ((*cloud)[v], (*cloud)[*w]));
      }
      // Nearest first, up to the search's float rounding of nearly equal distances.
      for (std::size_t j = 1; j < got.size (); ++j)
        ASSERT_GE (got[j], got[j - 1] - 1e-6 * got[j]) << "not nearest first";
      const auto expected = bruteForceKnnDistances (*cloud, members, v, k);
      for (int j = 0; j < k; ++j)
        ASSERT_NEAR (got[j], expected[j], 1e-6 * expected[j] + 1e-12) << "k " << k << ", point " << v;
    }
  }
}

TEST (NeighbourhoodGraph, ResultsOutsideTheSubsetAreDroppedLeavingShortRows)
{
  // The search covers the whole cloud, the pipeline only every other point: each
  // row keeps those of the k nearest that are pipeline points, so rows differ in
  // length and are packed from a fixed stride.
  const auto cloud = randomCloud (1000, 1.0, 5);
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud (cloud);
  pcl::Indices members;
  for (pcl::index_t i = 0; i < 1000; i += 2)
    members.push_back (i);
  NeighbourhoodOptions options;
  options.k = 10;
  const Neighbourhoods result = searchNeighbourhoods (tree, members, options);
  ASSERT_TRUE (result.success) << result.message;
  ASSERT_EQ (result.neighbours.size (), members.size ());
  const auto all = allIndices (cloud->size ());
  std::set<int> degrees;
  for (std::size_t v = 0; v < members.size (); ++v) {
    // Brute force: the members among the 10 nearest other points of the cloud.
    std::vector<std::pair<double, pcl::index_t>> nearest;
    for (auto m : all)
      if (m != members[v])
        nearest.emplace_back (sqrDistance ((*cloud)[members[v]], (*cloud)[m]), m);
    std::sort (nearest.begin (), nearest.end ());
    std::vector<double> expected;
    for (int j = 0; j < 10; ++j)
      if (nearest[j].second % 2 == 0)
        expected.push_back (nearest[j].first);
    std::vector<double> got;
    for (auto w = result.neighbours.begin (v); w != result.neighbours.end (v); ++w)
      got.push_back (sqrDistance ((*cloud)[members[v]], (*cloud)[members[*w]]));
    ASSERT_EQ (got.size (), expected.size ()) << "point " << v;
    for (std::size_t j = 0; j < got.size (); ++j)
      ASSERT_NEAR (got[j], expected[j], 1e-6 * expected[j] + 1e-12);
    degrees.insert (result.neighbours.degree (v));
  }
  EXPECT_GT (degrees.size (), 3u) << "rows of several lengths";
}

TEST (NeighbourhoodGraph, BallAgreesWithBruteForce)
{
  const auto cloud = randomCloud (1500, 1.0, 11);
  const auto members = allIndices (cloud->size ());
  NeighbourhoodOptions options;
  options.radius = 0.2;
  const Neighbourhoods result = searchAll (cloud, members, options);
  ASSERT_TRUE (result.success) << result.message;
  for (std::size_t v = 0; v < cloud->size (); ++v) {
    std::set<pcl::index_t> got (result.neighbours.begin (v), result.neighbours.end (v));
    std::set<pcl::index_t> expected;
    for (auto m : members)
      if (static_cast<std::size_t> (m) != v &&
          sqrDistance ((*cloud)[v], (*cloud)[m]) < options.radius * options.radius)
        expected.insert (m);
    // Points within float rounding of the sphere may go either way; there are
    // none in a random cloud at this size, so the sets must agree exactly.
    ASSERT_EQ (got, expected) << "point " << v;
  }
}

TEST (NeighbourhoodGraph, SubsetIsRenumbered)
{
  const auto cloud = randomCloud (1000, 1.0, 3);
  pcl::Indices members;
  for (pcl::index_t i = 0; i < 1000; i += 3)
    members.push_back (i);
  NeighbourhoodOptions options;
  options.k = 8;
  const Neighbourhoods result = searchAll (cloud, members, options);
  ASSERT_TRUE (result.success) << result.message;
  ASSERT_EQ (result.neighbours.size (), members.size ());
  for (std::size_t v = 0; v < members.size (); ++v) {
    std::vector<double> got;
    for (auto w = result.neighbours.begin (v); w != result.neighbours.end (v); ++w) {
      ASSERT_GE (*w, 0);
      ASSERT_LT (static_cast<std::size_t> (*w), members.size ());
      got.push_back (sqrDistance ((*cloud)[members[v]], (*cloud)[members[*w]]));
    }
    const auto expected = bruteForceKnnDistances (*cloud, members, members[v], 8);
    ASSERT_EQ (got.size (), expected.size ());
    for (std::size_t j = 0; j < got.size (); ++j)
      ASSERT_NEAR (got[j], expected[j], 1e-6 * expected[j] + 1e-12);
  }
}

TEST (NeighbourhoodGraph, ScaleInvariant)
{
  const auto cloud = randomCloud (800, 1.0, 5);
  const auto members = allIndices (cloud->size ());
  NeighbourhoodOptions options;
  options.k = 10;
  const Neighbourhoods reference = searchAll (cloud, members, options);
  for (double scale : {1e-4, 1e4}) {
    auto scaled = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> (*cloud);
    for (auto& p : *scaled)
      p.getVector3fMap () *= static_cast<float> (scale);
    const Neighbourhoods result = searchAll (scaled, members, options);
    ASSERT_TRUE (result.success);
    for (std::size_t v = 0; v < cloud->size (); ++v) {
      std::set<pcl::index_t> a (reference.neighbours.begin (v), reference.neighbours.end (v));
      std::set<pcl::index_t> b (result.neighbours.begin (v), result.neighbours.end (v));
      EXPECT_EQ (a, b) << "scale " << scale << ", point " << v;
    }
  }
}

TEST (NeighbourhoodGraph, SymmetricGraphIsTheUnionOfBothDirections)
{
  const auto cloud = randomCloud (3000, 1.0, 9);
  const auto members = allIndices (cloud->size ());
  const Neighbourhoods nb = searchAll (cloud, members, {});
  ASSERT_TRUE (nb.success);
  const CsrGraph g = symmetricGraph (nb.neighbours);
  ASSERT_EQ (g.size (), cloud->size ());

  std::set<std::pair<pcl::index_t, pcl::index_t>> expected;
  for (std::size_t v = 0; v < nb.neighbours.size (); ++v)
    for (auto w = nb.neighbours.begin (v); w != nb.neighbours.end (v); ++w) {
      expected.emplace (static_cast<pcl::index_t> (v), *w);
      expected.emplace (*w, static_cast<pcl::index_t> (v));
    }
  std::set<std::pair<pcl::index_t, pcl::index_t>> got;
  for (std::size_t v = 0; v < g.size (); ++v) {
    EXPECT_TRUE (std::is_sorted (g.begin (v), g.end (v)));
    EXPECT_EQ (std::adjacent_find (g.begin (v), g.end (v)), g.end (v)) << "repeated entry";
    for (auto w = g.begin (v); w != g.end (v); ++w) {
      EXPECT_NE (static_cast<std::size_t> (*w), v) << "self loop";
      got.emplace (static_cast<pcl::index_t> (v), *w);
    }
  }
  EXPECT_EQ (got, expected);
  EXPECT_GE (g.numEntries (), nb.neighbours.numEntries ()); // never loses an edge
}

TEST (NeighbourhoodGraph, SymmetricGraphDropsSelfLoopsAndRepeats)
{
  CsrGraph directed;
  directed.offsets = {0, 3, 4, 5};
  directed.adjacency = {0, 1, 1, 0, 2}; // 0: {0,1,1}, 1: {0}, 2: {2}
  const CsrGraph g = symmetricGraph (directed);
  ASSERT_EQ (g.size (), 3u);
  EXPECT_EQ (std::vector<pcl::index_t> (g.begin (0), g.end (0)), std::vector<pcl::index_t>{1});
  EXPECT_EQ (std::vector<pcl::index_t> (g.begin (1), g.end (1)), std::vector<pcl::index_t>{0});
  EXPECT_EQ (g.degree (2), 0);
}

TEST (NeighbourhoodGraph, ComponentsOfTwoSeparateClusters)
{
  auto cloud = randomCloud (400, 1.0, 4);
  for (std::size_t i = 200; i < 400; ++i)
    (*cloud)[i].x += 100.0f; // far away: kNN never crosses
  const Neighbourhoods nb = searchAll (cloud, allIndices (400), {});
  std::vector<pcl::index_t> labels;
  EXPECT_EQ (connectedComponents (symmetricGraph (nb.neighbours), labels), 2u);
  EXPECT_NE (labels[0], labels[399]);
}

TEST (NeighbourhoodGraph, RejectsBadParameters)
{
  const auto cloud = randomCloud (50, 1.0, 1);
  NeighbourhoodOptions options;
  options.k = 0;
  EXPECT_FALSE (searchAll (cloud, allIndices (50), options).success);
  options.k = 12;
  options.radius = -1.0;
  EXPECT_FALSE (searchAll (cloud, allIndices (50), options).success);
}

TEST (NeighbourhoodGraph, KAndCapUpToIntMaxGiveEveryOtherPoint)
{
  // k + 1 (the query point is among the results)
  // overflowed an int for k = INT_MAX, undefined behaviour; likewise the cap of ball
  // neighbourhoods.
  const auto cloud = randomCloud (30, 1.0, 5);
  NeighbourhoodOptions options;
  options.k = std::numeric_limits<int>::max ();
  Neighbourhoods result = searchAll (cloud, allIndices (30), options);
  ASSERT_TRUE (result.success) << result.message;
  for (std::size_t v = 0; v < 30; ++v)
    EXPECT_EQ (result.neighbours.degree (v), 29);
  options.radius = 10.0;
  options.max_neighbours = std::numeric_limits<int>::max ();
  result = searchAll (cloud, allIndices (30), options);
  ASSERT_TRUE (result.success) << result.message;
  for (std::size_t v = 0; v < 30; ++v)
    EXPECT_EQ (result.neighbours.degree (v), 29);
}

TEST (NeighbourhoodGraph, PiecesJoinAlongOrAcrossTheSurface)
{
  // Two strips of a plane, 0.2 apart, each a piece at 4 neighbours and joined by
  // 20: along the plane. The same strips stacked 0.25 above each other: joined
  // across them.
  pcl::meshless::Points3 flat, stacked;
  for (int piece = 0; piece < 2; ++piece)
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 3; ++j) {
        const double x = 0.1 * i + 0.013 * j, y = 0.1 * j;
        flat.emplace_back (x, y + piece * 0.4, 0.0);
        stacked.emplace_back (x, y, piece * 0.25);
      }
  for (const auto* points : {&flat, &stacked}) {
    const auto narrow = meshless_test::bruteForceKnn (*points, 4);
    std::vector<pcl::index_t> labels;
    ASSERT_GT (pcl::meshless::connectedComponents (pcl::meshless::symmetricGraph (narrow), labels),
               1u);
    const auto wide = meshless_test::bruteForceKnn (*points, 20);
    std::vector<pcl::index_t> joined;
    ASSERT_EQ (pcl::meshless::connectedComponents (pcl::meshless::symmetricGraph (wide), joined),
               1u);
    const double along = pcl::meshless::joinsAlongTheSurface (*points, narrow, labels, wide);
    if (points == &flat)
      EXPECT_GT (along, 0.5);
    else
      EXPECT_LT (along, 0.25);
  }
  EXPECT_EQ (pcl::meshless::joinsAlongTheSurface (flat, {}, {}, {}), 0.0) << "sizes differ";
}
