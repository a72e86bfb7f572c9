// pcl_surface_compare INPUT [-reference MESH] [-out DIR] [options]
//
// Runs PCL's GreedyProjectionTriangulation and pcl::SphericalMeshlessReconstruction on
// the same cloud and prints one markdown table with a row per method: time, peak
// memory and the mesh metrics of pcl::meshless::checkMesh, plus, with -reference, the
// sampled distance and normal deviation to the reference mesh. With -out it writes
// both meshes (binary PLY) and one PNG per method, rendered off screen from the same
// camera (needs an X display; run under xvfb-run on a headless machine).
#include <meshless_tools/cloud_io.h>
#include "command_line.h"
#include <meshless_tools/greedy_projection.h>
#include <meshless_tools/mesh_render.h>

#include <pcl/common/common.h>
#include <pcl/console/time.h>
#include <pcl/filters/filter.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <meshless_tools/mesh_distance.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace {

using meshless_tools::CommandLine;
using meshless_tools::fail;
using meshless_tools::format;
using meshless_tools::toPoints;
using meshless_tools::toTriangles;

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

constexpr const char* kTool = "pcl_surface_compare";

void
usage (const char* program)
{
  pcl::console::print_info (
      "usage: %s INPUT [-reference MESH] [-out DIR] [options]\n"
      "INPUT   .pcd, .ply or .xyz (x y z per line)\n"
      "MESH    .ply reference surface for distances and normal deviation\n"
      "DIR     receives NAME_greedy.ply, NAME_spherical.ply and a PNG of each\n"
      "options:\n"
      "  -samples N   points sampled per mesh for distances (default 100000)\n"
      "  -size P      picture width and height in pixels (default 600)\n"
      "  -topology T  sphere (default), closed (any genus) or disc, for the meshless class\n",
      program);
}

/** A value in kB from /proc/self/status ("VmRSS", "VmHWM"), or -1. */
long
statusKb (const std::string& key)
{
  std::ifstream status ("/proc/self/status");
  std::string line;
  while (std::getline (status, line))
    if (line.compare (0, key.size () + 1, key + ":") == 0)
      return std::atol (line.c_str () + key.size () + 1);
  return -1;
}

/** Measures the peak resident set of one method relative to its start: freed memory
  * goes back to the system and the kernel's high-water mark is reset first, so each
  * method is measured on its own although both run in one process. */
class PeakMemory
{
public:
  PeakMemory ()
  {
    malloc_trim (0);
    std::ofstream clear ("/proc/self/clear_refs");
    clear << "5";
    clear.flush ();
    resettable_ = static_cast<bool> (clear);
    start_kb_ = statusKb ("VmRSS");
  }

  /** Megabytes above the start, or nothing where the kernel cannot say. */
  std::optional<double>
  megabytes () const
  {
    const long peak_kb = statusKb ("VmHWM");
    if (!resettable_ || peak_kb < 0 || start_kb_ < 0)
      return std::nullopt;
    return static_cast<double> (peak_kb - start_kb_) / 1024.0;
  }

private:
  bool resettable_ = false;
  long start_kb_ = -1;
};

struct MethodResult
{
  std::string name;
  pcl::PolygonMesh mesh;
  double seconds = 0.0;
  std::optional<double> memory_mb;
  pcl::meshless::MeshReport report;
  std::optional<pcl::meshless::MeshDistanceReport> distance;
  /** The longest edge over the median edge: a triangle across a gap or a crease. */
  double longest_over_median = 0.0;
  /** The positions the triangles run through, where not the input's (a noisy
    * cloud's projections). */
  pcl::PointCloud<pcl::PointXYZ>::ConstPtr positions;
};

double
longestOverMedianEdge (const pcl::meshless::Points3& vertices,
                       const pcl::meshless::Triangles& triangles)
{
  std::vector<double> lengths;
  lengths.reserve (3 * triangles.size ());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k)
      lengths.push_back ((vertices[t[k]] - vertices[t[(k + 1) % 3]]).norm ());
  if (lengths.empty ())
    return 0.0;
  const auto middle = lengths.begin () + static_cast<std::ptrdiff_t> (lengths.size () / 2);
  std::nth_element (lengths.begin (), middle, lengths.end ());
  const double median = *middle;
  const double longest = *std::max_element (lengths.begin (), lengths.end ());
  return median > 0.0 ? longest / median : 0.0;
}

void
printTable (const std::vector<MethodResult>& results, bool with_reference)
{
  std::printf ("\n| method | time | peak memory | triangles | vertices used / unused | "
               "boundary edges / loops | non-manifold edges / vertices | components | "
               "Euler / genus | inconsistent edges | self-intersecting pairs | "
               "mean smallest angle | longest / median edge |");
  if (with_reference)
    std::printf (" distance mean / p99 / max | largest from the mesh | normal deviation |");
  std::printf ("\n|---|---|---|---|---|---|---|---|---|---|---|---|---|");
  if (with_reference)
    std::printf ("---|---|---|");
  std::printf ("\n");
  for (const MethodResult& r : results) {
    const pcl::meshless::MeshReport& m = r.report;
    std::printf (
        "| %s | %.2f s | %s | %zu | %zu / %zu | %zu / %zu | %zu / %zu | %zu | %ld / %s "
        "| %zu | %zu | %.1f deg | %.1f |",
        r.name.c_str (), r.seconds,
        r.memory_mb ? format ("%.0f MB", *r.memory_mb).c_str () : "n/a",
        m.num_triangles, m.used_vertices, m.unused_vertices, m.boundary_edges,
        m.boundary_loops, m.non_manifold_edges, m.non_manifold_vertices, m.components,
        m.euler_characteristic, m.genus < 0 ? "-" : std::to_string (m.genus).c_str (),
        m.inconsistent_edges, m.self_intersecting_pairs, m.mean_min_angle_deg,
        r.longest_over_median);
    if (with_reference) {
      if (r.distance && r.distance->success)
        std::printf (" %.2e / %.2e / %.2e | %.2e | %.1f deg |", r.distance->two_sided.mean,
                     r.distance->two_sided.p99, r.distance->two_sided.max,
                     r.distance->to_reference.max, r.distance->normal_deviation_deg);
      else
        std::printf (" - | - | - |");
    }
    std::printf ("\n");
  }
}

struct CompareOptions
{
  std::string input, reference_path, out_dir;
  pcl::meshless::MeshDistanceOptions distance;
  int picture_size = 600;
  pcl::meshless::Topology topology = pcl::meshless::Topology::Sphere;
};

/** The options, or false with the reason in `error`. */
bool
parseOptions (int argc, char** argv, CompareOptions& options, std::string& error)
{
  CommandLine line (argc, argv,
                    {{"-h", false}, {"--help", false}, {"-reference", true}, {"-out", true},
                     {"-samples", true}, {"-size", true}, {"-topology", true}});
  int samples = static_cast<int> (options.distance.samples);
  int& size = options.picture_size;
  int topology = -1;
  const bool read = line.choose ("-topology", {"sphere", "disc", "closed"}, topology) &&
                    line.read ("-reference", options.reference_path) &&
                    line.read ("-out", options.out_dir) && line.read ("-samples", samples) &&
                    line.read ("-size", size) &&
                    (samples >= 1 || line.reject ("-samples", "must be 1 or more")) &&
                    ((size >= 16 && size <= 4096) || line.reject ("-size", "takes 16 to 4096 pixels"));
  error = line.error ();
  if (read && error.empty () && line.positional ().size () != 1)
    error = line.positional ().empty () ? "expected INPUT (see -h)"
                                        : "more than one INPUT (see -h)";
  if (!error.empty ())
    return false;
  options.distance.samples = static_cast<std::size_t> (samples);
  const pcl::meshless::Topology topologies[] = {pcl::meshless::Topology::Sphere,
                                                pcl::meshless::Topology::Disc,
                                                pcl::meshless::Topology::Closed};
  if (topology >= 0)
    options.topology = topologies[topology];
  options.input = line.positional ()[0];
  return true;
}

/** The input's finite points (greedy projection needs them; both methods get the
  * same cloud) and the reference mesh when there is one. */
std::string
loadInputs (const CompareOptions& options, Cloud& cloud,
            pcl::meshless::Points3& reference_vertices,
            pcl::meshless::Triangles& reference_triangles)
{
  const meshless_tools::QuietPclLog quiet;
  Cloud loaded;
  std::string error = meshless_tools::loadCloud (options.input, loaded);
  if (!error.empty ())
    return error;
  pcl::Indices kept;
  pcl::removeNaNFromPointCloud (loaded, cloud, kept);
  if (cloud.size () < 4)
    return options.input + ": fewer than 4 finite points";
  if (!options.reference_path.empty ())
    error = meshless_tools::loadMesh (options.reference_path, reference_vertices,
                                      reference_triangles);
  return error;
}

/** Both methods on the same cloud and search tree, each timed and measured alone. */
std::vector<MethodResult>
runMethods (const Cloud::Ptr& cloud, const pcl::search::KdTree<pcl::PointXYZ>::Ptr& tree,
            const meshless_tools::GreedyParameters& parameters, pcl::meshless::Topology topology)
{
  std::vector<MethodResult> results (2);
  pcl::console::TicToc timer;
  {
    MethodResult& greedy = results[0];
    greedy.name = "greedy projection";
    const PeakMemory memory;
    timer.tic ();
    meshless_tools::greedyProjection (cloud, tree, parameters, greedy.mesh);
    greedy.seconds = timer.toc () / 1000.0;
    greedy.memory_mb = memory.megabytes ();
  }
  MethodResult& spherical = results[1];
  spherical.name = "spherical meshless";
  const PeakMemory memory;
  timer.tic ();
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setSearchMethod (tree);
  reconstruction.setTopology (topology);
  // A measuring tool: a mesh with folds left is measured, not refused.
  reconstruction.setAllowSelfIntersections (true);
  reconstruction.setReleaseFreedMemory (true); // its peak memory as the CLI measures it
  {
    const meshless_tools::QuietPclLog quiet;
    reconstruction.reconstruct (spherical.mesh);
  }
  spherical.seconds = timer.toc () / 1000.0;
  spherical.memory_mb = memory.megabytes ();
  if (reconstruction.getReport ().smoothed) {
    spherical.positions = reconstruction.getVertexCloud ();
    pcl::console::print_info ("spherical meshless: through the points projected onto "
                              "surfaces fitted to them (noise %.2f spacings)\n",
                              reconstruction.getReport ().noise.noise_ratio);
  }
  if (!reconstruction.getReport ().success)
    pcl::console::print_info ("spherical meshless failed: %s\n",
                              reconstruction.getReport ().message.c_str ());
  return results;
}

/** Both meshes as binary PLY and, with a display, a PNG each from one camera. */
std::string
writeOutputs (const CompareOptions& options, const Cloud& cloud,
              const std::vector<MethodResult>& results)
{
  std::error_code code;
  std::filesystem::create_directories (options.out_dir, code);
  if (code)
    return "cannot create " + options.out_dir + ": " + code.message ();
  const std::string stem = std::filesystem::path (options.input).stem ().string ();
  const bool can_render = std::getenv ("DISPLAY") != nullptr;
  // The same camera for every method, fitted to the cloud's bounding box whatever
  // triangles the method made.
  pcl::PointXYZ lo, hi;
  pcl::getMinMax3D (cloud, lo, hi);
  const std::array<double, 6> bounds{lo.x, hi.x, lo.y, hi.y, lo.z, hi.z};
  meshless_tools::RenderOptions render;
  render.size = options.picture_size;
  for (std::size_t m = 0; m < results.size (); ++m) {
    const std::string base = (std::filesystem::path (options.out_dir) /
                              (stem + (m == 0 ? "_greedy" : "_spherical")))
                                 .string ();
    std::string error = meshless_tools::saveMesh (base + ".ply", results[m].mesh);
    if (error.empty () && can_render)
      error = meshless_tools::renderPng (results[m].mesh, bounds, base + ".png", render);
    if (!error.empty ())
      return error;
  }
  pcl::console::print_info (
      "\nwrote %s/%s_{greedy,spherical}.ply%s\n", options.out_dir.c_str (), stem.c_str (),
      can_render ? " and .png" : " (no DISPLAY: pictures skipped, use xvfb-run)");
  return "";
}

int
run (int argc, char** argv)
{
  CompareOptions options;
  std::string error;
  if (pcl::console::find_switch (argc, argv, "-h") ||
      pcl::console::find_switch (argc, argv, "--help")) {
    usage (argv[0]);
    return 0;
  }
  if (!parseOptions (argc, argv, options, error))
    return fail (kTool, error);
  auto cloud = pcl::make_shared<Cloud> ();
  pcl::meshless::Points3 reference_vertices;
  pcl::meshless::Triangles reference_triangles;
  error = loadInputs (options, *cloud, reference_vertices, reference_triangles);
  if (!error.empty ())
    return fail (kTool, error);

  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>> ();
  tree->setInputCloud (cloud);
  const meshless_tools::GreedyParameters parameters =
      meshless_tools::greedyParameters (*tree, *cloud);
  pcl::console::print_info ("input: %s, %zu finite points\n", options.input.c_str (),
                            cloud->size ());
  pcl::console::print_info ("greedy projection: %s\n", parameters.describe ().c_str ());
  pcl::console::print_info (
      "spherical meshless: default options (k = 12, mean value weights, base polyhedron "
      "by size; a mesh with folds left is kept and its pairs counted)\n");
  std::fflush (stdout);
  std::vector<MethodResult> results = runMethods (cloud, tree, parameters, options.topology);

  const bool with_reference = !options.reference_path.empty ();
  for (MethodResult& r : results) {
    // Both meshes are written and rendered over the plain points (greedy projection
    // keeps the normals in its cloud, which would shade by their arbitrary signs).
    const Cloud& points = r.positions ? *r.positions : *cloud;
    const pcl::meshless::Points3 vertices = toPoints (points);
    pcl::toPCLPointCloud2 (points, r.mesh.cloud);
    const pcl::meshless::Triangles triangles = toTriangles (r.mesh);
    r.report = pcl::meshless::checkMesh (vertices, triangles);
    r.longest_over_median = longestOverMedianEdge (vertices, triangles);
    if (!with_reference)
      continue;
    r.distance = pcl::meshless::compareToReference (
        vertices, triangles, reference_vertices, reference_triangles, options.distance);
    if (!r.distance->success)
      pcl::console::print_info ("%s: no distance: %s\n", r.name.c_str (),
                                r.distance->message.c_str ());
  }
  printTable (results, with_reference);
  if (!options.out_dir.empty ()) {
    error = writeOutputs (options, *cloud, results);
    if (!error.empty ())
      return fail (kTool, error);
  }
  return 0;
}

} // namespace

int
main (int argc, char** argv)
{
  // PCL and VTK may throw (out of memory, unreadable files): one line, exit 1.
  try {
    return run (argc, argv);
  } catch (const std::exception& e) {
    return fail (kTool, e.what ());
  }
}
