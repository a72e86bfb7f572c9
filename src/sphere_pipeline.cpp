/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "common/constants.h"
#include "common/stage_clock.h"
#include "common/threads.h"

#include "common/freed_memory.h"

#include <pcl/surface/meshless/cut_paths.h>
#include "handles.h"
#include <pcl/surface/meshless/grown_base_mesh.h>
#include <pcl/surface/meshless/merge.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/normal_orientation.h>
#include <pcl/surface/meshless/patch_split.h>
#include <pcl/surface/meshless/patch_triangulation.h>
#include <pcl/surface/meshless/sphere_pipeline.h>
#include <pcl/surface/meshless/surface_graphs.h>

#include <algorithm>
#include <mutex>
#include <numeric>
#include <random>

namespace pcl {
namespace meshless {

namespace {

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

/** The steps of triangulateSphere over one cloud: the surface graphs once, then
  * base meshes in turn until one gives a closed triangulation. */
class SpherePipeline
{
public:
  SpherePipeline (const Points3& points,
                  const CsrGraph& neighbourhoods,
                  const SpherePipelineOptions& options)
  : points_ (points)
  , neighbourhoods_ (neighbourhoods)
  , options_ (options)
  , n_ (points.size ())
  , clock_ (options.progress)
  {}

  SphereTriangulation
  run ()
  {
    if (n_ < 4) {
      result_.message = "a closed triangulation needs at least four points";
      return std::move (result_);
    }
    if (!buildGraphs ())
      return std::move (result_);
    findCornerCandidates ();
    const bool user_base = !options_.user_base_mesh.faces.empty ();
    if (options_.refuse_handles && !user_base && hasHandles ())
      return std::move (result_);
    if (options_.grown_base_mesh && !user_base && options_.known_genus >= 0)
      grown_genus_ = result_.stats.genus = options_.known_genus;
    else if (options_.grown_base_mesh && !user_base && !findGenus ())
      return std::move (result_);
    if ((options_.refuse_handles || options_.grown_base_mesh) && !user_base &&
        !clock_.done ("genus", 0.22, "genus " + std::to_string (result_.stats.genus)))
      return cancelledRun ();
    if (user_base && !checkUserBaseMesh ())
      return std::move (result_);
    const int attempts = user_base ? 1 : std::max (1, options_.max_base_attempts);
    const int first = user_base ? 0 : std::max (0, options_.first_attempt);
    for (int attempt = first; attempt < first + attempts; ++attempt) {
      result_.stats.base_attempts = static_cast<std::size_t> (attempt - first + 1);
      result_.stats.base_attempt = attempt;
      if (tryBaseMesh (attempt) == Attempt::Finished)
        return std::move (result_);
    }
    result_.message = "no base mesh worked after " + std::to_string (attempts) + " attempt(s) (" +
                      (grown_genus_ > 0
                           ? "the paths between the grown regions' corners found no room: thin "
                             "parts, or many small regions"
                           : "is the cloud sphere-like? a handle or a boundary leaves no room for "
                             "the paths; so may parts thinner than the point spacing") +
                      "); the last problem: " + last_problem_;
    return std::move (result_);
  }

private:
  /** Finished: the run ends (a triangulation, or cancelled). TryNext: this base
    * mesh failed for last_problem_. */
  enum class Attempt
  {
    Finished,
    TryNext
  };

  /** What the surface graphs are built with. */
  SurfaceGraphOptions
  surfaceGraphOptions () const
  {
    SurfaceGraphOptions graphs;
    graphs.weights = options_.weights;
    graphs.separate_thin_sheets = options_.separate_thin_sheets;
    graphs.max_neighbour_elevation_deg = options_.max_neighbour_elevation_deg;
    graphs.plane_weight_width = options_.plane_weight_width;
    graphs.normal_fit = options_.normal_fit;
    graphs.num_threads = options_.num_threads;
    return graphs;
  }

  /** The symmetric graph, the rings, the mutual graph and the weights.
    * \return false (the message set) if they cannot be built. */
  bool
  buildGraphs ()
  {
    const double stage_fraction[] = {0.05, 0.15, 0.2}; // graph, rings, weights
    int stage = 0;
    surface_ = buildSurfaceGraphs (points_, neighbourhoods_, surfaceGraphOptions (),
                                   [&] (const std::string& name, const std::string& detail) {
                                     return clock_.done (name, stage_fraction[stage++], detail);
                                   });
    result_.stats.graph_pieces = surface_.pieces;
    if (!surface_.success) {
      result_.message = surface_.message;
      return false;
    }
    if (options_.separate_thin_sheets && surface_.sheet_edges_dropped == 0) {
      result_.message = "no edges across thin parts to drop (or dropping them would "
                        "disconnect the graph)";
      return false;
    }
    SpherePipelineStats& stats = result_.stats;
    stats.normals_flipped = surface_.normals_flipped;
    stats.thin_part_edges = options_.separate_thin_sheets ? surface_.sheet_edges_dropped
                                                          : surface_.sheet_edges_droppable;
    stats.weight_fallbacks = surface_.weights.num_fallbacks;
    return true;
  }

  /** Corners of D only where the ring surrounds the point and the mutual graph
    * offers several ways out: a sharp tip (all neighbours on one side) would leave
    * no room for three or more paths in the right cyclic order. And only in the
    * largest component of the mutual graph, which the paths are routed in (thin
    * parts whose rings disagree with the rest may form components of their own). */
  void
  findCornerCandidates ()
  {
    const CsrGraph& mutual = surface_.mutual;
    corner_eligible_.assign (n_, 0);
    std::size_t eligible_count = 0;
    std::vector<pcl::index_t> mutual_component;
    const std::size_t mutual_components = connectedComponents (mutual, mutual_component);
    std::vector<std::size_t> mutual_size (mutual_components, 0);
    for (auto c : mutual_component)
      ++mutual_size[c];
    const auto main_component = static_cast<pcl::index_t> (
        std::max_element (mutual_size.begin (), mutual_size.end ()) - mutual_size.begin ());
    for (std::size_t v = 0; v < n_; ++v) {
      corner_eligible_[v] = surface_.ordered.largest_gap[v] < 0.9 * pi &&
                            mutual.degree (v) >= 4 && mutual_component[v] == main_component;
      eligible_count += corner_eligible_[v];
    }
    if (eligible_count < 4)
      corner_eligible_.clear (); // a tiny or degenerate cloud: let any point be a corner
  }

  /** A user D: closed and of genus 0, or of any genus with a grown D.
    * \return false (the message set) if it is not valid. */
  bool
  checkUserBaseMesh ()
  {
    std::string problem;
    const int genus = closedBaseMeshGenus (options_.user_base_mesh, n_, problem);
    if (genus > 0 && !options_.grown_base_mesh)
      problem = "the base mesh is not a sphere (genus " + std::to_string (genus) +
                "): use setTopology (Topology::Closed)";
    if (!problem.empty ()) {
      result_.message = "invalid base mesh: " + problem;
      return false;
    }
    result_.stats.genus = genus;
    return true;
  }

  /** \return true (the message set) if the cloud clearly has handles
    * (clearHandles); an ambiguous topology is left to the polyhedra. */
  bool
  hasHandles ()
  {
    const int genus =
        clearHandles (points_, surface_.mutual, surface_.ordered.rings, corner_eligible_);
    if (genus == 0)
      return false;
    result_.stats.genus = genus;
    result_.message = handlesRefusal (genus);
    return true;
  }

  /** The closed topology's genus, from a D grown once. Genus 0 goes on with the
    * polyhedra, as the sphere topology does: their few large patches leave the paths
    * more room than the many regions of a grown D. \return false (the message set)
    * if no D could be grown: the genus is unknown. */
  bool
  findGenus ()
  {
    GrownBaseMesh grown =
        growBaseMesh (points_, surface_.mutual, surface_.ordered.rings, corner_eligible_);
    if (!grown.success) {
      result_.stats.genus = -1;
      result_.message = "the genus could not be found: " + grown.message;
      return false;
    }
    grown_genus_ = result_.stats.genus = grown.genus;
    first_grown_ = std::move (grown.mesh);
    return true;
  }

  /** A grown D for attempt number `attempt`: later attempts start from other
    * points, so that their regions, paths and corners differ; more seeds would make
    * smaller regions, which leave the paths less room. */
  BaseMesh
  grownBaseMesh (int attempt)
  {
    if (attempt == 0 && !first_grown_.faces.empty ())
      return first_grown_;
    GrownBaseMeshOptions grow;
    grow.start = static_cast<std::uint32_t> (attempt);
    GrownBaseMesh grown =
        growBaseMesh (points_, surface_.mutual, surface_.ordered.rings, corner_eligible_, grow);
    if (!grown.success) {
      last_problem_ = grown.message;
      return {};
    }
    if (grown_genus_ >= 0 && grown.genus != grown_genus_) {
      last_problem_ = "base meshes grown from different seeds have different genera (" +
                      std::to_string (grown_genus_) + " and " +
                      std::to_string (grown.genus) +
                      "): the topology is ambiguous at this sampling";
      return {};
    }
    grown_genus_ = result_.stats.genus = grown.genus;
    return std::move (grown.mesh);
  }

  /** D of attempt number `attempt`: the user's, or a rotated polyhedron. Every
    * second attempt tries the next polyhedron: other corners, and patches of
    * another size, fail for other reasons than a mere rotation. */
  BaseMesh
  baseMesh (int attempt)
  {
    if (!options_.user_base_mesh.faces.empty ())
      return options_.user_base_mesh;
    if (options_.grown_base_mesh && grown_genus_ > 0)
      return grownBaseMesh (attempt);
    const BasePolyhedron first_polyhedron = polyhedronForSize (options_.polyhedron, n_);
    const BasePolyhedron polyhedron = options_.alternate_polyhedra && attempt % 2 == 1
                                          ? nextPolyhedron (first_polyhedron)
                                          : first_polyhedron;
    const int rotation = options_.alternate_polyhedra ? attempt / 2 : attempt;
    return polyhedronBaseMesh (points_, polyhedron, attemptRotation (rotation), corner_eligible_,
                               options_.corners);
  }

  /** Cut paths and patches for one base mesh, then the patches' triangulations. */
  Attempt
  tryBaseMesh (int attempt)
  {
    last_problem_ = "two base mesh directions picked the same point";
    const BaseMesh base = baseMesh (attempt);
    if (base.faces.empty ())
      return Attempt::TryNext;
    result_.stats.base_faces = base.faces.size ();
    const CutPaths paths =
        computeCutPaths (points_, surface_.mutual, surface_.ordered.rings, base);
    if (!paths.success) {
      last_problem_ = paths.message;
      return Attempt::TryNext;
    }
    const PatchSplit split = splitIntoPatches (points_, surface_.mutual, surface_.graph,
                                              surface_.weights.neighbours, base, paths);
    if (!split.success) {
      last_problem_ = split.message;
      return Attempt::TryNext;
    }
    recordSplit (base, paths, split);
    if (!clock_.done ("split", 0.35,
                      std::to_string (base.faces.size ()) + " patches, largest " +
                          std::to_string (result_.stats.largest_patch) + " points"))
      return cancelled ();
    return triangulateAndMerge (split);
  }

  void
  recordSplit (const BaseMesh& base, const CutPaths& paths, const PatchSplit& split)
  {
    SpherePipelineStats& stats = result_.stats;
    stats.path_points = 0;
    for (const auto& path : paths.paths)
      stats.path_points += path.size () - 2;
    stats.path_points += base.vertices.size ();
    stats.side_conflicts = split.num_side_conflicts;
    stats.reassigned = split.num_reassigned;
    stats.largest_patch = 0;
    for (const auto& patch : split.patches)
      stats.largest_patch = std::max (stats.largest_patch, patch.points.size ());
  }

  /** One parameterization and triangulation per patch, then the merge; a failed
    * patch or merge leads to the next base mesh. */
  Attempt
  triangulateAndMerge (const PatchSplit& split)
  {
    const CsrGraph cut_candidates =
        candidatesNearCuts (surface_.graph, surface_.weights.neighbours, split);
    makeRoomForPatchSolves ();
    std::vector<PatchTriangulation> triangulated = triangulatePatches (split, cut_candidates);
    std::vector<Triangles> patch_triangles;
    if (!collectPatchTriangles (triangulated, patch_triangles)) {
      rebuildGraphs ();
      return Attempt::TryNext;
    }
    if (!clock_.done ("patches", 0.9,
                      options_.patch_flips.enabled
                          ? std::to_string (result_.stats.patch_flips) + " flips"
                          : ""))
      return cancelled ();

    MergedTriangulation merged = mergePatches (patch_triangles, n_);
    if (!merged.success) {
      last_problem_ = merged.message;
      rebuildGraphs ();
      return Attempt::TryNext;
    }
    result_.stats.repair_flips = merged.num_repair_flips;
    result_.triangles = std::move (merged.triangles);
    result_.normals = surface_.ordered.normals;
    if (!clock_.done ("merge", 1.0, std::to_string (merged.num_repair_flips) + " repair flips"))
      return cancelled ();
    result_.success = true;
    return Attempt::Finished;
  }

  /** The patches solved in parallel, one large set of LU factors at a time
    * (SolveOptions::factorization_lock), the largest patches first so that the
    * small ones fill the waits: a lower peak memory on large clouds for a little
    * time. */
  std::vector<PatchTriangulation>
  triangulatePatches (const PatchSplit& split, const CsrGraph& cut_candidates) const
  {
    const std::size_t faces = split.patches.size ();
    std::vector<PatchTriangulation> triangulated (faces);
    PatchRingContext patch_rings;
    patch_rings.points = &points_;
    patch_rings.candidates = &cut_candidates;
    patch_rings.normals = &surface_.ordered.normals;
    patch_rings.weights.type = options_.weights;
    std::mutex factorization;
    SolveOptions solve = options_.solve;
    solve.factorization_lock = &factorization;
    std::vector<std::size_t> largest_first (faces);
    std::iota (largest_first.begin (), largest_first.end (), std::size_t {0});
    std::stable_sort (largest_first.begin (), largest_first.end (),
                      [&] (std::size_t a, std::size_t b) {
                        return split.patches[a].points.size () > split.patches[b].points.size ();
                      });
    const int threads = threadCount (options_.num_threads);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t> (faces); ++k) {
      const std::size_t f = largest_first[k];
      triangulated[f] = triangulatePatch (points_, surface_.weights, split.patches[f], solve,
                                          &patch_rings, options_.patch_flips);
      Points2 ().swap (triangulated[f].uv); // not needed here; memory at the peak
    }
    return triangulated;
  }

  /** Moves the patches' triangles out and sums their statistics.
    * \return false (last_problem_ set) at the first patch that failed. */
  bool
  collectPatchTriangles (std::vector<PatchTriangulation>& triangulated,
                         std::vector<Triangles>& patch_triangles)
  {
    SpherePipelineStats& stats = result_.stats;
    stats.smallest_parameter_edge = 1.0;
    stats.patch_flips = 0;
    for (auto& patch : triangulated) {
      if (!patch.success) {
        last_problem_ = patch.message;
        return false;
      }
      stats.smallest_parameter_edge = std::min (stats.smallest_parameter_edge, patch.smallest_edge);
      stats.patch_flips += patch.flips;
      patch_triangles.push_back (std::move (patch.triangles));
    }
    return true;
  }

  /** The rings and the mutual graph served the paths and the split, and the
    * patches read G only next to the cuts (candidatesNearCuts): the patch solves
    * set the peak memory of large clouds, so these go before them. What the graphs,
    * the paths and the split freed then goes back to the system: with more than
    * one thread, the other threads' allocations cannot reuse the first one's free
    * memory (glibc keeps an arena per thread). */
  void
  makeRoomForPatchSolves ()
  {
    const auto release = [] (auto& array) { std::decay_t<decltype (array)> ().swap (array); };
    release (surface_.graph.offsets);
    release (surface_.graph.adjacency);
    release (surface_.mutual.offsets);
    release (surface_.mutual.adjacency);
    release (surface_.ordered.rings.offsets);
    release (surface_.ordered.rings.adjacency);
    release (surface_.ordered.largest_gap);
    if (options_.release_freed_memory)
      releaseFreedMemory ();
  }

  /** What makeRoomForPatchSolves released, built again for a next attempt after a
    * failed patch or merge (SpherePipelineStats::rebuilds). */
  void
  rebuildGraphs ()
  {
    ++result_.stats.rebuilds;
    SurfaceGraphs again = buildSurfaceGraphs (points_, neighbourhoods_, surfaceGraphOptions ());
    surface_.graph = std::move (again.graph);
    surface_.mutual = std::move (again.mutual);
    surface_.ordered.rings = std::move (again.ordered.rings);
    surface_.ordered.largest_gap = std::move (again.ordered.largest_gap);
  }

  SphereTriangulation
  cancelledRun ()
  {
    cancelled ();
    return std::move (result_);
  }

  Attempt
  cancelled ()
  {
    result_.message = "cancelled by the progress callback";
    return Attempt::Finished;
  }

  const Points3& points_;
  const CsrGraph& neighbourhoods_;
  const SpherePipelineOptions& options_;
  const std::size_t n_;
  StageClock clock_;
  SphereTriangulation result_;
  SurfaceGraphs surface_;
  /** Per point: whether it may be a corner of D (empty: any point may). */
  std::vector<char> corner_eligible_;
  /** The genus of the first D grown in this run (-1 before). */
  int grown_genus_ = -1;
  /** The D grown to find the genus (attempt 0's D when the genus is not 0). */
  BaseMesh first_grown_;
  std::string last_problem_;
};

} // namespace

SphereTriangulation
triangulateSphere (const Points3& points,
                   const CsrGraph& neighbourhoods,
                   const SpherePipelineOptions& options)
{
  return SpherePipeline (points, neighbourhoods, options).run ();
}

} // namespace meshless
} // namespace pcl
