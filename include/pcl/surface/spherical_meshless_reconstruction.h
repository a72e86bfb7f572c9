/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/Vertices.h>
#include <pcl/surface/meshless/reconstruct.h>
#include <pcl/surface/reconstruction.h>

#include <string>
#include <utility>
#include <vector>

namespace pcl {

/** \brief What the last reconstruct() call did: success or the reason, stage
  * timings, the pipeline's statistics and the check of the result. */
using SphericalMeshlessReport = meshless::ReconstructionReport;

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
  * component, Euler characteristic 2, normals pointing outward. With
  * setTopology (Topology::Closed) the genus g is found from the cloud (base meshes
  * grown from it, paper §5) and the result has 2n - 4 + 4g triangles and Euler
  * characteristic 2 - 2g (getReport ().stats.genus). The class checks
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
  * Noise about as large as the point spacing can fail every base mesh. In the
  * closed topologies the class then measures it and, where it is that large, runs
  * again on the points projected onto quadratic surfaces fitted to their
  * neighbours (setPointSmoothing): the mesh then runs through those projections,
  * one per point with the point's index, written into the output cloud and
  * getVertexCloud (), and getReport ().smoothed says so.
  *
  * With setTopology (Topology::Disc) the class reconstructs an open surface (a
  * partial scan, a face, terrain) instead: one boundary loop is found from the
  * points' Delaunay rings, mapped to a circle, and the whole cloud is one patch.
  * The result is one manifold, consistently oriented disc through every point
  * (self-intersections refused as above).
  * Inner boundary loops (holes) are kept open when they can be cut out cleanly;
  * otherwise the reconstruction stops with a message saying so.
  *
  * \note In the sphere topology a cloud that clearly has handles is refused with a
  *       message naming its genus; a handle the grown regions cannot see at the
  *       sampling and that leaves no fold gives a genus-0 mesh through the points.
  * \ingroup surface
  */
template <typename PointInT>
class SphericalMeshlessReconstruction : public MeshConstruction<PointInT>
{
public:
  /** \brief See meshless::max_area_against_normals. */
  static constexpr double max_area_against_normals = meshless::max_area_against_normals;
  /** \brief See meshless::max_local_fold_hops. */
  static constexpr std::size_t max_local_fold_hops = meshless::max_local_fold_hops;
  /** \brief See meshless::max_hull_points. */
  static constexpr std::size_t max_hull_points = meshless::max_hull_points;

  using Ptr = shared_ptr<SphericalMeshlessReconstruction<PointInT>>;
  using ConstPtr = shared_ptr<const SphericalMeshlessReconstruction<PointInT>>;

  using MeshConstruction<PointInT>::input_;
  using MeshConstruction<PointInT>::indices_;
  using MeshConstruction<PointInT>::tree_;

  /** \brief The topology of the surface the cloud samples: Sphere (closed, genus 0,
    * the default) or Disc (open, one outer boundary; holes kept open where possible). */
  using Topology = meshless::Topology;
  using WeightType = meshless::WeightType;
  using BasePolyhedron = meshless::BasePolyhedron;
  using ProgressCallback = meshless::ProgressCallback;
  using PointSmoothing = meshless::PointSmoothing;

  SphericalMeshlessReconstruction () = default;
  ~SphericalMeshlessReconstruction () override = default;

  /** \brief Number of nearest neighbours k of each point (paper: about 10-12).
    * \param[in] k at least 3; default 12. Used when the search radius is 0. */
  inline void
  setNumberOfNeighbours (int k)
  {
    options_.k = k;
  }
  inline int
  getNumberOfNeighbours () const
  {
    return options_.k;
  }

  /** \brief Ball neighbourhoods of this radius instead of k nearest neighbours.
    * \param[in] radius in the cloud's units; 0 (default) selects k nearest. */
  inline void
  setSearchRadius (double radius)
  {
    options_.radius = radius;
  }
  inline double
  getSearchRadius () const
  {
    return options_.radius;
  }

  /** \brief Closed sphere-like object (default), closed object of the genus found
    * in the cloud (Closed), or open disc-like surface (Disc). */
  inline void
  setTopology (Topology topology)
  {
    options_.topology = topology;
  }
  inline Topology
  getTopology () const
  {
    return options_.topology;
  }

  /** \brief Convex-combination weights. Default: WeightType::MeanValue. */
  inline void
  setWeightType (WeightType type)
  {
    options_.weights = type;
  }
  inline WeightType
  getWeightType () const
  {
    return options_.weights;
  }

  /** \brief The regular polyhedron whose directions pick the base mesh D.
    * Default: BasePolyhedron::BySize, the tetrahedron (the paper's) up to 500,000
    * points and the octahedron above, whose smaller patches need less memory (see
    * meshless::polyhedronForSize). More faces give shorter paths and smaller, less
    * distorted patches, and more corners that may land in thin parts. */
  inline void
  setBasePolyhedron (BasePolyhedron polyhedron)
  {
    options_.polyhedron = polyhedron;
  }
  inline BasePolyhedron
  getBasePolyhedron () const
  {
    return options_.polyhedron;
  }

  /** \brief A user base mesh D (paper §5) instead of a polyhedron or a grown D: a
    * closed, consistently oriented manifold, of genus 0 for Topology::Sphere and of
    * any genus for Topology::Closed (the result takes its genus).
    * \param[in] vertices indices into the input cloud
    * \param[in] faces polygons of three or more corners over positions into
    *            `vertices`, counter-clockwise seen from outside; each becomes one
    *            disc patch, its sides cut paths between its corners
    * \note validated at reconstruct(); an invalid mesh, or one whose paths cannot
    *       be routed through the cloud, is an error. Pass empty arrays to go back to
    *       the polyhedron. */
  void
  setBaseMesh (const pcl::Indices& vertices, const std::vector<pcl::Vertices>& faces)
  {
    options_.base_vertices = vertices;
    options_.base_faces = faces;
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
    options_.optimize = optimize;
  }
  inline bool
  getOptimize () const
  {
    return options_.optimize;
  }

  /** \brief Rules of the edge-swap optimization (cost function, fold bound, angle
    * pass, look-ahead); what the swaps need to know of the mesh and the machine the
    * class sets. The disc topology makes no look-ahead: it would re-triangulate gaps
    * whose long edges the cut for missed holes looks for. */
  inline void
  setOptimizationOptions (const meshless::SwapRules& options)
  {
    options_.swaps = options;
  }
  inline const meshless::SwapRules&
  getOptimizationOptions () const
  {
    return options_.swaps;
  }

  /** \brief Called after each stage with its timing; return false to cancel. */
  inline void
  setProgressCallback (ProgressCallback callback)
  {
    options_.progress = std::move (callback);
  }

  /** \brief Sphere topology: how many further base meshes (the next rotations and
    * polyhedra) to try when the result still intersects itself after the swaps and
    * the repair, or keeps neighbours on one side of the surface far apart on the
    * mesh (getReport ().separated_neighbours: a mesh across a part thinner than the
    * spacing); the result with the fewest intersecting pairs is kept. If they
    * remain, the whole sequence runs once more on k + 2 nearest neighbours (not
    * with a search radius; getReport ().neighbours_k says which k the result came
    * from). Each try costs about one more run, and only runs left with pairs or
    * neighbours apart make them. 0 makes none of them; ignored with a user base
    * mesh. Default 2. */
  inline void
  setBaseRetries (int retries)
  {
    options_.base_retries = retries;
  }
  inline int
  getBaseRetries () const
  {
    return options_.base_retries;
  }

  /** \brief Whether the output check counts self-intersecting triangle pairs
    * (default true; costs about as much as one stage). Off, nothing is counted, so
    * no fold is repaired (before or after the swaps) and no retry is made. */
  inline void
  setCheckSelfIntersections (bool check)
  {
    options_.check_self_intersections = check;
  }
  inline bool
  getCheckSelfIntersections () const
  {
    return options_.check_self_intersections;
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
    options_.allow_self_intersections = allow;
  }
  inline bool
  getAllowSelfIntersections () const
  {
    return options_.allow_self_intersections;
  }

  /** \brief Whether the mesh may run through the points moved onto quadratic
    * surfaces fitted to a few dozen neighbours each (PCL's MLS) instead of the points
    * themselves. Default IfNoisy: only where the run on the points fails and they lie
    * more than meshless::min_noise_ratio of their spacing off those surfaces (noise
    * about as large as the spacing); getReport ().smoothed then says so, with a
    * PCL_WARN, and the output cloud holds the moved positions (getVertexCloud ()).
    * In disc mode only up to meshless::max_disc_noise_ratio: noisier, a hole's rim
    * can be missed on the projections. Off: always through the points as given.
    * Always: a smoothed mesh of any cloud, disc mode too.
    * Where the run failed on a graph in one piece and no smoothed run succeeded, the
    * call runs once more at twice the k (getReport ().neighbours_k): closed
    * topologies where every base mesh failed at genus 0, and the sphere topology
    * where the repair left folds too (with IfNoisy or Off); open surfaces only with
    * IfNoisy and noise measured below meshless::min_noise_ratio.
    * Not with Always nor with a search radius. */
  inline void
  setPointSmoothing (PointSmoothing smoothing)
  {
    options_.smoothing = smoothing;
  }
  inline PointSmoothing
  getPointSmoothing () const
  {
    return options_.smoothing;
  }

  /** \brief The points the last reconstruct ()'s triangles run through, indexed as
    * the input: the input cloud itself, or a copy with the moved points' positions
    * where getReport ().smoothed (see setPointSmoothing). Null before a run. */
  inline typename pcl::PointCloud<PointInT>::ConstPtr
  getVertexCloud () const
  {
    return vertex_cloud_;
  }

  /** \brief Worker threads for the stages that run in parallel (neighbour queries,
    * rings, weights, patches, checks, swaps); 0 (default) uses OpenMP's default team,
    * all cores unless OMP_NUM_THREADS says otherwise. On large meshes the output
    * check runs its topology pass on one more thread beside them. The result is the
    * same for every count. No global OpenMP setting is touched. */
  inline void
  setNumberOfThreads (unsigned int nr_threads = 0)
  {
    options_.num_threads = nr_threads;
  }
  inline unsigned int
  getNumberOfThreads () const
  {
    return options_.num_threads;
  }

  /** \brief Return the allocator's freed memory to the operating system between
    * stages (glibc's malloc_trim). Lowers the peak resident memory of large clouds,
    * whose stages free and allocate hundreds of MB; it trims the whole process's
    * heap, which belongs to the host application, so it is off by default (the
    * command-line tool turns it on). */
  inline void
  setReleaseFreedMemory (bool release)
  {
    options_.release_freed_memory = release;
  }
  inline bool
  getReleaseFreedMemory () const
  {
    return options_.release_freed_memory;
  }

  /** \brief Reconstruct a mesh over the input cloud (all of it, as
    * MeshConstruction does); see the class description.
    * \note The input and the indices are checked before anything else: no input
    *       cloud or an index outside it gives PCL_ERROR and an empty mesh. */
  void
  reconstruct (pcl::PolygonMesh& output) override;

  /** \brief Reconstruct the triangles only, as indices into the input cloud; where
    * getReport ().smoothed they run through getVertexCloud ()'s positions, not the
    * input's. */
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

  meshless::ReconstructionOptions options_;
  SphericalMeshlessReport report_;
  typename pcl::PointCloud<PointInT>::ConstPtr vertex_cloud_;
};

} // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl/surface/impl/spherical_meshless_reconstruction.hpp>
#endif
