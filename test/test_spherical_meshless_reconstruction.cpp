// The PCL class: the public face, input hygiene, failure contract, and the
// invariants on real clouds.
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <meshless_tools/cloud_io.h>
#include <meshless_tools/mesh_distance.h>
#include <meshless_tools/synthetic_clouds.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include "test_support.h"

#include <limits>
#include <map>
#include <random>
#include <set>

namespace {

template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr
generatedCloud (pcl::meshless::SyntheticShape shape, const pcl::meshless::SyntheticCloudOptions& options)
{
  auto cloud = pcl::make_shared<pcl::PointCloud<PointT>> ();
  for (const auto& p : pcl::meshless::sampleShape (shape, options)) {
    PointT q;
    q.x = static_cast<float> (p.x ());
    q.y = static_cast<float> (p.y ());
    q.z = static_cast<float> (p.z ());
    cloud->push_back (q);
  }
  return cloud;
}

template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr
generatedCloud (pcl::meshless::SyntheticShape shape, std::size_t n, std::uint32_t seed = 1)
{
  return generatedCloud<PointT> (shape, {n, seed, 0.0});
}

/** Limbs a few spacings thick with noise and 10:1 density: the generated class
  * whose first base mesh keeps a few folds that the retries remove. */
pcl::PointCloud<pcl::PointXYZ>::Ptr
foldingLimbs (std::size_t n, double noise, std::uint32_t seed)
{
  pcl::meshless::SyntheticCloudOptions options;
  options.num_points = n;
  options.seed = seed;
  options.noise = noise;
  options.uneven = 10.0;
  return generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::ThinLimbs, options);
}

/** Invariants of a successful result over the cloud indices `expected_vertices`. */
void
expectClosedGenusZero (const std::vector<pcl::Vertices>& polygons,
                       const std::set<pcl::index_t>& expected_vertices)
{
  const std::size_t n = expected_vertices.size ();
  ASSERT_EQ (polygons.size (), 2 * n - 4);
  std::set<pcl::index_t> used;
  std::map<std::pair<pcl::index_t, pcl::index_t>, int> directed;
  for (const auto& polygon : polygons) {
    ASSERT_EQ (polygon.vertices.size (), 3u);
    for (int k = 0; k < 3; ++k) {
      used.insert (polygon.vertices[k]);
      ++directed[{polygon.vertices[k], polygon.vertices[(k + 1) % 3]}];
    }
  }
  EXPECT_EQ (used, expected_vertices) << "every point a vertex, no other vertex";
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ (count, 1) << "edge used twice in the same direction";
    EXPECT_EQ (directed.count ({edge.second, edge.first}), 1u) << "boundary edge";
  }
  // Euler characteristic: V - E + F = 2.
  EXPECT_EQ (static_cast<long> (n) - static_cast<long> (directed.size () / 2) +
                 static_cast<long> (polygons.size ()),
             2);
}

std::set<pcl::index_t>
range (std::size_t n)
{
  std::set<pcl::index_t> all;
  for (std::size_t i = 0; i < n; ++i)
    all.insert (static_cast<pcl::index_t> (i));
  return all;
}

/** Self-intersecting pairs of `polygons` (triangles over the cloud's indices) by a
  * full check on the cloud's own coordinates. */
std::size_t
fullCheckPairs (const pcl::PointCloud<pcl::PointXYZ>& cloud, const std::vector<pcl::Vertices>& polygons)
{
  pcl::meshless::Points3 points;
  for (const auto& p : cloud)
    points.emplace_back (p.x, p.y, p.z);
  pcl::meshless::Triangles triangles;
  for (const auto& polygon : polygons)
    triangles.push_back ({static_cast<pcl::index_t> (polygon.vertices[0]),
                          static_cast<pcl::index_t> (polygon.vertices[1]),
                          static_cast<pcl::index_t> (polygon.vertices[2])});
  return pcl::meshless::checkMesh (points, triangles).self_intersecting_pairs;
}

} // namespace

TEST (SphericalMeshlessReconstruction, PolygonMeshOfAGeneratedCloud)
{
  auto cloud = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::BumpySphere, 4000);
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  EXPECT_EQ (reconstruction.getNumberOfNeighbours (), 12);
  EXPECT_EQ (reconstruction.getWeightType (), pcl::meshless::WeightType::MeanValue);
  reconstruction.setInputCloud (cloud);
  std::vector<std::string> stages;
  reconstruction.setProgressCallback ([&] (const pcl::meshless::ProgressReport& r) {
    stages.push_back (r.stage);
    return true;
  });
  pcl::PolygonMesh mesh;
  reconstruction.reconstruct (mesh);
  const auto& report = reconstruction.getReport ();
  ASSERT_TRUE (report.success) << report.message;
  EXPECT_EQ (mesh.cloud.width * mesh.cloud.height, cloud->size ());
  expectClosedGenusZero (mesh.polygons, range (cloud->size ()));
  EXPECT_TRUE (report.mesh.isSphereLike ());
  EXPECT_GT (report.mesh.signed_volume, 0.0);
  EXPECT_EQ (stages.front (), "neighbourhoods");
  EXPECT_EQ (stages.back (), "handle check"); // the closed mesh looked at for a cut handle
  EXPECT_EQ (report.stage_seconds.size (), stages.size ());
}

TEST (SphericalMeshlessReconstruction, OtherPointTypesAndTheVerticesOverload)
{
  auto normals = generatedCloud<pcl::PointNormal> (pcl::meshless::SyntheticShape::Sphere, 2000);
  pcl::SphericalMeshlessReconstruction<pcl::PointNormal> a;
  a.setInputCloud (normals);
  std::vector<pcl::Vertices> polygons;
  a.reconstruct (polygons);
  ASSERT_TRUE (a.getReport ().success) << a.getReport ().message;
  expectClosedGenusZero (polygons, range (normals->size ()));

  auto colour = generatedCloud<pcl::PointXYZRGBA> (pcl::meshless::SyntheticShape::Ellipsoid, 2000);
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZRGBA> b;
  b.setInputCloud (colour);
  b.setSearchMethod (pcl::make_shared<pcl::search::KdTree<pcl::PointXYZRGBA>> ());
  b.reconstruct (polygons);
  ASSERT_TRUE (b.getReport ().success) << b.getReport ().message;
  expectClosedGenusZero (polygons, range (colour->size ()));
}

TEST (SphericalMeshlessReconstruction, HonoursIndicesNonFinitePointsAndDuplicates)
{
  auto cloud = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Sphere, 3000);
  // Every third point is the subset; NaNs and duplicates are mixed in.
  auto indices = pcl::make_shared<pcl::Indices> ();
  std::set<pcl::index_t> expected;
  for (pcl::index_t i = 0; i < 3000; i += 3) {
    indices->push_back (i);
    expected.insert (i);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN ();
  for (int j = 0; j < 20; ++j) {
    cloud->push_back (pcl::PointXYZ (nan, 0.0f, nan));
    indices->push_back (static_cast<pcl::index_t> (cloud->size () - 1));
    cloud->push_back ((*cloud)[3 * j]); // a duplicate of a subset point
    indices->push_back (static_cast<pcl::index_t> (cloud->size () - 1));
  }
  indices->push_back (0); // a repeated index is the same point, not a duplicate
  cloud->is_dense = false;

  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setIndices (indices);
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  const auto& report = reconstruction.getReport ();
  ASSERT_TRUE (report.success) << report.message;
  EXPECT_EQ (report.num_non_finite, 20u);
  EXPECT_EQ (report.num_duplicates, 20u);
  EXPECT_EQ (report.num_points, expected.size ());
  expectClosedGenusZero (polygons, expected);
}

TEST (SphericalMeshlessReconstruction, BadInputGivesAnEmptyResultAndAReason)
{
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  pcl::PolygonMesh mesh;

  auto three = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  three->push_back ({0, 0, 0});
  three->push_back ({1, 0, 0});
  three->push_back ({0, 1, 0});
  reconstruction.setInputCloud (three);
  reconstruction.reconstruct (mesh);
  EXPECT_FALSE (reconstruction.getReport ().success);
  EXPECT_TRUE (mesh.polygons.empty ());
  EXPECT_NE (reconstruction.getReport ().message.find ("four distinct"), std::string::npos);

  auto sphere = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Sphere, 1000);
  reconstruction.setInputCloud (sphere);
  reconstruction.setNumberOfNeighbours (2);
  reconstruction.reconstruct (mesh);
  EXPECT_FALSE (reconstruction.getReport ().success);
  EXPECT_TRUE (mesh.polygons.empty ());
  EXPECT_EQ (mesh.cloud.data.size (), 0u);
  EXPECT_NE (reconstruction.getReport ().message.find ("setNumberOfNeighbours"), std::string::npos);

  reconstruction.setNumberOfNeighbours (12);
  reconstruction.setSearchRadius (-1.0);
  reconstruction.reconstruct (mesh);
  EXPECT_NE (reconstruction.getReport ().message.find ("setSearchRadius"), std::string::npos);

  reconstruction.setSearchRadius (1e-6); // nobody has a neighbour that close
  reconstruction.reconstruct (mesh);
  EXPECT_FALSE (reconstruction.getReport ().success);
  EXPECT_NE (reconstruction.getReport ().message.find ("no neighbour"), std::string::npos);

  reconstruction.setSearchRadius (0.0);
  reconstruction.setBaseMesh ({0, 1, 2}, {});
  std::vector<pcl::Vertices> faces (1);
  faces[0].vertices = {0, 1, 2};
  reconstruction.setBaseMesh ({0, 1, 2}, faces);
  reconstruction.reconstruct (mesh);
  EXPECT_FALSE (reconstruction.getReport ().success);
  EXPECT_NE (reconstruction.getReport ().message.find ("base mesh"), std::string::npos);

  // Two spheres far apart: the graph is disconnected.
  auto two = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Sphere, 1000);
  const auto other = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Sphere, 1000, 2);
  for (const auto& p : *other)
    two->push_back (pcl::PointXYZ (p.x + 10.0f, p.y, p.z));
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> fresh;
  fresh.setInputCloud (two);
  fresh.reconstruct (mesh);
  EXPECT_FALSE (fresh.getReport ().success);
  EXPECT_NE (fresh.getReport ().message.find ("disconnected"), std::string::npos);
}

TEST (SphericalMeshlessReconstruction, AUserBaseMeshIsUsed)
{
  auto cloud = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Sphere, 3000);
  // Corners near +-x, +-y, +-z by brute force: an octahedron given by the user.
  const Eigen::Vector3f axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  pcl::Indices corners;
  for (const auto& axis : axes) {
    pcl::index_t best = 0;
    for (std::size_t i = 0; i < cloud->size (); ++i)
      if ((*cloud)[i].getVector3fMap ().dot (axis) > (*cloud)[best].getVector3fMap ().dot (axis))
        best = static_cast<pcl::index_t> (i);
    corners.push_back (best);
  }
  std::vector<pcl::Vertices> faces;
  for (int x : {0, 1})
    for (int y : {2, 3})
      for (int z : {4, 5}) {
        pcl::Vertices f;
        // counter-clockwise from outside: (x, y, z) is outward when the octant's
        // sign product is positive.
        const bool positive = ((x == 0) == (y == 2)) == (z == 4);
        f.vertices = positive ? pcl::Indices{x, y, z} : pcl::Indices{x, z, y};
        faces.push_back (f);
      }
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setBaseMesh (corners, faces);
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  ASSERT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
  EXPECT_EQ (reconstruction.getReport ().stats.base_faces, 8u);
  expectClosedGenusZero (polygons, range (cloud->size ()));

  // The class numbers its points in its own (spatial) order and looks the corners up
  // by their cloud indices, whatever order setIndices gives them in.
  auto reversed = pcl::make_shared<pcl::Indices> ();
  for (std::size_t i = cloud->size (); i-- > 0;)
    reversed->push_back (static_cast<pcl::index_t> (i));
  reconstruction.setIndices (reversed);
  reconstruction.reconstruct (polygons);
  ASSERT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
  EXPECT_EQ (reconstruction.getReport ().stats.base_faces, 8u);
  expectClosedGenusZero (polygons, range (cloud->size ()));
  // A corner outside the indices is named as such.
  reversed->erase (std::find (reversed->begin (), reversed->end (), corners[2]));
  reconstruction.setIndices (reversed);
  reconstruction.reconstruct (polygons);
  EXPECT_FALSE (reconstruction.getReport ().success);
  EXPECT_NE (reconstruction.getReport ().message.find ("base mesh vertex"), std::string::npos)
      << reconstruction.getReport ().message;
  EXPECT_TRUE (polygons.empty ());
}

/** The cloud at `path` reconstructed with `reconstruction`'s settings; false if it
  * cannot be read. */
bool
reconstructFile (const std::string& path,
                 pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>& reconstruction,
                 std::vector<pcl::Vertices>& polygons)
{
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  if (pcl::io::loadPCDFile (path, *cloud) != 0)
    return false;
  reconstruction.setInputCloud (cloud);
  reconstruction.reconstruct (polygons);
  return true;
}

class SharedGenusZeroCloud : public ::testing::TestWithParam<std::string>
{};

TEST_P (SharedGenusZeroCloud, ClosesUpWithEveryInvariant)
{
  MESHLESS_REQUIRE_SHARED_FILE (path, "clouds/" + GetParam () + ".pcd");
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  std::vector<pcl::Vertices> polygons;
  ASSERT_TRUE (reconstructFile (path, reconstruction, polygons)) << path;
  const auto& report = reconstruction.getReport ();
  ASSERT_TRUE (report.success) << report.message;
  expectClosedGenusZero (polygons, range (report.num_points));
  EXPECT_TRUE (report.mesh.isSphereLike ()) << pcl::meshless::describe (report.mesh);
  RecordProperty ("self_intersecting_pairs", static_cast<int> (report.mesh.self_intersecting_pairs));
  // The default base polyhedron takes more faces above its size limit (the
  // attempts after the octahedron alternate with the icosahedron, never fewer).
  EXPECT_EQ (reconstruction.getBasePolyhedron (), pcl::meshless::BasePolyhedron::BySize);
  if (report.num_points > 4 * pcl::meshless::points_per_base_face_by_size)
    EXPECT_GE (report.stats.base_faces, 8u);
  else if (report.stats.base_attempt == 0)
    EXPECT_EQ (report.stats.base_faces, 4u); // the first attempt: the tetrahedron
  // The clean clouds (points on a reference surface, no noise) come out embedded,
  // thin limbs (armadillo, horse), ears (bunny: its last folds at the ear rims need
  // the fold repair's discs closed over pinches) and legs a few points around
  // (cow_igl: its hooves need normals that face outwards there, see orientNormals)
  // and a blade thinner than the point spacing (screwdriver: a pleat at its tip's
  // rim opens only with the fold repair's longer runs of swaps) included.
  const std::set<std::string> clean{"bunny_igl", "cow_igl", "spot", "fandisk_6475", "armadillo_igl",
                                    "horse", "screwdriver"};
  if (clean.count (GetParam ()))
    EXPECT_EQ (report.mesh.self_intersecting_pairs, 0u) << pcl::meshless::describe (report.mesh);
}

// Every genus-0 cloud of the shared data, the noisy, layered and million-point ones
// included: the topological invariants must hold on each. Self-intersections are
// recorded (and stated in the README); asserted absent only on the clean clouds
// above: thin parts below the point spacing (ear tips, noisy layers) still fold.
INSTANTIATE_TEST_SUITE_P (SharedData,
                          SharedGenusZeroCloud,
                          ::testing::Values ("bunny_igl",
                                             "cow_igl",
                                             "spot",
                                             "fandisk_6475",
                                             "armadillo_igl",
                                             "horse",
                                             "screwdriver",
                                             "armadillo_noisy_100k",
                                             "bunny_rawscans_merged10",
                                             "armadillo_uniform_1m"));

TEST (SphericalMeshlessReconstruction, FandiskHasThePapersTriangleCountAndNoIntersections)
{
  // The paper's Fig. 10: 6,475 points, 12,946 triangles.
  MESHLESS_REQUIRE_SHARED_FILE (path, "clouds/fandisk_6475.pcd");
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  ASSERT_EQ (pcl::io::loadPCDFile (path, *cloud), 0);
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  ASSERT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
  EXPECT_EQ (polygons.size (), 12946u);
  EXPECT_EQ (reconstruction.getReport ().mesh.self_intersecting_pairs, 0u)
      << pcl::meshless::describe (reconstruction.getReport ().mesh);
}

TEST (SphericalMeshlessReconstruction, OtherBaseMeshesAreTriedWhilePairsRemain)
{
  // Thin limbs whose first base mesh keeps pairs: the retries try the next ones
  // and keep a result only if it has fewer pairs; none when switched off. (Such
  // a result only comes back when asked for.)
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (foldingLimbs (5000, 0.002, 1));
  reconstruction.setAllowSelfIntersections (true);
  reconstruction.setBaseRetries (0);
  std::vector<pcl::Vertices> first;
  reconstruction.reconstruct (first);
  const auto once = reconstruction.getReport ();
  ASSERT_TRUE (once.success) << once.message;
  EXPECT_EQ (once.base_retries, 0u);
  ASSERT_GT (once.mesh.self_intersecting_pairs, 0u) << "the fixture no longer folds: choose another";

  reconstruction.setBaseRetries (2);
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  const auto& retried = reconstruction.getReport ();
  ASSERT_TRUE (retried.success) << retried.message;
  expectClosedGenusZero (polygons, range (retried.num_points));
  EXPECT_GE (retried.base_retries, 1u);
  EXPECT_LE (retried.base_retries, 2u);
  // On this cloud a later base mesh has fewer pairs (measured: none).
  EXPECT_TRUE (retried.base_retry_kept);
  if (retried.base_retry_kept) {
    EXPECT_LT (retried.mesh.self_intersecting_pairs, once.mesh.self_intersecting_pairs);
    EXPECT_NE (retried.stats.base_attempt, once.stats.base_attempt);
  }
  else {
    EXPECT_EQ (retried.mesh.self_intersecting_pairs, once.mesh.self_intersecting_pairs);
    EXPECT_EQ (polygons.size (), first.size ());
  }

  reconstruction.setBaseRetries (-1);
  reconstruction.reconstruct (polygons);
  EXPECT_TRUE (polygons.empty ());
  EXPECT_NE (reconstruction.getReport ().message.find ("setBaseRetries"), std::string::npos)
      << reconstruction.getReport ().message;
}

TEST (SphericalMeshlessReconstruction, FoldsLeftAreRetriedWithTwoMoreNeighbours)
{
  // Thin limbs, all points but every fifth (through setIndices), where every
  // base mesh leaves folds with k = 12 and the sequence with k + 2 neighbours
  // ends without any. Retries off: the folds stay.
  auto cloud = foldingLimbs (5000, 0.001, 11);
  auto subset = pcl::make_shared<pcl::Indices> ();
  for (std::size_t i = 0; i < cloud->size (); ++i)
    if (i % 5 != 4)
      subset->push_back (static_cast<pcl::index_t> (i));
  std::set<pcl::index_t> vertices (subset->begin (), subset->end ());

  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setIndices (subset);
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  const auto report = reconstruction.getReport ();
  ASSERT_TRUE (report.success) << report.message;
  expectClosedGenusZero (polygons, vertices);
  EXPECT_EQ (report.mesh.self_intersecting_pairs, 0u);
  ASSERT_EQ (report.neighbours_k, 14) << "the fixture no longer folds with 12: choose another";

  reconstruction.setBaseRetries (0);
  reconstruction.setAllowSelfIntersections (true);
  reconstruction.reconstruct (polygons);
  ASSERT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
  EXPECT_EQ (reconstruction.getReport ().neighbours_k, 12);
  EXPECT_GT (reconstruction.getReport ().mesh.self_intersecting_pairs, 0u);
}

TEST (SphericalMeshlessReconstruction, PairsLeftFailUnlessAllowed)
{
  // Thin limbs without retries keep pairs (the first base mesh's result): by
  // default a failure naming them and the setter, with an empty mesh; allowed, the
  // closed mesh with the same count.
  const auto cloud = foldingLimbs (5000, 0.0025, 5);
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  EXPECT_FALSE (reconstruction.getAllowSelfIntersections ());
  reconstruction.setBaseRetries (0);
  reconstruction.setAllowSelfIntersections (true);
  std::vector<pcl::Vertices> kept;
  reconstruction.reconstruct (kept);
  const auto allowed = reconstruction.getReport ();
  ASSERT_TRUE (allowed.success) << allowed.message;
  expectClosedGenusZero (kept, range (allowed.num_points));
  // The final check tests only pairs with a triangle changed since the raw check
  // (MeshCheckOptions::known_apart): it counts what a full check of the result
  // counts.
  EXPECT_EQ (fullCheckPairs (*cloud, kept), allowed.mesh.self_intersecting_pairs);
  ASSERT_GT (allowed.mesh.self_intersecting_pairs, 0u) << "the fixture no longer folds: choose another";
  // Pairs the raw repair left are counted by the swaps (they are told that the mesh
  // is free of pairs only where it is).
  if (allowed.raw_fold_repair.pairs_before > 0)
    EXPECT_EQ (allowed.optimization.self_intersections_before, allowed.raw_fold_repair.pairs_after);

  reconstruction.setAllowSelfIntersections (false);
  pcl::PolygonMesh refused;
  reconstruction.reconstruct (refused);
  const auto& report = reconstruction.getReport ();
  EXPECT_FALSE (report.success);
  EXPECT_TRUE (refused.polygons.empty ());
  EXPECT_TRUE (refused.cloud.data.empty ());
  EXPECT_EQ (report.mesh.self_intersecting_pairs, allowed.mesh.self_intersecting_pairs);
  EXPECT_NE (report.message.find (std::to_string (allowed.mesh.self_intersecting_pairs) + " pair"),
             std::string::npos)
      << report.message;
  EXPECT_NE (report.message.find ("setAllowSelfIntersections"), std::string::npos) << report.message;
}

TEST (SphericalMeshlessReconstruction, NearSideRunOnPlanesThatTurnsBackGivesWayToSpheres)
{
  // Thin limbs about five points around: every base mesh fails on the rings as
  // ordered, and the run on the near side's planes is kept, since its raw mesh
  // does not turn back; after the swaps and the repair it does. Without retries
  // that mesh is refused; with them, the near side runs again on spheres through
  // the points, at once (no other base mesh is tried on a mesh that turns back),
  // and closes the cloud.
  const auto cloud = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::ThinLimbs, 1400, 7);
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  std::vector<std::string> near_side;
  reconstruction.setProgressCallback ([&] (const pcl::meshless::ProgressReport& r) {
    if (r.stage == "near side")
      near_side.push_back (r.detail);
    return true;
  });
  std::vector<pcl::Vertices> polygons;
  reconstruction.setBaseRetries (0);
  reconstruction.reconstruct (polygons);
  const auto once = reconstruction.getReport ();
  ASSERT_EQ (near_side.size (), 1u) << "the fixture no longer needs the near side: choose another";
  ASSERT_NE (near_side[0].find ("on planes"), std::string::npos)
      << near_side[0] << ": the fixture no longer keeps the planes' run: choose another";
  ASSERT_FALSE (once.success) << "the fixture no longer turns back: choose another";
  ASSERT_NE (once.message.find ("faces against the cloud's normals"), std::string::npos)
      << once.message << ": the fixture no longer turns back: choose another";
  EXPECT_TRUE (polygons.empty ());
  EXPECT_FALSE (once.near_side_sphere_fit);

  near_side.clear ();
  reconstruction.setBaseRetries (2);
  reconstruction.reconstruct (polygons);
  const auto& retried = reconstruction.getReport ();
  ASSERT_EQ (near_side.size (), 1u);
  EXPECT_NE (near_side[0].find ("on planes"), std::string::npos) << near_side[0];
  ASSERT_TRUE (retried.success) << retried.message;
  expectClosedGenusZero (polygons, range (retried.num_points));
  EXPECT_TRUE (retried.near_side_rings);
  EXPECT_TRUE (retried.near_side_sphere_fit) << "the spheres' run replaced the planes'";
  EXPECT_EQ (retried.base_retries, 0u) << "a mesh that turns back goes to the near side at once";
}

TEST (SphericalMeshlessReconstruction, RawFoldsAreRepairedBeforeTheSwaps)
{
  // The 1:1:6 ellipsoid's raw triangulation folds near its tips (its patches
  // squeeze there). With the optimization on, those folds are re-meshed before the
  // swaps and reported; the count is that of the raw triangulation itself.
  auto cloud = generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Ellipsoid, 3000);
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  // Without the angle pass, whose flips start inside the patches
  // (flipFlatEdgesInPatch), the raw triangulation is the one of a run without
  // optimization, compared below.
  pcl::meshless::EdgeSwapOptions no_angle_pass;
  no_angle_pass.improve_angles = false;
  reconstruction.setOptimizationOptions (no_angle_pass);
  std::vector<std::string> stages;
  reconstruction.setProgressCallback ([&] (const pcl::meshless::ProgressReport& r) {
    stages.push_back (r.stage);
    return true;
  });
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  const auto repaired = reconstruction.getReport ();
  ASSERT_TRUE (repaired.success) << repaired.message;
  expectClosedGenusZero (polygons, range (cloud->size ()));
  EXPECT_EQ (repaired.mesh.self_intersecting_pairs, 0u);
  if (repaired.raw_fold_repair.pairs_before == 0)
    GTEST_SKIP () << "the raw triangulation does not fold any more: nothing to repair first";
  EXPECT_LT (repaired.raw_fold_repair.pairs_after, repaired.raw_fold_repair.pairs_before);
  EXPECT_GT (repaired.raw_fold_repair.regions_remeshed, 0u);
  // The swaps start from what the repair left: counted by the swaps themselves
  // where pairs are left, taken as 0 (not counted again) where none are.
  EXPECT_EQ (repaired.optimization.self_intersections_before,
             repaired.raw_fold_repair.pairs_after);
  const auto raw_repair_stage = std::find (stages.begin (), stages.end (), "repair raw");
  ASSERT_NE (raw_repair_stage, stages.end ());
  EXPECT_LT (raw_repair_stage - stages.begin (),
             std::find (stages.begin (), stages.end (), "optimize") - stages.begin ());

  // The raw triangulation alone (no optimization, no intersection check: no repair,
  // no retry) has exactly the pairs the repair started from.
  reconstruction.setOptimize (false);
  reconstruction.setCheckSelfIntersections (false);
  std::vector<pcl::Vertices> raw;
  reconstruction.reconstruct (raw);
  ASSERT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
  EXPECT_EQ (reconstruction.getReport ().raw_fold_repair.pairs_before, 0u);
  EXPECT_EQ (fullCheckPairs (*cloud, raw), repaired.raw_fold_repair.pairs_before);

  // Without the optimization, the same folds are repaired after the check instead.
  reconstruction.setCheckSelfIntersections (true);
  reconstruction.reconstruct (raw);
  const auto& plain = reconstruction.getReport ();
  ASSERT_TRUE (plain.success) << plain.message;
  EXPECT_EQ (plain.raw_fold_repair.pairs_before, 0u);
  EXPECT_EQ (plain.fold_repair.pairs_before, repaired.raw_fold_repair.pairs_before);
}

TEST (SphericalMeshlessReconstruction, AnInstanceReusedWithASmallerCloud)
{
  // PCL's indices of all points from the first cloud must not be read as the user's.
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  std::vector<pcl::Vertices> polygons;
  reconstruction.setInputCloud (generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Sphere, 2000));
  reconstruction.reconstruct (polygons);
  ASSERT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
  reconstruction.setInputCloud (generatedCloud<pcl::PointXYZ> (pcl::meshless::SyntheticShape::Sphere, 500, 2));
  reconstruction.reconstruct (polygons);
  ASSERT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
  expectClosedGenusZero (polygons, range (500));
}

TEST (SphericalMeshlessReconstruction, FoldedTrianglesOpenOutOnCleanClouds)
{
  // The clean clouds are their reference meshes' vertices. Triangles folded across a
  // part lie off the surface; the angle pass opens steep quads out where a swap makes
  // them turn less, the look-ahead's sequences of swaps where several must change
  // together, and the mesh must then stay within a small distance of the reference
  // (two-sided mean, fraction of the diagonal). spot's folds at its ears and horns:
  // without the unfolding its distance is several times larger; its crease by the
  // legs: without the look-ahead its largest distance is about twice as large.
  struct Case
  {
    std::string name;
    double bound;
    bool check_the_rules;
  };
  const Case cases[] = {{"spot", 4e-5, true}, {"fandisk_6475", 3e-6, false}, {"horse", 1.3e-5, false}};
  for (const auto& [name, bound, check_the_rules] : cases) {
    SCOPED_TRACE (name);
    MESHLESS_REQUIRE_SHARED_FILE (cloud_path, "clouds/" + name + ".pcd");
    MESHLESS_REQUIRE_SHARED_FILE (mesh_path, "meshes/" + name + ".ply");
    auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
    ASSERT_EQ (pcl::io::loadPCDFile (cloud_path, *cloud), 0);
    pcl::meshless::Points3 reference_points;
    pcl::meshless::Triangles reference;
    ASSERT_EQ (meshless_tools::loadMesh (mesh_path, reference_points, reference), "");
    const auto distanceWith = [&] (bool unfold, bool look_ahead) {
      pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
      pcl::meshless::SwapRules rules;
      rules.angle_pass_unfolds_steep_quads = unfold;
      if (!look_ahead)
        rules.look_ahead_depth = rules.crease_look_ahead_depth = 0;
      reconstruction.setOptimizationOptions (rules);
      reconstruction.setInputCloud (cloud);
      std::vector<pcl::Vertices> polygons;
      reconstruction.reconstruct (polygons);
      EXPECT_TRUE (reconstruction.getReport ().success) << reconstruction.getReport ().message;
      pcl::meshless::Triangles triangles;
      for (const auto& polygon : polygons)
        triangles.push_back ({static_cast<pcl::index_t> (polygon.vertices[0]),
                              static_cast<pcl::index_t> (polygon.vertices[1]),
                              static_cast<pcl::index_t> (polygon.vertices[2])});
      const auto report = pcl::meshless::compareToReference (
          meshless_tools::toPoints (*cloud), triangles, reference_points, reference);
      EXPECT_TRUE (report.success) << report.message;
      return report;
    };
    const auto both = distanceWith (true, true);
    EXPECT_LT (both.two_sided.mean, bound);
    if (!check_the_rules)
      continue;
    const auto unfolded = distanceWith (true, false);
    EXPECT_GT (distanceWith (false, false).two_sided.mean, 2.0 * unfolded.two_sided.mean);
    EXPECT_GT (unfolded.to_reference.max, 1.8 * both.to_reference.max);
  }
}

TEST (SphericalMeshlessReconstruction, NoiseAtThePointSpacingGivesAMeshNearerThanItsPoints)
{
  // 20,000 samples of spot with Gaussian noise of about 0.7 point spacings: the run on
  // the points finds no room for its paths at 12 neighbours and closes at 24, through
  // the noise; by default the run on their projections comes first and closes with
  // every invariant. Its mesh lies nearer the reference than the same triangles
  // through the points as given, and than the mesh through them (two-sided mean).
  MESHLESS_REQUIRE_SHARED_FILE (cloud_path, "clouds/spot_20k_noise5.pcd");
  MESHLESS_REQUIRE_SHARED_FILE (mesh_path, "meshes/spot.ply");
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  ASSERT_EQ (pcl::io::loadPCDFile (cloud_path, *cloud), 0);
  pcl::meshless::Points3 reference_points;
  pcl::meshless::Triangles reference;
  ASSERT_EQ (meshless_tools::loadMesh (mesh_path, reference_points, reference), "");

  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setPointSmoothing (pcl::meshless::PointSmoothing::Off);
  pcl::PolygonMesh as_given;
  reconstruction.reconstruct (as_given);
  {
    const auto& report = reconstruction.getReport ();
    ASSERT_TRUE (report.success) << report.message;
    EXPECT_EQ (report.neighbours_k, 24);
    EXPECT_FALSE (report.smoothed);
    EXPECT_TRUE (report.mesh.isSphereLike ()) << pcl::meshless::describe (report.mesh);
    EXPECT_EQ (report.mesh.self_intersecting_pairs, 0u);
    EXPECT_EQ (as_given.polygons.size (), 2 * cloud->size () - 4);
  }
  pcl::meshless::Triangles given_triangles;
  for (const auto& polygon : as_given.polygons)
    given_triangles.push_back ({static_cast<pcl::index_t> (polygon.vertices[0]),
                                static_cast<pcl::index_t> (polygon.vertices[1]),
                                static_cast<pcl::index_t> (polygon.vertices[2])});
  const auto through_given = pcl::meshless::compareToReference (
      meshless_tools::toPoints (*cloud), given_triangles, reference_points, reference);

  reconstruction.setPointSmoothing (pcl::meshless::PointSmoothing::IfNoisy);
  pcl::PolygonMesh mesh;
  reconstruction.reconstruct (mesh);
  const auto& report = reconstruction.getReport ();
  ASSERT_TRUE (report.success) << report.message;
  EXPECT_TRUE (report.smoothed);
  EXPECT_TRUE (report.mesh.isSphereLike ()) << pcl::meshless::describe (report.mesh);
  EXPECT_EQ (report.mesh.self_intersecting_pairs, 0u);
  EXPECT_EQ (report.mesh.unused_vertices, 0u);
  EXPECT_EQ (mesh.polygons.size (), 2 * cloud->size () - 4);
  pcl::PointCloud<pcl::PointXYZ> vertices;
  pcl::fromPCLPointCloud2 (mesh.cloud, vertices);
  ASSERT_EQ (vertices.size (), cloud->size ());
  pcl::meshless::Triangles triangles;
  for (const auto& polygon : mesh.polygons)
    triangles.push_back ({static_cast<pcl::index_t> (polygon.vertices[0]),
                          static_cast<pcl::index_t> (polygon.vertices[1]),
                          static_cast<pcl::index_t> (polygon.vertices[2])});
  const auto moved = pcl::meshless::compareToReference (meshless_tools::toPoints (vertices),
                                                        triangles, reference_points, reference);
  const auto given = pcl::meshless::compareToReference (meshless_tools::toPoints (*cloud),
                                                        triangles, reference_points, reference);
  ASSERT_TRUE (moved.success && given.success && through_given.success);
  EXPECT_LT (moved.two_sided.mean, 0.6 * given.two_sided.mean);
  EXPECT_LT (moved.two_sided.mean, 0.6 * through_given.two_sided.mean);
  // The output's check, repeated on the positions it holds.
  const auto check = pcl::meshless::checkMesh (meshless_tools::toPoints (vertices), triangles);
  EXPECT_EQ (check.self_intersecting_pairs, 0u);
}
