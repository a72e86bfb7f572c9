/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
// At the level of the PCL class: the same input and options give the identical mesh
// whatever setNumberOfThreads says, the class leaves OpenMP's global setting alone,
// and two instances
// reconstructing different clouds at the same time (from two std::threads, each with
// its own OpenMP team) give what each gives alone. The stages' own determinism is
// tested with them (SpherePipeline, EdgeSwap, MeshChecks).
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <meshless_tools/synthetic_clouds.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include "test_support.h"

#include <omp.h>

#include <atomic>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Reconstruction = pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>;
using pcl::meshless::SyntheticShape;

Cloud::Ptr
generated (SyntheticShape shape, std::size_t n, std::uint32_t seed, double noise = 0.0)
{
  auto cloud = pcl::make_shared<Cloud> ();
  for (const auto& p : pcl::meshless::sampleShape (shape, {n, seed, noise}))
    cloud->push_back (pcl::PointXYZ (static_cast<float> (p.x ()),
                                     static_cast<float> (p.y ()),
                                     static_cast<float> (p.z ())));
  return cloud;
}

/** What must be identical between two runs: the triangles in their order and
  * rotation, and what the report says about them. */
struct Result
{
  bool success = false;
  std::string message;
  std::vector<std::vector<pcl::index_t>> triangles;
  std::size_t self_intersecting_pairs = 0;
  bool thin_sheet_retry = false;
  std::size_t swaps = 0;
};

void
expectIdentical (const Result& a, const Result& b)
{
  EXPECT_EQ (a.success, b.success);
  EXPECT_EQ (a.message, b.message);
  EXPECT_EQ (a.self_intersecting_pairs, b.self_intersecting_pairs);
  EXPECT_EQ (a.thin_sheet_retry, b.thin_sheet_retry);
  EXPECT_EQ (a.swaps, b.swaps);
  ASSERT_EQ (a.triangles.size (), b.triangles.size ());
  std::size_t different = 0;
  for (std::size_t t = 0; t < a.triangles.size (); ++t)
    different += a.triangles[t] != b.triangles[t];
  EXPECT_EQ (different, 0u) << "triangles differ (of " << a.triangles.size () << ")";
}

/** One case: a cloud and how the instance is set up. */
struct Case
{
  std::string name;
  Cloud::Ptr cloud;
  std::function<void (Reconstruction&)> configure = [] (Reconstruction&) {};
};

Result
run (const Case& c, unsigned int threads = 0)
{
  Reconstruction reconstruction;
  reconstruction.setInputCloud (c.cloud);
  reconstruction.setNumberOfThreads (threads);
  c.configure (reconstruction);
  std::vector<pcl::Vertices> polygons;
  reconstruction.reconstruct (polygons);
  const auto& report = reconstruction.getReport ();
  Result result;
  result.success = report.success;
  result.message = report.message;
  for (const auto& polygon : polygons)
    result.triangles.emplace_back (polygon.vertices.begin (), polygon.vertices.end ());
  result.self_intersecting_pairs = report.mesh.self_intersecting_pairs;
  result.thin_sheet_retry = report.thin_sheet_retry;
  result.swaps = report.optimization.swaps;
  return result;
}

/** Sphere and disc topology, the default options and others, a noisy cloud that
  * needs the fallbacks, and (with the shared data) a real cloud whose first
  * results intersect themselves, so that the thin-sheet retry runs too, and the
  * same kept with its pairs. Small enough for the sanitizers. */
std::vector<Case>
cases ()
{
  std::vector<Case> all;
  all.push_back ({"bumpy sphere", generated (SyntheticShape::BumpySphere, 3000, 3)});
  all.push_back ({"noisy bumpy sphere, icosahedron, shape-preserving",
                  generated (SyntheticShape::BumpySphere, 2500, 4, 0.01),
                  [] (Reconstruction& r) {
                    r.setBasePolyhedron (pcl::meshless::BasePolyhedron::Icosahedron);
                    r.setWeightType (pcl::meshless::WeightType::ShapePreserving);
                  }});
  all.push_back ({"sphere, ball neighbourhoods, no optimization",
                  generated (SyntheticShape::Sphere, 2000, 5), [] (Reconstruction& r) {
                    r.setSearchRadius (0.15);
                    r.setOptimize (false);
                  }});
  all.push_back (
      {"height field as a disc", generated (SyntheticShape::HeightField, 2500, 6),
       [] (Reconstruction& r) { r.setTopology (Reconstruction::Topology::Disc); }});
  // A cloud whose result comes from the thin-sheet retry (and the base retries
  // after it).
  const std::string cow = meshless_test::sharedFile ("clouds/cow_igl.pcd");
  if (!cow.empty ()) {
    auto cloud = pcl::make_shared<Cloud> ();
    if (pcl::io::loadPCDFile (cow, *cloud) == 0) {
      all.push_back ({"cow_igl (thin-sheet retry)", cloud});
      // The first base mesh alone leaves folds: a result with pairs, allowed, whose
      // count must not depend on the threads either.
      all.push_back ({"cow_igl, first base mesh, pairs allowed", cloud, [] (Reconstruction& r) {
                        r.setBaseRetries (0);
                        r.setAllowSelfIntersections (true);
                      }});
    }
    else
      ADD_FAILURE () << "cannot read " << cow;
  }
  return all;
}

} // namespace

TEST (Concurrency, IdenticalMeshWithAnyNumberOfThreads)
{
  for (const Case& c : cases ()) {
    SCOPED_TRACE (c.name);
    const int global_threads = omp_get_max_threads ();
    const Result one = run (c, 1);
    EXPECT_EQ (omp_get_max_threads (), global_threads) << "the global setting changed";
    ASSERT_TRUE (one.success) << one.message;
    if (c.name.find ("thin-sheet retry") != std::string::npos)
      EXPECT_TRUE (one.thin_sheet_retry) << "the case should exercise the retry";
    for (const unsigned int t : {2u, 3u, 4u}) {
      SCOPED_TRACE (std::to_string (t) + " threads");
      expectIdentical (one, run (c, t));
    }
    // And with the default, all cores.
    expectIdentical (one, run (c));
  }
}

TEST (Concurrency, TwoInstancesAtTheSameTime)
{
  const std::vector<Case> all = cases ();
  ASSERT_GE (all.size (), 2u);
  std::vector<Result> alone;
  for (const Case& c : all)
    alone.push_back (run (c));

  // Each pair of different cases at once, both started when both threads are ready;
  // each instance asks for two threads so that the teams overlap as well.
  for (std::size_t a = 0; a < all.size (); ++a) {
    const std::size_t b = (a + 1) % all.size ();
    SCOPED_TRACE (all[a].name + " together with " + all[b].name);
    std::atomic<int> ready{0};
    Result together[2];
    auto worker = [&] (int slot, const Case& c) {
      ++ready;
      while (ready.load () < 2)
        std::this_thread::yield ();
      together[slot] = run (c, 2);
    };
    std::thread first (worker, 0, std::cref (all[a]));
    std::thread second (worker, 1, std::cref (all[b]));
    first.join ();
    second.join ();
    expectIdentical (alone[a], together[0]);
    expectIdentical (alone[b], together[1]);
  }
}
