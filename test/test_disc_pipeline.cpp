// Open surfaces: boundary loops from the rings, one disc patch, holes kept open.
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <pcl/surface/meshless/disc_pipeline.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <pcl/surface/meshless/normal_orientation.h>
#include <meshless_tools/synthetic_clouds.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include "test_support.h"

#include <Eigen/Geometry>

#include <cmath>

using namespace pcl::meshless;

namespace {

constexpr double pi = 3.14159265358979323846;

void
expectDisc (const Points3& points, const DiscTriangulation& result, std::size_t holes = 0)
{
  ASSERT_TRUE (result.success) << result.message;
  const MeshReport report = checkMesh (points, result.triangles);
  EXPECT_TRUE (report.isManifold ()) << describe (report);
  EXPECT_TRUE (report.isOriented ()) << describe (report);
  EXPECT_EQ (report.components, 1u);
  EXPECT_EQ (report.unused_vertices, 0u) << "every point a vertex";
  EXPECT_EQ (report.boundary_loops, 1 + holes);
  EXPECT_EQ (report.euler_characteristic, 1 - static_cast<long> (holes));
  EXPECT_EQ (report.self_intersecting_pairs, 0u) << describe (report);
}

Points3
hemisphere (std::size_t n)
{
  Points3 points;
  for (const auto& p : sampleShape (SyntheticShape::Sphere, {2 * n, 3, 0.0}))
    if (p.z () > 0.05)
      points.push_back (p);
  return points;
}

} // namespace

TEST (DiscPipeline, BoundaryLoopOfAFlatDiscGoesRoundTheRim)
{
  const Points3 points = sampleShape (SyntheticShape::Disc, {2000, 2, 0.0});
  const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
  OrderedNeighbourhoods ordered = orderNeighbourhoods (points, graph);
  const CsrGraph mutual = mutualRingGraph (ordered.rings);
  orientNormals (points, graph, mutual, ordered);
  const BoundaryLoops loops =
      findBoundaryLoops (points, ordered.normals, ordered.rings, mutual, ordered.largest_gap);
  ASSERT_TRUE (loops.success) << loops.message;
  ASSERT_EQ (loops.loops.size (), 1u);
  const auto& loop = loops.loops[0];
  double turned = 0.0; // total polar angle swept: one full turn around the centre
  for (std::size_t k = 0; k < loop.size (); ++k) {
    const Eigen::Vector2d a = points[loop[k]].head<2> ();
    const Eigen::Vector2d b = points[loop[(k + 1) % loop.size ()]].head<2> ();
    EXPECT_GT (a.norm (), 0.9) << "a loop point away from the rim";
    turned += std::atan2 (a.x () * b.y () - a.y () * b.x (), a.dot (b));
  }
  EXPECT_NEAR (std::abs (turned), 2.0 * pi, 1e-9);
}

TEST (DiscPipeline, DiscHeightFieldAndHemisphereAreManifoldDiscs)
{
  for (SyntheticShape shape : {SyntheticShape::Disc, SyntheticShape::HeightField}) {
    const Points3 points = sampleShape (shape, {3000, 5, 0.0});
    expectDisc (points, triangulateDisc (points, meshless_test::bruteForceKnn (points, 12)));
  }
  const Points3 cap = hemisphere (2000);
  expectDisc (cap, triangulateDisc (cap, meshless_test::bruteForceKnn (cap, 12)));
}

TEST (DiscPipeline, InvariantUnderRotationAndScale)
{
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd (1.1, Eigen::Vector3d (0.2, -1, 0.5).normalized ()).toRotationMatrix ();
  for (double scale : {1e-4, 1e4}) {
    Points3 points = sampleShape (SyntheticShape::HeightField, {2500, 8, 0.0});
    for (auto& p : points)
      p = scale * (rotation * p);
    expectDisc (points, triangulateDisc (points, meshless_test::bruteForceKnn (points, 12)));
  }
}

TEST (DiscPipeline, AClosedCloudHasNoBoundary)
{
  const Points3 points = sampleShape (SyntheticShape::Sphere, {1500, 1, 0.0});
  const DiscTriangulation result = triangulateDisc (points, meshless_test::bruteForceKnn (points, 12));
  EXPECT_FALSE (result.success);
  EXPECT_NE (result.message.find ("no boundary loop"), std::string::npos) << result.message;
}

TEST (DiscPipeline, AHoleIsKeptOpen)
{
  // An annulus-like disc: a flat disc with a round hole off its centre.
  Points3 points;
  for (const auto& p : sampleShape (SyntheticShape::Disc, {4000, 3, 0.0}))
    if ((p.head<2> () - Eigen::Vector2d (0.2, 0.1)).norm () > 0.25)
      points.push_back (p);
  expectDisc (points, triangulateDisc (points, meshless_test::bruteForceKnn (points, 12)), 1);
}

TEST (DiscPipeline, PclPartialViewsGiveAManifoldMeshOrAClearMessage)
{
  // PCL's own single views: bunny.pcd (one open patch) and milk.pcd (a depth view
  // with shadows). Documented behaviour: a manifold, oriented mesh through every
  // point with the holes kept open, or an empty result and a message.
  for (const std::string name : {"bunny_pcl", "milk_pcl"}) {
    MESHLESS_REQUIRE_SHARED_FILE (path, "clouds/" + name + ".pcd");
    auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
    ASSERT_EQ (pcl::io::loadPCDFile (path, *cloud), 0);
    pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
    reconstruction.setTopology (pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>::Topology::Disc);
    reconstruction.setInputCloud (cloud);
    std::vector<pcl::Vertices> polygons;
    reconstruction.reconstruct (polygons);
    const auto& report = reconstruction.getReport ();
    if (report.success) {
      EXPECT_TRUE (report.mesh.isManifold ()) << name << ": " << describe (report.mesh);
      EXPECT_TRUE (report.mesh.isOriented ()) << name;
      EXPECT_EQ (report.mesh.unused_vertices, 0u) << name;
      EXPECT_EQ (report.mesh.boundary_loops, 1 + report.holes) << name;
    }
    else {
      EXPECT_TRUE (polygons.empty ()) << name;
      EXPECT_FALSE (report.message.empty ()) << name;
    }
    RecordProperty (name + "_success", report.success ? 1 : 0);
  }
}

TEST (DiscPipeline, FaceScanIsOneManifoldDiscThroughEveryPoint)
{
  MESHLESS_REQUIRE_SHARED_FILE (path, "clouds/face_igl.pcd");
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  ASSERT_EQ (pcl::io::loadPCDFile (path, *cloud), 0);
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setTopology (pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>::Topology::Disc);
  reconstruction.setInputCloud (cloud);
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  const auto& report = reconstruction.getReport ();
  ASSERT_TRUE (report.success) << report.message;
  EXPECT_EQ (report.num_points, cloud->size ());
  EXPECT_TRUE (report.mesh.isDiscLike ()) << describe (report.mesh);
  EXPECT_EQ (report.mesh.unused_vertices, 0u);
  EXPECT_EQ (report.mesh.self_intersecting_pairs, 0u) << describe (report.mesh);
}
