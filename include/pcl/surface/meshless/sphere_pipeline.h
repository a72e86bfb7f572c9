/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/base_mesh.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/parameterization.h>
#include <pcl/surface/meshless/patch_flips.h>
#include <pcl/surface/meshless/types.h>
#include <pcl/surface/meshless/weights.h>

#include <functional>

namespace pcl {
namespace meshless {

/** \brief What a long run reports as it goes. */
struct ProgressReport
{
  /** \brief Name of the stage that just finished ("neighbourhoods", "rings", ...). */
  std::string stage;
  /** \brief Share of the whole work done so far, 0 .. 1 (by typical stage cost). */
  double fraction = 0.0;
  /** \brief Wall time the stage took (seconds). */
  double seconds = 0.0;
  /** \brief A short line of what the stage found (sizes, counts). */
  std::string detail;
};

/** \brief Called after each stage; return false to cancel the reconstruction. */
using ProgressCallback = std::function<bool (const ProgressReport&)>;

struct SpherePipelineOptions
{
  /** \brief Default: WeightType::MeanValue. */
  WeightType weights = WeightType::MeanValue;
  /** \brief Base mesh D when no user base mesh is given. Default:
    * BasePolyhedron::BySize, the paper's tetrahedron, or more faces for very large
    * clouds (see polyhedronForSize). */
  BasePolyhedron polyhedron = BasePolyhedron::BySize;
  /** \brief A user base mesh (vertices are indices into the points); used instead
    * of `polyhedron` when it has faces. */
  BaseMesh user_base_mesh;
  /** \brief D grown from the cloud (growBaseMesh) instead of a polyhedron, of the
    * genus the cloud has; a user base mesh may then have any genus too. Default
    * false (sphere topology). */
  bool grown_base_mesh = false;
  /** \brief Before the polyhedra, grow D to find the cloud's genus and stop with a
    * message naming it if the cloud has handles: a genus-0 mesh would span them.
    * Default false. */
  bool refuse_handles = false;
  /** \brief With a grown D: the genus an earlier run found (a retry need not grow
    * D once more to know it); -1 to find it. Default -1. */
  int known_genus = -1;
  /** \brief How many rotations of the polyhedron to try when paths cross or a
    * region cannot be formed. Default 12. */
  int max_base_attempts = 12;
  /** \brief Number of the first attempt (0: the unrotated polyhedron). Attempts are
    * numbered in one deterministic sequence of rotations and polyhedra; a caller
    * that wants a different D than the one a run succeeded with starts after it
    * (SpherePipelineStats::base_attempt + 1). Default 0. */
  int first_attempt = 0;
  /** \brief Whether every second attempt uses the next larger polyhedron
    * (tetrahedron -> octahedron -> icosahedron -> tetrahedron) instead of the next
    * rotation. Default true. */
  bool alternate_polyhedra = true;
  /** \brief How the polyhedron's directions pick the corners of D. Default:
    * CornerPlacement::AlongRays (the paper's farthest points sit on the tips of
    * limbs, where paths find no room). */
  CornerPlacement corners = CornerPlacement::AlongRays;
  /** \brief Drop kNN edges across parts thinner than the point spacing before
    * cutting (see buildSurfaceGraphs). If there is no such edge to drop, the run
    * stops at once with a message (it would repeat a run without them). Default
    * false. */
  bool separate_thin_sheets = false;
  /** \brief Rings without the neighbours seen more steeply than this from the
    * plane of a point's neighbourhood (OrderingOptions). Default 90: all kept. */
  double max_neighbour_elevation_deg = 90.0;
  /** \brief Gaussian weights on the rings' plane fits (OrderingOptions). Default 0:
    * unweighted. */
  double plane_weight_width = 0.0;
  /** \brief The rings' normal fit (OrderingOptions). Default NormalFit::Plane. */
  NormalFit normal_fit = NormalFit::Plane;
  SolveOptions solve;
  /** \brief The edge swaps' angle pass inside each patch, in parallel with the
    * other patches' solves (flipFlatEdgesInPatch). Default: off; the class turns it
    * on when its optimization runs the angle pass. */
  PatchFlipOptions patch_flips;
  /** \brief Return freed memory to the system before the patch solves
    * (releaseFreedMemory). Default false: the heap is the caller's. */
  bool release_freed_memory = false;
  /** \brief Threads for the graphs and the patches (0 = all cores). */
  int num_threads = 0;
  ProgressCallback progress;
};

/** \brief Statistics of a run (for logs, the CLI and benchmarks). */
struct SpherePipelineStats
{
  /** \brief Attempts made in this run. */
  std::size_t base_attempts = 0;
  /** \brief Number of the attempt whose D the result was made with (see
    * SpherePipelineOptions::first_attempt). */
  int base_attempt = 0;
  std::size_t base_faces = 0;
  /** \brief Genus of D, hence of the result: 0 for the polyhedra; for a grown D the
    * genus found from the cloud (-1 if it could not be found). */
  int genus = 0;
  std::size_t path_points = 0;
  std::size_t largest_patch = 0;
  std::size_t side_conflicts = 0;
  std::size_t reassigned = 0;
  std::size_t repair_flips = 0;
  std::size_t normals_flipped = 0;
  /** \brief Edges across parts thinner than the point spacing: dropped (with
    * separate_thin_sheets), or that a run with it would drop (without). */
  std::size_t thin_part_edges = 0;
  std::size_t weight_fallbacks = 0;
  double smallest_parameter_edge = 0.0;
  /** \brief Edges flipped inside the patches (SpherePipelineOptions::patch_flips). */
  std::size_t patch_flips = 0;
  /** \brief Times the rings and the mutual graph were built again for a next
    * attempt: they are released before the patch solves (for the peak memory) and
    * rebuilt when a patch or the merge fails. */
  std::size_t rebuilds = 0;
  /** \brief Connected components of the neighbourhood graph (more than one: the
    * run failed before any base mesh). */
  std::size_t graph_pieces = 0;
};

struct SphereTriangulation : StageStatus
{
  /** \brief 2n - 4 + 4g triangles (g = stats.genus), outward oriented, over the
    * point indices. */
  Triangles triangles;
  /** \brief The points' least-squares normals, oriented outward (the triangles'
    * orientation follows them). */
  std::vector<Eigen::Vector3f> normals;
  SpherePipelineStats stats;
};

/** \brief §3-§4 after the neighbourhood search: the symmetric graph, rings and
  * orientation, weights, base mesh, cut paths, patch split, one meshless
  * parameterization and Delaunay triangulation per patch, merge.
  * \param[in] points n distinct points
  * \param[in] neighbourhoods directed neighbourhoods N(v) (from searchNeighbourhoods)
  * \return the closed triangulation, or the reason it could not be built. The
  *         caller checks the result's invariants (checkMesh).
  */
SphereTriangulation
triangulateSphere (const Points3& points,
                   const CsrGraph& neighbourhoods,
                   const SpherePipelineOptions& options = {});

} // namespace meshless
} // namespace pcl
