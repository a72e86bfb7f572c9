/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/Vertices.h>
#include <pcl/surface/meshless/base_mesh.h>
#include <pcl/surface/meshless/edge_swap.h>
#include <pcl/surface/meshless/fold_repair.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/point_smoothing.h>
#include <pcl/surface/meshless/sphere_pipeline.h>
#include <pcl/surface/meshless/weights.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

/** \file
  * The whole reconstruction as one PointT-free call: the PCL class converts its
  * input, hands over a neighbour search through its tree, and writes the result.
  */
namespace pcl {
namespace meshless {

/** \brief The topology of the surface the cloud samples. */
enum class Topology
{
  Sphere, ///< closed, genus 0 (default); a cloud with handles is refused
  Disc,   ///< open, one outer boundary (holes kept open where possible)
  Closed  ///< closed, of the genus found from the cloud (ReconstructionReport::stats.genus)
};

/** \brief Whether the mesh may run through the points moved onto surfaces fitted to
  * their neighbours (projectOntoFittedSurfaces) instead of the points themselves. */
enum class PointSmoothing
{
  /** The points as given: a cloud whose noise is about its point spacing may fail. */
  Off,
  /** Default: where the run on the points fails (not on a handle the sphere
    * topology refuses) and they lie, in the median, more than min_noise_ratio of
    * their spacing off the surfaces fitted to them, the run is repeated on their
    * projections (ReconstructionReport::smoothed says so). In disc mode only up to
    * max_disc_noise_ratio: noisier, the sample's gaps pass for holes and holes'
    * rims are missed. */
  IfNoisy,
  /** Every run on the projections: a smoothed mesh of any cloud, disc mode too. */
  Always
};

/** \brief What a user chooses; the pipeline's internal settings are derived from it.
  * Defaults are the class's defaults. */
struct ReconstructionOptions
{
  Topology topology = Topology::Sphere;
  /** \brief Nearest neighbours k (used when radius is 0); at least 3. */
  int k = 12;
  /** \brief Ball neighbourhoods of this radius instead of k nearest (0 = k nearest). */
  double radius = 0.0;
  WeightType weights = WeightType::MeanValue;
  BasePolyhedron polyhedron = BasePolyhedron::BySize;
  /** \brief A user base mesh over input cloud indices (empty = the polyhedron). */
  pcl::Indices base_vertices;
  std::vector<pcl::Vertices> base_faces;
  /** \brief Edge swaps after the raw triangulation. */
  bool optimize = true;
  SwapRules swaps;
  /** \brief Further base meshes tried while the result intersects itself (or, sphere
    * topology, keeps neighbours apart: see separated_neighbours), then the same
    * sequence on k + 2 neighbours; 0 makes none. */
  int base_retries = 2;
  bool check_self_intersections = true;
  bool allow_self_intersections = false;
  PointSmoothing smoothing = PointSmoothing::IfNoisy;
  /** \brief Worker threads; 0 = OpenMP's default team (all cores unless
    * OMP_NUM_THREADS says otherwise). */
  unsigned int num_threads = 0;
  /** \brief Return the allocator's freed memory to the system between stages
    * (releaseFreedMemory): lowers the peak of large clouds, but the heap is the host
    * application's, so it is the caller's choice. */
  bool release_freed_memory = false;
  ProgressCallback progress;
};

/** \brief What one reconstruction did: success or the reason, stage timings, the
  * pipeline's statistics and the check of the result. */
struct ReconstructionReport
{
  bool success = false;
  /** \brief Empty on success; else the cause, naming the parameter to check. */
  std::string message;
  /** \brief Finite input points used (after removing duplicates). */
  std::size_t num_points = 0;
  /** \brief Non-finite points skipped (only possible with is_dense = false); filled by
    * the caller that dropped them (the PCL class). */
  std::size_t num_non_finite = 0;
  /** \brief Exact duplicates merged into the first point at the same position;
    * they stay in the output cloud as unused vertices. */
  std::size_t num_duplicates = 0;
  /** \brief (stage, seconds) in order. */
  std::vector<std::pair<std::string, double>> stage_seconds;
  SpherePipelineStats stats;
  /** \brief Disc topology: inner boundary loops (holes) kept open. */
  std::size_t holes = 0;
  /** \brief Of `holes`, those whose rims the boundary walk missed: cut open where
    * triangles spanned them (meshless::openMissedHoles). */
  std::size_t holes_opened = 0;
  /** \brief The result comes from the second attempt with thin parts separated
    * (the first one intersected itself more). */
  bool thin_sheet_retry = false;
  /** \brief The result comes from rings of each point's near side only
    * (OrderingOptions::max_neighbour_elevation_deg): every base mesh failed on the
    * rings as ordered, or left more intersecting pairs. */
  bool near_side_rings = false;
  /** \brief With near_side_rings: the rings' normals are those of spheres through
    * the points (NormalFit::SphereThroughPoint); the near side's run on weighted
    * planes had failed, turned back or left more pairs. */
  bool near_side_sphere_fit = false;
  /** \brief On a small cloud (at most max_hull_points points) whose points all lie
    * on their convex hull, the pipeline failed or its mesh intersected itself, and
    * the hull is the result (convexHullThroughAll; not optimized). */
  bool convex_hull = false;
  /** \brief Further base meshes tried because the result intersected itself or kept
    * neighbours apart, and whether one of them gave the result (fewer intersecting
    * pairs, or none and no neighbours kept apart). */
  std::size_t base_retries = 0;
  bool base_retry_kept = false;
  /** \brief The k of the neighbourhoods the result came from: the given one; two,
    * three or four times it where the given one's graph fell into pieces of one
    * closed surface; twice it where a closed surface's regions grew only there; twice
    * the k a failed run ended on where it failed in one piece (see
    * setPointSmoothing); two more where folds were left (0 with a search radius). */
  int neighbours_k = 0;
  /** \brief The edge-swap optimization (when enabled). */
  EdgeSwapResult optimization;
  /** \brief Local folds of the raw triangulation, re-meshed away before the
    * optimization (sphere topology with the optimization and the intersection check
    * on, when the raw triangulation intersects itself). */
  FoldRepairResult raw_fold_repair;
  /** \brief Local folds the final check found, re-meshed away where possible
    * (where the repair was tried; see area_against_normals). */
  FoldRepairResult fold_repair;
  /** \brief Share of the mesh's area facing against the cloud's oriented normals,
    * the mesh turned as a whole counting as facing along them
    * (areaFacingAgainstNormals). Closed topologies: on the mesh kept; above
    * max_area_against_normals, with self-intersections, the cloud is rejected as not
    * sphere-like. Disc topology: before the final repair; above it the repair is not
    * tried and a self-intersecting map is refused (it folded over itself). */
  double area_against_normals = 0.0;
  /** \brief Sphere topology: intersecting pairs whose triangles lie more than
    * max_local_fold_hops edges apart (distantIntersectingPairs); any such pair
    * rejects the cloud as not sphere-like. */
  std::size_t distant_intersecting_pairs = 0;
  /** \brief Closed topologies: nearest-neighbour pairs with agreeing normals that
    * the mesh puts more than max_neighbour_hops edges apart
    * (neighboursSeparatedByTheMesh); above max_separated_neighbours, the mesh has
    * cut through a handle (or a part thinner than the spacing) and the cloud is
    * rejected. 0 where it was not counted: disc mode, a convex hull, a failure
    * before the final check. */
  std::size_t separated_neighbours = 0;
  /** \brief The check of the output mesh (valid when the pipeline produced one). */
  MeshReport mesh;
  /** \brief How far the points lie off the surfaces fitted to them: the fit the mesh
    * runs through (or the last one tried), where PointSmoothing asked for one (after
    * a failed run, or always); else zero. */
  PointNoise noise;
  /** \brief The mesh runs through the points' projections onto those surfaces
    * (Reconstruction::smoothed_points), not through the points as given. */
  bool smoothed = false;
};

/** \brief Share of area facing against the cloud's normals above which a
  * self-intersecting closed result means the cloud is not sphere-like (genus-0
  * clouds stay far below it; a handle or a boundary turns a large part back), and
  * an open surface's map has folded over itself. Above it no fold repair is tried. */
constexpr double max_area_against_normals = 0.08;
/** \brief Edge distance up to which two intersecting triangles count as a local fold
  * rather than the surface passing through itself. */
constexpr std::size_t max_local_fold_hops = 16;
/** \brief Edge distance up to which a closed mesh may put two nearest neighbours
  * on one side of the surface (neighboursSeparatedByTheMesh). */
constexpr std::size_t max_neighbour_hops = 16;
/** \brief Neighbour pairs a closed mesh may put far apart (separated_neighbours)
  * and still count as faithful: genus-0 results measured leave none, a handle cut
  * and capped leaves a loop of them around its tube. */
constexpr std::size_t max_separated_neighbours = 8;
/** \brief Clouds up to this size whose pipeline fails or leaves intersecting pairs
  * get their convex hull if every point lies on it. */
constexpr std::size_t max_hull_points = 100;

/** \brief The points as the pipeline numbers them. */
struct PreparedPoints
{
  /** \brief Centred on `centroid` (double precision keeps clouds far from the origin
    * accurate) and ordered along a Z-order curve, so that neighbours in space are
    * mostly neighbours in memory. */
  Points3 points;
  /** \brief Pipeline point i is input point cloud_indices[i]. */
  pcl::Indices cloud_indices;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
  /** \brief Exact duplicates dropped (the first of equal points is kept). */
  std::size_t num_duplicates = 0;
  /** \brief Each dropped duplicate: its input index and the pipeline index of the
    * point it repeats. */
  std::vector<std::pair<pcl::index_t, pcl::index_t>> duplicates;
};

/** \brief Drops exact duplicates, centres and orders the points.
  * \param[in] xyz the finite input points
  * \param[in] cloud_indices their input indices, ascending and distinct
  */
PreparedPoints
preparePoints (const std::vector<Eigen::Vector3f>& xyz, const pcl::Indices& cloud_indices);

/** \brief Empty if the options are usable, else the cause naming the setter. */
std::string
checkOptions (const ReconstructionOptions& options);

/** \brief Neighbourhoods N(v) of the prepared points for k nearest neighbours (or the
  * options' radius): the caller's search structure, asked again with k + 2 by the
  * retries. */
using NeighbourSearch = std::function<Neighbourhoods (int k)>;

/** \brief A reconstruction's triangles over the prepared points, and its report. */
struct Reconstruction
{
  Triangles triangles;
  ReconstructionReport report;
  /** \brief Where report.smoothed: the positions of the prepared points the triangles
    * run through, centred like PreparedPoints::points; else empty. */
  Points3 smoothed_points;
};

/** \brief The closed (or disc) triangulation through the prepared points: the
  * pipeline, the optimization, the check of the result and the retry policy.
  * On failure the report says why and the triangles are empty.
  */
Reconstruction
reconstruct (const PreparedPoints& prepared,
             const NeighbourSearch& search,
             const ReconstructionOptions& options);

} // namespace meshless
} // namespace pcl
