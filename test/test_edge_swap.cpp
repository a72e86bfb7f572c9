/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/delaunay_2d.h>
#include <pcl/surface/meshless/edge_swap.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <meshless_tools/mesh_distance.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <utility>

using namespace pcl::meshless;

namespace {

using Edge = std::pair<pcl::index_t, pcl::index_t>;

Edge
undirected (pcl::index_t u, pcl::index_t v)
{
  return {std::min (u, v), std::max (u, v)};
}

using meshless_test::boundaryEdges;
using meshless_test::edgeUse;

bool
hasEdge (const Triangles& triangles, pcl::index_t u, pcl::index_t v)
{
  return edgeUse (triangles).count (undirected (u, v)) > 0;
}

/** Swaps edge u-v of a consistently oriented mesh the way the stage does, for building
  * bad inputs; false if u-v is not an interior edge or the new edge exists. */
bool
flipEdge (Triangles& triangles, pcl::index_t u, pcl::index_t v)
{
  int t0 = -1, t1 = -1, i0 = 0, i1 = 0;
  for (int t = 0; t < static_cast<int> (triangles.size ()); ++t)
    for (int i = 0; i < 3; ++i) {
      if (triangles[t][i] == u && triangles[t][(i + 1) % 3] == v) {
        t0 = t;
        i0 = i;
      }
      if (triangles[t][i] == v && triangles[t][(i + 1) % 3] == u) {
        t1 = t;
        i1 = i;
      }
    }
  if (t0 < 0 || t1 < 0)
    return false;
  const pcl::index_t c = triangles[t0][(i0 + 2) % 3], d = triangles[t1][(i1 + 2) % 3];
  if (c == d || hasEdge (triangles, c, d))
    return false;
  triangles[t0] = {u, d, c};
  triangles[t1] = {d, v, c};
  return true;
}

/** Loop-subdivided-style icosphere (midpoint subdivision projected to the sphere). */
void
icosphere (int levels, Points3& points, Triangles& triangles)
{
  const double g = (1.0 + std::sqrt (5.0)) / 2.0;
  points = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
            {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
               {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
               {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& p : points)
    p.normalize ();
  for (int level = 0; level < levels; ++level) {
    std::map<Edge, pcl::index_t> middle;
    const auto mid = [&] (pcl::index_t a, pcl::index_t b) {
      const auto [it, inserted] = middle.emplace (undirected (a, b), static_cast<pcl::index_t> (points.size ()));
      if (inserted)
        points.push_back ((points[a] + points[b]).normalized ());
      return it->second;
    };
    Triangles finer;
    for (const Triangle& t : triangles) {
      const pcl::index_t ab = mid (t[0], t[1]), bc = mid (t[1], t[2]), ca = mid (t[2], t[0]);
      finer.push_back ({t[0], ab, ca});
      finer.push_back ({t[1], bc, ab});
      finer.push_back ({t[2], ca, bc});
      finer.push_back ({ab, bc, ca});
    }
    triangles.swap (finer);
  }
}

/** The icosphere with random edges flipped (only flips that keep the mesh valid). */
void
scrambledSphere (Points3& points, Triangles& triangles)
{
  icosphere (3, points, triangles);
  std::mt19937 random (7);
  for (int k = 0; k < 400; ++k) {
    const Triangle t = triangles[random () % triangles.size ()];
    const int i = static_cast<int> (random () % 3);
    flipEdge (triangles, t[i], t[(i + 1) % 3]);
  }
}

/** The unit icosphere with every vertex moved by a random vector whose coordinates
  * are uniform in [-amplitude, amplitude]. */
void
shakenSphere (int levels, double amplitude, std::uint32_t seed, Points3& points,
              Triangles& triangles)
{
  icosphere (levels, points, triangles);
  std::mt19937 random (seed);
  std::uniform_real_distribution<double> offset (-amplitude, amplitude);
  for (auto& p : points)
    p += Eigen::Vector3d (offset (random), offset (random), offset (random));
}

/** z = -slope |x - y| on an n x n grid, every cell cut by its anti-diagonal: a ridge
  * along x = y that the cells along it cross. */
void
ridgeGrid (int n, double slope, Points3& points, Triangles& triangles)
{
  points.clear ();
  triangles.clear ();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      points.emplace_back (i, j, -slope * std::abs (i - j));
  const auto id = [n] (int i, int j) { return static_cast<pcl::index_t> (j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      triangles.push_back ({id (i, j), id (i + 1, j), id (i, j + 1)});
      triangles.push_back ({id (i + 1, j), id (i + 1, j + 1), id (i, j + 1)});
    }
}

/** The topology and boundary of `after` match `before`, and nothing is duplicated. */
void
expectSameTopology (const Points3& points, const Triangles& before, const Triangles& after)
{
  const MeshReport r0 = checkMesh (points, before), r1 = checkMesh (points, after);
  EXPECT_EQ (r1.num_triangles, r0.num_triangles);
  EXPECT_EQ (r1.num_edges, r0.num_edges);
  EXPECT_EQ (r1.used_vertices, r0.used_vertices);
  EXPECT_EQ (r1.euler_characteristic, r0.euler_characteristic);
  EXPECT_EQ (r1.components, r0.components);
  EXPECT_TRUE (r1.isManifold ());
  EXPECT_TRUE (r1.isOriented ());
  EXPECT_EQ (r1.non_manifold_edges, 0u);
  EXPECT_EQ (r1.duplicate_triangles, 0u);
  EXPECT_EQ (r1.degenerate_triangles, 0u);
  EXPECT_EQ (boundaryEdges (after), boundaryEdges (before));
}

} // namespace

TEST (EdgeSwap, TetrahedronHasNothingToSwap)
{
  const Points3 points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Triangles triangles{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const Triangles input = triangles;
  const EdgeSwapResult result = optimizeBySwaps (points, triangles);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_EQ (result.swaps, 0u); // every swap would duplicate an edge
  EXPECT_EQ (triangles, input);
  EXPECT_EQ (result.self_intersections_before, 0u);
  EXPECT_EQ (result.self_intersections_after, 0u);
}

TEST (EdgeSwap, OctahedronStaysValid)
{
  const Points3 points{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  Triangles triangles{{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                      {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const Triangles input = triangles;
  for (const SwapCost cost : {SwapCost::AngleBetweenNormals, SwapCost::IntegratedMeanCurvature,
                              SwapCost::SquaredMeanCurvature, SwapCost::TotalAbsoluteCurvature}) {
    Triangles work = input;
    EdgeSwapOptions options;
    options.cost = cost;
    const EdgeSwapResult result = optimizeBySwaps (points, work, options);
    ASSERT_TRUE (result.success) << result.message;
    // The regular octahedron is optimal: a swap makes the quad non-convex.
    EXPECT_EQ (result.swaps, 0u);
    EXPECT_LE (result.cost_after, result.cost_before);
    EXPECT_TRUE (checkMesh (points, work).isSphereLike ());
    expectSameTopology (points, input, work);
  }
}

TEST (EdgeSwap, RidgeEdgesAppearInHeightField)
{
  // z = -|x - y| on a 7 x 7 grid: a ridge along the diagonal x = y. Every cell is cut
  // by the anti-diagonal, which crosses the ridge in the cells along it.
  const int n = 7;
  Points3 points;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      points.emplace_back (i, j, -std::abs (i - j));
  const auto id = [n] (int i, int j) { return static_cast<pcl::index_t> (j * n + i); };
  Triangles triangles;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      triangles.push_back ({id (i, j), id (i + 1, j), id (i, j + 1)});
      triangles.push_back ({id (i + 1, j), id (i + 1, j + 1), id (i, j + 1)});
    }
  const Triangles input = triangles;
  for (const SwapCost cost : {SwapCost::AngleBetweenNormals, SwapCost::IntegratedMeanCurvature,
                              SwapCost::SquaredMeanCurvature, SwapCost::TotalAbsoluteCurvature}) {
    Triangles work = input;
    EdgeSwapOptions options;
    options.cost = cost;
    options.improve_angles = false; // the descent alone; the angle pass is tested below
    const EdgeSwapResult result = optimizeBySwaps (points, work, options);
    ASSERT_TRUE (result.success) << result.message;
    // The edge costs see only the ridge; the vertex costs (H^2 A, (|k1|+|k2|) A)
    // also depend on the fan areas, so they may swap flat edges too.
    if (cost == SwapCost::AngleBetweenNormals || cost == SwapCost::IntegratedMeanCurvature) {
      EXPECT_EQ (result.swaps, static_cast<std::size_t> (n - 1));
    }
    EXPECT_LT (result.cost_after, result.cost_before);
    if (cost == SwapCost::AngleBetweenNormals) { // only the ridge bends, by acos (-1/3)
      // Angles come from a polynomial arctangent, within 4e-8 radians each.
      EXPECT_NEAR (result.cost_after, (n - 1) * std::acos (-1.0 / 3.0), (n - 1) * 4e-8);
    }
    for (int i = 0; i + 1 < n; ++i)
      EXPECT_TRUE (hasEdge (work, id (i, i), id (i + 1, i + 1))) << "ridge edge " << i;
    EXPECT_TRUE (checkMesh (points, work).isDiscLike ());
    expectSameTopology (points, input, work);
  }
}

namespace {

/** Random points on two planes meeting at a crease (a ridge or a valley, at an
  * angle to the axes), with the Delaunay triangulation of their projection: fans
  * of triangles cross the crease and cut it off. */
struct CreaseSample
{
  CreaseSample (double slope, std::uint32_t seed, std::size_t size)
    : slope (slope), across (std::cos (0.4), std::sin (0.4)),
      spacing (2.0 / std::sqrt (static_cast<double> (size)))
  {
    std::mt19937 random (seed);
    std::uniform_real_distribution<double> coordinate (-1.0, 1.0);
    Points2 flat (size);
    for (auto& q : flat) {
      q = Eigen::Vector2d (coordinate (random), coordinate (random));
      points.emplace_back (q.x (), q.y (), -slope * std::abs (q.dot (across)));
    }
    const Delaunay2DResult delaunay = delaunay2D (flat);
    EXPECT_TRUE (delaunay.success) << delaunay.message;
    triangles = delaunay.triangles;
  }

  /** Distance to the two half-planes, in the plane of `across` and z. */
  double
  distance (const Eigen::Vector3d& p) const
  {
    const Eigen::Vector2d uz (p.head<2> ().dot (across), p.z ());
    double best = uz.norm ();
    for (const double side : {1.0, -1.0}) {
      const Eigen::Vector2d ray = Eigen::Vector2d (side, -slope).normalized ();
      const double along = uz.dot (ray);
      if (along > 0.0)
        best = std::min (best, (uz - along * ray).norm ());
    }
    return best;
  }

  /** Largest and mean distance of the centroids and edge midpoints, in spacings,
    * away from the square's sides (the convex hull's slivers there are the same in
    * all runs). */
  std::pair<double, double>
  distances (const Triangles& mesh) const
  {
    double far = 0.0, sum = 0.0;
    std::size_t count = 0;
    for (const Triangle& t : mesh) {
      const Eigen::Vector3d &a = points[t[0]], &b = points[t[1]], &c = points[t[2]];
      if (std::max ({a.head<2> ().lpNorm<Eigen::Infinity> (), b.head<2> ().lpNorm<Eigen::Infinity> (),
                     c.head<2> ().lpNorm<Eigen::Infinity> ()}) > 0.8)
        continue;
      for (const Eigen::Vector3d& q : {Eigen::Vector3d ((a + b + c) / 3.0), Eigen::Vector3d ((a + b) / 2.0),
                                       Eigen::Vector3d ((b + c) / 2.0), Eigen::Vector3d ((c + a) / 2.0)}) {
        far = std::max (far, distance (q));
        sum += distance (q);
        ++count;
      }
    }
    return {far / spacing, sum / static_cast<double> (std::max<std::size_t> (count, 1)) / spacing};
  }

  /** The swaps on a copy of the Delaunay triangles, checked to keep the topology
    * and to leave no intersecting pair. */
  EdgeSwapResult
  optimize (const EdgeSwapOptions& options, Triangles& work) const
  {
    work = triangles;
    const EdgeSwapResult result = optimizeBySwaps (points, work, options);
    EXPECT_TRUE (result.success) << result.message;
    expectSameTopology (points, triangles, work);
    EXPECT_EQ (result.self_intersections_after, 0u);
    return result;
  }

  double slope;
  Eigen::Vector2d across;
  double spacing;
  Points3 points;
  Triangles triangles;
};

} // namespace

TEST (EdgeSwap, LookAheadFollowsCreases)
{
  // The descent alone stops where several swaps must change together; the
  // look-ahead goes on to a lower cost and brings the triangles nearer the surface.
  double sum_descent = 0.0, sum_look_ahead = 0.0;
  for (const double slope : {0.6, -0.8, 1.0})
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      SCOPED_TRACE ("slope " + std::to_string (slope) + " seed " + std::to_string (seed));
      const CreaseSample sample (slope, seed, 600);
      const auto farthest = [&] (const Triangles& mesh) { return sample.distances (mesh).first; };
      // The descent and the look-ahead alone.
      EdgeSwapOptions descent;
      descent.improve_angles = false;
      descent.look_ahead_depth = 0;
      descent.crease_look_ahead_depth = 0;
      EdgeSwapOptions look_ahead = descent;
      look_ahead.look_ahead_depth = 4;
      Triangles by_descent, by_look_ahead;
      const EdgeSwapResult r0 = sample.optimize (descent, by_descent);
      const EdgeSwapResult r1 = sample.optimize (look_ahead, by_look_ahead);
      EXPECT_GT (r1.look_ahead_swaps, 0u);
      EXPECT_EQ (r1.swaps, r1.descent_swaps + r1.look_ahead_swaps + r1.intersection_swaps);
      EXPECT_LT (r1.cost_after, 0.9 * r0.cost_after);
      // A limit on the swaps holds with the look-ahead's tried ones among them.
      EdgeSwapOptions limited = look_ahead;
      limited.max_swaps = r0.descent_swaps + 7;
      Triangles by_limited;
      EXPECT_LE (sample.optimize (limited, by_limited).swaps, limited.max_swaps);
      EXPECT_LE (farthest (by_look_ahead), farthest (by_descent));
      sum_descent += farthest (by_descent);
      sum_look_ahead += farthest (by_look_ahead);
      // All passes: the angle pass runs last and makes quads that turn less than
      // its bound locally Delaunay again, so here it undoes most of that; the
      // look-ahead must not leave the mesh farther from the surface.
      Triangles by_defaults;
      sample.optimize (EdgeSwapOptions (), by_defaults);
      EdgeSwapOptions without = EdgeSwapOptions ();
      without.look_ahead_depth = 0;
      without.crease_look_ahead_depth = 0;
      Triangles by_without;
      sample.optimize (without, by_without);
      EXPECT_LE (farthest (by_defaults), farthest (by_without));
    }
  EXPECT_LT (sum_look_ahead, 0.6 * sum_descent);
}

TEST (EdgeSwap, CreaseLookAheadGoesDeeperAtSharpCreases)
{
  // Creases turning by 2 atan |slope|: after the look-ahead's rounds, deeper
  // sequences from the crease's edges lower the cost further (never raise it:
  // they start where the first rounds stopped) and bring the triangles nearer.
  // A crease turning by less than their 45 degrees gives them no start.
  double sum_first = 0.0, sum_crease = 0.0;
  std::size_t members = 0, crease_kept = 0;
  for (const double slope : {0.3, 0.6, -0.8, 1.0, 1.5, -2.0})
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      SCOPED_TRACE ("slope " + std::to_string (slope) + " seed " + std::to_string (seed));
      const CreaseSample sample (slope, seed, 600);
      EdgeSwapOptions first;
      first.improve_angles = false;
      first.crease_look_ahead_depth = 0;
      EdgeSwapOptions crease = first;
      crease.crease_look_ahead_depth = 8;
      Triangles by_first, by_crease;
      const EdgeSwapResult r0 = sample.optimize (first, by_first);
      const EdgeSwapResult r1 = sample.optimize (crease, by_crease);
      EXPECT_EQ (r1.swaps, r1.descent_swaps + r1.look_ahead_swaps + r1.intersection_swaps);
      if (std::abs (slope) < 0.4) {
        EXPECT_EQ (by_crease, by_first);
        continue;
      }
      EXPECT_LE (r1.cost_after, r0.cost_after);
      ++members;
      if (r1.cost_after < r0.cost_after)
        ++crease_kept;
      sum_first += sample.distances (by_first).second;
      sum_crease += sample.distances (by_crease).second;
      // A limit on the swaps holds with the deeper sequences' tried ones among them.
      EdgeSwapOptions limited = crease;
      limited.max_swaps = r0.swaps + 5;
      Triangles by_limited;
      EXPECT_LE (sample.optimize (limited, by_limited).swaps, limited.max_swaps);
    }
  EXPECT_GE (4 * crease_kept, 3 * members);
  EXPECT_LT (sum_crease, 0.8 * sum_first);
}

TEST (EdgeSwap, LookAheadLeavesAFlatDelaunayMeshAlone)
{
  // Nothing turns: no sequence starts, and the triangles come back as they went in.
  const CreaseSample flat (0.0, 3, 400);
  Triangles work;
  const EdgeSwapResult result = flat.optimize (EdgeSwapOptions (), work);
  EXPECT_EQ (result.swaps, 0u);
  EXPECT_EQ (result.look_ahead_swaps, 0u);
  EXPECT_EQ (work, flat.triangles);
}

TEST (EdgeSwap, DescentMakesNoEdgeLongerThanItsQuad)
{
  // A gentle ridge grid stretched along the ridge (x = y) by 1.5: the ridge edges
  // the curvature descent makes are now the longest edge of their quads (2.12
  // against sides of 1.37 and the old diagonal 1.41).
  const int n = 7;
  Points3 points;
  Triangles input;
  ridgeGrid (n, 0.5, points, input);
  for (Eigen::Vector3d& p : points) {
    const double along = 0.75 * (p.x () + p.y ()), across = 0.5 * (p.x () - p.y ());
    p = Eigen::Vector3d (along + across, along - across, p.z ());
  }
  const auto id = [n] (int i, int j) { return static_cast<pcl::index_t> (j * n + i); };
  const auto longest = [&] (const Triangles& triangles) {
    double length = 0.0;
    for (const Triangle& t : triangles)
      for (int k = 0; k < 3; ++k)
        length = std::max (length, (points[t[k]] - points[t[(k + 1) % 3]]).norm ());
    return length;
  };
  for (const bool keep : {false, true}) {
    SCOPED_TRACE (keep ? "rule on" : "rule off");
    Triangles work = input;
    EdgeSwapOptions options;
    options.improve_angles = false;
    options.descent_keeps_longest_edge = keep;
    const EdgeSwapResult result = optimizeBySwaps (points, work, options);
    ASSERT_TRUE (result.success) << result.message;
    expectSameTopology (points, input, work);
    for (int i = 0; i + 1 < n; ++i)
      EXPECT_EQ (hasEdge (work, id (i, i), id (i + 1, i + 1)), !keep) << "ridge edge " << i;
    if (keep) {
      EXPECT_EQ (result.descent_swaps, 0u);
      EXPECT_EQ (longest (work), longest (input));
    }
    else {
      EXPECT_EQ (result.descent_swaps, static_cast<std::size_t> (n - 1));
      EXPECT_GT (longest (work), longest (input));
    }
  }
}

TEST (EdgeSwap, AnglePassTakesShortDiagonalsAndKeepsTheRidge)
{
  // The same ridge: on each tilted half the grid cells are rhombi with angles of 60
  // and 120 degrees; the angle pass must cut every flat rhombus along its short
  // diagonal (both triangles equilateral) and leave the ridge (70.5 degrees) alone.
  const int n = 7;
  Points3 points;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      points.emplace_back (i, j, -std::abs (i - j));
  const auto id = [n] (int i, int j) { return static_cast<pcl::index_t> (j * n + i); };
  Triangles triangles;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      triangles.push_back ({id (i, j), id (i + 1, j), id (i, j + 1)});
      triangles.push_back ({id (i + 1, j), id (i + 1, j + 1), id (i, j + 1)});
    }
  const Triangles input = triangles;
  const EdgeSwapResult result = optimizeBySwaps (points, triangles);
  ASSERT_TRUE (result.success) << result.message;
  for (int i = 0; i + 1 < n; ++i)
    EXPECT_TRUE (hasEdge (triangles, id (i, i), id (i + 1, i + 1))) << "ridge edge " << i;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      // Short diagonal of the rhombus (length sqrt 2 against sqrt 6): between the
      // two corners at the same height, (i, j) and (i + 1, j + 1), on both halves.
      EXPECT_TRUE (hasEdge (triangles, id (i, j), id (i + 1, j + 1))) << "cell " << i << "," << j;
    }
  const MeshReport report = checkMesh (points, triangles);
  EXPECT_TRUE (report.isDiscLike ());
  EXPECT_NEAR (report.mean_min_angle_deg, 60.0, 1e-6);
  expectSameTopology (points, input, triangles);
}

TEST (EdgeSwap, ScrambledSphereIsRepaired)
{
  Points3 points;
  Triangles triangles;
  scrambledSphere (points, triangles);
  const MeshReport before = checkMesh (points, triangles);
  ASSERT_TRUE (before.isSphereLike ());
  for (const SwapCost cost : {SwapCost::AngleBetweenNormals, SwapCost::IntegratedMeanCurvature,
                              SwapCost::SquaredMeanCurvature, SwapCost::TotalAbsoluteCurvature}) {
    Triangles work = triangles;
    EdgeSwapOptions options;
    options.cost = cost;
    std::vector<char> rewritten (triangles.size (), 0);
    options.rewritten = &rewritten;
    const EdgeSwapResult result = optimizeBySwaps (points, work, options);
    ASSERT_TRUE (result.success) << result.message;
    EXPECT_GT (result.swaps, 0u);
    // Every slot whose triangle changed is marked (MeshCheckOptions::known_apart
    // relies on it).
    std::size_t changed = 0;
    for (std::size_t t = 0; t < work.size (); ++t)
      if (work[t] != triangles[t]) {
        ++changed;
        EXPECT_TRUE (rewritten[t]) << "slot " << t << " changed unmarked";
      }
    EXPECT_GT (changed, 0u);
    EXPECT_LT (result.cost_after, result.cost_before);
    const MeshReport after = checkMesh (points, work);
    EXPECT_TRUE (after.isSphereLike ());
    EXPECT_EQ (after.self_intersecting_pairs, 0u);
    EXPECT_EQ (result.self_intersections_before, before.self_intersecting_pairs);
    EXPECT_EQ (result.self_intersections_after, 0u);
    EXPECT_GT (after.mean_min_angle_deg, before.mean_min_angle_deg + 5.0);
    EXPECT_NEAR (after.signed_volume, before.signed_volume, 1e-9 + 0.05 * before.signed_volume);
    expectSameTopology (points, triangles, work);
  }
}

TEST (EdgeSwap, MaxSwapsIsHonoured)
{
  Points3 points;
  Triangles triangles;
  scrambledSphere (points, triangles);
  EdgeSwapOptions options;
  options.max_swaps = 5;
  const Triangles input = triangles;
  const EdgeSwapResult result = optimizeBySwaps (points, triangles, options);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_EQ (result.swaps, 5u);
  EXPECT_LT (result.cost_after, result.cost_before);
  expectSameTopology (points, input, triangles);
}

TEST (EdgeSwap, FoldIsRemoved)
{
  // A flat 5 x 5 grid cut by the diagonals i,j - i+1,j+1, with vertex (3,3) pulled
  // towards (2,2) so that the quad (2,2), (3,2), (3,3), (2,3) is a dart; flipping
  // its diagonal (2,2)-(3,3) folds two triangles over each other.
  const int n = 5;
  Points3 points;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      points.emplace_back (i, j, 0.05 * (i * i + j * j)); // a gentle bowl
  const auto id = [n] (int i, int j) { return static_cast<pcl::index_t> (j * n + i); };
  points[id (3, 3)] = Eigen::Vector3d (2.3, 2.3, 0.05 * 2 * 2.3 * 2.3);
  Triangles triangles;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      triangles.push_back ({id (i, j), id (i + 1, j), id (i + 1, j + 1)});
      triangles.push_back ({id (i, j), id (i + 1, j + 1), id (i, j + 1)});
    }
  ASSERT_EQ (checkMesh (points, triangles).self_intersecting_pairs, 0u);
  ASSERT_TRUE (flipEdge (triangles, id (2, 2), id (3, 3)));
  const MeshReport before = checkMesh (points, triangles);
  ASSERT_TRUE (before.isDiscLike ());
  ASSERT_GT (before.self_intersecting_pairs, 0u);

  for (const bool targeted : {true, false}) {
    Triangles work = triangles;
    EdgeSwapOptions options;
    options.remove_self_intersections = targeted;
    const EdgeSwapResult result = optimizeBySwaps (points, work, options);
    ASSERT_TRUE (result.success) << result.message;
    const MeshReport after = checkMesh (points, work);
    EXPECT_EQ (after.self_intersecting_pairs, 0u) << "targeted " << targeted;
    EXPECT_TRUE (after.isDiscLike ());
    expectSameTopology (points, triangles, work);
    if (targeted) {
      EXPECT_EQ (result.self_intersections_before, before.self_intersecting_pairs);
      EXPECT_EQ (result.self_intersections_after, 0u);
    }
  }
}

TEST (EdgeSwap, IsDeterministic)
{
  Points3 points;
  Triangles triangles;
  scrambledSphere (points, triangles);
  for (const SwapCost cost : {SwapCost::AngleBetweenNormals, SwapCost::TotalAbsoluteCurvature}) {
    EdgeSwapOptions options;
    options.cost = cost;
    Triangles first = triangles, second = triangles;
    const EdgeSwapResult r1 = optimizeBySwaps (points, first, options);
    const EdgeSwapResult r2 = optimizeBySwaps (points, second, options);
    ASSERT_TRUE (r1.success && r2.success);
    EXPECT_EQ (first, second);
    EXPECT_EQ (r1.swaps, r2.swaps);
    EXPECT_EQ (r1.cost_after, r2.cost_after);
  }
}

TEST (EdgeSwap, RejectsInvalidInputUntouched)
{
  const Points3 points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  const std::vector<Triangles> bad{
      {{0, 1, 2}, {0, 1, 3}},                          // inconsistent orientation
      {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}},               // edge in three triangles
      {{0, 1, 7}},                                     // index out of range
      {{0, 1, 1}},                                     // repeated index
      {{0, 1, 2}, {0, 3, 4}}};                         // bowtie: two fans at vertex 0
  for (const Triangles& input : bad) {
    Triangles work = input;
    const EdgeSwapResult result = optimizeBySwaps (points, work);
    EXPECT_FALSE (result.success);
    EXPECT_FALSE (result.message.empty ());
    EXPECT_EQ (work, input);
  }
}

TEST (EdgeSwap, EmptyMeshIsFine)
{
  Triangles triangles;
  const EdgeSwapResult result = optimizeBySwaps ({}, triangles);
  EXPECT_TRUE (result.success) << result.message;
  EXPECT_EQ (result.swaps, 0u);
}

TEST (EdgeSwap, FlatEdgesAreLeftToTheAnglePass)
{
  // The ridge of RidgeEdgesAppearInHeightField made shallow: its faces turn by 4.9
  // degrees, below descent_min_dihedral_deg, so the descent leaves the cells alone.
  const int n = 7;
  Points3 points;
  Triangles triangles;
  ridgeGrid (n, 0.03, points, triangles);
  const auto id = [n] (int i, int j) { return static_cast<pcl::index_t> (j * n + i); };
  EdgeSwapOptions options;
  options.improve_angles = false;
  Triangles work = triangles;
  EdgeSwapResult result = optimizeBySwaps (points, work, options);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_EQ (result.descent_swaps, 0u);
  EXPECT_EQ (work, triangles);
  // Without the bound the descent finds the ridge, as on the steep one.
  options.descent_min_dihedral_deg = 0.0;
  work = triangles;
  result = optimizeBySwaps (points, work, options);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_EQ (result.descent_swaps, static_cast<std::size_t> (n - 1));
  for (int i = 0; i + 1 < n; ++i)
    EXPECT_TRUE (hasEdge (work, id (i, i), id (i + 1, i + 1))) << "ridge edge " << i;
}

TEST (EdgeSwap, PassesAreCountedSeparately)
{
  Points3 points;
  Triangles triangles;
  scrambledSphere (points, triangles);
  const EdgeSwapResult result = optimizeBySwaps (points, triangles);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_GT (result.descent_swaps, 0u);
  EXPECT_EQ (result.swaps, result.descent_swaps + result.look_ahead_swaps +
                               result.intersection_swaps + result.angle_swaps);
}

TEST (EdgeSwap, NoisyInputStaysCloseToTheSurface)
{
  // 642 points of the unit sphere shaken by up to 0.08 in each coordinate, about
  // 60% of their spacing: the median turn between adjacent faces is 35 degrees, so
  // the input counts as noisy. Lowering the curvature alone moves the surface off
  // the true sphere (here by 7%); with the rule the mesh ends closer to it than it
  // started, its normals closer too, and no pair of triangles left intersecting.
  Points3 points, sphere_points;
  Triangles triangles, sphere;
  shakenSphere (3, 0.08, 11, points, triangles);
  icosphere (6, sphere_points, sphere);
  MeshDistanceOptions distance_options;
  distance_options.samples = 50000;
  const MeshDistanceReport before =
      compareToReference (points, triangles, sphere_points, sphere, distance_options);
  ASSERT_TRUE (before.success) << before.message;

  Triangles work = triangles;
  const EdgeSwapResult result = optimizeBySwaps (points, work);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_TRUE (result.noisy) << "median dihedral " << result.median_dihedral_deg;
  EXPECT_GT (result.descent_swaps, 0u);
  const MeshDistanceReport after =
      compareToReference (points, work, sphere_points, sphere, distance_options);
  EXPECT_LT (after.two_sided.mean, before.two_sided.mean);
  EXPECT_LT (after.normal_deviation_deg, before.normal_deviation_deg);
  EXPECT_LT (result.self_intersections_after, result.self_intersections_before);
  expectSameTopology (points, triangles, work);

  // The rule off: the descent pulls the surface away from the sphere.
  EdgeSwapOptions off;
  off.noisy_median_dihedral_deg = 180.0;
  Triangles free = triangles;
  const EdgeSwapResult unruled = optimizeBySwaps (points, free, off);
  ASSERT_TRUE (unruled.success) << unruled.message;
  EXPECT_FALSE (unruled.noisy);
  const MeshDistanceReport far =
      compareToReference (points, free, sphere_points, sphere, distance_options);
  EXPECT_GT (far.two_sided.mean, before.two_sided.mean);
}

TEST (EdgeSwap, CleanSphereIsNotNoisy)
{
  Points3 points;
  Triangles triangles;
  scrambledSphere (points, triangles);
  const EdgeSwapResult result = optimizeBySwaps (points, triangles);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_FALSE (result.noisy);
  EXPECT_LT (result.median_dihedral_deg, 25.0);
}

TEST (EdgeSwap, IntersectionCountsMatchCheckMesh)
{
  // Points shaken by about their spacing: a crumpled mesh with hundreds of
  // intersecting pairs of every kind (sharing an edge, a vertex, nothing), which the
  // optimizer's own count (plane filters first, exact tests after) must match.
  Points3 points;
  Triangles triangles;
  shakenSphere (3, 0.12, 11, points, triangles);
  const MeshReport before = checkMesh (points, triangles);
  ASSERT_GT (before.self_intersecting_pairs, 100u);
  for (const SwapCost cost : {SwapCost::AngleBetweenNormals, SwapCost::IntegratedMeanCurvature,
                              SwapCost::TotalAbsoluteCurvature}) {
    EdgeSwapOptions options;
    options.cost = cost;
    Triangles work = triangles;
    const EdgeSwapResult result = optimizeBySwaps (points, work, options);
    ASSERT_TRUE (result.success) << result.message;
    const MeshReport after = checkMesh (points, work);
    EXPECT_EQ (result.self_intersections_before, before.self_intersecting_pairs);
    EXPECT_EQ (result.self_intersections_after, after.self_intersecting_pairs);
    EXPECT_LE (after.self_intersecting_pairs, before.self_intersecting_pairs);
    EXPECT_TRUE (after.isSphereLike ());
    expectSameTopology (points, triangles, work);
  }
}

TEST (EdgeSwap, InputKnownFreeOfIntersectionsSkipsOnlyTheFirstCount)
{
  // Without pairs, trusting the caller changes nothing; with pairs, the skipped
  // count is missing (the promise was wrong), which is why the class makes it
  // only after checkMesh and the fold repair have counted none.
  EdgeSwapOptions counting, trusting;
  trusting.input_free_of_intersections = true;
  Points3 points;
  Triangles triangles;
  shakenSphere (3, 0.03, 11, points, triangles);
  ASSERT_EQ (checkMesh (points, triangles).self_intersecting_pairs, 0u);
  Triangles counted = triangles, trusted = triangles;
  const EdgeSwapResult a = optimizeBySwaps (points, counted, counting);
  const EdgeSwapResult b = optimizeBySwaps (points, trusted, trusting);
  ASSERT_TRUE (a.success && b.success);
  EXPECT_GT (a.swaps, 0u);
  EXPECT_EQ (counted, trusted);
  EXPECT_EQ (a.swaps, b.swaps);
  // The swaps still count what they would create: none here, in the mesh itself.
  EXPECT_EQ (b.self_intersections_after, 0u);
  EXPECT_EQ (checkMesh (points, trusted).self_intersecting_pairs, 0u);

  shakenSphere (3, 0.12, 11, points, triangles);
  counted = trusted = triangles;
  const EdgeSwapResult c = optimizeBySwaps (points, counted, counting);
  const EdgeSwapResult d = optimizeBySwaps (points, trusted, trusting);
  ASSERT_TRUE (c.success && d.success);
  EXPECT_GT (c.self_intersections_before, 100u);
  EXPECT_EQ (d.self_intersections_before, 0u);
  EXPECT_TRUE (checkMesh (points, trusted).isSphereLike ());
}

TEST (EdgeSwap, PointsInFirstUseOrderNeedNoRenumbering)
{
  Points3 shaken;
  Triangles shaken_triangles;
  shakenSphere (3, 0.12, 11, shaken, shaken_triangles);
  // The same mesh with its points numbered in the order the triangles first use
  // them, the numbering the optimizer makes for itself: without renumbering it must
  // do exactly the same, on the caller's points.
  std::vector<pcl::index_t> renumbered (shaken.size (), -1);
  Points3 points;
  Triangles triangles = shaken_triangles;
  for (Triangle& t : triangles)
    for (pcl::index_t& v : t) {
      if (renumbered[v] < 0) {
        renumbered[v] = static_cast<pcl::index_t> (points.size ());
        points.push_back (shaken[v]);
      }
      v = renumbered[v];
    }
  ASSERT_EQ (points.size (), shaken.size ());
  EdgeSwapOptions renumbering, in_place;
  in_place.renumber_vertices = false;
  Triangles a = triangles, b = triangles;
  const EdgeSwapResult ra = optimizeBySwaps (points, a, renumbering);
  const EdgeSwapResult rb = optimizeBySwaps (points, b, in_place);
  ASSERT_TRUE (ra.success && rb.success);
  EXPECT_GT (ra.swaps, 0u);
  EXPECT_EQ (a, b);
  EXPECT_EQ (ra.swaps, rb.swaps);
  EXPECT_EQ (ra.self_intersections_before, rb.self_intersections_before);

  // In any other order the result is as valid, with the same counts as checkMesh.
  Triangles c = shaken_triangles;
  const EdgeSwapResult rc = optimizeBySwaps (shaken, c, in_place);
  ASSERT_TRUE (rc.success);
  const MeshReport report = checkMesh (shaken, c);
  EXPECT_TRUE (report.isSphereLike ());
  EXPECT_EQ (rc.self_intersections_after, report.self_intersecting_pairs);
  EXPECT_LT (rc.cost_after, rc.cost_before);

  // A point no triangle uses: renumbered all the same (the optimizer works on used
  // vertices only), so the result is the renumbering one's.
  Points3 with_unused = points;
  with_unused.push_back (Eigen::Vector3d (5.0, 5.0, 5.0));
  Triangles d = triangles;
  const EdgeSwapResult rd = optimizeBySwaps (with_unused, d, in_place);
  ASSERT_TRUE (rd.success) << rd.message;
  EXPECT_EQ (d, a);
}

TEST (EdgeSwap, SameResultForAnyThreadCount)
{
  Points3 points;
  Triangles triangles;
  shakenSphere (3, 0.12, 11, points, triangles);
  Triangles results[2];
  EdgeSwapResult reports[2];
  for (int k = 0; k < 2; ++k) {
    EdgeSwapOptions options;
    options.num_threads = k + 1;
    results[k] = triangles;
    reports[k] = optimizeBySwaps (points, results[k], options);
    ASSERT_TRUE (reports[k].success) << reports[k].message;
  }
  EXPECT_EQ (results[0], results[1]);
  EXPECT_EQ (reports[0].swaps, reports[1].swaps);
  EXPECT_EQ (reports[0].self_intersections_before, reports[1].self_intersections_before);
  EXPECT_EQ (reports[0].cost_after, reports[1].cost_after);
}
