/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
// The shared machinery of src/common/ against brute-force references.
#include "common/constants.h"
#include "common/half_edges.h"
#include "common/threads.h"
#include "common/uniform_grid.h"
#include "common/union_find.h"

#include <gtest/gtest.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <utility>
#include <vector>

using namespace pcl::meshless;

namespace {

/** Random triangles over n vertices with three distinct corners each: shared,
  * repeated and opposite edges in any mix (non-manifold soups included). */
Triangles
randomTriangles (std::size_t count, int n, std::mt19937& random)
{
  std::uniform_int_distribution<int> vertex (0, n - 1);
  Triangles triangles;
  while (triangles.size () < count) {
    const Triangle t = {vertex (random), vertex (random), vertex (random)};
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
      triangles.push_back (t);
  }
  return triangles;
}

pcl::index_t
tail (const Triangles& triangles, std::int32_t h)
{
  return triangles[h / 3][h % 3];
}

pcl::index_t
head (const Triangles& triangles, std::int32_t h)
{
  return triangles[h / 3][(h % 3 + 1) % 3];
}

/** A closed, consistently oriented octahedron. */
const Triangles octahedron = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

} // namespace

// ---------------------------------------------------------------------------
// Constants and threads.

TEST (Common, ConstantsAreThePiTheStagesUsed)
{
  EXPECT_EQ (pi, 3.14159265358979323846);
  EXPECT_EQ (two_pi, 6.283185307179586476925286766559);
}

TEST (Common, ThreadCountKeepsARequestAndFillsZero)
{
  EXPECT_GE (threadCount (0), 1);
#ifdef _OPENMP
  EXPECT_EQ (threadCount (3), 3);
  EXPECT_EQ (threadCount (0), omp_get_max_threads ());
#else
  EXPECT_EQ (threadCount (3), 1);
#endif
}

// ---------------------------------------------------------------------------
// Half-edges.

TEST (Common, HalfEdgesGroupedBySmallerVertexInEdgeOrder)
{
  // A tetrahedron: 12 half-edges, each of its 6 edges twice, once each way.
  const Triangles tetrahedron = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {0, 2, 3}};
  const HalfEdgeGroups groups = groupHalfEdges (tetrahedron, 4);
  ASSERT_EQ (groups.start.size (), 5u);
  ASSERT_EQ (groups.ends.size (), 12u);
  EXPECT_EQ (groups.start[4], 12u);
  std::vector<int> seen (12, 0);
  for (std::size_t v = 0; v < 4; ++v)
    for (std::uint32_t k = groups.start[v]; k < groups.start[v + 1]; ++k) {
      const auto [larger, h] = groups.ends[k];
      const pcl::index_t a = tail (tetrahedron, h), b = head (tetrahedron, h);
      EXPECT_EQ (std::min (a, b), static_cast<pcl::index_t> (v));
      EXPECT_EQ (std::max (a, b), larger);
      if (k > groups.start[v])
        EXPECT_LT (groups.ends[k - 1], groups.ends[k]); // sorted, each once
      ++seen[h];
    }
  for (int count : seen)
    EXPECT_EQ (count, 1);
  // The two half-edges of an edge are adjacent: vertex 0 has edges to 1, 2, 3.
  EXPECT_EQ (groups.start[1] - groups.start[0], 6u);
  EXPECT_EQ (groups.ends[0].first, groups.ends[1].first);
}

TEST (Common, EachEdgeVisitedOnceWithAllItsHalfEdgesInEdgeOrder)
{
  std::mt19937 random (7);
  for (int round = 0; round < 20; ++round) {
    const int n = 5 + round;
    const Triangles triangles = randomTriangles (static_cast<std::size_t> (3 * n), n, random);
    // Brute force: half-edge ids per (smaller, larger) vertex.
    std::map<std::pair<pcl::index_t, pcl::index_t>, std::vector<std::int32_t>> reference;
    for (std::int32_t h = 0; h < static_cast<std::int32_t> (3 * triangles.size ()); ++h) {
      const pcl::index_t a = tail (triangles, h), b = head (triangles, h);
      reference[{std::min (a, b), std::max (a, b)}].push_back (h);
    }
    auto expected = reference.begin ();
    const HalfEdgeGroups groups = groupHalfEdges (triangles, static_cast<std::size_t> (n));
    forEachEdge (groups, [&] (std::size_t smaller, const HalfEdgeGroups::Entry* first,
                              const HalfEdgeGroups::Entry* last) {
      ASSERT_NE (expected, reference.end ());
      EXPECT_EQ (static_cast<pcl::index_t> (smaller), expected->first.first);
      EXPECT_EQ (first->first, expected->first.second);
      std::vector<std::int32_t> ids;
      for (const HalfEdgeGroups::Entry* e = first; e != last; ++e) {
        EXPECT_EQ (e->first, expected->first.second);
        ids.push_back (e->second);
      }
      EXPECT_EQ (ids, expected->second); // ascending, as the brute force found them
      ++expected;
    });
    EXPECT_EQ (expected, reference.end ());
  }
}

TEST (Common, GroupsLeaveOutTheTrianglesThatAreNoFaces)
{
  // The second triangle names a vertex out of range: it must not be touched.
  const Triangles triangles = {{0, 1, 2}, {0, 1, 99}, {2, 1, 3}};
  const HalfEdgeGroups groups =
      groupHalfEdges (triangles, 4, [] (std::size_t t) { return t != 1; });
  ASSERT_EQ (groups.ends.size (), 6u);
  for (const auto& entry : groups.ends)
    EXPECT_NE (entry.second / 3, 1);
}

TEST (Common, TwinsOfAClosedMeshPairUp)
{
  const std::vector<std::int32_t> twin = halfEdgeTwins (octahedron, 6);
  ASSERT_EQ (twin.size (), 24u);
  for (std::int32_t h = 0; h < 24; ++h) {
    ASSERT_GE (twin[h], 0);
    EXPECT_EQ (twin[twin[h]], h);
    EXPECT_EQ (tail (octahedron, twin[h]), head (octahedron, h));
    EXPECT_EQ (head (octahedron, twin[h]), tail (octahedron, h));
  }
}

TEST (Common, TwinIsTheLowestReverseHalfEdgeInAnySoup)
{
  std::mt19937 random (11);
  for (int round = 0; round < 20; ++round) {
    const int n = 4 + round;
    const Triangles triangles = randomTriangles (static_cast<std::size_t> (2 * n), n, random);
    const std::vector<std::int32_t> twin = halfEdgeTwins (triangles, static_cast<std::size_t> (n));
    const auto count = static_cast<std::int32_t> (3 * triangles.size ());
    ASSERT_EQ (static_cast<std::int32_t> (twin.size ()), count);
    for (std::int32_t h = 0; h < count; ++h) {
      std::int32_t expected = -1;
      for (std::int32_t g = 0; g < count && expected < 0; ++g)
        if (tail (triangles, g) == head (triangles, h) && head (triangles, g) == tail (triangles, h))
          expected = g;
      EXPECT_EQ (twin[h], expected) << "half-edge " << h << " of round " << round;
    }
  }
}

TEST (Common, TwinsOfABoundaryAreMissing)
{
  // The octahedron without its last face: the three edges of the hole have no twin.
  const Triangles open (octahedron.begin (), octahedron.end () - 1);
  const std::vector<std::int32_t> twin = halfEdgeTwins (open, 6);
  int missing = 0;
  for (std::int32_t h = 0; h < static_cast<std::int32_t> (twin.size ()); ++h)
    if (twin[h] < 0)
      ++missing;
    else
      EXPECT_EQ (twin[twin[h]], h);
  EXPECT_EQ (missing, 3);
}

// ---------------------------------------------------------------------------
// Union-find.

template <typename Index>
void
checkAgainstLabels (int n, int joins, std::uint32_t seed)
{
  std::mt19937 random (seed);
  std::uniform_int_distribution<int> element (0, n - 1);
  DisjointSets<Index> sets (static_cast<std::size_t> (n));
  std::vector<int> label (static_cast<std::size_t> (n));
  for (int x = 0; x < n; ++x)
    label[x] = x;
  for (int k = 0; k < joins; ++k) {
    const int a = element (random), b = element (random);
    const bool apart = label[a] != label[b];
    EXPECT_EQ (sets.join (static_cast<Index> (a), static_cast<Index> (b)), apart);
    // Brute force: relabel the larger label's members with the smaller label,
    // which keeps every label the smallest member of its set.
    const int keep = std::min (label[a], label[b]), drop = std::max (label[a], label[b]);
    for (int& l : label)
      if (l == drop)
        l = keep;
  }
  int roots = 0, sets_expected = 0;
  for (int x = 0; x < n; ++x) {
    EXPECT_EQ (sets.find (static_cast<Index> (x)), static_cast<Index> (label[x]));
    roots += sets.isRoot (static_cast<Index> (x)) ? 1 : 0;
    sets_expected += label[x] == x ? 1 : 0;
  }
  EXPECT_EQ (roots, sets_expected);
}

TEST (Common, UnionFindRootIsTheSmallestMember)
{
  checkAgainstLabels<std::uint32_t> (200, 150, 3u);
  checkAgainstLabels<int> (50, 80, 5u);
  checkAgainstLabels<int> (1, 3, 9u);
}

// ---------------------------------------------------------------------------
// Grid cells.

TEST (Common, OverlappingBoxesShareAGridCell)
{
  const GridFrame frame (Eigen::Vector3d (0.3, -1.1, 2.0), 0.25, -(1 << 19), 1 << 19);
  std::mt19937 random (13);
  std::uniform_real_distribution<double> coordinate (-2.0, 2.0), size (0.0, 2.0);
  const auto randomBox = [&] (Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = coordinate (random);
      hi[k] = lo[k] + size (random);
    }
  };
  int overlapping = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Eigen::Vector3d alo, ahi, blo, bhi;
    randomBox (alo, ahi);
    randomBox (blo, bhi);
    if (trial % 4 == 0) { // touching boxes overlap too
      const int k = trial % 3;
      bhi[k] += ahi[k] - blo[k];
      blo[k] = ahi[k];
    }
    const CellRange a = frame.cellsOf (alo, ahi), b = frame.cellsOf (blo, bhi);
    bool cells_meet = true;
    for (int k = 0; k < 3; ++k)
      cells_meet = cells_meet && a.lo[k] <= b.hi[k] && b.lo[k] <= a.hi[k];
    const bool boxes_meet = (alo.array () <= bhi.array ()).all () && (blo.array () <= ahi.array ()).all ();
    overlapping += boxes_meet ? 1 : 0;
    if (boxes_meet)
      EXPECT_TRUE (cells_meet);
    // A point of the box lies in a cell of its range.
    const Eigen::Vector3d inside = alo + 0.5 * (ahi - alo);
    EXPECT_TRUE (a.contains (frame.cellsOf (inside, inside).lo));
  }
  EXPECT_GT (overlapping, 100); // the property was exercised
}

TEST (Common, GridCellsAreClampedAndCounted)
{
  const GridFrame frame (Eigen::Vector3d::Zero (), 1.0, -8, 7);
  const double huge = std::numeric_limits<double>::max ();
  const CellRange all = frame.cellsOf (Eigen::Vector3d::Constant (-huge), Eigen::Vector3d::Constant (huge));
  EXPECT_EQ (all.lo, (GridCell{-8, -8, -8}));
  EXPECT_EQ (all.hi, (GridCell{7, 7, 7}));
  EXPECT_EQ (all.count (), 16.0 * 16.0 * 16.0);
  int visited = 0;
  forEachCell (all, [&] (const GridCell& c) {
    EXPECT_TRUE (all.contains (c));
    ++visited;
  });
  EXPECT_EQ (visited, 16 * 16 * 16);
  // Cells are half-open: a point on a cell's lower face belongs to that cell.
  const CellRange one = frame.cellsOf (Eigen::Vector3d (1.0, -1.0, 0.5), Eigen::Vector3d (1.0, -1.0, 0.5));
  EXPECT_EQ (one.lo, (GridCell{1, -1, 0}));
  EXPECT_EQ (one.count (), 1.0);
}

TEST (Common, VisitStampsReportEachSlotOncePerQuery)
{
  VisitStamps visits (10);
  for (int query = 0; query < 3; ++query) {
    visits.startQuery ();
    for (std::int32_t t = 0; t < 10; ++t)
      EXPECT_TRUE (visits.firstVisit (t));
    for (std::int32_t t = 0; t < 10; ++t)
      EXPECT_FALSE (visits.firstVisit (t));
  }
}
