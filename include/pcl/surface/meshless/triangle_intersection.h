/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <Eigen/Core>

namespace pcl {
namespace meshless {

/** \brief Exact sign of det[b - a, c - a]: +1 if a, b, c turn counter-clockwise, -1
  * if clockwise, 0 if they are collinear (or two of them coincide).
  *
  * The determinant is evaluated in floating point first; its sign is returned when a
  * conservative error bound certifies it. Otherwise the coordinates are converted
  * exactly to integers on a common power-of-two scale and the determinant is
  * evaluated in arbitrary precision. The result is therefore the sign of the exact
  * determinant of the given doubles, for any finite coordinates (no overflow, no
  * underflow issues). Coordinates must be finite.
  */
int
orient2d (const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c);

/** \brief The sign of det[b - a, c - a, d - a] when a floating-point evaluation
  * certifies it, else 0.
  *
  * Positive means d lies on the side the normal of the counter-clockwise triangle
  * a, b, c points to. A non-zero result is always the exact sign; 0 means "not
  * certified" (the exact value may or may not be 0), for callers that can settle
  * most cases without the exact evaluation. Coordinates must be finite.
  */
int
orient3dIfCertain (const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d);

/** \brief Exact sign of det[b - a, c - a, d - a]: +1 if d lies on the side the normal
  * of the counter-clockwise triangle a, b, c points to, -1 on the other side, 0 if the
  * four points are coplanar.
  *
  * orient3dIfCertain first, then an arbitrary-precision evaluation on the exact
  * integer images of the doubles. Exact for any finite coordinates.
  */
int
orient3d (const Eigen::Vector3d& a,
          const Eigen::Vector3d& b,
          const Eigen::Vector3d& c,
          const Eigen::Vector3d& d);

/** \brief The coordinate axis (0, 1 or 2) along which triangle a, b, c projects to a
  * non-degenerate 2D triangle, or -1 if the three points are exactly collinear (then
  * every axis-aligned projection is degenerate).
  *
  * Axes are tried in order of decreasing absolute normal component (ties in index
  * order), so the projection is normally the best conditioned one; the decision
  * whether a projection is degenerate is exact (orient2d). The projection drops the
  * coordinate `axis` and keeps the other two in cyclic order, so the sign of the
  * projected triangle's turn is the sign of the normal's `axis` component.
  *
  * This is the per-triangle precomputation trianglesIntersect needs: compute it once
  * per triangle and pass it with every test of that triangle. -1 marks a degenerate
  * triangle, which trianglesIntersect does not accept. Coordinates must be finite.
  */
int
projectionAxis (const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/** \brief projectionAxis of triangle t over `vertices` (indices must be in range). */
int
projectionAxis (const Points3& vertices, const Triangle& t);

/** \brief Whether the closed triangles s and t, given by indices into `vertices`,
  * intersect beyond what their shared vertex indices entitle them to. Exact.
  *
  * The triangles are closed point sets (boundary included), so touching counts as
  * intersecting. What the indices they share entitle them to:
  * - no shared index: the triangles intersect iff they have any common point, a
  *   touch at a single point included (a vertex on the other's edge or interior, two
  *   edges crossing, coincident vertices with different indices, coplanar overlap).
  * - one shared index v: the common point v is allowed; they intersect iff they have
  *   any other common point, for example one crossing the other's interior, or,
  *   coplanar, their corners at v overlapping beyond v (sectors that only touch at v
  *   do not intersect).
  * - two shared indices u, w: the common edge u-w is allowed; on different planes
  *   the triangles meet exactly in that edge and do not intersect. Coplanar, they
  *   intersect iff their third vertices lie on the same side of the edge (a fold-over,
  *   the faces overlap), regardless of orientation; on opposite sides they do not.
  * - three shared indices: the faces coincide; they intersect.
  *
  * Coplanar configurations are decided exactly, in the projection along axis_s
  * (which is an affine bijection of their common plane). Every geometric decision is
  * taken with orient2d / orient3d, so the answer is the exact one for the given
  * doubles, independent of the axes passed (as long as they are valid) and of the
  * order of s and t; it does not depend on tolerances.
  *
  * Preconditions: every index of s and t is in range of `vertices`; each triangle has
  * three pairwise distinct indices and finite, non-collinear vertices, and axis_s,
  * axis_t are their projectionAxis results (hence >= 0). Exactly degenerate triangles
  * (projectionAxis -1) must be filtered out by the caller. Vertex orientation
  * (counter-clockwise or not) does not matter. Neither prints nor throws.
  */
bool
trianglesIntersect (const Points3& vertices,
                    const Triangle& s,
                    int axis_s,
                    const Triangle& t,
                    int axis_t);

/** \brief trianglesIntersect with the projection axes computed on the fly; false if
  * either triangle is degenerate (a repeated index or exactly collinear vertices), as
  * degenerate triangles are left out of intersection counts. For single tests; loops
  * over many pairs should compute projectionAxis once per triangle. */
bool
trianglesIntersect (const Points3& vertices, const Triangle& s, const Triangle& t);

} // namespace meshless
} // namespace pcl
