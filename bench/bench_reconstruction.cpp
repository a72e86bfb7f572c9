// Greedy projection and pcl::SphericalMeshlessReconstruction timed on the same clouds:
// generated bumpy spheres of 10k and 100k points and, when present, the shared clouds
// (../shared/data/clouds or $MESHLESS_DATA_DIR/clouds). Each benchmark reports points
// per second; at the end the time ratios spherical / greedy and spherical / kNN floor
// per cloud, measured in the same run, and the growth of the time per point over the
// generated clouds. Greedy projection's time includes its normal estimation, both
// include building the search tree. The kNN floor is one pass of PCL's KdTree build
// plus a k = 12 query for every point, single-threaded: what any method built on
// k nearest neighbours pays at least.
#include <meshless_tools/cloud_io.h>
#include <meshless_tools/greedy_projection.h>

#include <pcl/console/print.h>
#include <pcl/search/kdtree.h>
#include <meshless_tools/synthetic_clouds.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

Cloud::Ptr
bumpySphere (std::size_t points)
{
  pcl::meshless::SyntheticCloudOptions options;
  options.num_points = points;
  auto cloud = pcl::make_shared<Cloud> ();
  for (const auto& p :
       pcl::meshless::sampleShape (pcl::meshless::SyntheticShape::BumpySphere, options))
    cloud->push_back (pcl::PointXYZ (static_cast<float> (p.x ()),
                                     static_cast<float> (p.y ()),
                                     static_cast<float> (p.z ())));
  return cloud;
}

void
setRate (benchmark::State& state, std::size_t points)
{
  state.counters["points/s"] = benchmark::Counter (
      static_cast<double> (points), benchmark::Counter::kIsIterationInvariantRate);
}

void
greedy (benchmark::State& state, const Cloud::ConstPtr& cloud)
{
  for (auto _ : state) {
    auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>> ();
    tree->setInputCloud (cloud);
    // The radius derivation is part of using greedy projection on an unknown cloud.
    const auto parameters = meshless_tools::greedyParameters (*tree, *cloud);
    pcl::PolygonMesh mesh;
    meshless_tools::greedyProjection (cloud, tree, parameters, mesh);
    if (mesh.polygons.empty ())
      state.SkipWithError ("greedy projection made no triangle");
    benchmark::DoNotOptimize (mesh);
  }
  setRate (state, cloud->size ());
}

void
spherical (benchmark::State& state, const Cloud::ConstPtr& cloud)
{
  for (auto _ : state) {
    pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
    reconstruction.setInputCloud (cloud);
    // A measuring tool: a mesh with folds left is measured, not refused.
    reconstruction.setAllowSelfIntersections (true);
    reconstruction.setReleaseFreedMemory (true); // as the CLI does, for its peak memory
    pcl::PolygonMesh mesh;
    reconstruction.reconstruct (mesh);
    if (!reconstruction.getReport ().success)
      state.SkipWithError (reconstruction.getReport ().message.c_str ());
    benchmark::DoNotOptimize (mesh);
  }
  setRate (state, cloud->size ());
}

void
knnFloor (benchmark::State& state, const Cloud::ConstPtr& cloud)
{
  for (auto _ : state) {
    pcl::search::KdTree<pcl::PointXYZ> tree;
    tree.setInputCloud (cloud);
    pcl::Indices neighbours;
    std::vector<float> distances;
    std::size_t found = 0;
    for (const auto& p : *cloud)
      found += static_cast<std::size_t> (tree.nearestKSearch (p, 12, neighbours, distances));
    benchmark::DoNotOptimize (found);
  }
  setRate (state, cloud->size ());
}

void
registerCloud (const std::string& name, const Cloud::ConstPtr& cloud)
{
  const std::vector<std::pair<const char*, void (*) (benchmark::State&, const Cloud::ConstPtr&)>>
      methods{{"knn_floor", knnFloor}, {"greedy", greedy}, {"spherical", spherical}};
  for (const auto& [method, run] : methods)
    benchmark::RegisterBenchmark ((std::string (method) + "/" + name).c_str (), run, cloud)
        ->Unit (benchmark::kMillisecond)
        ->UseRealTime ();
}

/** The console output, then the ratio of the two methods' times on each cloud. */
class RatioReporter : public benchmark::ConsoleReporter
{
public:
  void
  ReportRuns (const std::vector<Run>& runs) override
  {
    ConsoleReporter::ReportRuns (runs);
    for (const Run& run : runs)
      if (run.run_type == Run::RT_Iteration && !run.error_occurred) {
        // "greedy/bunny_igl/real_time" -> method "greedy", cloud "bunny_igl".
        const std::string name = run.benchmark_name ();
        const auto slash = name.find ('/');
        const auto end = name.find ('/', slash + 1);
        seconds_[name.substr (slash + 1, end - slash - 1)][name.substr (0, slash)] =
            run.GetAdjustedRealTime ();
      }
  }

  void
  Finalize () override
  {
    ConsoleReporter::Finalize ();
    std::printf ("\ntime ratios (same run):  spherical / greedy   spherical / kNN floor\n");
    for (const auto& [cloud, times] : seconds_)
      if (times.count ("spherical"))
        std::printf ("  %-24s %18s %23s\n", cloud.c_str (),
                     ratio (times, "greedy").c_str (), ratio (times, "knn_floor").c_str ());
    // Near-linear growth: time per point on the generated clouds, against 100k.
    const auto base = seconds_.find ("bumpy_sphere_100k");
    if (base != seconds_.end () && base->second.count ("spherical")) {
      std::printf ("\ntime per point against bumpy_sphere_100k (spherical):\n");
      for (const auto& [cloud, points] :
           std::vector<std::pair<std::string, double>>{{"bumpy_sphere_10k", 1e4},
                                                       {"bumpy_sphere_100k", 1e5},
                                                       {"bumpy_sphere_1000k", 1e6}}) {
        const auto it = seconds_.find (cloud);
        if (it != seconds_.end () && it->second.count ("spherical"))
          std::printf ("  %-24s %6.2f\n", cloud.c_str (),
                       (it->second.at ("spherical") / points) /
                           (base->second.at ("spherical") / 1e5));
      }
    }
  }

private:
  static std::string
  ratio (const std::map<std::string, double>& times, const std::string& other)
  {
    if (!times.count (other) || !(times.at (other) > 0.0))
      return "-";
    char text[32];
    std::snprintf (text, sizeof text, "%.2f", times.at ("spherical") / times.at (other));
    return text;
  }

  /** Real time per iteration by cloud, then by method. */
  std::map<std::string, std::map<std::string, double>> seconds_;
};

} // namespace

int
main (int argc, char** argv)
{
  benchmark::Initialize (&argc, argv);
  if (benchmark::ReportUnrecognizedArguments (argc, argv))
    return 1;
  // The reconstruction's warnings (self-intersections on thin parts) would repeat once
  // per iteration between the timing lines.
  pcl::console::setVerbosityLevel (pcl::console::L_ERROR);
  // Generated clouds of 10k, 100k and 1M points (the growth from one to the next
  // is the scaling); then every genus-0 shared cloud. Select with
  // --benchmark_filter (e.g. 'bumpy|bunny_igl' for a quick run).
  for (const std::size_t points : {10000, 100000, 1000000})
    registerCloud ("bumpy_sphere_" + std::to_string (points / 1000) + "k",
                   bumpySphere (points));
  const char* data = std::getenv ("MESHLESS_DATA_DIR");
  const std::filesystem::path clouds =
      std::filesystem::path (data ? data : MESHLESS_SHARED_DATA_DIR) / "clouds";
  for (const char* name :
       {"bunny_igl", "cow_igl", "spot", "fandisk_6475", "armadillo_igl", "horse",
        "armadillo_noisy_100k", "bunny_rawscans_merged10", "armadillo_uniform_1m"}) {
    const std::string path = (clouds / (std::string (name) + ".pcd")).string ();
    auto cloud = pcl::make_shared<Cloud> ();
    if (std::filesystem::exists (path) &&
        meshless_tools::loadCloud (path, *cloud).empty ())
      registerCloud (name, cloud);
  }
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks (&reporter);
  benchmark::Shutdown ();
  return 0;
}
