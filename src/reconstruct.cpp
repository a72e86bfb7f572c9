/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "retry_policy.h"

#include <pcl/surface/meshless/convex_hull.h>
#include <pcl/surface/meshless/disc_pipeline.h>
#include "handles.h"
#include <pcl/surface/meshless/grown_base_mesh.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/neighbourhood_search.h>
#include <pcl/surface/meshless/surface_graphs.h>
#include <pcl/search/kdtree.h>
#include "common/freed_memory.h"
#include <pcl/surface/meshless/reconstruct.h>
#include "common/spatial_order.h"

#include <Eigen/Eigenvalues> // SelfAdjointEigenSolver

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>

namespace pcl {
namespace meshless {

namespace {

/** \brief factor * k, saturated: a caller may ask for more neighbours than an int holds
  * times the factor, and a search clamps them to the cloud anyway. */
int
timesNeighbours (int factor, int k)
{
  return k > std::numeric_limits<int>::max () / factor ? std::numeric_limits<int>::max ()
                                                       : factor * k;
}

/** \brief For each point the first point at its position (itself unless it is an
  * exact duplicate). Sorting one contiguous array of coordinates is far faster than
  * sorting indices that load their points. */
std::vector<std::uint32_t>
firstOfEachPosition (const std::vector<Eigen::Vector3f>& xyz, std::size_t& num_duplicates)
{
  struct Keyed
  {
    float x, y, z;
    std::uint32_t k;
  };
  std::vector<Keyed> sorted (xyz.size ());
  for (std::size_t k = 0; k < xyz.size (); ++k)
    sorted[k] = {xyz[k].x (), xyz[k].y (), xyz[k].z (), static_cast<std::uint32_t> (k)};
  // By position, then by index, so that the first of equal points is kept.
  std::sort (sorted.begin (), sorted.end (), [] (const Keyed& a, const Keyed& b) {
    if (a.x != b.x)
      return a.x < b.x;
    if (a.y != b.y)
      return a.y < b.y;
    if (a.z != b.z)
      return a.z < b.z;
    return a.k < b.k;
  });
  std::vector<std::uint32_t> first_of (xyz.size ());
  num_duplicates = 0;
  for (std::size_t j = 0; j < sorted.size (); ++j) {
    const bool repeats = j > 0 && sorted[j].x == sorted[j - 1].x &&
                         sorted[j].y == sorted[j - 1].y && sorted[j].z == sorted[j - 1].z;
    first_of[sorted[j].k] = repeats ? first_of[sorted[j - 1].k] : sorted[j].k;
    num_duplicates += repeats;
  }
  return first_of;
}

/** \brief Float coordinates far from the origin against the cloud's size (a small
  * object in UTM coordinates) are quantized before the class sees them: failures
  * then say so, since the stage that fails cannot know why. */
std::string
precisionHint (const PreparedPoints& prepared)
{
  const Points3& points = prepared.points;
  double largest = 0.0;
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const auto& p : points) {
    largest = std::max (largest, (p + prepared.centroid).cwiseAbs ().maxCoeff ());
    lo = lo.cwiseMin (p);
    hi = hi.cwiseMax (p);
  }
  const double float_step =
      largest * static_cast<double> (std::numeric_limits<float>::epsilon ());
  const double size = (hi - lo).norm ();
  if (!(float_step > size / 200.0))
    return "";
  char text[256];
  std::snprintf (text, sizeof text,
                 " (the coordinates reach %.3g against a cloud %.3g across: in float they "
                 "are only %.3g apart there; subtract an offset such as the centroid "
                 "before filling the cloud)",
                 largest, size, float_step);
  return text;
}

/** \brief Empty, or why the points enclose no volume (all on one plane or line).
  * The bound is relative: far below any real object's thickness and above float
  * rounding of a tilted plane. */
std::string
flatness (const Points3& points)
{
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero ();
  for (const auto& p : points)
    covariance += p * p.transpose ();
  const Eigen::Vector3d variances =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> (covariance, Eigen::EigenvaluesOnly)
          .eigenvalues (); // ascending
  if (variances[0] > 1e-12 * variances[2])
    return "";
  return std::string ("all points lie ") +
         (variances[1] > 1e-12 * variances[2] ? "in one plane" : "on one line") +
         ": there is no closed surface through them (for a flat open surface use "
         "setTopology (Topology::Disc))";
}

/** \brief One reconstruct () call: the first run of the pipeline, its finishing and
  * the retries, with the failures worded for the user. */
class Conductor
{
public:
  Conductor (const PreparedPoints& prepared, const NeighbourSearch& search,
             const ReconstructionOptions& options)
  : prepared_ (prepared)
  , points_ (prepared.points)
  , search_ (search)
  , options_ (options)
  , k_ (options.k)
  , closed_ (options.topology != Topology::Disc)
  , record_ ([this] (const ProgressReport& stage) {
    result_.report.stage_seconds.emplace_back (stage.stage, stage.seconds);
    cancelled_ |= options_.progress && !options_.progress (stage);
    return !cancelled_;
  })
  , clock_ (record_)
  , finisher_ (points_, options_, result_, clock_)
  {}

  Conductor (const Conductor&) = delete;
  Conductor&
  operator= (const Conductor&) = delete;

  Reconstruction
  run ();

  /** \brief After run (): it failed on the points' geometry, which noise may cause,
    * rather than on too few points, a cancellation or a handle the sphere topology
    * refuses. */
  bool
  failedOnTheSurface () const
  {
    return failed_on_the_surface_;
  }

  /** \brief After run (): a run at twice the neighbours may succeed where this one
    * failed on a graph in one piece (not separate objects; pieces joined count as
    * one): a closed run whose every base mesh of the class's own failed at genus 0
    * (no handle seen, no mesh made to repair), a sphere's run on the class's own
    * base meshes refused for the folds its repair left, or an open surface's run.
    * Whether it is made (noise, search radius) is reconstruct ()'s to decide. */
  bool
  widerMayHelp () const
  {
    return wider_may_help_;
  }

  /** \brief After run (): the progress callback said cancel. */
  bool
  cancelled () const
  {
    return cancelled_;
  }

private:
  /** \brief The result handed to the caller (empty triangles on failure). */
  Reconstruction
  take ()
  {
    if (!result_.report.success)
      result_.triangles.clear ();
    return {std::move (result_.triangles), std::move (result_.report), {}};
  }

  bool
  fail (const std::string& reason);
  bool
  searchNeighbourhoods ();
  bool
  userBaseMesh (BaseMesh& base_mesh);
  bool
  firstSphereRun ();
  bool
  firstDiscRun ();
  void
  finishAndRetry ();
  bool
  finalVerdict (std::optional<std::size_t> separated, bool replaced_apart);
  int
  handlesWithDenserNeighbourhoods () const;
  Neighbourhoods
  twiceAsManyNeighbours () const;
  bool
  joinPiecesOfOneSurface ();
  SurfaceGraphs
  surfaceGraphsOf (const Neighbourhoods& neighbourhoods) const;
  std::string
  turnsBackMessage () const;
  bool
  countSeparatedNeighbours (std::optional<std::size_t> counted);
  std::string
  cutMessage () const;
  void
  growWithDenserNeighbourhoods (const SpherePipelineOptions& options, SphereTriangulation& first);
  bool
  routedAtK (const SpherePipelineOptions& options,
             const Neighbourhoods& denser,
             SphereTriangulation& first);
  void
  polyhedraWhereNoGenus (SpherePipelineOptions options, SphereTriangulation& first);
  void
  ringsOnTheNearSide (const SpherePipelineOptions& options, SphereTriangulation& first);

  const PreparedPoints& prepared_;
  const Points3& points_;
  const NeighbourSearch& search_;
  const ReconstructionOptions& options_;
  /** The neighbours per point the run uses: options_.k, or more where the graph at
    * options_.k falls apart into pieces of one surface. */
  int k_;
  const bool closed_;
  CurrentResult result_;
  ProgressCallback record_;
  StageClock clock_;
  MeshFinisher finisher_;
  std::string precision_hint_; // appended to failures once the points are known
  std::string pieces_hint_;    // why a graph in pieces stayed in pieces
  Neighbourhoods neighbourhoods_;
  SpherePipelineOptions first_options_; // the first run's, which the retries vary
  bool cancelled_ = false;              // the user's callback said cancel, anywhere
  bool genus_presumed_ = false; // genus 0 from the polyhedra, no D grown: only if they succeed
  bool handles_seen_ = false;   // by the polyhedra's check, where no D of that genus grew
  bool failed_on_the_surface_ = false;
  bool wider_may_help_ = false;
  bool folds_left_ = false; // refused for intersecting pairs the repair left
};

bool
Conductor::fail (const std::string& reason)
{
  std::string unknown_genus;
  if (genus_presumed_) {
    result_.report.stats.genus = -1;
    unknown_genus = " (no set of regions, of any genus, could be grown from the cloud, so "
                    "the genus is unknown: a handle about as thin as the point spacing "
                    "would look like this)";
  }
  result_.report.message = reason + unknown_genus + pieces_hint_ + precision_hint_;
  result_.triangles.clear ();
  return false;
}

bool
Conductor::searchNeighbourhoods ()
{
  clock_.restart ();
  neighbourhoods_ = search_ (k_);
  if (!neighbourhoods_.success)
    return fail (neighbourhoods_.message);
  if (neighbourhoods_.num_empty > 0)
    return fail (std::to_string (neighbourhoods_.num_empty) + " point(s) have no neighbour" +
                 (options_.radius > 0.0 ? " within the search radius (increase setSearchRadius)"
                                        : " (check setNumberOfNeighbours)"));
  if (!clock_.done ("neighbourhoods", 0.02, std::to_string (points_.size ()) + " points"))
    return fail ("cancelled by the progress callback");
  result_.report.neighbours_k = options_.radius > 0.0 ? 0 : k_;
  return true;
}

bool
Conductor::userBaseMesh (BaseMesh& base_mesh)
{
  // The user's base mesh refers to cloud indices; the pipeline to its points.
  const pcl::Indices& cloud_indices = prepared_.cloud_indices;
  std::vector<std::pair<pcl::index_t, pcl::index_t>> pipeline_of; // (cloud, pipeline)
  pipeline_of.reserve (cloud_indices.size ());
  for (std::size_t i = 0; i < cloud_indices.size (); ++i)
    pipeline_of.emplace_back (cloud_indices[i], static_cast<pcl::index_t> (i));
  std::sort (pipeline_of.begin (), pipeline_of.end ());
  for (const auto v : options_.base_vertices) {
    const auto it = std::lower_bound (pipeline_of.begin (), pipeline_of.end (),
                                      std::make_pair (static_cast<pcl::index_t> (v),
                                                      pcl::index_t{-1}));
    if (it == pipeline_of.end () || it->first != v)
      return fail ("a base mesh vertex is not a finite, distinct input point (setBaseMesh)");
    base_mesh.vertices.push_back (it->second);
  }
  for (const auto& face : options_.base_faces) {
    if (face.vertices.size () < 3)
      return fail ("base mesh faces must have at least three corners (setBaseMesh)");
    base_mesh.faces.emplace_back (face.vertices.begin (), face.vertices.end ());
  }
  return true;
}

bool
Conductor::firstSphereRun ()
{
  SpherePipelineOptions options;
  options.weights = options_.weights;
  options.polyhedron = options_.polyhedron;
  options.release_freed_memory = options_.release_freed_memory;
  options.num_threads = static_cast<int> (options_.num_threads);
  options.progress = record_;
  options.grown_base_mesh = options_.topology == Topology::Closed;
  options.refuse_handles = options_.topology == Topology::Sphere && options_.base_faces.empty ();
  // The swaps' angle pass starts inside the patches, where they are triangulated in
  // parallel (flipFlatEdgesInPatch); the swaps find most of it done.
  options.patch_flips.enabled = options_.optimize && options_.swaps.improve_angles;
  options.patch_flips.max_dihedral_deg = options_.swaps.angle_pass_max_dihedral_deg;
  options.patch_flips.max_fold_angle_deg = options_.swaps.max_fold_angle_deg;
  if (!options_.base_faces.empty () && !userBaseMesh (options.user_base_mesh))
    return false;
  first_options_ = options;
  first_options_.refuse_handles = false; // the first run looks for them; its retries need not
  SphereTriangulation first = triangulateSphere (points_, neighbourhoods_.neighbours, options);
  if (!first.success && first.stats.graph_pieces > 1 && !cancelled_ && joinPiecesOfOneSurface ())
    first = triangulateSphere (points_, neighbourhoods_.neighbours, options);
  if (!first.success && options.grown_base_mesh && first.stats.genus < 0)
    growWithDenserNeighbourhoods (options, first);
  polyhedraWhereNoGenus (options, first);
  if (!first.success && !cancelled_ && first.stats.graph_pieces <= 1)
    ringsOnTheNearSide (options, first);
  if (options_.release_freed_memory)
    releaseFreedMemory (); // the pipeline's graphs and factors
  ReconstructionReport& report = result_.report;
  report.stats = first.stats;
  if (options.grown_base_mesh)
    first_options_.known_genus = first.stats.genus;
  if (first.success) {
    result_.triangles = std::move (first.triangles);
    result_.normals = std::move (first.normals);
    return true;
  }
  // A few dozen points leave the pipeline too little to work with; if they all lie
  // on their convex hull, that is the closed surface through them.
  // Not where the cloud was found to have handles: the hull has none.
  if (options_.base_faces.empty () && first.stats.genus <= 0) {
    result_.triangles = convexHullThroughAll (points_, max_hull_points);
    if (!result_.triangles.empty ())
      report.stats.genus = 0;
  }
  if (result_.triangles.empty ()) {
    // Neighbourhoods spanning much of the cloud are not local: name the setter.
    const std::size_t n = points_.size ();
    const bool wide = 4 * neighbourhoods_.neighbours.numEntries () >= n * n;
    return fail (std::string (options_.topology == Topology::Closed ? "the closed"
                                                                    : "the spherical") +
                 " reconstruction failed: " + first.message +
                 (wide ? std::string (" (the neighbourhoods span a quarter of the cloud or "
                                      "more on average: lower ") +
                             (options_.radius > 0.0 ? "setSearchRadius)"
                                                    : "setNumberOfNeighbours)")
                       : std::string ()));
  }
  report.convex_hull = true;
  clock_.restart ();
  clock_.done ("hull", 0.9, std::to_string (result_.triangles.size ()) + " triangles");
  return true;
}

/** \brief The surface graphs over other neighbourhoods than the first run's, with
  * its weights and threads. */
SurfaceGraphs
Conductor::surfaceGraphsOf (const Neighbourhoods& neighbourhoods) const
{
  SurfaceGraphOptions graphs;
  graphs.weights = options_.weights;
  graphs.num_threads = static_cast<int> (options_.num_threads);
  return buildSurfaceGraphs (points_, neighbourhoods.neighbours, graphs);
}

/** \brief Where the k nearest neighbours fall apart into dense groups of one
  * closed surface (the vertices of a mesh whose long thin triangles join small
  * clusters), 2k, 3k or 4k neighbours, the first that join every piece along the
  * surface, replace them, once a run has failed on the pieces (the check would cost
  * every run a pass over the graph). Not for open surfaces: a scan's shadow would
  * be bridged. Separate objects stay apart: far apart, no wider neighbourhood
  * joins them; nearly touching, the joins run across their surfaces (as they seem
  * to round a thin part sampled in rings far apart, whose rings' planes stand
  * across it).
  * \return true if they were replaced (and the stage line says so). */
bool
Conductor::joinPiecesOfOneSurface ()
{
  if (!closed_ || options_.radius > 0.0)
    return false;
  clock_.restart ();
  const int threads = static_cast<int> (options_.num_threads);
  std::vector<pcl::index_t> pieces, joined;
  const std::size_t count =
      connectedComponents (symmetricGraph (neighbourhoods_.neighbours, threads), pieces);
  if (count <= 1)
    return false;
  // Clusters of one surface join about all along it, a mesh's vertices around long
  // thin triangles about half, objects that nearly touch not at all.
  const double min_joins_along = 0.25;
  for (int factor = 2; factor <= 4 && !cancelled_; ++factor) {
    Neighbourhoods wider = search_ (timesNeighbours (factor, options_.k));
    if (!wider.success || wider.num_empty > 0 ||
        connectedComponents (symmetricGraph (wider.neighbours, threads), joined) != 1)
      continue;
    if (joinsAlongTheSurface (points_, neighbourhoods_.neighbours, pieces, wider.neighbours) <
        min_joins_along) {
      pieces_hint_ = " (" + std::to_string (timesNeighbours (factor, options_.k)) +
                     " neighbours join its pieces only across their surfaces: separate "
                     "objects, or a thin part sampled in rings farther apart than "
                     "their points)";
      return false;
    }
    neighbourhoods_ = std::move (wider);
    k_ = timesNeighbours (factor, options_.k);
    result_.report.neighbours_k = k_;
    return clock_.done ("neighbourhoods", 0.02,
                        "the " + std::to_string (options_.k) +
                            "-nearest-neighbour graph fell into " + std::to_string (count) +
                            " pieces of one surface: k = " + std::to_string (k_));
  }
  return false;
}

/** \brief The 2k nearest neighbours where the rings at k disagree too much to grow D;
  * not successful with a search radius, or if some point has none. */
Neighbourhoods
Conductor::twiceAsManyNeighbours () const
{
  if (options_.radius > 0.0)
    return {};
  Neighbourhoods denser = search_ (timesNeighbours (2, k_));
  if (denser.num_empty > 0)
    denser.success = false;
  return denser;
}

/** \brief No grown D at k neighbours: on anisotropic samples (the vertices of long
  * thin triangles) the rings of neighbouring points disagree; at 2k they agree more.
  * `first` is replaced if that run succeeds. */
void
Conductor::growWithDenserNeighbourhoods (const SpherePipelineOptions& options,
                                         SphereTriangulation& first)
{
  if (cancelled_)
    return;
  clock_.restart ();
  Neighbourhoods denser = twiceAsManyNeighbours ();
  if (!denser.success ||
      !clock_.done ("neighbourhoods", 0.02, "k = " + std::to_string (timesNeighbours (2, k_))))
    return;
  if (routedAtK (options, denser, first) || cancelled_)
    return;
  SphereTriangulation second = triangulateSphere (points_, denser.neighbours, options);
  if (!second.success) {
    // A handle seen at 2k is not left to the genus-0 polyhedra.
    if (second.stats.genus > 0) {
      first.stats.genus = second.stats.genus;
      first.message = second.message;
    }
    return;
  }
  first = std::move (second);
  neighbourhoods_ = std::move (denser);
  result_.report.neighbours_k = timesNeighbours (2, k_);
}

/** \brief A D of genus above 0 grown at 2k, routed and mapped at k: wider
  * neighbourhoods also widen the maps' stencils and the triangles' reach (farther
  * from the surface). \return true if that run succeeded (it replaces `first`). */
bool
Conductor::routedAtK (const SpherePipelineOptions& options,
                      const Neighbourhoods& denser,
                      SphereTriangulation& first)
{
  SpherePipelineOptions at_k = options;
  {
    const SurfaceGraphs surface = surfaceGraphsOf (denser);
    if (!surface.success)
      return false;
    GrownBaseMesh grown = growBaseMesh (points_, surface.mutual, surface.ordered.rings);
    if (!grown.success || grown.genus <= 0)
      return false;
    at_k.user_base_mesh = std::move (grown.mesh);
  } // the 2k graphs go before the run at k
  SphereTriangulation second = triangulateSphere (points_, neighbourhoods_.neighbours, at_k);
  if (!second.success || cancelled_)
    return false;
  first = std::move (second);
  return true;
}

/** \brief No D grown at k nor at 2k: regions only a few points around thin limbs
  * give rings too noisy to read a dual from. The sphere topology's polyhedra then
  * try, under its check for clear handles; a mesh from them passes the verdict a
  * sphere run passes, so its genus 0 is as sure as that topology's. `first` is
  * replaced if that run succeeds; nothing runs unless `first` is a closed run that
  * failed to find its genus on the class's own base meshes. */
void
Conductor::polyhedraWhereNoGenus (SpherePipelineOptions options, SphereTriangulation& first)
{
  if (cancelled_ || first.success || !options.grown_base_mesh || first.stats.genus >= 0 ||
      !options.user_base_mesh.faces.empty ())
    return;
  options.grown_base_mesh = false;
  options.refuse_handles = true;
  SphereTriangulation sphere = triangulateSphere (points_, neighbourhoods_.neighbours, options);
  if (!sphere.success) {
    handles_seen_ |= sphere.stats.genus > 0;
    if (sphere.stats.genus > 0)
      first.message += "; " + std::to_string (sphere.stats.genus) +
                       " handle(s) were seen, but no base mesh of that genus could be grown";
    return;
  }
  first = std::move (sphere);
  first.stats.genus = 0;
  genus_presumed_ = true;
}

/** \brief Every base mesh failed on the rings as ordered: around a part a few point
  * spacings around they reach its far side and fold. Not where handles were seen,
  * and kept only if it does not turn back before its repair (a hidden handle). */
void
Conductor::ringsOnTheNearSide (const SpherePipelineOptions& options, SphereTriangulation& first)
{
  if (first.stats.genus > 0 || handles_seen_ || !options.user_base_mesh.faces.empty () ||
      !options_.check_self_intersections)
    return;
  clock_.restart ();
  for (const NormalFit fit : near_side_fits) {
    const SpherePipelineOptions near_side = nearSideOptions (options, fit);
    SphereTriangulation again = triangulateSphere (points_, neighbourhoods_.neighbours, near_side);
    const bool presumed = genus_presumed_;
    polyhedraWhereNoGenus (near_side, again);
    if (cancelled_ || handles_seen_) {
      genus_presumed_ = presumed;
      return;
    }
    if (!again.success || finisher_.turnsBackUnrepaired (again.triangles, again.normals)) {
      genus_presumed_ = presumed;
      continue;
    }
    first = std::move (again);
    first_options_ = nearSideOptions (first_options_, fit);
    result_.report.near_side_rings = true;
    result_.report.near_side_sphere_fit = fit == NormalFit::SphereThroughPoint;
    clock_.done ("near side", 0.35,
                 std::string ("rings of the near side only, ") +
                     (fit == NormalFit::SphereThroughPoint ? "on spheres" : "on planes") +
                     ": every base mesh failed on the rings as ordered");
    return;
  }
}

bool
Conductor::firstDiscRun ()
{
  DiscPipelineOptions options;
  options.weights = options_.weights;
  options.num_threads = static_cast<int> (options_.num_threads);
  options.progress = record_;
  DiscTriangulation disc = triangulateDisc (points_, neighbourhoods_.neighbours, options);
  result_.report.stats.graph_pieces = disc.graph_pieces;
  if (!disc.success)
    return fail ("the disc reconstruction failed: " + disc.message);
  result_.report.holes = disc.holes;
  result_.triangles = std::move (disc.triangles);
  result_.normals = std::move (disc.normals);
  finisher_.useNeighbours (&neighbourhoods_.neighbours); // to find holes the walk missed
  return true;
}

/** \brief The genus read again with twice the neighbours, after a sphere run turned
  * back: on anisotropic samples (the vertices of long thin triangles) the rings at k
  * disagree too much to grow D. 0 if the cloud does not clearly have handles. */
int
Conductor::handlesWithDenserNeighbourhoods () const
{
  if (options_.topology != Topology::Sphere)
    return 0;
  const Neighbourhoods denser = twiceAsManyNeighbours ();
  if (!denser.success)
    return 0;
  const SurfaceGraphs surface = surfaceGraphsOf (denser);
  return surface.success ? clearHandles (points_, surface.mutual, surface.ordered.rings) : 0;
}

/** \brief Why a closed mesh that turns back over itself is refused, with what to
  * change for the topology asked for. */
std::string
Conductor::turnsBackMessage () const
{
  const ReconstructionReport& report = result_.report;
  const bool sphere = options_.topology == Topology::Sphere;
  return std::string ("the cloud does not look like the surface of one ") +
         (sphere ? "sphere-like" : "closed") +
         " object: a closed mesh through it intersects itself (" +
         std::to_string (report.mesh.self_intersecting_pairs) + " pairs" +
         (report.distant_intersecting_pairs > 0
              ? ", " + std::to_string (report.distant_intersecting_pairs) +
                    " of them between parts of it far apart"
              : std::string ()) +
         ") and " +
         std::to_string (static_cast<int> (100.0 * report.area_against_normals + 0.5)) +
         "% of its area faces against the cloud's normals (" +
         (sphere ? "a handle: use setTopology (Topology::Closed); " : "") +
         "a boundary: use setTopology (Topology::Disc); parts thinner than the point "
         "spacing: sample them more densely; or far outliers: remove them)";
}

/** \brief Counts the neighbours on one side of the surface that the closed mesh
  * puts far apart (report.separated_neighbours): a handle whose tube it cut and
  * capped, which neither a fold nor the area facing against the normals shows;
  * `counted` if the retries counted them on this mesh already.
  * \return false if the progress callback cancelled */
bool
Conductor::countSeparatedNeighbours (std::optional<std::size_t> counted)
{
  ReconstructionReport& report = result_.report;
  if (counted) {
    report.separated_neighbours = *counted;
    return !cancelled_;
  }
  clock_.restart ();
  report.separated_neighbours = neighboursSeparatedByTheMesh (
      points_, result_.triangles, neighbourhoods_.neighbours, result_.normals,
      max_neighbour_hops, static_cast<int> (options_.num_threads));
  return clock_.done ("handle check", 1.0,
                      std::to_string (report.separated_neighbours) +
                          " neighbour pairs far apart on the mesh");
}

/** \brief Why a closed mesh that cut through a handle is refused. */
std::string
Conductor::cutMessage () const
{
  const ReconstructionReport& report = result_.report;
  const bool sphere = options_.topology == Topology::Sphere;
  return std::string (sphere ? "the cloud does not look like the surface of one sphere-like "
                               "object"
                             : "the genus could not be found") +
         ": a closed mesh through it puts " + std::to_string (report.separated_neighbours) +
         " pairs of neighbouring points with agreeing normals more than " +
         std::to_string (max_neighbour_hops) +
         " edges apart, as a mesh that cut through a handle does (" +
         (sphere ? "use setTopology (Topology::Closed); " : "sample the handles more densely; ") +
         "a part thinner than the point spacing may also: sample it more densely)";
}

bool
Conductor::finalVerdict (std::optional<std::size_t> separated, bool replaced_apart)
{
  ReconstructionReport& report = result_.report;
  const bool turns_back =
      closed_ && finisher_.turnsBack (result_.triangles, result_.normals, report.mesh,
                                      report.area_against_normals,
                                      report.distant_intersecting_pairs);
  // A result of the near side's rings may stand in for one that turned back: the
  // handles are looked for as if it had.
  const int genus =
      turns_back || report.near_side_rings || replaced_apart ? handlesWithDenserNeighbourhoods ()
                                                             : 0;
  if (genus > 0) {
    report.stats.genus = genus;
    return fail (handlesRefusal (genus));
  }
  if (turns_back)
    return fail (turnsBackMessage ());
  if (closed_ && !countSeparatedNeighbours (separated))
    return fail ("cancelled by the progress callback");
  if (report.separated_neighbours > max_separated_neighbours) {
    if (options_.topology == Topology::Closed)
      report.stats.genus = -1; // not the genus 0 of the polyhedra it came from
    return fail (cutMessage ());
  }
  // An open surface's map folded over itself is no mesh to return, even where
  // intersections are allowed: the walk missed the outline.
  if (!closed_ && report.mesh.self_intersecting_pairs > 0 &&
      report.area_against_normals > max_area_against_normals) {
    char share[32];
    std::snprintf (share, sizeof share, "%.0f%%", 100.0 * report.area_against_normals);
    return fail (std::string ("the map folds over itself: ") + share +
                 " of the mesh's area faces against the points' normals and " +
                 std::to_string (report.mesh.self_intersecting_pairs) +
                 " pair(s) of triangles intersect (the boundary walk missed the outline, "
                 "as noise along it makes it do; setPointSmoothing (PointSmoothing::Always) "
                 "meshes the points' projections, or more neighbours may find it)");
  }
  // Runs of swaps too costly for every attempt's repair, on the result kept.
  if (report.mesh.self_intersecting_pairs > 0 &&
      !finisher_.repairWithLongerRuns (result_.triangles, result_.normals, report))
    return fail ("cancelled by the progress callback");
  folds_left_ = report.mesh.self_intersecting_pairs > 0 && !options_.allow_self_intersections;
  if (folds_left_)
    return fail (std::to_string (report.mesh.self_intersecting_pairs) +
                 " pair(s) of triangles still intersect each other " +
                 (report.fold_repair.tangle
                      ? std::string ("(a tangle rather than local folds, not repaired)")
                      : std::string ("after the repair") +
                            (closed_ ? " and the retries, in local folds" : "") +
                            " (parts thinner than the point spacing, or noise)") +
                 ": the mesh is " +
                 (closed_ ? "closed" : "manifold") +
                 " but not embedded (setAllowSelfIntersections (true) returns it anyway; "
                 "more neighbours or a denser sample may avoid the folds)");
  report.success = true;
  return true;
}

Reconstruction
Conductor::run ()
{
  const std::size_t n = points_.size ();
  result_.report.num_points = n;
  result_.report.num_duplicates = prepared_.num_duplicates;
  if (n < (closed_ ? 4u : 3u)) {
    fail (std::string ("a ") +
          (closed_ ? "closed surface needs at least four" : "disc needs at least three") +
          " distinct finite points; the input has " + std::to_string (n));
    return take ();
  }
  precision_hint_ = precisionHint (prepared_);
  const std::string flat = closed_ ? flatness (points_) : "";
  if (!flat.empty ())
    fail (flat);
  else if (searchNeighbourhoods ()) {
    const ReconstructionReport& report = result_.report;
    const bool routed = closed_ ? firstSphereRun () : firstDiscRun ();
    if (routed)
      finishAndRetry ();
    failed_on_the_surface_ = !report.success && !cancelled_ &&
                             !(options_.topology == Topology::Sphere && report.stats.genus > 0);
    // A closed run where every base mesh of the class's own failed at genus 0, or a
    // sphere's run refused for the folds its repair left. Not the closed topology's
    // folds: its wider run finds the genus again, and neighbourhoods that bridge two
    // sheets could give it a handle.
    const bool sphere_folds = options_.topology == Topology::Sphere && folds_left_;
    const bool closed_may_widen = (!routed || sphere_folds) && options_.base_faces.empty () &&
                                  report.stats.genus == 0;
    wider_may_help_ = failed_on_the_surface_ && report.stats.graph_pieces == 1 &&
                      (!closed_ || closed_may_widen);
  }
  return take ();
}

void
Conductor::finishAndRetry ()
{
  // The policy holds the denser neighbourhoods the finisher may use: it lives until
  // the verdict.
  RetryPolicy policy (points_, neighbourhoods_.neighbours, options_, finisher_, result_, clock_);
  FinishedMesh first;
  const std::string problem = finisher_.finish (result_.triangles, result_.normals, first);
  const double against = first.area_against_normals;
  result_.adopt (std::move (first));
  if (!closed_) // closed topologies: the verdict measures it on the mesh kept
    result_.report.area_against_normals = against;
  if (!problem.empty ()) {
    fail (problem);
    return;
  }
  // Once the callback has said cancel, the call fails, even if a retry ran on.
  if ((closed_ && !policy.run (first_options_, search_)) || cancelled_) {
    fail ("cancelled by the progress callback");
    return;
  }
  finalVerdict (policy.separatedNeighbours (), policy.replacedOneKeepingNeighboursApart ());
}

} // namespace

PreparedPoints
preparePoints (const std::vector<Eigen::Vector3f>& xyz, const pcl::Indices& cloud_indices)
{
  PreparedPoints prepared;
  const std::vector<std::uint32_t> first_of = firstOfEachPosition (xyz, prepared.num_duplicates);
  std::vector<std::size_t> kept;
  kept.reserve (xyz.size () - prepared.num_duplicates);
  for (std::size_t k = 0; k < xyz.size (); ++k)
    if (first_of[k] == k)
      kept.push_back (k);
  const std::size_t n = kept.size ();
  for (const auto k : kept)
    prepared.centroid += xyz[k].cast<double> ();
  if (n > 0)
    prepared.centroid /= static_cast<double> (n);
  Points3 points (n);
  for (std::size_t i = 0; i < n; ++i)
    points[i] = xyz[kept[i]].cast<double> () - prepared.centroid;
  // Every stage walks neighbourhoods: numbered along a Z-order curve, neighbours in
  // space are mostly neighbours in memory.
  const std::vector<pcl::index_t> order = mortonOrder (points);
  prepared.points.resize (n);
  prepared.cloud_indices.resize (n);
  std::vector<pcl::index_t> pipeline_index;
  if (prepared.num_duplicates > 0)
    pipeline_index.assign (xyz.size (), -1);
  for (std::size_t i = 0; i < n; ++i) {
    prepared.points[i] = points[order[i]];
    prepared.cloud_indices[i] = cloud_indices[kept[order[i]]];
    if (!pipeline_index.empty ())
      pipeline_index[kept[order[i]]] = static_cast<pcl::index_t> (i);
  }
  prepared.duplicates.reserve (prepared.num_duplicates);
  if (prepared.num_duplicates > 0)
    for (std::size_t k = 0; k < first_of.size (); ++k)
      if (first_of[k] != k)
        prepared.duplicates.emplace_back (cloud_indices[k], pipeline_index[first_of[k]]);
  return prepared;
}

std::string
checkOptions (const ReconstructionOptions& options)
{
  if (!(options.radius >= 0.0) || !std::isfinite (options.radius))
    return "the search radius must be finite and not negative (setSearchRadius)";
  if (options.radius == 0.0 && options.k < 3)
    return "the number of neighbours must be at least 3 (setNumberOfNeighbours)";
  if (options.base_retries < 0)
    return "the number of base mesh retries must not be negative (setBaseRetries)";
  return "";
}

namespace {

/** \brief Neighbourhoods among `points` through PCL's kd-tree: the noisy points'
  * nearest neighbours are not their projections' nearest. */
NeighbourSearch
searchAmong (const Points3& points, const ReconstructionOptions& options)
{
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  cloud->resize (points.size ());
  for (std::size_t i = 0; i < points.size (); ++i)
    (*cloud)[i].getVector3fMap () = points[i].cast<float> ();
  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>> ();
  tree->setInputCloud (cloud);
  pcl::Indices all (points.size ());
  std::iota (all.begin (), all.end (), 0);
  return [tree, all = std::move (all), &options] (int k) {
    NeighbourhoodOptions neighbourhood;
    neighbourhood.k = k;
    neighbourhood.radius = options.radius;
    neighbourhood.num_threads = static_cast<int> (options.num_threads);
    return searchNeighbourhoods (*tree, all, neighbourhood);
  };
}

/** \brief The runs on the points projected onto surfaces fitted to them, after
  * `failed` (a failed run on the points themselves; empty for PointSmoothing::Always):
  * fitted over 4k neighbours, then over 6k where that run fails too. The result is
  * the first projections' run that succeeds, else `failed` with the noise measured
  * (or, asked to smooth always, the last run). `cancelled` says whether the progress
  * callback stopped it, `noise_ratio` what the first fit, which decides, measured
  * (-1 if none). */
Reconstruction
runOnFittedSurfaces (const PreparedPoints& prepared,
                     const NeighbourSearch& search,
                     const ReconstructionOptions& options,
                     Reconstruction failed,
                     bool& cancelled,
                     double& noise_ratio)
{
  cancelled = false;
  noise_ratio = -1.0;
  const bool always = options.smoothing == PointSmoothing::Always;
  ReconstructionReport& report = failed.report;
  report.num_points = prepared.points.size ();
  report.num_duplicates = prepared.num_duplicates;
  Reconstruction second;
  PointNoise first_fit; // what decides whether the cloud is noisy
  // A few dozen neighbours average noise about as large as their spacing; where its
  // larger swings still leave the paths no room, more of them.
  for (const int factor : {4, 6}) {
    const auto start = std::chrono::steady_clock::now ();
    const int wide_k = timesNeighbours (factor, options.k);
    PreparedPoints moved = prepared;
    {
      const Neighbourhoods wide = search (wide_k);
      if (!wide.success && factor == 4) {
        if (always)
          report.message = wide.message;
        return failed;
      }
      if (!wide.success)
        break; // the run on the first projections failed: said below
      SmoothedPoints smoothed = projectOntoFittedSurfaces (
          prepared.points, wide.neighbours, static_cast<int> (options.num_threads));
      moved.points = std::move (smoothed.points);
      report.noise = smoothed.noise;
      if (factor == 4) {
        first_fit = smoothed.noise;
        noise_ratio = first_fit.noise_ratio;
      }
    } // the wide neighbourhoods go before the run
    const double seconds =
        std::chrono::duration<double> (std::chrono::steady_clock::now () - start).count ();
    char detail[112];
    std::snprintf (detail, sizeof detail,
                   "%d neighbours: points %.2f spacings off the fitted surfaces (median)",
                   wide_k, report.noise.noise_ratio);
    report.stage_seconds.emplace_back ("smoothing", seconds);
    if (options.progress && !options.progress ({"smoothing", 0.01, seconds, detail})) {
      report.message = "cancelled by the progress callback";
      cancelled = true;
      return failed;
    }
    if (!always && first_fit.noise_ratio < min_noise_ratio)
      return failed;
    if (!always && options.topology == Topology::Disc &&
        first_fit.noise_ratio > max_disc_noise_ratio) {
      char ratio[32];
      std::snprintf (ratio, sizeof ratio, "%.2f", first_fit.noise_ratio);
      report.message += std::string ("; the points lie ") + ratio +
                        " point spacings off surfaces fitted to them (median), too noisy "
                        "to tell an open surface's holes from the gaps of its sample "
                        "(setPointSmoothing (PointSmoothing::Always) meshes their projections anyway)";
      return failed;
    }
    const NeighbourSearch moved_search = searchAmong (moved.points, options);
    Conductor conductor (moved, moved_search, options);
    second = conductor.run ();
    report.stage_seconds.insert (report.stage_seconds.end (),
                                 second.report.stage_seconds.begin (),
                                 second.report.stage_seconds.end ());
    if (conductor.cancelled ()) {
      report.message = "cancelled by the progress callback";
      cancelled = true;
      return failed;
    }
    if (second.report.success) {
      second.smoothed_points = std::move (moved.points);
      break;
    }
  }
  if (!second.report.success && !always) {
    char ratio[32];
    std::snprintf (ratio, sizeof ratio, "%.2f", first_fit.noise_ratio);
    report.message += std::string ("; so did the runs on the points moved onto surfaces "
                                   "fitted to them (they lie ") +
                      ratio + " point spacings off them in the median)";
    return failed;
  }
  second.report.noise = report.noise; // the fit the mesh runs through
  second.report.smoothed = second.report.success;
  second.report.stage_seconds = std::move (report.stage_seconds);
  return second;
}

/** \brief A run at twice the neighbours, after a run on a graph in one piece failed
  * (Conductor::widerMayHelp) and the smoothing did not help: where the k nearest of
  * a point lie on one side of it (small clusters, a sparse sample of a curved part,
  * density falling off steeply) its ring stays open and its weights are the
  * fallback's: closed runs find no room for their paths or keep folds, open ones
  * fold or cannot cut their holes out. Twice as many close such rings. After the
  * smoothing, so that noise at the spacing is meshed through fitted surfaces rather
  * than through wider neighbourhoods of its swings. The result is that run if it
  * succeeds, else `failed` saying so. */
Reconstruction
runWithTwiceTheNeighbours (const PreparedPoints& prepared,
                           const NeighbourSearch& search,
                           const ReconstructionOptions& options,
                           Reconstruction failed)
{
  // Twice the k the run ended on: it may have joined pieces with more already, or
  // kept a retry's k + 2.
  ReconstructionOptions wider = options;
  wider.k = timesNeighbours (2, std::max (options.k, failed.report.neighbours_k));
  // Neighbourhoods spanning a quarter of the cloud are no longer local.
  if (4 * static_cast<std::size_t> (wider.k) >= prepared.points.size ())
    return failed;
  Conductor conductor (prepared, search, wider);
  Reconstruction second = conductor.run ();
  ReconstructionReport& report = failed.report;
  report.stage_seconds.insert (report.stage_seconds.end (),
                               second.report.stage_seconds.begin (),
                               second.report.stage_seconds.end ());
  if (conductor.cancelled ()) {
    report.message = "cancelled by the progress callback";
    return failed;
  }
  // A refusal naming the handles the wider run saw is the clearer reason.
  const bool handles_seen =
      options.topology == Topology::Sphere && second.report.stats.genus > 0;
  if (!second.report.success && !handles_seen) {
    report.message += "; so did a run with " + std::to_string (wider.k) + " neighbours";
    return failed;
  }
  second.report.noise = report.noise;
  second.report.stage_seconds = std::move (report.stage_seconds);
  return second;
}

} // namespace

Reconstruction
reconstruct (const PreparedPoints& prepared,
             const NeighbourSearch& search,
             const ReconstructionOptions& options)
{
  Reconstruction result;
  result.report.message = checkOptions (options);
  if (!result.report.message.empty ())
    return result;
  bool cancelled = false;
  double noise_ratio = -1.0;
  if (options.smoothing == PointSmoothing::Always && prepared.points.size () >= 4)
    return runOnFittedSurfaces (prepared, search, options, std::move (result), cancelled,
                                noise_ratio);
  bool failed_on_the_surface = false;
  bool wider_may_help = false;
  {
    Conductor first (prepared, search, options);
    result = first.run ();
    failed_on_the_surface = first.failedOnTheSurface ();
    wider_may_help = first.widerMayHelp ();
  } // its neighbourhoods and finisher go before another run
  if (result.report.success || !failed_on_the_surface)
    return result;
  if (options.smoothing == PointSmoothing::IfNoisy) {
    result = runOnFittedSurfaces (prepared, search, options, std::move (result), cancelled,
                                  noise_ratio);
    if (result.report.success)
      return result;
  }
  // An open surface only where its noise was measured and found too low to smooth:
  // wider neighbourhoods through noise may close its holes or the sample's gaps.
  const bool holes_uncertain =
      options.topology == Topology::Disc && !(noise_ratio >= 0.0 && noise_ratio < min_noise_ratio);
  if (!wider_may_help || cancelled || options.radius > 0.0 || holes_uncertain)
    return result;
  return runWithTwiceTheNeighbours (prepared, search, options, std::move (result));
}

} // namespace meshless
} // namespace pcl
