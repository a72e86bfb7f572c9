#include <pcl/surface/meshless/convex_hull.h>
#include <pcl/surface/meshless/mesh_checks.h>

#include <gtest/gtest.h>

#include <limits>
#include <random>

using namespace pcl::meshless;

namespace {

/** The hull must be a closed, outward, embedded sphere through every point. */
void
expectClosedThroughAll (const Points3& points, const Triangles& hull)
{
  ASSERT_EQ (hull.size (), 2 * points.size () - 4);
  const MeshReport report = checkMesh (points, hull);
  EXPECT_TRUE (report.isSphereLike ()) << describe (report);
  EXPECT_EQ (report.unused_vertices, 0u);
  EXPECT_GT (report.signed_volume, 0.0) << "outward";
  EXPECT_EQ (report.self_intersecting_pairs, 0u);
}

Points3
onSphere (std::size_t n, std::uint32_t seed)
{
  std::mt19937 random (seed);
  std::normal_distribution<double> gauss;
  Points3 points;
  while (points.size () < n)
    points.push_back (Eigen::Vector3d (gauss (random), gauss (random), gauss (random)).normalized ());
  return points;
}

} // namespace

TEST (ConvexHull, TetrahedronAndOctahedron)
{
  const Points3 tetrahedron{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  expectClosedThroughAll (tetrahedron, convexHullThroughAll (tetrahedron));
  Points3 octahedron;
  for (int axis = 0; axis < 3; ++axis)
    for (const double s : {1.0, -1.0}) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero ();
      p[axis] = s;
      octahedron.push_back (p);
    }
  expectClosedThroughAll (octahedron, convexHullThroughAll (octahedron));
}

TEST (ConvexHull, RandomPointsOnASphere)
{
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    const Points3 points = onSphere (60, seed);
    expectClosedThroughAll (points, convexHullThroughAll (points));
  }
}

TEST (ConvexHull, NoHullThroughEveryPointIsEmpty)
{
  // A point inside.
  Points3 inside = onSphere (20, 4);
  inside.push_back (Eigen::Vector3d (0.1, 0.0, 0.0));
  EXPECT_TRUE (convexHullThroughAll (inside).empty ());
  // A cube: square faces, four coplanar points each, no unique triangles.
  Points3 cube;
  for (int i = 0; i < 8; ++i)
    cube.push_back (Eigen::Vector3d (i & 1, (i >> 1) & 1, (i >> 2) & 1));
  EXPECT_TRUE (convexHullThroughAll (cube).empty ());
  // Flat, too few, too many, not finite.
  EXPECT_TRUE (convexHullThroughAll ({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 3, 0}}).empty ());
  EXPECT_TRUE (convexHullThroughAll ({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).empty ());
  const Points3 many = onSphere (40, 5);
  EXPECT_TRUE (convexHullThroughAll (many, 39).empty ());
  EXPECT_FALSE (convexHullThroughAll (many, 40).empty ());
  Points3 nan = onSphere (10, 6);
  nan[3].x () = std::numeric_limits<double>::quiet_NaN ();
  EXPECT_TRUE (convexHullThroughAll (nan).empty ());
}
