// Orienting the least-squares normals (normal_orientation.h): one outward sign on
// round shapes and on thin limbs.
#include <pcl/surface/meshless/normal_orientation.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <meshless_tools/synthetic_clouds.h>

#include <meshless_tools/cloud_io.h>
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace pcl::meshless;

namespace {

/** Normals, rings and graphs as buildSurfaceGraphs makes them before orienting. */
struct Unoriented
{
  CsrGraph graph, mutual;
  OrderedNeighbourhoods ordered;
};

Unoriented
unoriented (const Points3& points, int k)
{
  Unoriented result;
  result.graph = meshless_test::bruteForceKnnGraph (points, k);
  result.ordered = orderNeighbourhoods (points, result.graph);
  result.mutual = mutualRingGraph (result.ordered.rings);
  return result;
}

} // namespace

TEST (NormalOrientation, BumpySphereFacesOutwardEverywhere)
{
  const Points3 points = sampleShape (SyntheticShape::BumpySphere, {3000, 11, 0.0});
  Unoriented surface = unoriented (points, 12);
  ASSERT_TRUE (surface.ordered.success);
  const NormalOrientation result =
      orientNormals (points, surface.graph, surface.mutual, surface.ordered);
  ASSERT_TRUE (result.success) << result.message;
  EXPECT_EQ (result.num_components, 1u);
  for (std::size_t v = 0; v < points.size (); ++v)
    ASSERT_GT (surface.ordered.normals[v].cast<double> ().dot (points[v]), 0.0)
        << "point " << v << " of a star-shaped cloud faces inwards";
}

TEST (NormalOrientation, CowLegsFaceOutwards)
{
  // cow_igl's legs are five or six points around, thinner than twice the point
  // spacing: kNN edges cross them, and a spanning tree through one such edge
  // turned a whole lower leg inwards (144 of the lowest tenth of the points,
  // before the regions' consensus). Judged against the reference mesh the cloud
  // was sampled from (its vertices), whose faces turn outwards.
  MESHLESS_REQUIRE_SHARED_FILE (cloud_path, "clouds/cow_igl.pcd");
  MESHLESS_REQUIRE_SHARED_FILE (mesh_path, "meshes/cow_igl.ply");
  pcl::PointCloud<pcl::PointXYZ> cloud;
  ASSERT_EQ (meshless_tools::loadCloud (cloud_path, cloud), "");
  const Points3 points = meshless_tools::toPoints (cloud);
  Points3 vertices;
  Triangles triangles;
  ASSERT_EQ (meshless_tools::loadMesh (mesh_path, vertices, triangles), "");

  // Reference normals (area-weighted) at the cloud's points: each point is a vertex.
  std::vector<Eigen::Vector3d> vertex_normal (vertices.size (), Eigen::Vector3d::Zero ());
  for (const Triangle& t : triangles) {
    const Eigen::Vector3d area =
        (vertices[t[1]] - vertices[t[0]]).cross (vertices[t[2]] - vertices[t[0]]);
    for (const pcl::index_t x : t)
      vertex_normal[x] += area;
  }
  double volume = 0.0;
  for (const Triangle& t : triangles)
    volume += vertices[t[0]].dot (vertices[t[1]].cross (vertices[t[2]]));
  ASSERT_GT (volume, 0.0) << "the reference mesh should turn outwards";

  // In the file's order (the pipeline numbers the points along a Z-order curve
  // first; the spanning trees break ties by number): measured 0 of 276 inwards in
  // both orders, 144 in both before the consensus.
  Unoriented surface = unoriented (points, 12);
  ASSERT_TRUE (surface.ordered.success);
  ASSERT_TRUE (orientNormals (points, surface.graph, surface.mutual, surface.ordered).success);

  // The lowest tenth of the points (the cow stands along -y): hooves and lower legs.
  std::vector<double> heights;
  for (const auto& p : points)
    heights.push_back (p.y ());
  std::nth_element (heights.begin (), heights.begin () + heights.size () / 10, heights.end ());
  const double cut = heights[heights.size () / 10];
  std::size_t low = 0, inwards = 0;
  for (std::size_t v = 0; v < points.size (); ++v) {
    if (!(points[v].y () < cut))
      continue;
    ++low;
    const auto nearest = std::min_element (vertices.begin (), vertices.end (),
                                           [&] (const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
                                             return (a - points[v]).squaredNorm () <
                                                    (b - points[v]).squaredNorm ();
                                           }) -
                         vertices.begin ();
    ASSERT_LT ((vertices[nearest] - points[v]).norm (), 1e-6) << "point " << v << " is not a vertex";
    inwards += surface.ordered.normals[v].cast<double> ().dot (vertex_normal[nearest]) < 0.0;
  }
  EXPECT_GT (low, 200u);
  EXPECT_EQ (inwards, 0u) << "of " << low << " points on the lower legs";
}
