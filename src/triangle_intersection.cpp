/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/triangle_intersection.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pcl {
namespace meshless {

namespace {

using Vector2 = Eigen::Vector2d;
using Vector3 = Eigen::Vector3d;
using boost::multiprecision::cpp_int;

// ---------------------------------------------------------------------------
// Orientation predicates: a floating-point evaluation whose sign is trusted only
// when a conservative error bound certifies it, and an exact evaluation otherwise.

constexpr double unit_roundoff = 0x1p-53;
/** Absolute error allowance for products that underflow: each such product is off
  * by at most 2^-1075, and at most one further multiplication scales that error. */
constexpr double underflow_slack = 0x1p-1000;
/** Above this the filter's sums might overflow; the exact path takes over. */
constexpr double filter_limit = 1e300;

/** The doubles x as integers on one common scale, x[i] = result[i] * 2^e for one e.
  * Every finite double is a 53-bit integer times a power of two, so this is exact;
  * scaling the coordinates of one axis by a positive power of two scales an
  * orientation determinant by a positive factor and keeps its sign. */
template <std::size_t N>
std::array<cpp_int, N>
toCommonScale (const std::array<double, N>& x)
{
  std::array<std::uint64_t, N> magnitude;
  std::array<int, N> exponent;
  int smallest = std::numeric_limits<int>::max ();
  for (std::size_t i = 0; i < N; ++i) {
    int e = 0;
    const double fraction = std::frexp (std::abs (x[i]), &e); // in [0.5, 1) or 0
    magnitude[i] = static_cast<std::uint64_t> (std::ldexp (fraction, 53));
    exponent[i] = e - 53;
    if (magnitude[i] != 0)
      smallest = std::min (smallest, exponent[i]);
  }
  std::array<cpp_int, N> result;
  for (std::size_t i = 0; i < N; ++i) {
    if (magnitude[i] == 0)
      continue;
    result[i] = magnitude[i];
    result[i] <<= (exponent[i] - smallest);
    if (x[i] < 0.0)
      result[i] = -result[i];
  }
  return result;
}

int
orient2dExact (const Vector2& a, const Vector2& b, const Vector2& c)
{
  const auto x = toCommonScale<3> ({a.x (), b.x (), c.x ()});
  const auto y = toCommonScale<3> ({a.y (), b.y (), c.y ()});
  const cpp_int det = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
  return det.sign ();
}

int
orient3dExact (const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d)
{
  std::array<std::array<cpp_int, 4>, 3> s;
  for (int k = 0; k < 3; ++k)
    s[k] = toCommonScale<4> ({a[k], b[k], c[k], d[k]});
  const cpp_int ux = s[0][1] - s[0][0], uy = s[1][1] - s[1][0], uz = s[2][1] - s[2][0];
  const cpp_int vx = s[0][2] - s[0][0], vy = s[1][2] - s[1][0], vz = s[2][2] - s[2][0];
  const cpp_int wx = s[0][3] - s[0][0], wy = s[1][3] - s[1][0], wz = s[2][3] - s[2][0];
  const cpp_int det =
      ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
  return det.sign ();
}

} // namespace

int
orient2d (const Vector2& a, const Vector2& b, const Vector2& c)
{
  const double left = (b.x () - a.x ()) * (c.y () - a.y ());
  const double right = (b.y () - a.y ()) * (c.x () - a.x ());
  const double det = left - right;
  const double permanent = std::abs (left) + std::abs (right);
  // Two rounded differences, one product and one subtraction: below 4 units of
  // roundoff relative to the permanent; twice that for margin.
  const double bound = 8.0 * unit_roundoff * permanent + underflow_slack;
  if (permanent < filter_limit && std::abs (det) > bound)
    return det > 0.0 ? 1 : -1;
  return orient2dExact (a, b, c);
}

int
orient3dIfCertain (const Vector3& a,
                   const Vector3& b,
                   const Vector3& c,
                   const Vector3& d)
{
  const double ux = b.x () - a.x (), uy = b.y () - a.y (), uz = b.z () - a.z ();
  const double vx = c.x () - a.x (), vy = c.y () - a.y (), vz = c.z () - a.z ();
  const double wx = d.x () - a.x (), wy = d.y () - a.y (), wz = d.z () - a.z ();
  const double vywz = vy * wz, vzwy = vz * wy;
  const double vzwx = vz * wx, vxwz = vx * wz;
  const double vxwy = vx * wy, vywx = vy * wx;
  const double det = ux * (vywz - vzwy) + uy * (vzwx - vxwz) + uz * (vxwy - vywx);
  const double permanent = std::abs (ux) * (std::abs (vywz) + std::abs (vzwy)) +
                           std::abs (uy) * (std::abs (vzwx) + std::abs (vxwz)) +
                           std::abs (uz) * (std::abs (vxwy) + std::abs (vywx));
  // Each term passes through at most 8 roundings (3 differences, 3 products or
  // subtractions, 2 sums): below 8 units of roundoff; twice that for margin. An
  // underflowed 2x2 product is scaled once more, by |u*|.
  const double bound =
      16.0 * unit_roundoff * permanent +
      (std::abs (ux) + std::abs (uy) + std::abs (uz) + 1.0) * underflow_slack;
  if (permanent < filter_limit && std::abs (det) > bound)
    return det > 0.0 ? 1 : -1;
  return 0;
}

int
orient3d (const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d)
{
  const int sign = orient3dIfCertain (a, b, c, d);
  return sign != 0 ? sign : orient3dExact (a, b, c, d);
}


namespace {

// ---------------------------------------------------------------------------
// Exact intersection tests of closed triangles.

/** Drops coordinate `axis`, keeping the other two in cyclic order so that a
  * triangle's turn in the projection is the sign of its normal's `axis` component. */
Vector2
project (const Vector3& p, int axis)
{
  return {p[(axis + 1) % 3], p[(axis + 2) % 3]};
}

/** x in the closed sector at v from ray v-a to ray v-b; turn = orient2d (v, a, b),
  * non-zero, so the sector is narrower than pi and two half-planes describe it. */
bool
inSector (
    const Vector2& v, const Vector2& a, const Vector2& b, int turn, const Vector2& x)
{
  return orient2d (v, a, x) * turn >= 0 && orient2d (v, x, b) * turn >= 0;
}

/** x in the closed triangle a, b, c with turn = orient2d (a, b, c) != 0. */
bool
inTriangle2d (
    const Vector2& x, const Vector2& a, const Vector2& b, const Vector2& c, int turn)
{
  return orient2d (a, b, x) * turn >= 0 && orient2d (b, c, x) * turn >= 0 &&
         orient2d (c, a, x) * turn >= 0;
}

/** Closed segments p-q and r-s (each of positive length) cross or touch where they
  * are not collinear; collinear segments count as apart. That is all a segment needs
  * against a triangle's edges: overlapping an edge collinearly puts an end of the
  * segment in the triangle, or a triangle vertex inside the segment, where the
  * vertex's other edge meets it non-collinearly. */
bool
segmentsMeet2d (const Vector2& p, const Vector2& q, const Vector2& r, const Vector2& s)
{
  const int o1 = orient2d (p, q, r), o2 = orient2d (p, q, s);
  if (o1 * o2 > 0 || (o1 == 0 && o2 == 0))
    return false;
  const int o3 = orient2d (r, s, p), o4 = orient2d (r, s, q);
  return o3 * o4 <= 0;
}

/** Some edge line of triangle t (turning `turn`) has all of `others` strictly on its
  * outer side. For two non-degenerate triangles this is exactly disjointness of the
  * closed triangles (separating axis theorem, tried on both triangles' edges). */
bool
separatedByEdge2d (const std::array<Vector2, 3>& t,
                   int turn,
                   const std::array<Vector2, 3>& others)
{
  for (int i = 0; i < 3; ++i) {
    const Vector2& a = t[i];
    const Vector2& b = t[(i + 1) % 3];
    if (orient2d (a, b, others[0]) * turn < 0 &&
        orient2d (a, b, others[1]) * turn < 0 && orient2d (a, b, others[2]) * turn < 0)
      return true;
  }
  return false;
}

/** Closed segment p-q meets the closed non-degenerate triangle a, b, c. op and oq are
  * the exact orientations of p and q relative to the triangle's plane; axis is the
  * triangle's projection axis, used when the segment lies in that plane. */
bool
segmentMeetsTriangle (const Vector3& p,
                      const Vector3& q,
                      int op,
                      int oq,
                      const Vector3& a,
                      const Vector3& b,
                      const Vector3& c,
                      int axis)
{
  if (op * oq > 0)
    return false;
  if (op == 0 && oq == 0) {
    const Vector2 pp = project (p, axis), pq = project (q, axis);
    const Vector2 pa = project (a, axis), pb = project (b, axis),
                  pc = project (c, axis);
    const int turn = orient2d (pa, pb, pc);
    return inTriangle2d (pp, pa, pb, pc, turn) || inTriangle2d (pq, pa, pb, pc, turn) ||
           segmentsMeet2d (pp, pq, pa, pb) || segmentsMeet2d (pp, pq, pb, pc) ||
           segmentsMeet2d (pp, pq, pc, pa);
  }
  // The line through p and q crosses the plane at a point of the segment; it passes
  // through the closed triangle iff it does not pass two edges on opposite sides.
  const int s1 = orient3d (p, q, a, b), s2 = orient3d (p, q, b, c),
            s3 = orient3d (p, q, c, a);
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

bool
allStrictlySameSign (const std::array<int, 3>& o)
{
  return (o[0] > 0 && o[1] > 0 && o[2] > 0) || (o[0] < 0 && o[1] < 0 && o[2] < 0);
}


/** Faces u, w, a and w, u, b sharing the edge u-w; axis is the first face's. */
bool
meetAlongEdge (
    const Vector3& u, const Vector3& w, const Vector3& a, const Vector3& b, int axis)
{
  // On different planes, the faces meet exactly in the line u-w, that is the edge.
  if (orient3dIfCertain (u, w, a, b) != 0)
    return false;
  // On opposite sides of the edge in the projection, they meet only in the edge.
  const Vector2 pu = project (u, axis), pw = project (w, axis);
  if (orient2d (pu, pw, project (a, axis)) * orient2d (pu, pw, project (b, axis)) < 0)
    return false;
  // Coplanar with a and b on the same side: the faces overlap (a fold-over).
  return orient3d (u, w, a, b) == 0;
}

/** Faces v, a, b and v, c, d sharing the vertex v. */
bool
meetAtVertex (const Vector3& v,
              const Vector3& a,
              const Vector3& b,
              int axis_s,
              const Vector3& c,
              const Vector3& d,
              int axis_t)
{
  const int oc = orient3dIfCertain (v, a, b, c), od = orient3dIfCertain (v, a, b, d);
  if (oc != 0 && oc == od)
    return false;
  const int oa = orient3dIfCertain (v, c, d, a), ob = orient3dIfCertain (v, c, d, b);
  if (oa != 0 && oa == ob)
    return false;

  // Near v each face fills the sector between its two edges at v, and a face meets
  // the other beyond v iff it does so near v; so in 2D the sectors decide.
  const Vector2 pv = project (v, axis_s), pa = project (a, axis_s),
                pb = project (b, axis_s);
  const Vector2 pc = project (c, axis_s), pd = project (d, axis_s);
  const int turn_s = orient2d (pv, pa, pb);
  const int turn_t = orient2d (pv, pc, pd);
  if (turn_t != 0 && !inSector (pv, pa, pb, turn_s, pc) &&
      !inSector (pv, pa, pb, turn_s, pd) && !inSector (pv, pc, pd, turn_t, pa) &&
      !inSector (pv, pc, pd, turn_t, pb))
    return false;

  const int ec = orient3d (v, a, b, c), ed = orient3d (v, a, b, d);
  if (ec == 0 && ed == 0)
    return true; // coplanar, and the sectors overlap (turn_t != 0 for coplanar faces)
  if (ec * ed > 0)
    return false;
  const int ea = orient3d (v, c, d, a), eb = orient3d (v, c, d, b);
  if (ea * eb > 0)
    return false;
  // Not coplanar: their intersection is a segment from v along the planes' common
  // line; its far end lies on the edge opposite v of one of the faces.
  return segmentMeetsTriangle (a, b, ea, eb, v, c, d, axis_t) ||
         segmentMeetsTriangle (c, d, ec, ed, v, a, b, axis_s);
}

/** Faces a and b without a common index. Every pair goes through up to three steps,
  * cheapest first: (1) a certified floating-point plane-side test, which settles
  * almost every pair on a curved surface; (2) an exact 2D test in the first face's
  * projection, which settles flat neighbourhoods, where step 1 cannot be certified,
  * and is the answer for coplanar pairs; (3) the exact 3D test. */
bool
meetApart (const std::array<const Vector3*, 3>& a,
           int axis_s,
           const std::array<const Vector3*, 3>& b,
           int axis_t)
{
  std::array<int, 3> ob, oa;
  for (int i = 0; i < 3; ++i)
    ob[i] = orient3dIfCertain (*a[0], *a[1], *a[2], *b[i]);
  if (allStrictlySameSign (ob))
    return false;
  for (int i = 0; i < 3; ++i)
    oa[i] = orient3dIfCertain (*b[0], *b[1], *b[2], *a[i]);
  if (allStrictlySameSign (oa))
    return false;

  std::array<Vector2, 3> pa, pb;
  for (int i = 0; i < 3; ++i) {
    pa[i] = project (*a[i], axis_s);
    pb[i] = project (*b[i], axis_s);
  }
  const int turn_s = orient2d (pa[0], pa[1], pa[2]);
  const int turn_t = orient2d (pb[0], pb[1], pb[2]);
  if (turn_t != 0 &&
      (separatedByEdge2d (pa, turn_s, pb) || separatedByEdge2d (pb, turn_t, pa)))
    return false;

  for (int i = 0; i < 3; ++i)
    ob[i] = orient3d (*a[0], *a[1], *a[2], *b[i]);
  if (ob[0] == 0 && ob[1] == 0 && ob[2] == 0)
    return true; // coplanar, and the projections overlap
  if (allStrictlySameSign (ob))
    return false;
  for (int i = 0; i < 3; ++i)
    oa[i] = orient3d (*b[0], *b[1], *b[2], *a[i]);
  if (allStrictlySameSign (oa))
    return false;
  // Not coplanar: the intersection is a segment on the planes' common line whose
  // ends lie on edges, so the faces meet iff an edge of one meets the other.
  for (int i = 0; i < 3; ++i) {
    const int k = (i + 1) % 3;
    if (segmentMeetsTriangle (*a[i], *a[k], oa[i], oa[k], *b[0], *b[1], *b[2],
                              axis_t) ||
        segmentMeetsTriangle (*b[i], *b[k], ob[i], ob[k], *a[0], *a[1], *a[2],
                              axis_s))
      return true;
  }
  return false;
}

} // namespace

int
projectionAxis (const Vector3& a, const Vector3& b, const Vector3& c)
{
  const Vector3 normal = (b - a).cross (c - a).cwiseAbs ();
  std::array<int, 3> order{0, 1, 2};
  std::sort (order.begin (), order.end (),
             [&normal] (int i, int j) { return normal[i] > normal[j]; });
  for (int axis : order)
    if (orient2d (project (a, axis), project (b, axis), project (c, axis)) != 0)
      return axis;
  return -1;
}

int
projectionAxis (const Points3& vertices, const Triangle& t)
{
  return projectionAxis (vertices[static_cast<std::size_t> (t[0])],
                         vertices[static_cast<std::size_t> (t[1])],
                         vertices[static_cast<std::size_t> (t[2])]);
}

bool
trianglesIntersect (const Points3& vertices,
                    const Triangle& s,
                    int axis_s,
                    const Triangle& t,
                    int axis_t)
{
  const auto point = [&vertices] (pcl::index_t i) -> const Vector3& {
    return vertices[static_cast<std::size_t> (i)];
  };
  std::array<int, 3> match{-1, -1, -1}; // match[i]: position in t of s[i]
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (s[i] == t[j]) {
        match[i] = j;
        ++shared;
      }
  if (shared == 0)
    return meetApart ({&point (s[0]), &point (s[1]), &point (s[2])}, axis_s,
                      {&point (t[0]), &point (t[1]), &point (t[2])}, axis_t);
  if (shared == 1) {
    const int i = match[0] >= 0 ? 0 : (match[1] >= 0 ? 1 : 2);
    const int j = match[i];
    // Cyclic rotations keep each face's orientation.
    return meetAtVertex (point (s[i]), point (s[(i + 1) % 3]), point (s[(i + 2) % 3]),
                         axis_s, point (t[(j + 1) % 3]), point (t[(j + 2) % 3]),
                         axis_t);
  }
  if (shared == 2) {
    const int i = match[0] < 0 ? 0 : (match[1] < 0 ? 1 : 2);
    const int j = 3 - match[(i + 1) % 3] - match[(i + 2) % 3];
    return meetAlongEdge (point (s[(i + 1) % 3]), point (s[(i + 2) % 3]), point (s[i]),
                          point (t[j]), axis_s);
  }
  return true; // the same vertex set: the faces coincide
}

bool
trianglesIntersect (const Points3& vertices, const Triangle& s, const Triangle& t)
{
  const auto distinct = [] (const Triangle& x) {
    return x[0] != x[1] && x[1] != x[2] && x[2] != x[0];
  };
  if (!distinct (s) || !distinct (t))
    return false;
  // Most pairs a broad phase hands over lie apart: the vertices of one that the
  // other does not share all certainly on one side of the other's plane. Then they
  // meet at most in what they share, which does not count; the exact tests below
  // (a projection axis each, then the overlap) are for the rest.
  const auto apart = [&vertices] (const Triangle& a, const Triangle& b) {
    int side = 0;
    for (const pcl::index_t v : b) {
      if (v == a[0] || v == a[1] || v == a[2])
        continue;
      const int o = orient3dIfCertain (vertices[a[0]], vertices[a[1]], vertices[a[2]], vertices[v]);
      if (o == 0 || (side != 0 && o != side))
        return false;
      side = o;
    }
    return side != 0;
  };
  if (apart (s, t) || apart (t, s))
    return false;
  const int axis_s = projectionAxis (vertices, s);
  const int axis_t = projectionAxis (vertices, t);
  if (axis_s < 0 || axis_t < 0)
    return false;
  return trianglesIntersect (vertices, s, axis_s, t, axis_t);
}

} // namespace meshless
} // namespace pcl
