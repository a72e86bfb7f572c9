// pcl_spherical_meshless_surface INPUT OUTPUT [options]
//
// Reconstructs a closed, oriented genus-0 triangle mesh through every point of a
// cloud with pcl::SphericalMeshlessReconstruction. INPUT is .pcd, .ply or .xyz
// (x y z per line), or -generate SHAPE[:N] for one of the project's own clouds.
// OUTPUT is .ply (binary), .vtk or .obj. Prints stage timings and the triangle
// count; exits 0 on success, otherwise 1 with a one-line reason on stderr that names
// the option or the file to change.
#include <meshless_tools/cloud_io.h>
#include "command_line.h"

#include <pcl/console/time.h>
#include <pcl/point_types.h>
#include <meshless_tools/synthetic_clouds.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>


#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

namespace {

using namespace pcl::console;
using meshless_tools::CommandLine;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Reconstruction = pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>;

constexpr const char* kTool = "pcl_spherical_meshless_surface";

const std::vector<meshless_tools::Flag> kFlags = {
    {"-h", false},        {"--help", false},   {"-generate", true}, {"-k", true},
    {"-radius", true},    {"-weights", true},  {"-topology", true}, {"-optimize", true},
    {"-base", true},      {"-retries", true},  {"-self_intersections", true},
    {"-threads", true},   {"-smooth", true}};

void
usage (const char* program)
{
  print_info (
      "usage: %s INPUT OUTPUT [options]\n"
      "       %s -generate SHAPE[:N] OUTPUT [options]\n"
      "INPUT   .pcd, .ply or .xyz (x y z per line)\n"
      "OUTPUT  .ply (binary), .vtk or .obj\n"
      "SHAPE   sphere, ellipsoid, bumpy_sphere, torus, thin_torus, fat_torus, double_torus,\n"
      "        knotted_tube, thin_limbs, disc, height_field (N points, default 20000)\n"
      "options:\n"
      "  -k N                 nearest neighbours (default 12)\n"
      "  -radius R            ball neighbourhood of radius R instead of k nearest\n"
      "  -weights W           uniform|distance|shape|meanvalue (default meanvalue)\n"
      "  -topology T          sphere (closed, genus 0, default), closed (closed, of the\n"
      "                       genus found from the cloud) or disc (open surface)\n"
      "  -optimize 0|1        edge-swap optimization (default 1)\n"
      "  -base B              auto|tetrahedron|octahedron|icosahedron (default auto:\n"
      "                       tetrahedron up to 500000 points, octahedron above)\n"
      "  -retries N           further base meshes tried while the result intersects\n"
      "                       itself, then k + 2 neighbours (default 2; 0 for speed,\n"
      "                       which leaves more clouds with folds, refused by default)\n"
      "  -self_intersections fail|keep\n"
      "                       a mesh whose triangles still intersect after the repair:\n"
      "                       an error (default) or written with a warning\n"
      "  -smooth S            off|auto|always: the mesh through the points moved onto\n"
      "                       surfaces fitted to their neighbours (auto, the default:\n"
      "                       only where noise about the point spacing fails the run)\n"
      "  -threads N           worker threads (default 0: all cores)\n",
      program, program);
}

/** The class's messages name its setters; a user of this tool needs the option. */
std::string
namingOptions (std::string message)
{
  static const std::pair<const char*, const char*> options[] = {
      {"setTopology (Topology::Disc)", "-topology disc"},
      {"setTopology (Topology::Closed)", "-topology closed"},
      {"setAllowSelfIntersections (true)", "-self_intersections keep"},
      {"setOptimize (false)", "-optimize 0"},
      {"setSearchRadius", "-radius"},
      {"setNumberOfNeighbours", "-k"},
      {"setBaseRetries", "-retries"},
      {"setBasePolyhedron", "-base"},
      {"setWeightType", "-weights"},
      {"setNumberOfThreads", "-threads"}};
  for (const auto& [setter, option] : options)
    for (std::size_t at; (at = message.find (setter)) != std::string::npos;)
      message.replace (at, std::strlen (setter), option);
  return message;
}

/** The numeric options, checked here so that a wrong value is refused before a large
  * cloud is read; the class checks them again. */
bool
readNumbers (CommandLine& line, Reconstruction& reconstruction, int& threads)
{
  int k = reconstruction.getNumberOfNeighbours ();
  int retries = reconstruction.getBaseRetries ();
  double radius = reconstruction.getSearchRadius ();
  if (!line.read ("-k", k) || !line.read ("-radius", radius) ||
      !line.read ("-retries", retries) || !line.read ("-threads", threads))
    return false;
  if (!std::isfinite (radius) || radius < 0.0)
    return line.reject ("-radius", "must be finite and not negative");
  if (radius == 0.0 && k < 3)
    return line.reject ("-k", "must be at least 3");
  if (retries < 0)
    return line.reject ("-retries", "must be 0 or more");
  if (threads < 0)
    return line.reject ("-threads", "must be 0 (all cores) or more");
  reconstruction.setNumberOfNeighbours (k);
  reconstruction.setSearchRadius (radius);
  reconstruction.setBaseRetries (retries);
  return true;
}

/** The options that name a choice; each left at the class's default when absent. */
bool
readChoices (CommandLine& line, Reconstruction& reconstruction)
{
  using Weights = Reconstruction::WeightType;
  using Base = Reconstruction::BasePolyhedron;
  const Weights weights[] = {Weights::Uniform, Weights::ReciprocalDistance,
                             Weights::ShapePreserving, Weights::MeanValue};
  const Base bases[] = {Base::BySize, Base::Tetrahedron, Base::Octahedron, Base::Icosahedron};
  const Reconstruction::Topology topologies[] = {Reconstruction::Topology::Sphere,
                                                 Reconstruction::Topology::Disc,
                                                 Reconstruction::Topology::Closed};
  const Reconstruction::PointSmoothing smoothings[] = {Reconstruction::PointSmoothing::Off,
                                                       Reconstruction::PointSmoothing::IfNoisy,
                                                       Reconstruction::PointSmoothing::Always};
  int weight = -1, topology = -1, optimize = -1, base = -1, intersections = -1, smooth = -1;
  if (!line.choose ("-weights", {"uniform", "distance", "shape", "meanvalue"}, weight) ||
      !line.choose ("-topology", {"sphere", "disc", "closed"}, topology) ||
      !line.choose ("-optimize", {"0", "1"}, optimize) ||
      !line.choose ("-base", {"auto", "tetrahedron", "octahedron", "icosahedron"}, base) ||
      !line.choose ("-self_intersections", {"fail", "keep"}, intersections) ||
      !line.choose ("-smooth", {"off", "auto", "always"}, smooth))
    return false;
  if (weight >= 0)
    reconstruction.setWeightType (weights[weight]);
  if (topology >= 0)
    reconstruction.setTopology (topologies[topology]);
  if (optimize >= 0)
    reconstruction.setOptimize (optimize == 1);
  if (base >= 0)
    reconstruction.setBasePolyhedron (bases[base]);
  if (intersections >= 0)
    reconstruction.setAllowSelfIntersections (intersections == 1);
  if (smooth >= 0)
    reconstruction.setPointSmoothing (smoothings[smooth]);
  return true;
}

/** -generate SHAPE[:N]: one of the project's own clouds. */
std::string
generateCloud (const std::string& spec, Cloud& cloud)
{
  const auto colon = spec.find (':');
  pcl::meshless::SyntheticShape shape;
  if (!pcl::meshless::parseSyntheticShape (spec.substr (0, colon), shape))
    return "-generate: unknown shape '" + spec.substr (0, colon) + "' (see -h)";
  pcl::meshless::SyntheticCloudOptions options;
  options.num_points = 20000;
  if (colon != std::string::npos) {
    // std::stoul would take "-1" as the largest count: digits only.
    const std::string count = spec.substr (colon + 1);
    if (count.empty () || count.size () > 9 ||
        count.find_first_not_of ("0123456789") != std::string::npos)
      return "-generate: the point count after ':' must be a whole number up to 100000000";
    options.num_points = std::stoul (count);
  }
  for (const auto& p : pcl::meshless::sampleShape (shape, options))
    cloud.push_back (pcl::PointXYZ (static_cast<float> (p.x ()), static_cast<float> (p.y ()),
                                    static_cast<float> (p.z ())));
  return "";
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

/** One line per stage. Printed at L_ALWAYS: the stages run while PCL's own log is
  * silenced (QuietPclLog), which print_info's L_INFO would be too. */
bool
printStage (const pcl::meshless::ProgressReport& stage)
{
  const long peak = peakResidentMegabytes ();
  print (L_ALWAYS, "  %-15s ", stage.stage.c_str ());
  print_value ("%7.3f", stage.seconds);
  print (L_ALWAYS, " s  %3.0f%%  %6s  %s\n", 100.0 * stage.fraction,
         peak < 0 ? "" : (std::to_string (peak) + " MB").c_str (), stage.detail.c_str ());
  std::fflush (stdout);
  return true;
}

void
printResult (const Reconstruction& reconstruction, const pcl::PolygonMesh& mesh,
             double seconds)
{
  const pcl::SphericalMeshlessReport& report = reconstruction.getReport ();
  print_info ("mesh: ");
  print_value ("%zu", mesh.polygons.size ());
  print_info (" triangles through ");
  print_value ("%zu", report.num_points);
  if (reconstruction.getTopology () == Reconstruction::Topology::Sphere)
    print_info (" points (2n - 4 = %zu) in ", 2 * report.num_points - 4);
  else if (reconstruction.getTopology () == Reconstruction::Topology::Closed)
    print_info (" points, genus %d (2n - 4 + 4g = %zu), in ", report.stats.genus,
                2 * report.num_points - 4 + 4 * static_cast<std::size_t> (report.stats.genus));
  else if (report.holes_opened > 0)
    print_info (" points, %zu hole(s) kept open (%zu cut open where the rim walk missed "
                "them), in ", report.holes, report.holes_opened);
  else
    print_info (" points, %zu hole(s) kept open, in ", report.holes);
  print_value ("%.2f", seconds);
  print_info (" s\n");
  if (reconstruction.getOptimize ())
    print_info ("optimization: %zu swaps, cost %.6g -> %.6g\n", report.optimization.swaps,
                report.optimization.cost_before, report.optimization.cost_after);
  print_info ("check: %s\n", pcl::meshless::describe (report.mesh).c_str ());
  if (report.num_duplicates > 0 || report.num_non_finite > 0)
    print_info ("input: %zu duplicate point(s) merged, %zu non-finite point(s) skipped\n",
                report.num_duplicates, report.num_non_finite);
  if (report.smoothed)
    print_warn ("%s: the points lie %.2f of their spacing off surfaces fitted to them "
                "(median): the mesh runs through their projections, moved by up to %g "
                "(-smooth off meshes the points as given or refuses)\n",
                kTool, report.noise.noise_ratio, report.noise.max_offset);
  if (report.mesh.self_intersecting_pairs > 0)
    print_warn ("%s: %zu pair(s) of triangles intersect in local folds (noisy or thin "
                "input); the mesh is %s and oriented all the same\n",
                kTool, report.mesh.self_intersecting_pairs,
                reconstruction.getTopology () == Reconstruction::Topology::Disc
                    ? "manifold"
                    : "closed");
}

/** The input cloud, generated or read; an empty string or the reason it failed. */
std::string
inputCloud (const CommandLine& line, const std::string& generate, Cloud& cloud)
{
  TicToc timer;
  timer.tic ();
  if (!generate.empty ()) {
    const std::string error = generateCloud (generate, cloud);
    if (!error.empty ())
      return error;
    print_info ("input: generated %s, ", generate.c_str ());
    print_value ("%zu", cloud.size ());
    print_info (" points\n");
    return cloud.empty () ? "the input cloud is empty" : "";
  }
  const std::string& path = line.positional ()[0];
  std::string error;
  {
    const meshless_tools::QuietPclLog quiet;
    error = meshless_tools::loadCloud (path, cloud);
  }
  if (!error.empty ())
    return error;
  print_info ("input: %s, ", path.c_str ());
  print_value ("%zu", cloud.size ());
  print_info (" points (");
  print_value ("%.2f", timer.toc () / 1000.0);
  print_info (" s to read)\n");
  return cloud.empty () ? path + ": the input cloud is empty" : "";
}

} // namespace

int
main (int argc, char** argv)
{
  CommandLine line (argc, argv, kFlags);
  if (line.error ().empty () && (line.has ("-h") || line.has ("--help"))) {
    usage (argv[0]);
    return 0;
  }
  Reconstruction reconstruction;
  std::string generate;
  int threads = 0;
  if (!line.read ("-generate", generate) || !readNumbers (line, reconstruction, threads) ||
      !readChoices (line, reconstruction) || !line.error ().empty ())
    return meshless_tools::fail (kTool, line.error ());
  const std::size_t expected_positional = generate.empty () ? 2 : 1;
  if (line.positional ().size () != expected_positional)
    return meshless_tools::fail (kTool, generate.empty ()
                                            ? "expected INPUT and OUTPUT (see -h)"
                                            : "expected OUTPUT after -generate SHAPE (see -h)");
  reconstruction.setNumberOfThreads (static_cast<unsigned int> (threads));
  // A tool owns its process: freed memory goes back to the system between stages,
  // which lowers the peak of large clouds.
  reconstruction.setReleaseFreedMemory (true);

  try {
    auto cloud = pcl::make_shared<Cloud> ();
    const std::string error = inputCloud (line, generate, *cloud);
    if (!error.empty ())
      return meshless_tools::fail (kTool, error);

    reconstruction.setProgressCallback (printStage);
    reconstruction.setInputCloud (cloud);
    pcl::PolygonMesh mesh;
    TicToc timer;
    timer.tic ();
    {
      const meshless_tools::QuietPclLog quiet;
      reconstruction.reconstruct (mesh);
    }
    if (!reconstruction.getReport ().success)
      return meshless_tools::fail (kTool, namingOptions (reconstruction.getReport ().message));
    printResult (reconstruction, mesh, timer.toc () / 1000.0);

    const std::string& output = line.positional ().back ();
    const std::string saved = meshless_tools::saveMesh (output, mesh);
    if (!saved.empty ())
      return meshless_tools::fail (kTool, saved);
    print_info ("wrote %s\n", output.c_str ());
  } catch (const std::exception& e) {
    // Out of memory, mostly: one line all the same.
    return meshless_tools::fail (kTool, e.what ());
  }
  return 0;
}
