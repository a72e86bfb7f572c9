// pcl_spherical_meshless_surface INPUT OUTPUT [options]
//
// Reconstructs a closed, oriented genus-0 triangle mesh through every point of a
// cloud with pcl::SphericalMeshlessReconstruction. INPUT is .pcd, .ply or .xyz
// (x y z per line), or -generate SHAPE[:N] for one of the project's own clouds.
// OUTPUT is .ply (binary), .vtk or .obj. Prints stage timings and the triangle
// count; exits 0 on success, otherwise 1 with a one-line reason on stderr.
#include "cloud_io.h"

#include <pcl/point_types.h>
#include <pcl/surface/meshless/synthetic_clouds.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace {

using meshless_tools::loadCloud;
using meshless_tools::saveMesh;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Clock = std::chrono::steady_clock;

void
usage (const char* program)
{
  std::printf (
      "usage: %s INPUT OUTPUT [options]\n"
      "       %s -generate SHAPE[:N] OUTPUT [options]\n"
      "INPUT   .pcd, .ply or .xyz (x y z per line)\n"
      "OUTPUT  .ply (binary), .vtk or .obj\n"
      "SHAPE   sphere, ellipsoid, bumpy_sphere, torus, disc, height_field (N points, "
      "default 20000)\n"
      "options:\n"
      "  -k N                 nearest neighbours (default 12)\n"
      "  -radius R            ball neighbourhood of radius R instead of k nearest\n"
      "  -weights W           uniform|distance|shape|meanvalue (default meanvalue)\n"
      "  -topology T          sphere (closed, default) or disc (open surface)\n"
      "  -optimize 0|1        edge-swap optimization (default 1)\n"
      "  -base B              auto|tetrahedron|octahedron|icosahedron (default auto:\n"
      "                       tetrahedron up to 500000 points, octahedron above)\n"
      "  -retries N           further base meshes tried while the result intersects\n"
      "                       itself, then k + 2 neighbours (default 2; 0 for speed,\n"
      "                       which leaves more clouds with folds, refused by default)\n"
      "  -self_intersections fail|keep\n"
      "                       a mesh whose triangles still intersect after the repair:\n"
      "                       an error (default) or written with a warning\n"
      "  -threads N           worker threads (default: all cores)\n",
      program, program);
}

double
secondsSince (Clock::time_point start)
{
  return std::chrono::duration<double> (Clock::now () - start).count ();
}

/** The process's peak resident set so far in MB (Linux's VmHWM), or -1 where
  * /proc does not say. Printed after each stage: where the peak rises. */
long
peakResidentMegabytes ()
{
  std::FILE* status = std::fopen ("/proc/self/status", "r");
  if (!status)
    return -1;
  char line[256];
  long kilobytes = -1;
  while (std::fgets (line, sizeof line, status))
    if (std::sscanf (line, "VmHWM: %ld kB", &kilobytes) == 1)
      break;
  std::fclose (status);
  return kilobytes < 0 ? -1 : kilobytes / 1024;
}

int
fail (const std::string& reason)
{
  std::fprintf (stderr, "pcl_spherical_meshless_surface: %s\n", reason.c_str ());
  return 1;
}

} // namespace

int
main (int argc, char** argv)
{
  using Reconstruction = pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>;
  std::vector<std::string> positional;
  std::string generate;
  Reconstruction reconstruction;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    auto value = [&] () -> std::string { return has_value ? argv[++i] : ""; };
    try {
      if (arg == "-h" || arg == "--help") {
        usage (argv[0]);
        return 0;
      }
      else if (arg == "-generate")
        generate = value ();
      else if (arg == "-k")
        reconstruction.setNumberOfNeighbours (std::stoi (value ()));
      else if (arg == "-radius")
        reconstruction.setSearchRadius (std::stod (value ()));
      else if (arg == "-threads") {
        const int threads = std::stoi (value ());
        if (threads < 1)
          return fail ("-threads needs a positive number");
        omp_set_num_threads (threads);
      }
      else if (arg == "-weights") {
        const std::string w = value ();
        if (w == "uniform")
          reconstruction.setWeightType (Reconstruction::WeightType::Uniform);
        else if (w == "distance")
          reconstruction.setWeightType (Reconstruction::WeightType::ReciprocalDistance);
        else if (w == "shape")
          reconstruction.setWeightType (Reconstruction::WeightType::ShapePreserving);
        else if (w == "meanvalue")
          reconstruction.setWeightType (Reconstruction::WeightType::MeanValue);
        else
          return fail ("unknown weight type '" + w + "' (uniform|distance|shape|meanvalue)");
      }
      else if (arg == "-optimize") {
        const std::string o = value ();
        if (o != "0" && o != "1")
          return fail ("-optimize takes 0 or 1");
        reconstruction.setOptimize (o == "1");
      }
      else if (arg == "-topology") {
        const std::string t = value ();
        if (t == "sphere")
          reconstruction.setTopology (Reconstruction::Topology::Sphere);
        else if (t == "disc")
          reconstruction.setTopology (Reconstruction::Topology::Disc);
        else
          return fail ("unknown topology '" + t + "' (sphere|disc)");
      }
      else if (arg == "-retries") {
        const int retries = std::stoi (value ());
        if (retries < 0)
          return fail ("-retries needs a number of at least 0");
        reconstruction.setBaseRetries (retries);
      }
      else if (arg == "-self_intersections") {
        const std::string x = value ();
        if (x != "fail" && x != "keep")
          return fail ("-self_intersections takes fail or keep");
        reconstruction.setAllowSelfIntersections (x == "keep");
      }
      else if (arg == "-base") {
        const std::string b = value ();
        if (b == "auto")
          reconstruction.setBasePolyhedron (Reconstruction::BasePolyhedron::BySize);
        else if (b == "tetrahedron")
          reconstruction.setBasePolyhedron (Reconstruction::BasePolyhedron::Tetrahedron);
        else if (b == "octahedron")
          reconstruction.setBasePolyhedron (Reconstruction::BasePolyhedron::Octahedron);
        else if (b == "icosahedron")
          reconstruction.setBasePolyhedron (Reconstruction::BasePolyhedron::Icosahedron);
        else
          return fail ("unknown base '" + b + "' (auto|tetrahedron|octahedron|icosahedron)");
      }
      else if (arg.size () > 1 && arg[0] == '-')
        return fail ("unknown option " + arg + " (see -h)");
      else
        positional.push_back (arg);
    }
    catch (const std::exception&) {
      return fail ("option " + arg + " needs a numeric value");
    }
  }
  const std::size_t expected_positional = generate.empty () ? 2 : 1;
  if (positional.size () != expected_positional)
    return fail (generate.empty () ? "expected INPUT and OUTPUT (see -h)"
                                   : "expected OUTPUT after -generate SHAPE (see -h)");
  const std::string output_path = positional.back ();

  auto cloud = pcl::make_shared<Cloud> ();
  auto start = Clock::now ();
  if (!generate.empty ()) {
    const auto colon = generate.find (':');
    pcl::meshless::SyntheticShape shape;
    if (!pcl::meshless::parseSyntheticShape (generate.substr (0, colon), shape))
      return fail ("unknown shape '" + generate.substr (0, colon) + "' (see -h)");
    pcl::meshless::SyntheticCloudOptions options;
    options.num_points = 20000;
    if (colon != std::string::npos) {
      // std::stoul would take "-1" as the largest count: accept digits only.
      const std::string count = generate.substr (colon + 1);
      constexpr std::size_t max_points = 100000000;
      if (count.empty () || count.size () > 9 ||
          count.find_first_not_of ("0123456789") != std::string::npos)
        return fail ("the point count after ':' must be a whole number up to " +
                     std::to_string (max_points));
      options.num_points = std::stoul (count);
    }
    for (const auto& p : pcl::meshless::sampleShape (shape, options))
      cloud->push_back (pcl::PointXYZ (static_cast<float> (p.x ()), static_cast<float> (p.y ()),
                                       static_cast<float> (p.z ())));
    std::printf ("input: generated %s, %zu points\n", generate.c_str (), cloud->size ());
  }
  else {
    const std::string error = loadCloud (positional[0], *cloud);
    if (!error.empty ())
      return fail (error);
    std::printf ("input: %s, %zu points (%.2f s to read)\n", positional[0].c_str (),
                 cloud->size (), secondsSince (start));
  }
  if (cloud->empty ())
    return fail ("the input cloud is empty");

  reconstruction.setProgressCallback ([] (const pcl::meshless::ProgressReport& stage) {
    const long peak = peakResidentMegabytes ();
    std::printf ("  %-15s %7.3f s  %3.0f%%  %6s  %s\n", stage.stage.c_str (), stage.seconds,
                 100.0 * stage.fraction,
                 peak < 0 ? "" : (std::to_string (peak) + " MB").c_str (), stage.detail.c_str ());
    std::fflush (stdout);
    return true;
  });
  reconstruction.setInputCloud (cloud);
  pcl::PolygonMesh mesh;
  start = Clock::now ();
  reconstruction.reconstruct (mesh);
  const double seconds = secondsSince (start);
  const pcl::SphericalMeshlessReport& report = reconstruction.getReport ();
  if (!report.success) {
    // The class names its setters; here the option that sets them.
    std::string reason = report.message;
    const std::string setter = "setAllowSelfIntersections (true)";
    const auto at = reason.find (setter);
    if (at != std::string::npos)
      reason.replace (at, setter.size (), "-self_intersections keep");
    return fail (reason);
  }

  if (reconstruction.getTopology () == Reconstruction::Topology::Sphere)
    std::printf ("mesh: %zu triangles through %zu points (2n - 4 = %zu) in %.2f s\n",
                 mesh.polygons.size (), report.num_points, 2 * report.num_points - 4, seconds);
  else
    std::printf ("mesh: %zu triangles through %zu points, %zu hole(s) kept open, in %.2f s\n",
                 mesh.polygons.size (), report.num_points, report.holes, seconds);
  if (reconstruction.getOptimize ())
    std::printf ("optimization: %zu swaps, cost %.6g -> %.6g\n", report.optimization.swaps,
                 report.optimization.cost_before, report.optimization.cost_after);
  std::printf ("check: %s\n", pcl::meshless::describe (report.mesh).c_str ());
  if (report.num_duplicates > 0 || report.num_non_finite > 0)
    std::printf ("input: %zu duplicate point(s) merged, %zu non-finite point(s) skipped\n",
                 report.num_duplicates, report.num_non_finite);
  const std::string error = saveMesh (output_path, mesh);
  if (!error.empty ())
    return fail (error);
  std::printf ("wrote %s\n", output_path.c_str ());
  return 0;
}
