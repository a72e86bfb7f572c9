/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/Vertices.h>
#include <pcl/surface/meshless/base_mesh.h>
#include <pcl/surface/meshless/convex_hull.h>
#include <pcl/surface/meshless/disc_pipeline.h>
#include <pcl/surface/meshless/edge_swap.h>
#include <pcl/surface/meshless/fold_repair.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <pcl/surface/meshless/spatial_order.h>
#include <pcl/surface/meshless/sphere_pipeline.h>
#include <pcl/surface/meshless/weights.h>
#include <pcl/surface/reconstruction.h>

#include <string>
#include <utility>
#include <vector>

namespace pcl {

/** \brief What the last reconstruct() call did: success or the reason, stage
  * timings, the pipeline's statistics and the check of the result. */
struct SphericalMeshlessReport
{
  bool success = false;
  /** \brief Empty on success; else the cause, naming the parameter to check. */
  std::string message;
  /** \brief Finite input points used (after removing duplicates). */
  std::size_t num_points = 0;
  /** \brief Non-finite points skipped (only possible with is_dense = false). */
  std::size_t num_non_finite = 0;
  /** \brief Exact duplicates merged into the first point at the same position;
    * they stay in the output cloud as unused vertices. */
  std::size_t num_duplicates = 0;
  /** \brief (stage, seconds) in order. */
  std::vector<std::pair<std::string, double>> stage_seconds;
  meshless::SpherePipelineStats stats;
  /** \brief Disc topology: inner boundary loops (holes) kept open. */
  std::size_t holes = 0;
  /** \brief The result comes from the second attempt with thin parts separated
    * (the first one intersected itself more). */
  bool thin_sheet_retry = false;
  /** \brief On a small cloud (at most
    * SphericalMeshlessReconstruction::max_hull_points points) whose points all lie
    * on their convex hull, the pipeline failed or its mesh intersected itself, and
    * the hull is the result (meshless::convexHullThroughAll; not optimized). */
  bool convex_hull = false;
  /** \brief Further base meshes tried because the result intersected itself, and
    * whether one of them gave the result (fewer intersecting pairs). */
  std::size_t base_retries = 0;
  bool base_retry_kept = false;
  /** \brief The k of the neighbourhoods the result came from: the given one, or
    * two more where folds were left with it (0 with a search radius). */
  int neighbours_k = 0;
  /** \brief The edge-swap optimization (when enabled). */
  meshless::EdgeSwapResult optimization;
  /** \brief Local folds of the raw triangulation, re-meshed away before the
    * optimization (meshless::repairFoldsByReinsertion; sphere topology with the
    * optimization and the intersection check on, when the raw triangulation
    * intersects itself). */
  meshless::FoldRepairResult raw_fold_repair;
  /** \brief Local folds the check found, re-meshed away where possible
    * (meshless::repairFoldsByReinsertion; runs when the output intersects itself). */
  meshless::FoldRepairResult fold_repair;
  /** \brief Sphere topology: share of the mesh's area facing against the cloud's
    * oriented normals (meshless::areaFacingAgainstNormals); above
    * SphericalMeshlessReconstruction::max_area_against_normals, with
    * self-intersections, the cloud is rejected as
    * not sphere-like. */
  double area_against_normals = 0.0;
  /** \brief Sphere topology: intersecting pairs of the output whose triangles lie
    * more than SphericalMeshlessReconstruction::max_local_fold_hops edges apart
    * (meshless::distantIntersectingPairs); any such pair rejects the cloud as not
    * sphere-like. */
  std::size_t distant_intersecting_pairs = 0;
  /** \brief The check of the output mesh (valid when the pipeline produced one). */
  meshless::MeshReport mesh;
};

/** \brief Closed, manifold, consistently oriented genus-0 triangulation through
  * every point of a cloud sampled from a sphere-like object.
  *
  * Implements K. Hormann and M. Reimers, "Triangulating Point Clouds with Spherical
  * Topology" (Curve and Surface Design: Saint-Malo 2002), which extends Floater and
  * Reimers' meshless parameterization: neighbourhoods from the search method,
  * convex-combination weights on Delaunay-ordered neighbourhoods, a base
  * tetrahedron (by default an octahedron above 500,000 points, see
  * setBasePolyhedron) whose edges become shortest paths that cut the cloud into disc
  * patches, one sparse linear solve and one exact 2D Delaunay triangulation per
  * patch, merged into one closed triangulation.
  *
  * For n distinct points the result has exactly 2n - 4 triangles, every point is a
  * vertex, every edge is shared by two triangles used in opposite directions, one
  * component, Euler characteristic 2, normals pointing outward. The class checks
  * these invariants on its own result; if they do not hold (or a stage fails) it
  * logs PCL_ERROR with the cause and returns an empty mesh. Self-intersecting
  * triangle pairs are counted too (getReport().mesh.self_intersecting_pairs; unless
  * setCheckSelfIntersections (false)), folds re-meshed, and in sphere mode further
  * base meshes and denser neighbourhoods tried; if pairs still remain the
  * reconstruction fails the same way, naming their number, unless
  * setAllowSelfIntersections (true) asks for such a mesh (returned with PCL_WARN:
  * the topology is guaranteed, the embedding of noisy or too thin parts is not).
  * A cloud that is not sphere-like (a handle, an open surface) is rejected when the
  * closed mesh through it intersects itself and either faces against the cloud's
  * oriented normals over more than max_area_against_normals of its area or passes
  * through itself between parts of the surface far apart on the mesh (more than
  * max_local_fold_hops edges); the pairs left otherwise are local folds.
  *
  * Exact duplicate points are merged (the first one is used; the others remain in
  * the output cloud as unused vertices). Non-finite points are skipped.
  *
  * With setTopology (Topology::Disc) the class reconstructs an open surface (a
  * partial scan, a face, terrain) instead: one boundary loop is found from the
  * points' Delaunay rings, mapped to a circle, and the whole cloud is one patch.
  * The result is one manifold, consistently oriented disc through every point
  * (self-intersections refused as above).
  * Inner boundary loops (holes) are kept open when they can be cut out cleanly;
  * otherwise the reconstruction stops with a message saying so.
  *
  * \note Surfaces of higher genus are not sphere-like: the class rejects them as
  *       described above, or (if the closed mesh happens not to intersect itself)
  *       returns a valid genus-0 mesh through their points.
  * \ingroup surface
  */
template <typename PointInT>
class SphericalMeshlessReconstruction : public MeshConstruction<PointInT>
{
public:
  /** \brief Share of area facing against the cloud's normals above which a
    * self-intersecting closed result means the cloud is not sphere-like (measured:
    * genus-0 clouds at most 2.5%, a torus 43%, fertility 30%, an open face 16%). */
  static constexpr double max_area_against_normals = 0.08;
  /** \brief Edge distance up to which two intersecting triangles count as a local
    * fold rather than the surface passing through itself. Measured after
    * optimization: genus-0 clouds' pairs at most 2 edges apart (clean) and 12 (the
    * layered bunny_rawscans_merged10, at most 8); rocker_arm (genus 1): 91 of its
    * 140 pairs more than 32 edges apart. */
  static constexpr std::size_t max_local_fold_hops = 16;
  /** \brief Clouds up to this size whose pipeline fails or leaves intersecting
    * pairs get their convex hull if every point lies on it (see
    * SphericalMeshlessReport::convex_hull). */
  static constexpr std::size_t max_hull_points = 100;

  using Ptr = shared_ptr<SphericalMeshlessReconstruction<PointInT>>;
  using ConstPtr = shared_ptr<const SphericalMeshlessReconstruction<PointInT>>;

  using MeshConstruction<PointInT>::input_;
  using MeshConstruction<PointInT>::indices_;
  using MeshConstruction<PointInT>::tree_;

  /** \brief The topology of the surface the cloud samples. */
  enum class Topology
  {
    Sphere, ///< closed, genus 0 (default)
    Disc    ///< open, one outer boundary (holes kept open where possible)
  };
  using WeightType = meshless::WeightType;
  using BasePolyhedron = meshless::BasePolyhedron;
  using ProgressCallback = meshless::ProgressCallback;

  SphericalMeshlessReconstruction () = default;
  ~SphericalMeshlessReconstruction () override = default;

  /** \brief Number of nearest neighbours k of each point (paper: about 10-12).
    * \param[in] k at least 3; default 12. Used when the search radius is 0. */
  inline void
  setNumberOfNeighbours (int k)
  {
    k_ = k;
  }
  inline int
  getNumberOfNeighbours () const
  {
    return k_;
  }

  /** \brief Ball neighbourhoods of this radius instead of k nearest neighbours.
    * \param[in] radius in the cloud's units; 0 (default) selects k nearest. */
  inline void
  setSearchRadius (double radius)
  {
    radius_ = radius;
  }
  inline double
  getSearchRadius () const
  {
    return radius_;
  }

  /** \brief Closed sphere-like object (default) or open disc-like surface. */
  inline void
  setTopology (Topology topology)
  {
    topology_ = topology;
  }
  inline Topology
  getTopology () const
  {
    return topology_;
  }

  /** \brief Convex-combination weights. Default: WeightType::MeanValue. */
  inline void
  setWeightType (WeightType type)
  {
    weights_ = type;
  }
  inline WeightType
  getWeightType () const
  {
    return weights_;
  }

  /** \brief The regular polyhedron whose directions pick the base mesh D.
    * Default: BasePolyhedron::BySize, the tetrahedron (the paper's) up to 500,000
    * points and the octahedron above, whose smaller patches need less memory (see
    * meshless::polyhedronForSize). More faces give shorter paths and smaller, less
    * distorted patches, and more corners that may land in thin parts. */
  inline void
  setBasePolyhedron (BasePolyhedron polyhedron)
  {
    polyhedron_ = polyhedron;
  }
  inline BasePolyhedron
  getBasePolyhedron () const
  {
    return polyhedron_;
  }

  /** \brief A user base mesh of sphere topology (paper §5) instead of a polyhedron.
    * \param[in] vertices indices into the input cloud
    * \param[in] faces triangles over positions into `vertices`, counter-clockwise
    *            seen from outside
    * \note validated at reconstruct(); an invalid mesh is an error. Pass empty
    *       arrays to go back to the polyhedron. */
  void
  setBaseMesh (const pcl::Indices& vertices, const std::vector<pcl::Vertices>& faces)
  {
    base_vertices_ = vertices;
    base_faces_ = faces;
  }

  /** \brief Optimize the raw triangulation by edge swaps (Dyn, Hormann, Kim and
    * Levin 2001): lower discrete curvature, fewer folds and intersections, better
    * angles. Swaps move no vertex, so every topological promise is kept. In sphere
    * topology with the intersection check on, the raw triangulation's folds are
    * re-meshed first (SphericalMeshlessReport::raw_fold_repair), the same repair a run
    * without optimization makes after its check. Default true. */
  inline void
  setOptimize (bool optimize)
  {
    optimize_ = optimize;
  }
  inline bool
  getOptimize () const
  {
    return optimize_;
  }

  /** \brief Options of the edge-swap optimization (cost function, fold bound). */
  inline void
  setOptimizationOptions (const meshless::EdgeSwapOptions& options)
  {
    swap_options_ = options;
  }
  inline const meshless::EdgeSwapOptions&
  getOptimizationOptions () const
  {
    return swap_options_;
  }

  /** \brief Called after each stage with its timing; return false to cancel. */
  inline void
  setProgressCallback (ProgressCallback callback)
  {
    progress_ = std::move (callback);
  }

  /** \brief Sphere topology: how many further base meshes (the next rotations and
    * polyhedra) to try when the result still intersects itself after the swaps and
    * the repair; the result with the fewest intersecting pairs is kept. If pairs
    * remain, the whole sequence runs once more on k + 2 nearest neighbours (not
    * with a search radius; getReport ().neighbours_k says which k the result came
    * from). Each try costs about one more run, and only runs with pairs left make
    * them. 0 makes none of them; ignored with a user base mesh. Default 2. */
  inline void
  setBaseRetries (int retries)
  {
    base_retries_ = retries;
  }
  inline int
  getBaseRetries () const
  {
    return base_retries_;
  }

  /** \brief Whether the output check counts self-intersecting triangle pairs
    * (default true; costs about as much as one stage). Off, nothing is counted, so
    * no fold is repaired (before or after the swaps) and no retry is made. */
  inline void
  setCheckSelfIntersections (bool check)
  {
    check_self_intersections_ = check;
  }
  inline bool
  getCheckSelfIntersections () const
  {
    return check_self_intersections_;
  }

  /** \brief Whether a mesh whose triangles still intersect each other in local
    * folds, after the repair and the retries, is returned (with PCL_WARN and the
    * count in getReport ()) rather than refused. Default false: with the check on
    * (setCheckSelfIntersections, the default) a success is then free of
    * self-intersections too. The folds that remain come from parts thinner than
    * the point spacing or from noise; a viewer or a volume estimate may well live
    * with a few. Without setCheckSelfIntersections nothing is counted, and nothing
    * refused. */
  inline void
  setAllowSelfIntersections (bool allow)
  {
    allow_self_intersections_ = allow;
  }
  inline bool
  getAllowSelfIntersections () const
  {
    return allow_self_intersections_;
  }

  /** \brief Reconstruct a mesh over the input cloud (all of it, as
    * MeshConstruction does); see the class description.
    * \note The input and the indices are checked before anything else: no input
    *       cloud or an index outside it gives PCL_ERROR and an empty mesh. */
  void
  reconstruct (pcl::PolygonMesh& output) override;

  /** \brief Reconstruct the triangles only, as indices into the input cloud. */
  void
  reconstruct (std::vector<pcl::Vertices>& polygons) override;

  /** \brief What the last reconstruct() did. */
  inline const SphericalMeshlessReport&
  getReport () const
  {
    return report_;
  }

protected:
  std::string
  getClassName () const override
  {
    return "SphericalMeshlessReconstruction";
  }

  void
  performReconstruction (pcl::PolygonMesh& output) override;

  void
  performReconstruction (std::vector<pcl::Vertices>& polygons) override;

private:
  /** \brief False (with report_ and PCL_ERROR saying why) when there is no input
    * cloud or an index lies outside it: checked before PCL's base class builds the
    * search tree over them, which would crash on such indices. */
  bool
  inputIsUsable ();

  /** \brief Runs the pipeline; fills report_ and, on success, polygons over
    * indices of the input cloud. */
  bool
  triangulate (std::vector<pcl::Vertices>& polygons);

  Topology topology_ = Topology::Sphere;
  int k_ = 12;
  double radius_ = 0.0;
  WeightType weights_ = WeightType::MeanValue;
  BasePolyhedron polyhedron_ = BasePolyhedron::BySize;
  pcl::Indices base_vertices_;
  std::vector<pcl::Vertices> base_faces_;
  ProgressCallback progress_;
  bool check_self_intersections_ = true;
  bool allow_self_intersections_ = false;
  bool optimize_ = true;
  meshless::EdgeSwapOptions swap_options_;
  int base_retries_ = 2;
  SphericalMeshlessReport report_;
};

} // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl/surface/impl/spherical_meshless_reconstruction.hpp>
#endif
