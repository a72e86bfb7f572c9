// pcl_optimization_report [CLOUD[=REFERENCE] ...] [options]
//
// What the edge-swap optimization (pcl::meshless::optimizeBySwaps) does to the
// reconstruction of each cloud, before -> after, as markdown tables:
// - before: pcl::SphericalMeshlessReconstruction with setOptimize (false), the raw
//   triangulation (the class's thin-part retry included);
// - after: optimizeBySwaps on that same triangulation with the options under test
//   (the library's defaults unless options below say otherwise), timed on its own;
// - share: the class with the optimization on (same options) run as a user runs it;
//   the time of its "optimize" stages (both attempts when it retries) over the whole
//   reconstruct () call, the median over -repeat runs.
// Quality: normal deviation and two-sided distance to the reference mesh
// (compareToReference), smallest angles and self-intersecting pairs (checkMesh), the
// share of edges that are reference edges and of the reference's sharp edges present
// (compareEdges; only where the cloud is made of the reference's vertices).
// With -out, NAME_before.png and NAME_after.png show both meshes with their edges
// and the reference's sharp edges the mesh misses in red (under xvfb-run when
// headless).
#include <meshless_tools/cloud_io.h>
#include "command_line.h"
#ifdef MESHLESS_WITH_RENDER
#include <meshless_tools/mesh_render.h>
#endif

#include <pcl/common/common.h>
#include <pcl/console/time.h>
#include <pcl/filters/filter.h>
#include <pcl/surface/meshless/edge_swap.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <meshless_tools/mesh_distance.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using meshless_tools::CommandLine;
using meshless_tools::fail;
using meshless_tools::format;
using meshless_tools::toTriangles;

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Clock = std::chrono::steady_clock;
namespace meshless = pcl::meshless;

constexpr const char* kTool = "pcl_optimization_report";

/** The default clouds: each made of its reference's vertices, except the noisy one,
  * whose reference is the mesh it was sampled from. */
const char* const default_clouds[] = {"fandisk_6475", "armadillo_igl", "bunny_igl", "horse",
                                      "armadillo_noisy_100k=armadillo_igl"};

void
usage (const char* program)
{
  std::printf (
      "usage: %s [CLOUD[=REFERENCE] ...] [options]\n"
      "CLOUD      a path (.pcd, .ply, .xyz) or a name in DATA/clouds (NAME.pcd)\n"
      "REFERENCE  a path or a name in DATA/meshes; default DATA/meshes/NAME.ply if it\n"
      "           exists. Without CLOUD: %s, %s, %s, %s, %s\n"
      "options:\n"
      "  -data DIR        shared data directory (default ../../shared/data, or\n"
      "                   $MESHLESS_DATA_DIR)\n"
      "  -repeat N        timing runs of the whole reconstruction per cloud (median,\n"
      "                   default 1; 0: none)\n"
      "  -samples N       points sampled per mesh for distances (default 100000;\n"
      "                   maxima also over 28 lattice points on every triangle)\n"
      "  -out DIR         pictures NAME_before.png, NAME_after.png (needs DISPLAY)\n"
      "  -size P          picture size in pixels (default 800)\n"
      "  -view X,Y,Z      camera direction from the model (default 0.5,0.4,1: front,\n"
      "                   a little from the right and above, y up)\n"
      "  -timing-only     only the timing runs (for clouds too large to compare)\n"
      "optimization options (default: the library's EdgeSwapOptions):\n"
      "  -cost abn|mean|squared|total\n"
      "  -descent-min-dihedral DEG  EdgeSwapOptions::descent_min_dihedral_deg\n"
      "  -noisy-median DEG          EdgeSwapOptions::noisy_median_dihedral_deg\n"
      "  -angles 0|1      EdgeSwapOptions::improve_angles\n"
      "  -longest 0|1     EdgeSwapOptions::descent_keeps_longest_edge\n"
      "  -look-ahead N    EdgeSwapOptions::look_ahead_depth (0: off)\n"
      "  -crease-look-ahead N  EdgeSwapOptions::crease_look_ahead_depth (0: off)\n"
      "  -intersections 0|1  EdgeSwapOptions::remove_self_intersections\n",
      program, default_clouds[0], default_clouds[1], default_clouds[2], default_clouds[3],
      default_clouds[4]);
}

double
secondsSince (Clock::time_point start)
{
  return std::chrono::duration<double> (Clock::now () - start).count ();
}

/** Processor time (user and system) of the whole process so far, all threads. */
double
processSeconds ()
{
  rusage usage;
  getrusage (RUSAGE_SELF, &usage);
  return static_cast<double> (usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double> (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double
median (std::vector<double> values)
{
  if (values.empty ())
    return 0.0;
  std::sort (values.begin (), values.end ());
  const std::size_t m = values.size () / 2;
  return values.size () % 2 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

/** What one mesh measures. */
struct Metrics
{
  meshless::MeshReport check;
  bool sphere_like = false; // closed, manifold, oriented outward, one component,
                            // Euler 2, 2n - 4 triangles, every point used
  std::optional<meshless::MeshDistanceReport> distance;
  std::optional<meshless::EdgeComparison> edges;
};

/** Timing of the class as a user runs it: wall time, and processor time of all
  * threads (less sensitive to other jobs on the machine). */
struct Timing
{
  double total = 0.0, optimize = 0.0, share = 0.0;
  double cpu_total = 0.0, cpu_optimize = 0.0, cpu_share = 0.0;
  std::size_t swaps = 0, attempts = 0;
  bool retry = false;
  std::size_t pairs = 0;
};

struct Row
{
  std::string name;
  std::size_t points = 0;
  Metrics before, after;
  meshless::EdgeSwapResult optimization;
  double optimize_alone = 0.0;
  bool before_retry = false;
  Timing timing;
  bool compared = false;
};

Metrics
measure (const meshless::Points3& vertices, const meshless::Triangles& triangles,
         const meshless::Points3* reference_vertices,
         const meshless::Triangles* reference_triangles,
         const meshless::MeshDistanceOptions& distance_options)
{
  Metrics m;
  m.check = meshless::checkMesh (vertices, triangles);
  m.sphere_like = m.check.isSphereLike () && m.check.signed_volume > 0.0 &&
                  m.check.unused_vertices == 0 &&
                  m.check.num_triangles == 2 * vertices.size () - 4;
  if (reference_vertices) {
    m.distance = meshless::compareToReference (vertices, triangles, *reference_vertices,
                                               *reference_triangles, distance_options);
    m.edges = meshless::compareEdges (vertices, triangles, *reference_vertices,
                                      *reference_triangles);
  }
  return m;
}

/** Runs the class once with the given optimization setting; fills mesh and returns
  * the wall time of reconstruct (), adding the optimize stages' time to *optimize. */
double
reconstruct (const Cloud::ConstPtr& cloud, bool optimize,
             const meshless::EdgeSwapOptions& options, pcl::PolygonMesh& mesh,
             double* optimize_seconds, std::size_t* optimize_stages,
             pcl::SphericalMeshlessReport* report, double* cpu_total = nullptr,
             double* cpu_optimize = nullptr)
{
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setOptimize (optimize);
  // A measuring tool: a mesh with folds left is measured, not refused.
  reconstruction.setAllowSelfIntersections (true);
  reconstruction.setReleaseFreedMemory (true); // its peak memory as the CLI measures it
  reconstruction.setOptimizationOptions (options);
  double in_optimize = 0.0, cpu_in_optimize = 0.0;
  std::size_t stages = 0;
  // The processor time between two callbacks is the stage's that just ended.
  double cpu_mark = processSeconds ();
  const double cpu_start = cpu_mark;
  reconstruction.setProgressCallback ([&] (const meshless::ProgressReport& stage) {
    const double now = processSeconds ();
    if (stage.stage == "optimize") {
      in_optimize += stage.seconds;
      cpu_in_optimize += now - cpu_mark;
      ++stages;
    }
    cpu_mark = now;
    return true;
  });
  const auto start = Clock::now ();
  reconstruction.reconstruct (mesh);
  const double seconds = secondsSince (start);
  if (cpu_total)
    *cpu_total = processSeconds () - cpu_start;
  if (cpu_optimize)
    *cpu_optimize = cpu_in_optimize;
  if (optimize_seconds)
    *optimize_seconds = in_optimize;
  if (optimize_stages)
    *optimize_stages = stages;
  if (report)
    *report = reconstruction.getReport ();
  return seconds;
}

std::string
describe (const meshless::EdgeSwapOptions& o)
{
  const char* costs[] = {"angle between normals", "integrated mean curvature",
                         "squared mean curvature", "total absolute curvature"};
  return std::string ("cost ") + costs[static_cast<int> (o.cost)] +
         ", descent from dihedral " + format ("%g deg", o.descent_min_dihedral_deg) +
         ", noisy from median dihedral " + format ("%g deg", o.noisy_median_dihedral_deg) +
         ", fold bound " + format ("%g deg", o.max_fold_angle_deg) +
         ", remove intersections " + (o.remove_self_intersections ? "on" : "off") +
         ", angle pass " + (o.improve_angles ? "on" : "off") +
         ", new edges no longer than their quad's longest " +
         (o.descent_keeps_longest_edge ? "on" : "off") +
         ", look-ahead " + std::to_string (o.look_ahead_depth) + " swaps deep" +
         ", at creases " + std::to_string (o.crease_look_ahead_depth) +
         (o.max_swaps ? ", at most " + std::to_string (o.max_swaps) + " swaps" : "");
}

std::string
arrow (const std::string& before, const std::string& after)
{
  return before + " -> " + after;
}

/** The metric rows of one cloud: name, before, after. */
std::vector<std::array<std::string, 3>>
metricRows (const Row& r)
{
  std::vector<std::array<std::string, 3>> rows;
  const auto add = [&rows] (const std::string& name, const std::string& b,
                            const std::string& a) { rows.push_back ({name, b, a}); };
  const auto invariants = [] (const Metrics& m) {
    return m.sphere_like ? std::string ("all hold") : "FAIL: " + meshless::describe (m.check);
  };
  add ("invariants (closed, manifold, oriented, 2n-4, Euler 2)", invariants (r.before),
       invariants (r.after));
  add ("swaps (descent + intersection removal + angle pass)", "-",
       std::to_string (r.optimization.swaps) + " (" +
           std::to_string (r.optimization.descent_swaps) + " + " +
           std::to_string (r.optimization.intersection_swaps) + " + " +
           std::to_string (r.optimization.angle_swaps) + ")");
  add ("optimize time (alone, this triangulation)", "-", format ("%.3f s", r.optimize_alone));
  if (r.compared)
    add ("input median dihedral (noisy input rule)", "-",
         format ("%.1f deg", r.optimization.median_dihedral_deg) +
             (r.optimization.noisy ? " (on)" : " (off)"));
  if (r.timing.attempts > 0) {
    add ("optimize time / whole run (class, wall, median)", "-",
         format ("%.3f s", r.timing.optimize) + " / " + format ("%.3f s", r.timing.total) +
             " = " + format ("%.0f%%", 100.0 * r.timing.share) +
             (r.timing.retry ? " (2 attempts)" : ""));
    add ("optimize time / whole run (class, processor time of all threads, median)", "-",
         format ("%.3f s", r.timing.cpu_optimize) + " / " +
             format ("%.3f s", r.timing.cpu_total) + " = " +
             format ("%.0f%%", 100.0 * r.timing.cpu_share));
  }
  if (!r.compared)
    return rows;
  const auto distance = [] (const Metrics& m, int which) -> std::string {
    if (!m.distance || !m.distance->success)
      return "-";
    const auto& d = m.distance->two_sided;
    return format ("%.2e", which == 0 ? d.mean : which == 1 ? d.p99 : d.max);
  };
  const auto normal = [] (const Metrics& m) -> std::string {
    return m.distance && m.distance->success
               ? format ("%.3f deg", m.distance->normal_deviation_deg)
               : "-";
  };
  add ("normal deviation", normal (r.before), normal (r.after));
  add ("distance mean", distance (r.before, 0), distance (r.after, 0));
  add ("distance p99", distance (r.before, 1), distance (r.after, 1));
  add ("distance max", distance (r.before, 2), distance (r.after, 2));
  const auto one_sided = [] (const Metrics& m) -> std::string {
    if (!m.distance || !m.distance->success)
      return "-";
    return format ("%.2e", m.distance->to_reference.mean) + " / " +
           format ("%.2e", m.distance->from_reference.mean);
  };
  add ("distance mean: mesh to reference / reference to mesh", one_sided (r.before),
       one_sided (r.after));
  add ("mean smallest angle", format ("%.2f deg", r.before.check.mean_min_angle_deg),
       format ("%.2f deg", r.after.check.mean_min_angle_deg));
  add ("smallest angle < 10 deg",
       format ("%.2f%%", 100.0 * r.before.check.share_min_angle_below_10),
       format ("%.2f%%", 100.0 * r.after.check.share_min_angle_below_10));
  // Edge agreement only means something when the cloud is the reference's vertices.
  const auto matched = [] (const Metrics& m) {
    return m.edges && m.edges->success && m.edges->unmatched_vertices == 0;
  };
  const auto edge_fraction = [&] (const Metrics& m) -> std::string {
    return matched (m) ? format ("%.4f", m.edges->reference_edge_fraction) : "-";
  };
  const auto sharp = [&] (const Metrics& m) -> std::string {
    if (!matched (m) || m.edges->sharp_edges == 0)
      return "-";
    return format ("%.4f", m.edges->sharp_edge_fraction) + " (" +
           std::to_string (m.edges->sharp_edges_found) + " of " +
           std::to_string (m.edges->sharp_edges) + ")";
  };
  add ("edges that are reference edges", edge_fraction (r.before), edge_fraction (r.after));
  add ("reference sharp edges (> 30 deg) present", sharp (r.before), sharp (r.after));
  add ("self-intersecting pairs", std::to_string (r.before.check.self_intersecting_pairs),
       std::to_string (r.after.check.self_intersecting_pairs));
  return rows;
}

void
printCloud (const Row& r)
{
  std::printf ("\n%s (%zu points)%s:\n\n| metric | before | after |\n|---|---|---|\n",
               r.name.c_str (), r.points,
               r.before_retry ? ", raw triangulation from the thin-part retry" : "");
  for (const auto& row : metricRows (r))
    std::printf ("| %s | %s | %s |\n", row[0].c_str (), row[1].c_str (), row[2].c_str ());
  std::fflush (stdout);
}

void
printSummary (const std::vector<Row>& rows)
{
  std::printf ("\nSummary (before -> after):\n\n"
               "| cloud | swaps | optimize / whole run (wall; processor) | normal deviation (deg) | "
               "distance mean / p99 / max | mean smallest angle (deg) | < 10 deg | "
               "reference edges | sharp edges | intersecting pairs |\n"
               "|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const auto cells = metricRows (r);
    const auto find = [&cells] (const std::string& name) -> const std::array<std::string, 3>* {
      for (const auto& c : cells)
        if (c[0] == name)
          return &c;
      return nullptr;
    };
    const auto pair = [&] (const std::string& name) -> std::string {
      const auto* c = find (name);
      if (!c)
        return "-";
      return (*c)[1] == "-" && (*c)[2] == "-" ? "-" : arrow ((*c)[1], (*c)[2]);
    };
    std::string share = "-";
    if (r.timing.attempts > 0)
      share = format ("%.2f s", r.timing.optimize) + " / " + format ("%.2f s", r.timing.total) +
              " (" + format ("%.0f%%", 100.0 * r.timing.share) + "; processor " +
              format ("%.0f%%", 100.0 * r.timing.cpu_share) + ")";
    std::string distance = "-";
    if (r.compared && find ("distance mean"))
      distance = arrow ((*find ("distance mean"))[1] + " / " + (*find ("distance p99"))[1] +
                            " / " + (*find ("distance max"))[1],
                        (*find ("distance mean"))[2] + " / " + (*find ("distance p99"))[2] +
                            " / " + (*find ("distance max"))[2]);
    std::printf ("| %s | %zu | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.name.c_str (),
                 r.optimization.swaps, share.c_str (), pair ("normal deviation").c_str (),
                 distance.c_str (), pair ("mean smallest angle").c_str (),
                 pair ("smallest angle < 10 deg").c_str (),
                 pair ("edges that are reference edges").c_str (),
                 pair ("reference sharp edges (> 30 deg) present").c_str (),
                 pair ("self-intersecting pairs").c_str ());
  }
}

#ifdef MESHLESS_WITH_RENDER
/** Mesh edges drawn, the reference's sharp edges the mesh misses in red. */
std::string
picture (const pcl::PolygonMesh& mesh, const Cloud& cloud, const Metrics& metrics,
         const meshless::Points3& reference_vertices, int size,
         const std::array<double, 3>& view, const std::string& path)
{
  pcl::PointXYZ lo, hi;
  pcl::getMinMax3D (cloud, lo, hi);
  meshless_tools::RenderOptions options;
  options.size = size;
  options.view = view;
  options.draw_edges = true;
  if (metrics.edges && metrics.edges->success) {
    meshless_tools::LineSet missing;
    for (const auto& e : metrics.edges->missing_sharp_edges)
      missing.segments.push_back ({reference_vertices[e[0]], reference_vertices[e[1]]});
    options.lines.push_back (missing);
  }
  return meshless_tools::renderPng (mesh, {lo.x, hi.x, lo.y, hi.y, lo.z, hi.z}, path,
                                    options);
}
#endif

struct ReportOptions
{
  std::string data_dir = std::getenv ("MESHLESS_DATA_DIR") ? std::getenv ("MESHLESS_DATA_DIR")
                                                           : "../../shared/data";
  std::string out_dir;
  int repeat = 1, picture_size = 800;
  std::array<double, 3> view{0.5, 0.4, 1.0};
  bool timing_only = false;
  meshless::MeshDistanceOptions distance;
  meshless::EdgeSwapOptions swaps;
  std::vector<std::string> specs;
};

const std::vector<meshless_tools::Flag> kFlags = {
    {"-h", false},          {"--help", false},        {"-data", true},
    {"-out", true},         {"-repeat", true},        {"-samples", true},
    {"-size", true},        {"-timing-only", false},  {"-view", true},
    {"-cost", true},        {"-descent-min-dihedral", true},
    {"-noisy-median", true}, {"-longest", true},     {"-angles", true},
    {"-intersections", true}, {"-look-ahead", true}, {"-crease-look-ahead", true}};

/** The optimization options under test; the library's defaults where not given. */
bool
readSwapOptions (CommandLine& line, meshless::EdgeSwapOptions& swaps)
{
  const meshless::SwapCost costs[] = {
      meshless::SwapCost::AngleBetweenNormals, meshless::SwapCost::IntegratedMeanCurvature,
      meshless::SwapCost::SquaredMeanCurvature, meshless::SwapCost::TotalAbsoluteCurvature};
  int cost = -1, longest = -1, angles = -1, intersections = -1;
  int look_ahead = static_cast<int> (swaps.look_ahead_depth);
  int crease_look_ahead = static_cast<int> (swaps.crease_look_ahead_depth);
  if (!line.choose ("-cost", {"abn", "mean", "squared", "total"}, cost) ||
      !line.read ("-descent-min-dihedral", swaps.descent_min_dihedral_deg) ||
      !line.read ("-noisy-median", swaps.noisy_median_dihedral_deg) ||
      !line.choose ("-longest", {"0", "1"}, longest) ||
      !line.read ("-look-ahead", look_ahead) ||
      (look_ahead < 0 && !line.reject ("-look-ahead", "must be 0 or more")) ||
      !line.read ("-crease-look-ahead", crease_look_ahead) ||
      (crease_look_ahead < 0 && !line.reject ("-crease-look-ahead", "must be 0 or more")) ||
      !line.choose ("-angles", {"0", "1"}, angles) ||
      !line.choose ("-intersections", {"0", "1"}, intersections))
    return false;
  if (cost >= 0)
    swaps.cost = costs[cost];
  if (longest >= 0)
    swaps.descent_keeps_longest_edge = longest == 1;
  swaps.look_ahead_depth = static_cast<std::size_t> (look_ahead);
  swaps.crease_look_ahead_depth = static_cast<std::size_t> (crease_look_ahead);
  if (angles >= 0)
    swaps.improve_angles = angles == 1;
  if (intersections >= 0)
    swaps.remove_self_intersections = intersections == 1;
  return true;
}

/** The options, or false with the reason in `error`. Counts out of range are
  * clamped to the nearest sensible one. */
bool
parseOptions (int argc, char** argv, ReportOptions& options, std::string& error)
{
  CommandLine line (argc, argv, kFlags);
  // The maxima over a lattice on every triangle as well: sampled maxima alone move
  // between two meshes that differ in a few triangles.
  options.distance.lattice_for_max = 6;
  int samples = static_cast<int> (options.distance.samples);
  if (!line.read ("-data", options.data_dir) || !line.read ("-out", options.out_dir) ||
      !line.read ("-repeat", options.repeat) || !line.read ("-samples", samples) ||
      !line.read ("-size", options.picture_size) || !line.read3 ("-view", options.view) ||
      !readSwapOptions (line, options.swaps) || !line.error ().empty ()) {
    error = line.error ();
    return false;
  }
#ifndef MESHLESS_WITH_RENDER
  if (error.empty () && !options.out_dir.empty ())
    error = "-out needs VTK's OpenGL rendering, which this build lacks";
#endif
  options.repeat = std::max (0, options.repeat);
  options.distance.samples = static_cast<std::size_t> (std::max (1, samples));
  options.picture_size = std::clamp (options.picture_size, 16, 4096);
  options.timing_only = line.has ("-timing-only");
  options.specs = line.positional ();
  if (options.specs.empty ())
    options.specs.assign (std::begin (default_clouds), std::end (default_clouds));
  return error.empty ();
}

/** CLOUD[=REFERENCE] as paths; bare names are looked up in the data directory, and
  * the reference defaults to DATA/meshes/NAME.ply when there is one. */
void
resolve (const std::string& spec, const std::string& data_dir, std::string& cloud_path,
         std::string& reference_path)
{
  const auto eq = spec.find ('=');
  const auto find = [&data_dir] (const std::string& s, const char* sub, const char* ext) {
    return std::filesystem::exists (s) ? s : data_dir + "/" + sub + "/" + s + ext;
  };
  cloud_path = find (spec.substr (0, eq), "clouds", ".pcd");
  reference_path.clear ();
  if (eq != std::string::npos)
    reference_path = find (spec.substr (eq + 1), "meshes", ".ply");
  else {
    const std::string stem = std::filesystem::path (cloud_path).stem ().string ();
    const std::string guess = data_dir + "/meshes/" + stem + ".ply";
    if (std::filesystem::exists (guess))
      reference_path = guess;
  }
}

/** The whole reconstruction as a user runs it, `repeat` times: the optimization's
  * share of the time (medians). */
std::string
timeRuns (const Cloud::ConstPtr& cloud, const ReportOptions& options, Row& row)
{
  std::vector<double> totals, optimizes, shares, cpu_totals, cpu_optimizes, cpu_shares;
  for (int k = 0; k < options.repeat; ++k) {
    pcl::PolygonMesh mesh;
    pcl::SphericalMeshlessReport report;
    double optimize = 0.0, cpu_total = 0.0, cpu_optimize = 0.0;
    std::size_t stages = 0;
    const double total = reconstruct (cloud, true, options.swaps, mesh, &optimize, &stages,
                                      &report, &cpu_total, &cpu_optimize);
    if (!report.success)
      return row.name + ": the reconstruction failed: " + report.message;
    totals.push_back (total);
    optimizes.push_back (optimize);
    shares.push_back (optimize / total);
    cpu_totals.push_back (cpu_total);
    cpu_optimizes.push_back (cpu_optimize);
    cpu_shares.push_back (cpu_total > 0.0 ? cpu_optimize / cpu_total : 0.0);
    row.timing.attempts = stages;
    row.timing.retry = report.thin_sheet_retry || stages > 1;
    row.timing.swaps = report.optimization.swaps;
    row.timing.pairs = report.mesh.self_intersecting_pairs;
    std::fprintf (stderr,
                  "  run %d: %.3f s, optimize %.3f s (%zu stage%s); processor %.3f s, "
                  "optimize %.3f s\n",
                  k + 1, total, optimize, stages, stages == 1 ? "" : "s", cpu_total,
                  cpu_optimize);
  }
  row.timing.total = median (totals);
  row.timing.optimize = median (optimizes);
  row.timing.share = median (shares);
  row.timing.cpu_total = median (cpu_totals);
  row.timing.cpu_optimize = median (cpu_optimizes);
  row.timing.cpu_share = median (cpu_shares);
  return "";
}

/** A reference mesh for the metrics: its vertices and triangles, both empty when
  * there is none. */
struct Reference
{
  meshless::Points3 vertices;
  meshless::Triangles triangles;
};

#ifdef MESHLESS_WITH_RENDER
/** NAME_before.png and NAME_after.png: the raw and the optimized triangulation. */
std::string
pictures (const pcl::PolygonMesh& raw, const meshless::Triangles& after, const Cloud& cloud,
          const Reference& reference, const ReportOptions& options, const Row& row)
{
  if (!std::getenv ("DISPLAY"))
    return "-out needs a display (run under xvfb-run)";
  pcl::PolygonMesh optimized = raw;
  for (std::size_t t = 0; t < after.size (); ++t)
    for (int k = 0; k < 3; ++k)
      optimized.polygons[t].vertices[k] = static_cast<pcl::index_t> (after[t][k]);
  const std::string base = (std::filesystem::path (options.out_dir) / row.name).string ();
  const pcl::PolygonMesh* meshes[] = {&raw, &optimized};
  const Metrics* metrics[] = {&row.before, &row.after};
  const char* suffixes[] = {"_before.png", "_after.png"};
  for (int m = 0; m < 2; ++m) {
    const std::string error = picture (*meshes[m], cloud, *metrics[m], reference.vertices,
                                       options.picture_size, options.view, base + suffixes[m]);
    if (!error.empty ())
      return error;
  }
  return "";
}
#endif

/** The raw triangulation (optimization off), optimizeBySwaps on it alone, and the
  * metrics of both. The optimizer gets the points centred, as the class gives them;
  * the metrics the original coordinates (exact matches with the reference). */
std::string
compareRaw (const Cloud::ConstPtr& cloud, const Reference& reference,
            const ReportOptions& options, Row& row)
{
  const meshless::Points3 vertices = meshless_tools::toPoints (*cloud);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
  for (const auto& v : vertices)
    centroid += v;
  centroid /= static_cast<double> (std::max<std::size_t> (1, vertices.size ()));
  meshless::Points3 centred;
  for (const auto& v : vertices)
    centred.push_back (v - centroid);

  pcl::PolygonMesh raw;
  pcl::SphericalMeshlessReport raw_report;
  reconstruct (cloud, false, options.swaps, raw, nullptr, nullptr, &raw_report);
  if (!raw_report.success)
    return row.name + ": the raw reconstruction failed: " + raw_report.message;
  row.before_retry = raw_report.thin_sheet_retry;
  const meshless::Triangles before = toTriangles (raw);
  meshless::Triangles after = before;
  pcl::console::TicToc timer;
  timer.tic ();
  row.optimization = meshless::optimizeBySwaps (centred, after, options.swaps);
  row.optimize_alone = timer.toc () / 1000.0;
  if (!row.optimization.success)
    return row.name + ": the optimization failed: " + row.optimization.message;
  row.compared = true;
  const bool with_reference = !reference.triangles.empty ();
  const auto* rv = with_reference ? &reference.vertices : nullptr;
  const auto* rt = with_reference ? &reference.triangles : nullptr;
  row.before = measure (vertices, before, rv, rt, options.distance);
  row.after = measure (vertices, after, rv, rt, options.distance);
#ifdef MESHLESS_WITH_RENDER
  if (!options.out_dir.empty ())
    return pictures (raw, after, *cloud, reference, options, row);
#endif
  return "";
}

/** One cloud's row: its timing runs and, unless -timing-only, the comparison. */
std::string
reportCloud (const std::string& spec, const ReportOptions& options, Row& row)
{
  std::string cloud_path, reference_path;
  resolve (spec, options.data_dir, cloud_path, reference_path);
  const meshless_tools::QuietPclLog quiet;
  Cloud loaded;
  std::string error = meshless_tools::loadCloud (cloud_path, loaded);
  if (!error.empty ())
    return error;
  auto cloud = pcl::make_shared<Cloud> ();
  pcl::Indices kept;
  pcl::removeNaNFromPointCloud (loaded, *cloud, kept);
  row.name = std::filesystem::path (cloud_path).stem ().string ();
  row.points = cloud->size ();
  Reference reference;
  if (!reference_path.empty () && !options.timing_only) {
    error = meshless_tools::loadMesh (reference_path, reference.vertices, reference.triangles);
    if (!error.empty ())
      return error;
  }
  std::fprintf (stderr, "%s: %zu points, reference %s\n", row.name.c_str (), cloud->size (),
                reference.triangles.empty () ? "none" : reference_path.c_str ());
  error = timeRuns (cloud, options, row);
  if (!error.empty ())
    return error;
  if (options.timing_only) {
    row.optimization.swaps = row.timing.swaps;
    return "";
  }
  return compareRaw (cloud, reference, options, row);
}

int
run (int argc, char** argv)
{
  if (pcl::console::find_switch (argc, argv, "-h") ||
      pcl::console::find_switch (argc, argv, "--help")) {
    usage (argv[0]);
    return 0;
  }
  ReportOptions options;
  std::string error;
  if (!parseOptions (argc, argv, options, error))
    return fail (kTool, error);
  if (!options.out_dir.empty ())
    std::filesystem::create_directories (options.out_dir);
  std::printf ("optimization options: %s\n", describe (options.swaps).c_str ());
  std::vector<Row> rows;
  for (const std::string& spec : options.specs) {
    Row row;
    error = reportCloud (spec, options, row);
    if (!error.empty ())
      return fail (kTool, error);
    printCloud (row);
    rows.push_back (std::move (row));
  }
  printSummary (rows);
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
