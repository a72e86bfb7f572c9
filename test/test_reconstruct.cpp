// The PointT-free entry point and its retry policy, driven without PCL's search.
#include "retry_policy.h"

#include <pcl/surface/meshless/mesh_checks.h>
#include <pcl/surface/meshless/reconstruct.h>
#include <meshless_tools/synthetic_clouds.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

namespace {

using namespace pcl::meshless;

PreparedPoints
prepared (const Points3& points)
{
  std::vector<Eigen::Vector3f> xyz;
  for (const auto& p : points)
    xyz.push_back (p.cast<float> ());
  pcl::Indices indices (points.size ());
  std::iota (indices.begin (), indices.end (), 0);
  return preparePoints (xyz, indices);
}

/** n points of a generated shape, prepared as the conductor gets them. */
PreparedPoints
preparedShape (SyntheticShape shape, std::size_t n)
{
  SyntheticCloudOptions cloud;
  cloud.num_points = n;
  return prepared (sampleShape (shape, cloud));
}

/** Brute-force neighbourhoods that remember which k they were asked for. */
struct CountingSearch
{
  const Points3* points;
  std::vector<int> asked;

  NeighbourSearch
  function ()
  {
    return [this] (int k) {
      asked.push_back (k);
      Neighbourhoods result;
      result.neighbours = meshless_test::bruteForceKnn (*points, k);
      result.success = true;
      return result;
    };
  }
};

TEST (PreparePoints, DropsDuplicatesKeepsTheFirstAndCentres)
{
  const std::vector<Eigen::Vector3f> xyz = {
      {0, 0, 0}, {2, 0, 0}, {0, 0, 0}, {0, 2, 0}, {2, 0, 0}, {0, 0, 2}};
  const pcl::Indices source = {10, 11, 12, 13, 14, 15};
  const PreparedPoints p = preparePoints (xyz, source);
  EXPECT_EQ (p.num_duplicates, 2u);
  ASSERT_EQ (p.points.size (), 4u);
  std::vector<pcl::index_t> kept (p.cloud_indices.begin (), p.cloud_indices.end ());
  std::sort (kept.begin (), kept.end ());
  EXPECT_EQ (kept, (std::vector<pcl::index_t>{10, 11, 13, 15}));
  EXPECT_TRUE (p.centroid.isApprox (Eigen::Vector3d (0.5, 0.5, 0.5)));
  for (std::size_t i = 0; i < p.points.size (); ++i) {
    const Eigen::Vector3d original = xyz[p.cloud_indices[i] - 10].cast<double> ();
    EXPECT_TRUE ((p.points[i] + p.centroid).isApprox (original));
  }
  // Each dropped duplicate names the pipeline point it repeats.
  ASSERT_EQ (p.duplicates.size (), 2u);
  for (const auto& [duplicate, repeated] : p.duplicates) {
    ASSERT_GE (repeated, 0);
    ASSERT_LT (static_cast<std::size_t> (repeated), p.points.size ());
    EXPECT_EQ (xyz[duplicate - 10], xyz[p.cloud_indices[repeated] - 10]) << duplicate;
    EXPECT_LT (p.cloud_indices[repeated], duplicate) << "the first of equal points";
  }
}

TEST (CheckOptions, NamesTheSetter)
{
  ReconstructionOptions options;
  EXPECT_EQ (checkOptions (options), "");
  options.k = 2;
  EXPECT_NE (checkOptions (options).find ("setNumberOfNeighbours"), std::string::npos);
  options = {};
  options.radius = -1.0;
  EXPECT_NE (checkOptions (options).find ("setSearchRadius"), std::string::npos);
  options = {};
  options.base_retries = -1;
  EXPECT_NE (checkOptions (options).find ("setBaseRetries"), std::string::npos);
}

TEST (Reconstruct, ClosedSphereThroughEveryPoint)
{
  const PreparedPoints points = preparedShape (SyntheticShape::BumpySphere, 2000);
  CountingSearch search{&points.points, {}};
  ReconstructionOptions options;
  options.num_threads = 1;
  const Reconstruction result = reconstruct (points, search.function (), options);
  ASSERT_TRUE (result.report.success) << result.report.message;
  EXPECT_EQ (result.triangles.size (), 2 * points.points.size () - 4);
  const MeshReport mesh = checkMesh (points.points, result.triangles);
  EXPECT_TRUE (mesh.isSphereLike ()) << describe (mesh);
  EXPECT_EQ (mesh.self_intersecting_pairs, 0u);
  EXPECT_EQ (mesh.unused_vertices, 0u);
  EXPECT_GT (mesh.signed_volume, 0.0);
  EXPECT_EQ (search.asked, std::vector<int>{12}); // a clean result asks no k + 2
}

TEST (Reconstruct, TwiceTheNeighboursWhereEveryBaseMeshFailedInOnePiece)
{
  // An ellipsoid in clusters of six: every base mesh fails at 12 neighbours on a
  // graph in one piece; the call asks for 24 once and closes there, smoothing off.
  SyntheticCloudOptions clustered;
  clustered.num_points = 2000;
  clustered.cluster_size = 6;
  const PreparedPoints points = prepared (sampleShape (SyntheticShape::Ellipsoid, clustered));
  CountingSearch search{&points.points, {}};
  ReconstructionOptions options;
  options.num_threads = 1;
  options.smoothing = PointSmoothing::Off;
  const Reconstruction result = reconstruct (points, search.function (), options);
  ASSERT_TRUE (result.report.success) << result.report.message;
  EXPECT_EQ (result.report.neighbours_k, 24);
  EXPECT_EQ (search.asked, (std::vector<int>{12, 24}));
  EXPECT_EQ (result.triangles.size (), 2 * points.points.size () - 4);
  EXPECT_TRUE (checkMesh (points.points, result.triangles).isSphereLike ());

  // An open surface whose noise was not measured (smoothing off) is not widened:
  // through noise more neighbours may close a hole. Clusters of eight fail at 12.
  SyntheticCloudOptions open;
  open.num_points = 5000;
  open.cluster_size = 8;
  open.holes = 1;
  const PreparedPoints disc = prepared (sampleShape (SyntheticShape::Disc, open));
  CountingSearch disc_search{&disc.points, {}};
  options.topology = Topology::Disc;
  const Reconstruction unmeasured = reconstruct (disc, disc_search.function (), options);
  EXPECT_FALSE (unmeasured.report.success);
  EXPECT_EQ (std::count (disc_search.asked.begin (), disc_search.asked.end (), 24), 0);
  options.smoothing = PointSmoothing::IfNoisy;
  disc_search.asked.clear ();
  const Reconstruction measured = reconstruct (disc, disc_search.function (), options);
  ASSERT_TRUE (measured.report.success) << measured.report.message;
  EXPECT_EQ (measured.report.neighbours_k, 24);
  EXPECT_EQ (measured.report.holes, 1u);
}

TEST (Reconstruct, CancelledByTheCallbackFailsEvenWhereTheStageGoesOn)
{
  const PreparedPoints points = preparedShape (SyntheticShape::Sphere, 1000);
  CountingSearch search{&points.points, {}};
  ReconstructionOptions options;
  std::vector<std::string> stages;
  // The final check is the last stage; nothing comes after it that could stop.
  options.progress = [&] (const ProgressReport& report) {
    stages.push_back (report.stage);
    return report.stage != "check";
  };
  const Reconstruction result = reconstruct (points, search.function (), options);
  ASSERT_FALSE (stages.empty ());
  EXPECT_EQ (stages.back (), "check");
  EXPECT_FALSE (result.report.success);
  EXPECT_TRUE (result.triangles.empty ());
  EXPECT_NE (result.report.message.find ("cancelled"), std::string::npos)
      << result.report.message;
}

TEST (Reconstruct, FailureIsEmptyWithAReason)
{
  const PreparedPoints points = prepared ({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  CountingSearch search{&points.points, {}};
  const Reconstruction result = reconstruct (points, search.function (), {});
  EXPECT_FALSE (result.report.success);
  EXPECT_TRUE (result.triangles.empty ());
  EXPECT_NE (result.report.message.find ("at least four"), std::string::npos);
  EXPECT_TRUE (search.asked.empty ());
}

/** The policy over a first run of the pipeline whose result is pretended to keep
  * intersecting pairs: a further base mesh that leaves none replaces it. */
class RetryPolicyTest : public ::testing::Test
{
protected:
  void
  SetUp () override
  {
    points_ = preparedShape (SyntheticShape::Sphere, 1500).points;
    neighbours_ = meshless_test::bruteForceKnn (points_, options_.k);
    pipeline_.polyhedron = BasePolyhedron::Tetrahedron;
    SphereTriangulation first = triangulateSphere (points_, neighbours_, pipeline_);
    ASSERT_TRUE (first.success) << first.message;
    current_.triangles = first.triangles;
    current_.normals = first.normals;
    current_.report.stats = first.stats;
  }

  Points3 points_;
  CsrGraph neighbours_;
  ReconstructionOptions options_;
  SpherePipelineOptions pipeline_;
  CurrentResult current_;
  ProgressCallback progress_;
  StageClock clock_{progress_};
};

TEST_F (RetryPolicyTest, KeepsABetterRunOnly)
{
  MeshFinisher finisher (points_, options_, current_, clock_);
  RetryPolicy policy (points_, neighbours_, options_, finisher, current_, clock_);
  bool kept = true;
  current_.report.mesh.self_intersecting_pairs = 0; // nothing to improve on
  SpherePipelineOptions next = pipeline_;
  next.first_attempt = 1;
  EXPECT_GE (policy.tryAnother (next, kept), 1);
  EXPECT_FALSE (kept);

  current_.report.mesh.self_intersecting_pairs = 5; // pretend folds were left
  EXPECT_GE (policy.tryAnother (next, kept), 1);
  EXPECT_TRUE (kept);
  EXPECT_EQ (current_.report.mesh.self_intersecting_pairs, 0u);
  EXPECT_EQ (current_.triangles.size (), 2 * points_.size () - 4);
}

TEST_F (RetryPolicyTest, FurtherBaseMeshesStopOnceClean)
{
  MeshFinisher finisher (points_, options_, current_, clock_);
  RetryPolicy policy (points_, neighbours_, options_, finisher, current_, clock_);
  current_.report.mesh.self_intersecting_pairs = 5;
  policy.run (pipeline_, {});
  EXPECT_EQ (current_.report.base_retries, 1u); // the first further layout was clean
  EXPECT_TRUE (current_.report.base_retry_kept);
  EXPECT_EQ (current_.report.mesh.self_intersecting_pairs, 0u);

  options_.base_retries = 0; // none asked for: nothing tried
  CurrentResult untouched;
  untouched.report.mesh.self_intersecting_pairs = 5;
  MeshFinisher other_finisher (points_, options_, untouched, clock_);
  RetryPolicy none (points_, neighbours_, options_, other_finisher, untouched, clock_);
  none.run (pipeline_, {});
  EXPECT_EQ (untouched.report.base_retries, 0u);
}

/** The first result with two far points' labels swapped in its triangles: still
  * closed, but the neighbours of each lie far from it on the mesh. Its pairs are
  * pretended away, so that only the neighbours kept apart call for the retries. */
TEST_F (RetryPolicyTest, FurtherBaseMeshesWhileTheResultKeepsNeighboursApart)
{
  const pcl::index_t u = 0;
  pcl::index_t w = 0;
  for (std::size_t v = 0; v < points_.size (); ++v)
    if ((points_[v] - points_[u]).norm () > (points_[w] - points_[u]).norm ())
      w = static_cast<pcl::index_t> (v);
  const Triangles clean = current_.triangles;
  const Normals normals = current_.normals;
  for (Triangle& t : current_.triangles)
    for (pcl::index_t& v : t)
      v = v == u ? w : v == w ? u : v;
  ASSERT_GT (neighboursSeparatedByTheMesh (points_, current_.triangles, neighbours_,
                                           current_.normals, max_neighbour_hops, 1),
             max_separated_neighbours);
  const Triangles swapped = current_.triangles;
  current_.report.mesh.self_intersecting_pairs = 0; // pretend no pairs: only apart

  MeshFinisher finisher (points_, options_, current_, clock_);
  RetryPolicy policy (points_, neighbours_, options_, finisher, current_, clock_);
  ASSERT_TRUE (policy.run (pipeline_, {}));
  EXPECT_GE (current_.report.base_retries, 1u);
  EXPECT_TRUE (current_.report.base_retry_kept);
  EXPECT_TRUE (policy.replacedOneKeepingNeighboursApart ());
  EXPECT_NE (current_.triangles, swapped);
  EXPECT_EQ (current_.report.mesh.self_intersecting_pairs, 0u);
  ASSERT_TRUE (policy.separatedNeighbours ().has_value ());
  EXPECT_LE (*policy.separatedNeighbours (), max_separated_neighbours);
  EXPECT_EQ (*policy.separatedNeighbours (),
             neighboursSeparatedByTheMesh (points_, current_.triangles, neighbours_,
                                           current_.normals, max_neighbour_hops, 1));

  // Without the intersection check nothing is counted, and nothing retried.
  CurrentResult unchecked;
  unchecked.triangles = swapped;
  unchecked.normals = normals;
  ReconstructionOptions no_check = options_;
  no_check.check_self_intersections = false;
  MeshFinisher unchecked_finisher (points_, no_check, unchecked, clock_);
  RetryPolicy off (points_, neighbours_, no_check, unchecked_finisher, unchecked, clock_);
  ASSERT_TRUE (off.run (pipeline_, {}));
  EXPECT_EQ (unchecked.report.base_retries, 0u);
  EXPECT_FALSE (off.separatedNeighbours ().has_value ());
  EXPECT_EQ (unchecked.triangles, swapped);

  // The clean first result keeps none apart: nothing is retried.
  CurrentResult untouched;
  untouched.triangles = clean;
  untouched.normals = normals;
  MeshFinisher other_finisher (points_, options_, untouched, clock_);
  RetryPolicy none (points_, neighbours_, options_, other_finisher, untouched, clock_);
  ASSERT_TRUE (none.run (pipeline_, {}));
  EXPECT_EQ (untouched.report.base_retries, 0u);
  EXPECT_FALSE (none.replacedOneKeepingNeighboursApart ());
  EXPECT_EQ (untouched.triangles, clean);
  ASSERT_TRUE (none.separatedNeighbours ().has_value ());
  EXPECT_LE (*none.separatedNeighbours (), max_separated_neighbours);
}

} // namespace
