// pcl_surface_compare INPUT [-reference MESH] [-out DIR] [options]
//
// Runs PCL's GreedyProjectionTriangulation and pcl::SphericalMeshlessReconstruction on
// the same cloud and prints one markdown table with a row per method: time, peak
// memory and the mesh metrics of pcl::meshless::checkMesh, plus, with -reference, the
// sampled distance and normal deviation to the reference mesh. With -out it writes
// both meshes (binary PLY) and one PNG per method, rendered off screen from the same
// camera (needs an X display; run under xvfb-run on a headless machine).
#include "cloud_io.h"
#include "greedy_projection.h"
#include "mesh_render.h"

#include <pcl/common/common.h>
#include <pcl/filters/filter.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <pcl/surface/meshless/mesh_distance.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <malloc.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace {

using meshless_tools::format;
using meshless_tools::toPoints;
using meshless_tools::toTriangles;

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Clock = std::chrono::steady_clock;

void
usage (const char* program)
{
  std::printf (
      "usage: %s INPUT [-reference MESH] [-out DIR] [options]\n"
      "INPUT   .pcd, .ply or .xyz (x y z per line)\n"
      "MESH    .ply reference surface for distances and normal deviation\n"
      "DIR     receives NAME_greedy.ply, NAME_spherical.ply and a PNG of each\n"
      "options:\n"
      "  -samples N   points sampled per mesh for distances (default 100000)\n"
      "  -size P      picture width and height in pixels (default 600)\n",
      program);
}

int
fail (const std::string& reason)
{
  std::fprintf (stderr, "pcl_surface_compare: %s\n", reason.c_str ());
  return 1;
}

double
secondsSince (Clock::time_point start)
{
  return std::chrono::duration<double> (Clock::now () - start).count ();
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
};

void
printTable (const std::vector<MethodResult>& results, bool with_reference)
{
  std::printf ("\n| method | time | peak memory | triangles | vertices used / unused | "
               "boundary edges / loops | non-manifold edges / vertices | components | "
               "Euler / genus | inconsistent edges | self-intersecting pairs | "
               "mean smallest angle |");
  if (with_reference)
    std::printf (" distance mean / p99 / max | normal deviation |");
  std::printf ("\n|---|---|---|---|---|---|---|---|---|---|---|---|");
  if (with_reference)
    std::printf ("---|---|");
  std::printf ("\n");
  for (const MethodResult& r : results) {
    const pcl::meshless::MeshReport& m = r.report;
    std::printf (
        "| %s | %.2f s | %s | %zu | %zu / %zu | %zu / %zu | %zu / %zu | %zu | %ld / %s "
        "| %zu | %zu | %.1f deg |",
        r.name.c_str (), r.seconds,
        r.memory_mb ? format ("%.0f MB", *r.memory_mb).c_str () : "n/a",
        m.num_triangles, m.used_vertices, m.unused_vertices, m.boundary_edges,
        m.boundary_loops, m.non_manifold_edges, m.non_manifold_vertices, m.components,
        m.euler_characteristic, m.genus < 0 ? "-" : std::to_string (m.genus).c_str (),
        m.inconsistent_edges, m.self_intersecting_pairs, m.mean_min_angle_deg);
    if (with_reference) {
      if (r.distance && r.distance->success)
        std::printf (" %.2e / %.2e / %.2e | %.1f deg |", r.distance->two_sided.mean,
                     r.distance->two_sided.p99, r.distance->two_sided.max,
                     r.distance->normal_deviation_deg);
      else
        std::printf (" - | - |");
    }
    std::printf ("\n");
  }
}

int
run (int argc, char** argv)
{
  std::string input, reference_path, out_dir;
  pcl::meshless::MeshDistanceOptions distance_options;
  int picture_size = 600;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    auto value = [&] () -> std::string { return has_value ? argv[++i] : ""; };
    if ((arg == "-reference" || arg == "-out" || arg == "-samples" || arg == "-size") &&
        !has_value)
      return fail (arg + " needs a value");
    try {
      if (arg == "-h" || arg == "--help") {
        usage (argv[0]);
        return 0;
      }
      else if (arg == "-reference")
        reference_path = value ();
      else if (arg == "-out")
        out_dir = value ();
      else if (arg == "-samples") {
        const long samples = std::stol (value ());
        if (samples < 1)
          return fail ("-samples needs a positive number");
        distance_options.samples = static_cast<std::size_t> (samples);
      }
      else if (arg == "-size") {
        picture_size = std::stoi (value ());
        if (picture_size < 16 || picture_size > 4096)
          return fail ("-size takes 16 to 4096 pixels");
      }
      else if (arg.size () > 1 && arg[0] == '-')
        return fail ("unknown option " + arg + " (see -h)");
      else if (input.empty ())
        input = arg;
      else
        return fail ("more than one INPUT (see -h)");
    } catch (const std::exception&) {
      return fail ("option " + arg + " needs a numeric value");
    }
  }
  if (input.empty ())
    return fail ("expected INPUT (see -h)");

  auto loaded = pcl::make_shared<Cloud> ();
  std::string error = meshless_tools::loadCloud (input, *loaded);
  if (!error.empty ())
    return fail (error);
  // Greedy projection needs finite points; both methods get the same cloud.
  auto cloud = pcl::make_shared<Cloud> ();
  pcl::Indices kept;
  pcl::removeNaNFromPointCloud (*loaded, *cloud, kept);
  if (cloud->size () < 4)
    return fail ("the input has fewer than 4 finite points");

  pcl::meshless::Points3 reference_vertices;
  pcl::meshless::Triangles reference_triangles;
  if (!reference_path.empty ()) {
    error = meshless_tools::loadMesh (reference_path, reference_vertices,
                                      reference_triangles);
    if (!error.empty ())
      return fail (error);
  }
  if (!out_dir.empty ()) {
    std::error_code code;
    std::filesystem::create_directories (out_dir, code);
    if (code)
      return fail ("cannot create " + out_dir + ": " + code.message ());
  }

  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>> ();
  tree->setInputCloud (cloud);
  const meshless_tools::GreedyParameters parameters =
      meshless_tools::greedyParameters (*tree, *cloud);
  std::printf ("input: %s, %zu finite points\n", input.c_str (), cloud->size ());
  std::printf ("greedy projection: %s\n", parameters.describe ().c_str ());
  std::printf ("spherical meshless: default options (k = 12, mean value weights, "
               "base polyhedron by size; a mesh with folds left is kept and its pairs counted)\n");
  std::fflush (stdout);

  std::vector<MethodResult> results (2);
  {
    MethodResult& greedy = results[0];
    greedy.name = "greedy projection";
    const PeakMemory memory;
    const auto start = Clock::now ();
    meshless_tools::greedyProjection (cloud, tree, parameters, greedy.mesh);
    greedy.seconds = secondsSince (start);
    greedy.memory_mb = memory.megabytes ();
  }
  {
    MethodResult& spherical = results[1];
    spherical.name = "spherical meshless";
    const PeakMemory memory;
    const auto start = Clock::now ();
    pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
    reconstruction.setInputCloud (cloud);
    reconstruction.setSearchMethod (tree);
    // A measuring tool: a mesh with folds left is measured, not refused.
    reconstruction.setAllowSelfIntersections (true);
    reconstruction.reconstruct (spherical.mesh);
    spherical.seconds = secondsSince (start);
    spherical.memory_mb = memory.megabytes ();
    if (!reconstruction.getReport ().success)
      std::printf ("spherical meshless failed: %s\n",
                   reconstruction.getReport ().message.c_str ());
  }

  const pcl::meshless::Points3 vertices = toPoints (*cloud);
  for (MethodResult& r : results) {
    // Both meshes are written and rendered over the plain points (greedy projection
    // keeps the normals in its cloud, which would shade by their arbitrary signs).
    pcl::toPCLPointCloud2 (*cloud, r.mesh.cloud);
    const pcl::meshless::Triangles triangles = toTriangles (r.mesh);
    r.report = pcl::meshless::checkMesh (vertices, triangles);
    if (!reference_path.empty ()) {
      r.distance =
          pcl::meshless::compareToReference (vertices, triangles, reference_vertices,
                                             reference_triangles, distance_options);
      if (!r.distance->success)
        std::printf ("%s: no distance: %s\n", r.name.c_str (),
                     r.distance->message.c_str ());
    }
  }
  printTable (results, !reference_path.empty ());

  if (!out_dir.empty ()) {
    const std::string stem = std::filesystem::path (input).stem ().string ();
    const bool can_render = std::getenv ("DISPLAY") != nullptr;
    // The same camera for every method, fitted to the cloud's bounding box whatever
    // triangles the method made.
    pcl::PointXYZ lo, hi;
    pcl::getMinMax3D (*cloud, lo, hi);
    const std::array<double, 6> bounds{lo.x, hi.x, lo.y, hi.y, lo.z, hi.z};
    meshless_tools::RenderOptions render;
    render.size = picture_size;
    for (std::size_t m = 0; m < results.size (); ++m) {
      const std::string base = (std::filesystem::path (out_dir) /
                                (stem + (m == 0 ? "_greedy" : "_spherical")))
                                   .string ();
      error = meshless_tools::saveMesh (base + ".ply", results[m].mesh);
      if (error.empty () && can_render)
        error = meshless_tools::renderPng (results[m].mesh, bounds, base + ".png", render);
      if (!error.empty ())
        return fail (error);
    }
    std::printf (
        "\nwrote %s/%s_{greedy,spherical}.ply%s\n", out_dir.c_str (), stem.c_str (),
        can_render ? " and .png" : " (no DISPLAY: pictures skipped, use xvfb-run)");
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
    return fail (e.what ());
  }
}
