/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "retry_policy.h"

#include <pcl/surface/meshless/convex_hull.h>
#include <pcl/surface/meshless/disc_pipeline.h>
#include "common/freed_memory.h"

#include <algorithm>
#include <cstdio>

namespace pcl {
namespace meshless {

SpherePipelineOptions
nearSideOptions (SpherePipelineOptions options, NormalFit fit)
{
  options.max_neighbour_elevation_deg = max_neighbour_elevation_on_retry;
  options.plane_weight_width = plane_weight_width_on_retry;
  options.normal_fit = fit;
  return options;
}

void
CurrentResult::adopt (FinishedMesh&& finished)
{
  report.optimization = std::move (finished.optimization);
  report.raw_fold_repair = std::move (finished.raw_repair);
  report.fold_repair = std::move (finished.repair);
  report.mesh = std::move (finished.mesh);
  report.holes = walkHoles () + finished.holes_opened;
  report.holes_opened = finished.holes_opened;
}

// ---------------------------------------------------------------------------

MeshFinisher::MeshFinisher (const Points3& points, const ReconstructionOptions& options,
                            const CurrentResult& current, StageClock& clock)
: points_ (points)
, options_ (options)
, current_ (current)
, clock_ (clock)
, closed_ (options.topology != Topology::Disc)
{
  check_.check_self_intersections = options.check_self_intersections;
  check_.max_listed_intersections = 65536; // for distantIntersectingPairs and the repair
  check_.num_threads = static_cast<int> (options.num_threads);
}

double
MeshFinisher::areaAgainstNormals (const Triangles& triangles, const Normals& normals) const
{
  if (normals.size () != points_.size ())
    return 0.0;
  // A mesh turned as a whole faces against its normals everywhere; the check below
  // turns it, so it counts as facing along them.
  const double against = areaFacingAgainstNormals (points_, triangles, normals);
  return std::min (against, 1.0 - against);
}

bool
MeshFinisher::turnsBack (const Triangles& triangles, const Normals& normals,
                         const MeshReport& mesh, double& against, std::size_t& distant) const
{
  against = areaAgainstNormals (triangles, normals);
  distant = closed_ ? distantIntersectingPairs (points_.size (), triangles,
                                                mesh.intersecting_pairs, max_local_fold_hops)
                    : 0;
  return mesh.self_intersecting_pairs > 0 &&
         (against > max_area_against_normals || distant > 0);
}

bool
MeshFinisher::turnsBackUnrepaired (const Triangles& triangles, const Normals& normals) const
{
  if (!closed_ || !options_.check_self_intersections)
    return false;
  const MeshReport raw = checkMesh (points_, triangles, check_);
  double against = 0.0;
  std::size_t distant = 0;
  return turnsBack (triangles, normals, raw, against, distant);
}

bool
MeshFinisher::repairFolds (Triangles& triangles, const Normals& normals, const MeshReport& mesh,
                           const char* stage, LongerSwapRuns longer_runs, FoldRepairResult& repair,
                           std::vector<char>* rewritten)
{
  // Only where the listed pairs are complete and the mesh does not turn back over
  // much of its area: such a mesh is refused whatever the repair does, and its
  // thousands of pairs would cost seconds (an open surface's map through noise at
  // the spacing folds so, before its points' projections are meshed).
  repair = {};
  if (mesh.self_intersecting_pairs == 0 ||
      mesh.intersecting_pairs.size () != mesh.self_intersecting_pairs || !mesh.isManifold () ||
      !mesh.isOriented () || areaAgainstNormals (triangles, normals) > max_area_against_normals)
    return true;
  clock_.restart ();
  FoldRepairOptions repair_options;
  // The maps from each vertex's own side serve parts thinner than the spacing on
  // closed surfaces; an open surface's folds are re-meshed in planes.
  if (closed_ && normals.size () == points_.size ()) {
    repair_options.neighbours = neighbours_;
    repair_options.normals = &normals;
  }
  repair_options.rewritten = rewritten;
  if (longer_runs == LongerSwapRuns::Off)
    repair_options.max_swaps_in_a_row_when_few = repair_options.max_swaps_in_a_row;
  repair_options.num_threads = static_cast<int> (options_.num_threads);
  repair = repairFoldsByReinsertion (points_, triangles, mesh.intersecting_pairs, repair_options);
  if (repair.tangle)
    return clock_.done (stage, 1.0,
                        "not tried: " + std::to_string (repair.pairs_before) +
                            " intersecting pairs among " + std::to_string (triangles.size ()) +
                            " triangles, a tangle rather than folds");
  return clock_.done (stage, 1.0,
                      std::to_string (repair.pairs_before) + " -> " +
                          std::to_string (repair.pairs_after) + " intersecting pairs, " +
                          std::to_string (repair.regions_remeshed) + " discs re-meshed, " +
                          std::to_string (repair.swaps) + " runs of swaps" +
                          (longer_runs == LongerSwapRuns::On
                               ? ", " + std::to_string (repair.longer_run_swaps_tried) +
                                     " swaps tried in longer runs" +
                                     (repair.longer_runs_cut_short ? " (the limit)" : "")
                               : std::string ()));
}

bool
MeshFinisher::repairWithLongerRuns (Triangles& triangles, const Normals& normals,
                                    ReconstructionReport& report)
{
  FoldRepairResult runs;
  if (!repairFolds (triangles, normals, report.mesh, "repair, longer runs", LongerSwapRuns::On, runs))
    return false;
  report.fold_repair.longer_run_swaps_tried = runs.longer_run_swaps_tried;
  report.fold_repair.longer_runs_cut_short = runs.longer_runs_cut_short;
  report.fold_repair.tangle = runs.tangle;
  if (runs.regions_remeshed + runs.swaps == 0)
    return true;
  report.mesh = checkMesh (points_, triangles, check_);
  report.fold_repair.regions_remeshed += runs.regions_remeshed;
  report.fold_repair.swaps += runs.swaps;
  report.fold_repair.pairs_after = report.mesh.self_intersecting_pairs;
  return true;
}

bool
MeshFinisher::checkAndRepairRaw (Triangles& triangles, const Normals& normals,
                                 FinishedMesh& finished, EdgeSwapOptions& swaps)
{
  // The raw folds first: re-meshed in discs they come out as the surface runs,
  // while the swaps' own removal of intersections can leave webs across parts
  // thinner than the point spacing.
  clock_.restart ();
  const MeshReport raw = checkMesh (points_, triangles, check_);
  if (raw.self_intersections_checked &&
      raw.intersecting_pairs.size () == raw.self_intersecting_pairs) {
    rewritten_.assign (triangles.size (), 0);
    raw_pairs_ = raw.intersecting_pairs;
  }
  if (!clock_.done ("check raw", 0.93,
                    std::to_string (raw.self_intersecting_pairs) + " intersecting pairs") ||
      !repairFolds (triangles, normals, raw, "repair raw", LongerSwapRuns::Off, finished.raw_repair,
                    rewritten_.empty () ? nullptr : &rewritten_))
    return false;
  // The repair ran only on a complete list and counts exactly; where it left no
  // pair, the swaps need not count again.
  const FoldRepairResult& repair = finished.raw_repair;
  const bool repaired = repair.success && repair.pairs_before > 0 &&
                        repair.pairs_before == raw.self_intersecting_pairs &&
                        repair.pairs_after == 0;
  swaps.input_free_of_intersections =
      raw.self_intersections_checked && (raw.self_intersecting_pairs == 0 || repaired);
  return true;
}

std::string
MeshFinisher::optimize (Triangles& triangles, const Normals& normals, FinishedMesh& finished)
{
  EdgeSwapOptions swaps;
  static_cast<SwapRules&> (swaps) = options_.swaps;
  swaps.renumber_vertices = false; // the points follow a Z-order curve already
  // On an open surface the look-ahead would re-triangulate gaps whose long edges
  // openMissedHoles looks for.
  if (!closed_) {
    swaps.look_ahead_depth = 0;
    swaps.crease_look_ahead_depth = 0;
  }
  swaps.num_threads = static_cast<int> (options_.num_threads);
  if (closed_ && options_.check_self_intersections &&
      !checkAndRepairRaw (triangles, normals, finished, swaps))
    return "cancelled by the progress callback";
  if (options_.release_freed_memory)
    releaseFreedMemory (); // the checks' and the repair's arrays
  swaps.rewritten = rewritten_.empty () ? nullptr : &rewritten_;
  clock_.restart ();
  finished.optimization = optimizeBySwaps (points_, triangles, swaps);
  if (!finished.optimization.success)
    return "the edge-swap optimization failed: " + finished.optimization.message +
           " (setOptimize (false) skips it)";
  if (!clock_.done ("optimize", 0.95, std::to_string (finished.optimization.swaps) + " swaps"))
    return "cancelled by the progress callback";
  return "";
}

void
MeshFinisher::checkFinal (const Triangles& triangles, FinishedMesh& finished)
{
  clock_.restart ();
  MeshCheckOptions final_check = check_;
  if (!rewritten_.empty ()) {
    std::vector<char>& known_apart = rewritten_; // in place: known apart = not rewritten
    for (char& r : known_apart)
      r = !r;
    for (const auto& [s, t] : raw_pairs_)
      known_apart[s] = known_apart[t] = 0;
    final_check.known_apart = &known_apart;
  }
  finished.mesh = checkMesh (points_, triangles, final_check);
  clock_.done ("check", 1.0);
}

std::string
MeshFinisher::verdict (Triangles& triangles, MeshReport& mesh, std::size_t holes_opened) const
{
  // A closed, consistently oriented mesh with a negative volume is inside out as a
  // whole (one far outlier with an unreliable normal can carry the orientation
  // vote): reversing every triangle turns it, and only the volume's sign changes.
  // Judged after the repair, since re-meshing an outlier's fan moves much volume.
  const long genus = current_.report.stats.genus;
  const bool closed_of_genus = mesh.isClosedManifold () && mesh.components == 1 &&
                               mesh.euler_characteristic == 2 - 2 * genus;
  if (closed_ && closed_of_genus && mesh.signed_volume < 0.0) {
    for (auto& t : triangles)
      std::swap (t[1], t[2]);
    mesh.signed_volume = -mesh.signed_volume;
  }
  const std::size_t n = points_.size ();
  const bool valid =
      closed_ ? closed_of_genus && genus >= 0 &&
                    static_cast<long> (triangles.size ()) == 2 * static_cast<long> (n) - 4 + 4 * genus &&
                    mesh.signed_volume > 0.0
              : mesh.isDiscWithHoles (current_.walkHoles () + holes_opened);
  if (!valid || mesh.unused_vertices != 0)
    return "the result failed its own check (a bug; please report it with the cloud): " +
           describe (mesh);
  return "";
}

std::string
MeshFinisher::finish (Triangles& triangles, const Normals& normals, FinishedMesh& finished)
{
  rewritten_.clear ();
  raw_pairs_.clear ();
  if (options_.optimize && !current_.report.convex_hull) {
    const std::string problem = optimize (triangles, normals, finished);
    if (!problem.empty ())
      return problem;
  }
  checkFinal (triangles, finished);
  if (!closed_)
    finished.area_against_normals = areaAgainstNormals (triangles, normals);
  // Local folds the swaps could not open: re-meshed, then checked again (the pair
  // list must be complete for the repair to trust it).
  if (!repairFolds (triangles, normals, finished.mesh, "repair", LongerSwapRuns::Off, finished.repair))
    return "cancelled by the progress callback";
  if (finished.repair.regions_remeshed > 0 || finished.repair.swaps > 0)
    finished.mesh = checkMesh (points_, triangles, check_);
  const std::string missed = openMissedHoles (triangles, finished);
  if (!missed.empty ())
    return missed;
  return verdict (triangles, finished.mesh, finished.holes_opened);
}

std::string
MeshFinisher::openMissedHoles (Triangles& triangles, FinishedMesh& finished) const
{
  // Only on swapped meshes: the raw triangulation's long triangles near the outline
  // are the parameterization's, not holes.
  if (closed_ || !options_.optimize || neighbours_ == nullptr)
    return "";
  const std::size_t regions = meshless::openMissedHoles (points_, *neighbours_, triangles);
  if (regions == 0)
    return "";
  finished.mesh = checkMesh (points_, triangles, check_);
  const MeshReport& mesh = finished.mesh;
  if (!mesh.isDiscWithHoles (current_.walkHoles () + regions) || mesh.unused_vertices != 0) {
    char span[32];
    std::snprintf (span, sizeof span, "%g", max_edge_over_spacing);
    return std::to_string (regions) + " region(s) of triangles with edges over " + span +
           " times their points' spacing span what look like holes whose rims the "
           "boundary walk missed, and removing them leaves no disc with holes (a ragged "
           "or noisy rim; setPointSmoothing (PointSmoothing::Always) or a denser sample "
           "may let the walk find it): " + describe (mesh);
  }
  finished.holes_opened = regions;
  return "";
}

// ---------------------------------------------------------------------------

RetryPolicy::RetryPolicy (const Points3& points, const CsrGraph& neighbours,
                          const ReconstructionOptions& options, MeshFinisher& finisher,
                          CurrentResult& current, StageClock& clock)
: points_ (points)
, options_ (options)
, finisher_ (finisher)
, current_ (current)
, clock_ (clock)
, neighbours_ (&neighbours)
, first_neighbours_ (neighbours)
{
  finisher_.useNeighbours (neighbours_);
}

bool
RetryPolicy::defective () const
{
  return current_.report.mesh.self_intersecting_pairs > 0 || apart_;
}

std::optional<std::size_t>
RetryPolicy::countSeparatedNeighbours (const Triangles& triangles, const Normals& normals)
{
  // Without the intersection check no retry runs, and the verdict counts them.
  if (options_.topology != Topology::Sphere || !options_.check_self_intersections)
    return std::nullopt;
  clock_.restart ();
  const std::size_t separated = neighboursSeparatedByTheMesh (
      points_, triangles, first_neighbours_, normals, max_neighbour_hops,
      static_cast<int> (options_.num_threads));
  clock_.done ("handle check", 1.0,
               std::to_string (separated) + " neighbour pairs far apart on the mesh");
  return separated;
}

bool
RetryPolicy::currentTurnsBack ()
{
  return finisher_.turnsBack (current_.triangles, current_.normals, current_.report.mesh,
                              current_.report.area_against_normals,
                              current_.report.distant_intersecting_pairs);
}

int
RetryPolicy::tryAnother (const SpherePipelineOptions& options, bool& kept,
                         SpherePipelineStats* stats, RawCheck raw_check)
{
  kept = false;
  SphereTriangulation other = triangulateSphere (points_, *neighbours_, options);
  if (stats)
    *stats = other.stats;
  if (!other.success)
    return -1;
  const int attempt = other.stats.base_attempt;
  if (raw_check == RawCheck::MustNotTurnBack &&
      finisher_.turnsBackUnrepaired (other.triangles, other.normals))
    return attempt;
  FinishedMesh finished;
  double against = 0.0;
  std::size_t distant = 0;
  // Where the result keeps neighbours apart, only a run without pairs that keeps
  // none apart replaces it; where it has pairs, one with fewer, which may.
  if (!finisher_.finish (other.triangles, other.normals, finished).empty () ||
      finished.mesh.self_intersecting_pairs >=
          (apart_ ? 1 : current_.report.mesh.self_intersecting_pairs) ||
      finisher_.turnsBack (other.triangles, other.normals, finished.mesh, against, distant))
    return attempt;
  const std::optional<std::size_t> separated =
      finished.mesh.self_intersecting_pairs == 0
          ? countSeparatedNeighbours (other.triangles, other.normals)
          : std::nullopt;
  const bool apart = separated && *separated > max_separated_neighbours;
  if (!apart_ || !apart) {
    replaced_apart_ = replaced_apart_ || apart_;
    separated_ = separated;
    apart_ = apart;
    current_.triangles = std::move (other.triangles);
    current_.normals = std::move (other.normals);
    current_.report.stats = other.stats;
    current_.report.near_side_rings = options.max_neighbour_elevation_deg < 90.0;
    current_.report.near_side_sphere_fit = options.normal_fit == NormalFit::SphereThroughPoint;
    if (denser_)
      current_.report.neighbours_k = denser_k_;
    current_.adopt (std::move (finished));
    kept = true;
  }
  return attempt;
}

void
RetryPolicy::retrySequence (SpherePipelineOptions options, const SpherePipelineStats& first)
{
  // Where the surface is thinner than the point spacing, kNN edges join its two
  // sides and the patches fold there: try again with those edges dropped (see
  // buildSurfaceGraphs), also when the first result turns back, since folds across
  // thin parts can turn a genus-0 cloud's first mesh back. A second result that
  // does not turn back passes the test the first one failed, so the further base
  // meshes may then run.
  int last_attempt = first.base_attempt;
  ReconstructionReport& report = current_.report;
  if (defective () && first.thin_part_edges > 0) {
    SpherePipelineOptions thin = options;
    thin.separate_thin_sheets = true;
    bool kept = false;
    SpherePipelineStats stats;
    tryAnother (thin, kept, &stats);
    if (kept) {
      report.thin_sheet_retry = true;
      options = thin;
      last_attempt = stats.base_attempt;
    }
  }
  // Other base meshes cut the surface elsewhere, and a fold left by one layout may
  // not form in another. Not for a result that turns back (a handle or a
  // boundary): another layout may hide the handle behind a membrane. Rings that
  // fold around a limb a few points across turn a genus-0 mesh back too; the
  // near side's run is tried, kept only if it does not turn back before its repair.
  if (!options_.base_faces.empty () || !defective ())
    return;
  if (currentTurnsBack ()) {
    tryNearSide (options);
    return;
  }
  for (int retry = 0; retry < options_.base_retries && defective (); ++retry) {
    SpherePipelineOptions next = options;
    next.first_attempt = last_attempt + 1;
    ++report.base_retries;
    bool kept = false;
    last_attempt = tryAnother (next, kept);
    report.base_retry_kept |= kept;
    if (last_attempt < 0)
      break;
  }
  // Around a part only a few point spacings across, rings that reach its far side
  // fold the patches: rings of the near side only (see OrderingOptions).
  if (defective ())
    tryNearSide (options);
}

void
RetryPolicy::tryNearSide (const SpherePipelineOptions& options)
{
  const bool on_the_near_side = options.max_neighbour_elevation_deg < 90.0;
  if (options_.base_retries == 0 || near_side_tried_ ||
      (on_the_near_side && options.normal_fit == NormalFit::SphereThroughPoint))
    return;
  near_side_tried_ = true; // once: not again on k + 2 neighbours
  for (const NormalFit fit : near_side_fits) {
    if (!defective ())
      return;
    if (on_the_near_side && fit == options.normal_fit)
      continue; // the run retried was this one
    SpherePipelineOptions near_side = nearSideOptions (options, fit);
    near_side.first_attempt = 0;
    bool kept = false;
    tryAnother (near_side, kept, nullptr, RawCheck::MustNotTurnBack);
  }
}

bool
RetryPolicy::retryDenser (const SpherePipelineOptions& first_options,
                          const NeighbourSearch& search)
{
  // Where a part is only a few points across, k neighbours may leave a point's ring
  // one-sided or spanning the part; two more close it. Costs up to as many runs
  // again, only on clouds that would otherwise keep their pairs or neighbours apart.
  clock_.restart ();
  // Two more than the first run used (a closed run may have needed 2k already).
  denser_k_ = std::max (options_.k, current_.report.neighbours_k) + 2;
  denser_neighbourhoods_ = search (denser_k_);
  if (!denser_neighbourhoods_.success || denser_neighbourhoods_.num_empty != 0)
    return true;
  if (!clock_.done ("neighbourhoods", 0.02,
                    std::to_string (points_.size ()) + " points, k = " +
                        std::to_string (denser_k_)))
    return false;
  neighbours_ = &denser_neighbourhoods_.neighbours;
  denser_ = true;
  finisher_.useNeighbours (neighbours_);
  SpherePipelineStats stats;
  bool kept = false;
  if (tryAnother (first_options, kept, &stats) >= 0)
    retrySequence (first_options, stats);
  return true;
}

void
RetryPolicy::convexHullFallback ()
{
  // A small cloud whose mesh still intersects itself (its neighbourhoods span much
  // of it): if every point lies on the convex hull, the hull is the closed surface
  // through them, free of intersections.
  ReconstructionReport& report = current_.report;
  Triangles hull = convexHullThroughAll (points_, max_hull_points);
  FinishedMesh finished;
  report.convex_hull = !hull.empty ();
  if (report.convex_hull && finisher_.finish (hull, current_.normals, finished).empty () &&
      finished.mesh.self_intersecting_pairs == 0) {
    current_.triangles = std::move (hull);
    separated_.reset ();
    current_.adopt (std::move (finished));
    clock_.restart ();
    clock_.done ("hull", 1.0, std::to_string (current_.triangles.size ()) + " triangles");
  }
  else
    report.convex_hull = false;
}

bool
RetryPolicy::run (const SpherePipelineOptions& first_options, const NeighbourSearch& search)
{
  ReconstructionReport& report = current_.report;
  if (clock_.cancelled ())
    return false;
  if (report.mesh.self_intersecting_pairs == 0 && options_.base_faces.empty () &&
      options_.base_retries > 0) {
    separated_ = countSeparatedNeighbours (current_.triangles, current_.normals);
    apart_ = separated_ && *separated_ > max_separated_neighbours;
  }
  retrySequence (first_options, report.stats);
  if (options_.base_faces.empty () && options_.radius == 0.0 && options_.base_retries > 0 &&
      defective () && !currentTurnsBack () &&
      static_cast<std::size_t> (std::max (options_.k, report.neighbours_k)) + 2 < points_.size () &&
      !retryDenser (first_options, search))
    return false;
  if (!report.convex_hull && report.mesh.self_intersecting_pairs > 0 &&
      options_.base_faces.empty () && points_.size () <= max_hull_points)
    convexHullFallback ();
  return true;
}

} // namespace meshless
} // namespace pcl
