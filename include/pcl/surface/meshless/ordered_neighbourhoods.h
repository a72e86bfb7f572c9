/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

namespace pcl {
namespace meshless {

/** \brief How a neighbourhood is brought into a plane before it is ordered (§2). */
enum class LocalPlane
{
  /** Least-squares plane of {v} and N(v); v and N(v) projected orthogonally into it
    * (the paper's main variant; the plane is the one pcl::NormalEstimation fits). */
  ProjectOntoFit,
  /** Least-squares plane of N(v) moved through v; each neighbour rotated about v
    * into it, so that its distance to v is kept (Gopi et al.). */
  RotateIntoFit
};

/** \brief What the normal of a point's ring is fitted to. */
enum class NormalFit
{
  /** The plane of least squares (the one pcl::NormalEstimation fits). */
  Plane,
  /** A sphere through the point (sphereThroughPointNormal). Around a part only a few
    * points around, a plane fitted to the neighbourhood takes the part's slice; a
    * sphere bends with the part and keeps its tangent plane. The sphere passes
    * through v whatever LocalPlane says (which then only chooses projection or
    * rotation); fits to fewer than min_points_for_sphere_fit neighbours take the
    * plane: three and v always lie on one sphere, and four leave one to spare. */
  SphereThroughPoint
};

/** \brief The fewest neighbours a sphere is fitted to (NormalFit::SphereThroughPoint). */
constexpr int min_points_for_sphere_fit = 5;

struct OrderingOptions
{
  /** \brief Default: LocalPlane::ProjectOntoFit. */
  LocalPlane plane = LocalPlane::ProjectOntoFit;
  /** \brief Neighbours seen from v more steeply than this (degrees, 0..90) above or
    * below the plane fitted to the whole neighbourhood are left out of v's ring, and
    * the plane is fitted again to the rest; where fewer than four remain, or they fit
    * no plane, every neighbour is kept. Where a part is only a few point spacings
    * around (a limb), the neighbourhood reaches its far side, whose points project
    * between the near ones and fold the ring. Default 90: all kept. */
  double max_neighbour_elevation_deg = 90.0;
  /** \brief Width of Gaussian weights on the plane fits (weightedLeastSquaresNormal:
    * the first over the candidates, the refit over those kept), in units of the
    * mean distance from v to its six nearest of the points fitted. Around a part a
    * few point spacings across, an unweighted plane through the whole
    * neighbourhood can stand across the part; weights that fall off within a
    * spacing fit the near side. 0 or less: unweighted, as pcl::NormalEstimation
    * (leastSquaresNormal). Default 0. */
  double plane_weight_width = 0.0;
  /** \brief What the normals (the fit and the refit) are fitted to, with the
    * weights of plane_weight_width. Default NormalFit::Plane. */
  NormalFit normal_fit = NormalFit::Plane;
  /** \brief Threads ordering the rings (0 = all cores). The rings do not depend on
    * it. Default 0. */
  int num_threads = 0;
};

/** \brief Delaunay-ordered neighbourhoods N'(v) of every point. */
struct OrderedNeighbourhoods : StageStatus
{
  /** \brief Row v: the neighbours of v that are joined to v in the Delaunay
    * triangulation of the projected neighbourhood, counter-clockwise around
    * normals[v]. */
  CsrGraph rings;
  /** \brief Unit normal of the plane each neighbourhood was ordered in. Its sign is
    * arbitrary (the ring order is counter-clockwise around this sign). */
  std::vector<Eigen::Vector3f> normals;
  /** \brief Largest angle (radians) between consecutive ring members around v;
    * at least pi when v lies on the convex hull of its projected neighbourhood
    * (a boundary point of an open surface, or an uneven neighbourhood), 2 pi for
    * rings of fewer than two members. */
  std::vector<float> largest_gap;
};

/** \brief Unit normal of the least-squares plane of the given points, computed the
  * way pcl::NormalEstimation does (centroid, covariance, pcl::solvePlaneParameters).
  * \param[in] points the cloud
  * \param[in] centre a point whose position is subtracted first (for precision)
  * \param[in] begin,end indices of the points to fit
  * \param[in] include_centre whether `centre` itself takes part in the fit
  * \return the unit normal, or zero if fewer than three points were given
  */
Eigen::Vector3d
leastSquaresNormal (const Points3& points,
                    pcl::index_t centre,
                    const pcl::index_t* begin,
                    const pcl::index_t* end,
                    bool include_centre);

/** \brief Unit normal of the plane fitted to v and the given points with Gaussian
  * weights: a point at distance d from v counts exp (-(d / (width * mean))^2), with
  * mean the mean distance from v to its six nearest among them; v itself, if it
  * takes part, counts 1. The eigenvector is taken as in leastSquaresNormal.
  * \return the unit normal, or zero if fewer than three points are given (v
  *         included if it takes part), width is not positive, the six nearest
  *         coincide with v, or the width times their distance is not finite
  */
Eigen::Vector3d
weightedLeastSquaresNormal (const Points3& points,
                            pcl::index_t centre,
                            const pcl::index_t* begin,
                            const pcl::index_t* end,
                            bool include_centre,
                            double width);

/** \brief Unit normal at v of the sphere (or plane) through v fitted to the given
  * points by algebraic distance: the smallest eigenvector of M - m m^T / s, with M,
  * m and s the weighted sums of d d^T, |d|^2 d and |d|^4 over the points' offsets d
  * from v. Weighted as weightedLeastSquaresNormal when width is positive, evenly
  * otherwise.
  * \return the unit normal, or zero if fewer than three points are given or they
  *         coincide with v
  */
Eigen::Vector3d
sphereThroughPointNormal (const Points3& points,
                          pcl::index_t centre,
                          const pcl::index_t* begin,
                          const pcl::index_t* end,
                          double width);

/** \brief Coordinates of the neighbours of v in the plane through v with the given
  * normal, relative to v, in a right-handed frame (e1, e2, normal).
  * \param[out] local  one 2D point per neighbour, in the order given
  */
void
localCoordinates (const Points3& points,
                  pcl::index_t v,
                  const pcl::index_t* begin,
                  const pcl::index_t* end,
                  const Eigen::Vector3d& normal,
                  LocalPlane plane,
                  Points2& local);

/** \brief The Delaunay neighbours of the origin among 2D points: the points whose
  * Voronoi cell shares an edge of positive length with the origin's cell in the
  * Voronoi diagram of {0} and the points.
  * \param[in] local 2D points (none at the origin takes part)
  * \param[out] ring positions into `local` of the Delaunay neighbours,
  *             counter-clockwise by angle starting from the positive x axis
  * \return the largest angular gap between consecutive ring members (radians)
  */
double
delaunayRing (const Points2& local, std::vector<int>& ring);

/** \brief Delaunay-order the neighbourhood of every point (paper §2).
  * \param[in] points n points
  * \param[in] candidates for each point the unordered neighbours to order (usually
  *            the symmetric graph G)
  */
OrderedNeighbourhoods
orderNeighbourhoods (const Points3& points,
                     const CsrGraph& candidates,
                     const OrderingOptions& options = {});

} // namespace meshless
} // namespace pcl
