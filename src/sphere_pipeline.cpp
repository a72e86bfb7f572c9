/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/cut_paths.h>
#include <pcl/surface/meshless/freed_memory.h>
#include <pcl/surface/meshless/merge.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/normal_orientation.h>
#include <pcl/surface/meshless/patch_split.h>
#include <pcl/surface/meshless/patch_triangulation.h>
#include <pcl/surface/meshless/sphere_pipeline.h>
#include <pcl/surface/meshless/surface_graphs.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <numeric>
#include <random>

namespace pcl {
namespace meshless {

namespace {

using Clock = std::chrono::steady_clock;

/** Reports stages to the user's callback; remembers a cancellation. */
class StageClock
{
public:
  explicit StageClock (const ProgressCallback& callback) : callback_ (callback) {}

  /** \return false if the user cancelled. */
  bool
  done (const std::string& stage, double fraction, const std::string& detail = "")
  {
    const auto now = Clock::now ();
    const double seconds = std::chrono::duration<double> (now - start_).count ();
    start_ = now;
    if (callback_ && !callback_ ({stage, fraction, seconds, detail}))
      cancelled_ = true;
    return !cancelled_;
  }

private:
  const ProgressCallback& callback_;
  Clock::time_point start_ = Clock::now ();
  bool cancelled_ = false;
};

/** Deterministic rotation number `attempt` (identity first). */
Eigen::Matrix3d
attemptRotation (int attempt)
{
  if (attempt == 0)
    return Eigen::Matrix3d::Identity ();
  std::mt19937 random (static_cast<std::uint32_t> (attempt));
  std::normal_distribution<double> gauss;
  const Eigen::Quaterniond q (gauss (random), gauss (random), gauss (random), gauss (random));
  return q.normalized ().toRotationMatrix ();
}

/** The polyhedron with the next larger number of faces (after the largest, the
  * smallest). */
BasePolyhedron
nextPolyhedron (BasePolyhedron polyhedron)
{
  switch (polyhedron) {
  case BasePolyhedron::Tetrahedron:
    return BasePolyhedron::Octahedron;
  case BasePolyhedron::Octahedron:
    return BasePolyhedron::Icosahedron;
  case BasePolyhedron::Icosahedron:
  case BasePolyhedron::BySize: // resolved before
    break;
  }
  return BasePolyhedron::Tetrahedron;
}

} // namespace

SphereTriangulation
triangulateSphere (const Points3& points,
                   const CsrGraph& neighbourhoods,
                   const SpherePipelineOptions& options)
{
  SphereTriangulation result;
  SpherePipelineStats& stats = result.stats;
  const std::size_t n = points.size ();
  StageClock clock (options.progress);
  auto cancelled = [&] () {
    result.message = "cancelled by the progress callback";
    return result;
  };
  if (n < 4) {
    result.message = "a closed triangulation needs at least four points";
    return result;
  }

  const double stage_fraction[] = {0.05, 0.15, 0.2}; // graph, rings, weights
  int stage = 0;
  SurfaceGraphs surface =
      buildSurfaceGraphs (points, neighbourhoods, options.weights,
                          [&] (const std::string& name, const std::string& detail) {
                            return clock.done (name, stage_fraction[stage++], detail);
                          },
                          options.separate_thin_sheets);
  if (!surface.success) {
    result.message = surface.message;
    return result;
  }
  if (options.separate_thin_sheets && surface.sheet_edges_dropped == 0) {
    result.message = "no edges across thin parts to drop (or dropping them would "
                     "disconnect the graph)";
    return result;
  }
  const CsrGraph& graph = surface.graph;
  const OrderedNeighbourhoods& ordered = surface.ordered;
  const CsrGraph& mutual = surface.mutual;
  const Weights& weights = surface.weights;
  stats.normals_flipped = surface.normals_flipped;
  stats.thin_part_edges =
      options.separate_thin_sheets ? surface.sheet_edges_dropped : surface.sheet_edges_droppable;
  stats.weight_fallbacks = weights.num_fallbacks;

  // Corners of D only where the ring surrounds the point and the mutual graph
  // offers several ways out: a sharp tip (all neighbours on one side) would leave
  // no room for three or more paths in the right cyclic order. And only in the
  // largest component of the mutual graph, which the paths are routed in (thin
  // parts whose rings disagree with the rest may form components of their own).
  std::vector<char> corner_eligible (n, 0);
  std::size_t eligible_count = 0;
  {
    std::vector<pcl::index_t> mutual_component;
    const std::size_t mutual_components = connectedComponents (mutual, mutual_component);
    std::vector<std::size_t> mutual_size (mutual_components, 0);
    for (auto c : mutual_component)
      ++mutual_size[c];
    const auto main_component = static_cast<pcl::index_t> (
        std::max_element (mutual_size.begin (), mutual_size.end ()) - mutual_size.begin ());
    for (std::size_t v = 0; v < n; ++v) {
      corner_eligible[v] = ordered.largest_gap[v] < 0.9 * 3.14159265358979 &&
                           mutual.degree (v) >= 4 && mutual_component[v] == main_component;
      eligible_count += corner_eligible[v];
    }
  }
  if (eligible_count < 4)
    corner_eligible.clear (); // a tiny or degenerate cloud: let any point be a corner

  const bool user_base = !options.user_base_mesh.faces.empty ();
  if (user_base) {
    const std::string problem = validateBaseMesh (options.user_base_mesh, n);
    if (!problem.empty ()) {
      result.message = "invalid base mesh: " + problem;
      return result;
    }
  }
  const int attempts = user_base ? 1 : std::max (1, options.max_base_attempts);
  std::string last_problem;
  const int first = user_base ? 0 : std::max (0, options.first_attempt);
  const BasePolyhedron first_polyhedron = polyhedronForSize (options.polyhedron, n);
  for (int attempt = first; attempt < first + attempts; ++attempt) {
    stats.base_attempts = static_cast<std::size_t> (attempt - first + 1);
    stats.base_attempt = attempt;
    // Every second attempt tries the next polyhedron: other corners, and patches
    // of another size, fail for other reasons than a mere rotation.
    const BasePolyhedron polyhedron =
        options.alternate_polyhedra && attempt % 2 == 1 ? nextPolyhedron (first_polyhedron)
                                                        : first_polyhedron;
    const int rotation = options.alternate_polyhedra ? attempt / 2 : attempt;
    const BaseMesh base = user_base ? options.user_base_mesh
                                    : polyhedronBaseMesh (points, polyhedron,
                                                          attemptRotation (rotation),
                                                          corner_eligible, options.corners);
    if (base.faces.empty ()) {
      last_problem = "two base mesh directions picked the same point";
      continue;
    }
    stats.base_faces = base.faces.size ();
    const CutPaths paths = computeCutPaths (points, mutual, ordered.rings, base);
    if (!paths.success) {
      last_problem = paths.message;
      continue;
    }
    const PatchSplit split = splitIntoPatches (points, mutual, graph,
                                              weights.neighbours, base, paths);
    if (!split.success) {
      last_problem = split.message;
      continue;
    }
    stats.path_points = 0;
    for (const auto& path : paths.paths)
      stats.path_points += path.size () - 2;
    stats.path_points += base.vertices.size ();
    stats.side_conflicts = split.num_side_conflicts;
    stats.reassigned = split.num_reassigned;
    stats.largest_patch = 0;
    for (const auto& patch : split.patches)
      stats.largest_patch = std::max (stats.largest_patch, patch.points.size ());
    if (!clock.done ("split", 0.35,
                     std::to_string (base.faces.size ()) + " patches, largest " +
                         std::to_string (stats.largest_patch) + " points"))
      return cancelled ();
    // The rings and the mutual graph served the paths and the split, and the
    // patches read G only next to the cuts; their solves set the peak memory of
    // large clouds (armadillo_uniform_1m: the stage's peak 749 -> 682 MB without
    // the rings and the mutual graph, -> 611 MB without G too). A next attempt, after a
    // failed patch or merge, builds them again (stats.rebuilds; of the shared
    // clouds armadillo_noisy_100k and bunny_rawscans_merged10 once each).
    const CsrGraph cut_candidates = candidatesNearCuts (graph, weights.neighbours, split);
    const auto release = [] (auto& array) { std::decay_t<decltype (array)> ().swap (array); };
    release (surface.graph.offsets);
    release (surface.graph.adjacency);
    release (surface.mutual.offsets);
    release (surface.mutual.adjacency);
    release (surface.ordered.rings.offsets);
    release (surface.ordered.rings.adjacency);
    release (surface.ordered.largest_gap);
    const auto rebuild = [&] () {
      ++stats.rebuilds;
      SurfaceGraphs again = buildSurfaceGraphs (points, neighbourhoods, options.weights, {},
                                                options.separate_thin_sheets);
      surface.graph = std::move (again.graph);
      surface.mutual = std::move (again.mutual);
      surface.ordered.rings = std::move (again.ordered.rings);
      surface.ordered.largest_gap = std::move (again.ordered.largest_gap);
    };

    // What the graphs, the paths and the split freed goes back to the system first:
    // the patches are solved on two threads, and the second one's allocations
    // cannot reuse the first one's free memory (glibc keeps an arena per thread).
    // armadillo_uniform_1m: the stage's peak 597 -> 590 MB.
    releaseFreedMemory ();
    const std::size_t faces = split.patches.size ();
    std::vector<PatchTriangulation> triangulated (faces);
    PatchRingContext patch_rings;
    patch_rings.points = &points;
    patch_rings.candidates = &cut_candidates;
    patch_rings.normals = &ordered.normals;
    patch_rings.weights.type = options.weights;
    // One large set of LU factors at a time (SolveOptions::factorization_lock), the
    // largest patches first so that the small ones fill the waits. Measured on
    // armadillo_uniform_1m with two threads: the stage's peak 866 -> 779 MB, its
    // time 2.5 -> 2.9 s.
    std::mutex factorization;
    SolveOptions solve = options.solve;
    solve.factorization_lock = &factorization;
    std::vector<std::size_t> largest_first (faces);
    std::iota (largest_first.begin (), largest_first.end (), std::size_t {0});
    std::stable_sort (largest_first.begin (), largest_first.end (), [&] (std::size_t a, std::size_t b) {
      return split.patches[a].points.size () > split.patches[b].points.size ();
    });
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t> (faces); ++k) {
      const std::size_t f = largest_first[k];
      triangulated[f] = triangulatePatch (points, weights, split.patches[f], solve, &patch_rings,
                                          options.patch_flips);
      Points2 ().swap (triangulated[f].uv); // not needed here; memory at the peak
    }
    std::vector<Triangles> patch_triangles;
    bool all_patches = true;
    stats.smallest_parameter_edge = 1.0;
    stats.patch_flips = 0;
    for (auto& patch : triangulated) {
      if (!patch.success) {
        last_problem = patch.message;
        all_patches = false;
        break;
      }
      stats.smallest_parameter_edge = std::min (stats.smallest_parameter_edge, patch.smallest_edge);
      stats.patch_flips += patch.flips;
      patch_triangles.push_back (std::move (patch.triangles));
    }
    if (!all_patches) {
      rebuild ();
      continue;
    }
    if (!clock.done ("patches", 0.9,
                     options.patch_flips.enabled ? std::to_string (stats.patch_flips) + " flips" : ""))
      return cancelled ();

    MergedTriangulation merged = mergePatches (patch_triangles, n);
    if (!merged.success) {
      last_problem = merged.message;
      rebuild ();
      continue;
    }
    stats.repair_flips = merged.num_repair_flips;
    result.triangles = std::move (merged.triangles);
    result.normals = ordered.normals;
    if (!clock.done ("merge", 1.0, std::to_string (merged.num_repair_flips) + " repair flips"))
      return cancelled ();
    result.success = true;
    return result;
  }
  result.message = "no base mesh worked after " + std::to_string (attempts) +
                   " attempt(s) (is the cloud sphere-like? a handle or a boundary leaves no "
                   "room for the paths; so may parts thinner than the point spacing); the last "
                   "problem: " + last_problem;
  return result;
}

} // namespace meshless
} // namespace pcl
