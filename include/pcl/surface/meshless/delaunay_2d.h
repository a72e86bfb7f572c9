/*
 * Software License Agreement (BSD License)
 *
 *  pcl_spherical_meshless: meshless triangulation of point clouds with spherical
 *  topology (Hormann and Reimers 2003) for the Point Cloud Library.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

/** \file
  * \brief Robust 2D Delaunay triangulation of parameter points.
  *
  * The parameter points of a meshless parameterization cluster extremely: radii like
  * exp(-25 U) put neighbouring points 1e-11 apart and closer inside the unit disc,
  * where floating-point orientation and incircle tests give wrong, even mutually
  * contradictory, answers. The design therefore makes every geometric decision exact:
  *
  * - <b>Snapping.</b> Coordinates are mapped to integers X = round(x 2^e), with 2^e the
  *   largest power of two for which max |coordinate| 2^e < 2^120. A power of two keeps
  *   the map exact: every coordinate whose magnitude is at least 2^-67 of the largest
  *   one is already a multiple of the grid spacing 2^-e (at most 2^-119 times the
  *   largest magnitude) and is represented without error. Only smaller coordinates are
  *   rounded, by at most half a grid spacing, i.e. about 4e-37 for points in the unit
  *   disc. A 64-bit grid (spacing 1e-18) would not do: with a million points at radii
  *   exp(-25 U) neighbours come within 1e-15, and rounding them by 1e-18 was measured
  *   to change Delaunay decisions of the input points; at exp(-35 U) it merged distinct
  *   points and flipped triangles. The grid is anchored at the origin rather than at
  *   the bounding box because far from the origin the input doubles themselves are
  *   coarser than the grid, so centring would gain nothing.
  * - <b>Duplicates.</b> Points that snap to the same grid node are one vertex.
  *   Identical points always do; distinct points only if, in each coordinate in which
  *   they differ, both values are below 2^-67 of the largest magnitude and closer than
  *   the grid spacing. Every such point is reported in Delaunay2DResult::duplicate_of
  *   against the smallest input index at its node, which is the one used in the
  *   triangulation.
  * - <b>Exact predicates.</b> The grid coordinates are stored as doubles, which hold
  *   them exactly: each is the scaled input coordinate or, if that was rounded, an
  *   integer below 2^53. With |X| < 2^120 the orientation determinant needs 243 bits
  *   and the incircle determinant 488. Both are evaluated in double precision with a
  *   forward error bound and recomputed in 256- and 512-bit integers only when the sign
  *   is not certain (collinear or nearly cocircular points, e.g. in a regular grid).
  * - <b>Algorithm.</b> Bowyer-Watson insertion into a triangulation of the whole plane
  *   closed by a symbolic infinite vertex: every hull edge carries a "ghost" triangle
  *   to that vertex, so points outside the hull are inserted like any other and the
  *   hull is exact (no super-triangle whose far vertices could bend it). A point
  *   conflicts with a triangle when it lies strictly inside its circumcircle, and with
  *   a ghost when it lies strictly outside the hull edge or strictly inside that edge.
  *   Strictness makes cocircular points harmless (any diagonal is Delaunay), and the
  *   two conflict rules together split hull edges at points lying on them, so collinear
  *   hull points become hull vertices. Points are inserted in a biased randomized
  *   insertion order (BRIO): rounds of doubling size, each sorted along a Hilbert curve
  *   whose cells split at medians, which adapts to any clustering. Each point is
  *   located by a stochastic visibility walk from the previous insertion, which thanks
  *   to the order takes a few steps on average.
  *
  * The result is exactly the Delaunay triangulation of the snapped points, and hence
  * of the input points wherever snapping is exact. Memory is linear in the number of
  * points.
  */
namespace pcl {
namespace meshless {

/** \brief Options of delaunay2D(). */
struct Delaunay2DOptions
{
  /** \brief Seed of the random part of the insertion order (default 1).
    *
    * The Delaunay triangulation is unique unless four or more points are cocircular;
    * only then does the seed decide which of the equally valid diagonals are chosen.
    */
  std::uint32_t random_seed = 1;
};

/** \brief Result of delaunay2D(). On failure only `success` and `message` are set. */
struct Delaunay2DResult : StageStatus
{
  /** \brief Counter-clockwise triangles as indices into the input points; their union
    * is the convex hull and they do not overlap. Duplicates are left out.
    */
  Triangles triangles;
  /** \brief Convex hull vertices in counter-clockwise order, including points lying on
    * hull edges, starting at the lowest of the leftmost points.
    */
  std::vector<pcl::index_t> hull;
  /** \brief Per input point: -1, or the index of the earlier point at the same grid
    * node that represents it in the triangulation (see the file documentation).
    */
  std::vector<pcl::index_t> duplicate_of;
  /** \brief Number of entries of duplicate_of that are not -1. */
  std::size_t num_duplicates = 0;
  /** \brief Spacing of the snapping grid in input units. */
  double grid_spacing = 0.0;
};

/** \brief Delaunay triangulation of 2D points with exact predicates.
  *
  * With n distinct points of which h lie on the convex hull boundary (vertices or on
  * hull edges), every distinct point is a vertex and there are exactly 2n - 2 - h
  * triangles. Fails if a coordinate is not finite or if there are no three
  * non-collinear points.
  *
  * \param[in] points the points; at most 357913941 (six indices per point must fit
  *   pcl::index_t's 32 bits)
  * \param[in] options see Delaunay2DOptions
  * \return triangles, hull and duplicates, or the reason of the failure
  */
Delaunay2DResult delaunay2D (const Points2& points,
                             const Delaunay2DOptions& options = {});

} // namespace meshless
} // namespace pcl
