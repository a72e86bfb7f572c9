/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/mesh_checks.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <Eigen/Geometry>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

namespace pcl {
namespace meshless {

namespace {

using Vector2 = Eigen::Vector2d;
using Vector3 = Eigen::Vector3d;
using boost::multiprecision::cpp_int;

constexpr double pi = 3.14159265358979323846;

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

/** Sign of det[b - a, c - a]: positive if a, b, c turn counter-clockwise. */
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

/** Sign of det[b - a, c - a, d - a] (positive if d lies on the side the normal of the
  * counter-clockwise triangle a, b, c points to) when the floating-point evaluation
  * certifies it, else 0: the caller decides whether the exact value is worth it. */
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

/** Decides for pairs of non-degenerate faces whether they meet beyond what their
  * shared indices allow. Every pair goes through up to three steps, cheapest first:
  * (1) a certified floating-point plane-side test, which settles almost every pair
  * on a curved surface; (2) an exact 2D test in the first face's projection, which
  * settles flat neighbourhoods, where step 1 cannot be certified, and is the answer
  * for coplanar pairs: if the projections meet only in the shared part, so do the
  * faces; (3) the exact 3D test. */
class PairTester
{
public:
  PairTester (const Points3& vertices,
              const Triangles& triangles,
              const std::vector<std::int8_t>& axis)
    : vertices_ (vertices), triangles_ (triangles), axis_ (axis)
  {
  }

  bool
  intersect (std::size_t f, std::size_t g) const
  {
    const Triangle& s = triangles_[f];
    const Triangle& t = triangles_[g];
    std::array<int, 3> match{-1, -1, -1}; // match[i]: position in t of s[i]
    int shared = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (s[i] == t[j]) {
          match[i] = j;
          ++shared;
        }
    if (shared == 0)
      return meetApart (s, axis_[f], t, axis_[g]);
    if (shared == 1) {
      const int i = match[0] >= 0 ? 0 : (match[1] >= 0 ? 1 : 2);
      const int j = match[i];
      // Cyclic rotations keep each face's orientation.
      return meetAtVertex (point (s[i]), point (s[(i + 1) % 3]), point (s[(i + 2) % 3]),
                           axis_[f], point (t[(j + 1) % 3]), point (t[(j + 2) % 3]),
                           axis_[g]);
    }
    if (shared == 2) {
      const int i = match[0] < 0 ? 0 : (match[1] < 0 ? 1 : 2);
      const int j = 3 - match[(i + 1) % 3] - match[(i + 2) % 3];
      return meetAlongEdge (point (s[(i + 1) % 3]), point (s[(i + 2) % 3]),
                            point (s[i]), point (t[j]), axis_[f]);
    }
    return true; // the same vertex set: the faces coincide
  }

private:
  const Vector3&
  point (pcl::index_t i) const
  {
    return vertices_[static_cast<std::size_t> (i)];
  }

  /** Faces u, w, a and w, u, b sharing the edge u-w. */
  bool
  meetAlongEdge (const Vector3& u,
                 const Vector3& w,
                 const Vector3& a,
                 const Vector3& b,
                 int axis) const
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
                int axis_t) const
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

  /** Faces without a common index. */
  bool
  meetApart (const Triangle& s, int axis_s, const Triangle& t, int axis_t) const
  {
    const std::array<const Vector3*, 3> a{&point (s[0]), &point (s[1]), &point (s[2])};
    const std::array<const Vector3*, 3> b{&point (t[0]), &point (t[1]), &point (t[2])};
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

  const Points3& vertices_;
  const Triangles& triangles_;
  const std::vector<std::int8_t>& axis_;
};

// ---------------------------------------------------------------------------
// Broad phase: a bounding-volume hierarchy over the faces in Morton order.

/** Closed axis-aligned box in single precision. */
struct Box
{
  std::array<float, 3> lo, hi;
};

/** Rounds to the nearest float, out-of-range values to infinity (a plain conversion
  * would be undefined there). The rounding is monotone, so the boxes of two faces with
  * a common point keep a common point: no candidate pair is lost. */
float
toFloat (double x)
{
  constexpr double largest = std::numeric_limits<float>::max ();
  if (x > largest)
    return std::numeric_limits<float>::infinity ();
  if (x < -largest)
    return -std::numeric_limits<float>::infinity ();
  return static_cast<float> (x);
}

bool
overlap (const Box& a, const Box& b)
{
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k])
      return false;
  return true;
}

Box
merge (const Box& a, const Box& b)
{
  Box m;
  for (int k = 0; k < 3; ++k) {
    m.lo[k] = std::min (a.lo[k], b.lo[k]);
    m.hi[k] = std::max (a.hi[k], b.hi[k]);
  }
  return m;
}

/** Spreads the low 21 bits of x to every third bit. */
std::uint64_t
spreadBits (std::uint64_t x)
{
  x &= 0x1fffffull;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

/** Binary tree over boxes; the boxes are stored in an order in which near boxes are
  * near each other (Morton order), and every node covers a contiguous range of that
  * order. The range lets each box visit only the boxes after it, so each candidate
  * pair is found once without a set of seen pairs. */
class BoxTree
{
public:
  explicit BoxTree (std::vector<Box> boxes) : boxes_ (std::move (boxes))
  {
    if (boxes_.empty ())
      return;
    // Median splits leave at least (leaf_size + 1) / 2 boxes per leaf, and a binary
    // tree has fewer than twice as many nodes as leaves.
    nodes_.reserve (2 * (boxes_.size () / ((leaf_size + 1) / 2)) + 1);
    build (0, static_cast<std::uint32_t> (boxes_.size ()));
  }

  /** Calls visit (q) for every q > p whose box overlaps box p. */
  template <typename Visit>
  void
  forEachLaterOverlap (std::uint32_t p, Visit&& visit) const
  {
    const Box& box = boxes_[p];
    // A balanced tree over at most 2^32 boxes is at most 30 levels deep.
    std::array<std::uint32_t, 64> stack;
    std::size_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.end <= p + 1 || !overlap (node.box, box))
        continue;
      if (node.right == 0) {
        for (std::uint32_t q = std::max (node.begin, p + 1); q < node.end; ++q)
          if (overlap (boxes_[q], box))
            visit (q);
      }
      else {
        stack[top++] = node.right;
        stack[top++] = static_cast<std::uint32_t> (&node - nodes_.data ()) + 1;
      }
    }
  }

private:
  static constexpr std::uint32_t leaf_size = 8;

  struct Node
  {
    Box box;
    std::uint32_t begin, end;
    /** Index of the right child (the left one follows its parent), 0 for a leaf. */
    std::uint32_t right;
  };

  std::uint32_t
  build (std::uint32_t begin, std::uint32_t end)
  {
    const auto index = static_cast<std::uint32_t> (nodes_.size ());
    nodes_.push_back ({boxes_[begin], begin, end, 0});
    if (end - begin <= leaf_size) {
      for (std::uint32_t i = begin + 1; i < end; ++i)
        nodes_[index].box = merge (nodes_[index].box, boxes_[i]);
      return index;
    }
    const std::uint32_t middle = begin + (end - begin) / 2;
    build (begin, middle);
    const std::uint32_t right = build (middle, end);
    nodes_[index].right = right;
    nodes_[index].box = merge (nodes_[index + 1].box, nodes_[right].box);
    return index;
  }

  std::vector<Box> boxes_;
  std::vector<Node> nodes_;
};

// ---------------------------------------------------------------------------
// Topology.

/** Union-find with path halving. The smaller index becomes the root, so a set's root
  * is its smallest member whatever the order of the unions. */
class DisjointSets
{
public:
  explicit DisjointSets (std::size_t n) : parent_ (n)
  {
    std::iota (parent_.begin (), parent_.end (), 0u);
  }

  std::uint32_t
  find (std::uint32_t x)
  {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }

  void
  unite (std::uint32_t a, std::uint32_t b)
  {
    a = find (a);
    b = find (b);
    if (a < b)
      parent_[b] = a;
    else if (b < a)
      parent_[a] = b;
  }

  bool
  isRoot (std::uint32_t x) const
  {
    return parent_[x] == x;
  }

private:
  std::vector<std::uint32_t> parent_;
};

enum class TriangleKind {
  Invalid,       // an index out of range
  RepeatedIndex, // in range, but not three distinct vertices
  Face
};

TriangleKind
classify (const Triangle& t, std::size_t num_vertices)
{
  for (pcl::index_t i : t)
    if (i < 0 || static_cast<std::size_t> (i) >= num_vertices)
      return TriangleKind::Invalid;
  if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
    return TriangleKind::RepeatedIndex;
  return TriangleKind::Face;
}

/** Half-edge id 3 * t + j: the edge of triangle t from corner j to corner j + 1. */
struct HalfEdge
{
  /** The larger vertex index of the edge; the smaller one is the bucket. */
  std::uint32_t high;
  std::uint32_t id;
};

class Topology
{
public:
  Topology (const Triangles& triangles, std::size_t num_vertices, MeshReport& report)
    : triangles_ (triangles), n_ (num_vertices), report_ (report)
  {
  }

  void
  run ()
  {
    std::vector<char> used (n_, 0);
    DisjointSets components (n_);
    for (std::size_t t = 0; t < triangles_.size (); ++t) {
      const Triangle& tri = triangles_[t];
      switch (classify (tri, n_)) {
      case TriangleKind::Invalid:
        ++report_.invalid_triangles;
        break;
      case TriangleKind::RepeatedIndex:
        ++report_.degenerate_triangles;
        break;
      case TriangleKind::Face:
        ++report_.num_faces;
        for (pcl::index_t v : tri)
          used[v] = 1;
        components.unite (tri[0], tri[1]);
        components.unite (tri[1], tri[2]);
        break;
      }
    }
    for (std::size_t v = 0; v < n_; ++v)
      if (used[v]) {
        ++report_.used_vertices;
        if (components.isRoot (static_cast<std::uint32_t> (v)))
          ++report_.components;
      }
    report_.unused_vertices = n_ - report_.used_vertices;

    scanEdges ();

    report_.euler_characteristic = static_cast<long> (report_.used_vertices) -
                                   static_cast<long> (report_.num_edges) +
                                   static_cast<long> (report_.num_faces);
    if (report_.isManifold () && report_.isOriented ()) {
      const long twice_genus = 2 * static_cast<long> (report_.components) -
                               report_.euler_characteristic -
                               static_cast<long> (report_.boundary_loops);
      report_.genus = twice_genus >= 0 && twice_genus % 2 == 0 ? twice_genus / 2 : -1;
    }
  }

private:
  std::uint32_t
  from (std::uint32_t id) const
  {
    return static_cast<std::uint32_t> (triangles_[id / 3][id % 3]);
  }

  std::uint32_t
  opposite (std::uint32_t id) const
  {
    return static_cast<std::uint32_t> (triangles_[id / 3][(id % 3 + 2) % 3]);
  }

  /** Corner id (3 * t + j) of vertex x, an end of half-edge id, in id's triangle. */
  std::uint32_t
  corner (std::uint32_t id, std::uint32_t x) const
  {
    return from (id) == x ? id : id - id % 3 + (id % 3 + 1) % 3;
  }

  /** Groups the half-edges by undirected edge (a bucket per smaller vertex, sorted by
    * larger vertex, then by opposite vertex so that duplicate faces are adjacent) and
    * derives every edge-based count from the groups. */
  void
  scanEdges ()
  {
    std::vector<std::uint32_t> offsets (n_ + 1, 0);
    for (const Triangle& tri : triangles_)
      if (classify (tri, n_) == TriangleKind::Face)
        for (int j = 0; j < 3; ++j)
          ++offsets[std::min (tri[j], tri[(j + 1) % 3]) + 1];
    std::partial_sum (offsets.begin (), offsets.end (), offsets.begin ());
    std::vector<HalfEdge> edges (offsets[n_]);
    {
      std::vector<std::uint32_t> fill (offsets.begin (), offsets.end () - 1);
      for (std::size_t t = 0; t < triangles_.size (); ++t) {
        const Triangle& tri = triangles_[t];
        if (classify (tri, n_) != TriangleKind::Face)
          continue;
        for (int j = 0; j < 3; ++j) {
          const auto a = static_cast<std::uint32_t> (tri[j]);
          const auto b = static_cast<std::uint32_t> (tri[(j + 1) % 3]);
          edges[fill[std::min (a, b)]++] = {std::max (a, b),
                                            static_cast<std::uint32_t> (3 * t + j)};
        }
      }
    }

    DisjointSets corners (3 * triangles_.size ()); // joined across manifold edges
    DisjointSets boundary (n_);                    // joined along boundary edges
    std::vector<char> on_boundary (n_, 0), on_non_manifold_edge (n_, 0);
    for (std::uint32_t low = 0; low < n_; ++low) {
      HalfEdge* const first = edges.data () + offsets[low];
      HalfEdge* const last = edges.data () + offsets[low + 1];
      std::sort (first, last, [this] (const HalfEdge& x, const HalfEdge& y) {
        if (x.high != y.high)
          return x.high < y.high;
        return opposite (x.id) < opposite (y.id);
      });
      for (HalfEdge* run = first; run != last;) {
        const std::uint32_t high = run->high;
        HalfEdge* run_end = run;
        while (run_end != last && run_end->high == high)
          ++run_end;
        ++report_.num_edges;
        const std::size_t uses = static_cast<std::size_t> (run_end - run);
        if (uses == 1) {
          ++report_.boundary_edges;
          boundary.unite (low, high);
          on_boundary[low] = on_boundary[high] = 1;
        }
        else if (uses == 2) {
          if ((from (run[0].id) == low) == (from (run[1].id) == low))
            ++report_.inconsistent_edges;
          corners.unite (corner (run[0].id, low), corner (run[1].id, low));
          corners.unite (corner (run[0].id, high), corner (run[1].id, high));
        }
        else {
          ++report_.non_manifold_edges;
          on_non_manifold_edge[low] = on_non_manifold_edge[high] = 1;
        }
        // A face is counted as a duplicate once, in the group of its two smallest
        // vertices (there its opposite vertex is above `high`).
        for (HalfEdge* e = run; e + 1 != run_end; ++e)
          if (opposite (e->id) > high && opposite (e->id) == opposite (e[1].id))
            ++report_.duplicate_triangles;
        run = run_end;
      }
    }

    for (std::uint32_t v = 0; v < n_; ++v)
      if (on_boundary[v] && boundary.isRoot (v))
        ++report_.boundary_loops;

    // Faces around a vertex joined through manifold edges form its fans; every fan
    // has exactly one root corner.
    std::vector<std::uint32_t> fans (n_, 0);
    for (std::size_t t = 0; t < triangles_.size (); ++t)
      if (classify (triangles_[t], n_) == TriangleKind::Face)
        for (int j = 0; j < 3; ++j)
          if (corners.isRoot (static_cast<std::uint32_t> (3 * t + j)))
            ++fans[triangles_[t][j]];
    for (std::size_t v = 0; v < n_; ++v)
      if (fans[v] > 1 && !on_non_manifold_edge[v])
        ++report_.non_manifold_vertices;
  }

  const Triangles& triangles_;
  const std::size_t n_;
  MeshReport& report_;
};

// ---------------------------------------------------------------------------
// Geometry.

int
threadCount (const MeshCheckOptions& options)
{
#ifdef _OPENMP
  return options.num_threads > 0 ? options.num_threads : omp_get_max_threads ();
#else
  return 1;
#endif
}

int
threadIndex ()
{
#ifdef _OPENMP
  return omp_get_thread_num ();
#else
  return 0;
#endif
}

/** Calls body (begin, end, thread) on the ranges [k * grain, (k + 1) * grain) covering
  * [0, n), in parallel if there is more than one (a team costs more than a small mesh,
  * all the more on busy cores). An exception leaving a parallel region would terminate
  * the program, so the first one is carried out of the region and rethrown. */
template <typename Body>
void
parallelRanges (std::size_t n, std::size_t grain, int threads, Body&& body)
{
  const auto ranges = static_cast<std::ptrdiff_t> ((n + grain - 1) / grain);
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic) num_threads(threads) if (ranges > 1)
  for (std::ptrdiff_t k = 0; k < ranges; ++k) {
    const std::size_t begin = static_cast<std::size_t> (k) * grain;
    try {
      body (begin, std::min (n, begin + grain), threadIndex ());
    } catch (...) {
#pragma omp critical(meshless_mesh_checks_failure)
      if (!failure)
        failure = std::current_exception ();
    }
  }
  if (failure)
    std::rethrow_exception (failure);
}

/** The axis along which the face projects to a non-degenerate triangle, preferring
  * the largest normal component for well-conditioned 2D predicates; -1 if the
  * vertices are exactly collinear (then every projection is degenerate). */
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

/** Smallest interior angle in radians: the one opposite the shortest edge. */
double
smallestAngle (const Vector3& a, const Vector3& b, const Vector3& c)
{
  const double la = (c - b).squaredNorm (), lb = (a - c).squaredNorm (),
               lc = (b - a).squaredNorm ();
  const Vector3* apex = &a;
  const Vector3 *p = &b, *q = &c;
  if (lb < la && lb <= lc) {
    apex = &b;
    p = &c;
    q = &a;
  }
  else if (lc < la && lc < lb) {
    apex = &c;
    p = &a;
    q = &b;
  }
  const Vector3 u = *p - *apex, v = *q - *apex;
  // atan2 stays accurate for tiny and for nearly straight angles, unlike acos.
  return std::atan2 (u.cross (v).norm (), u.dot (v));
}

/** Cap on MeshCheckOptions::max_listed_intersections: the buffers are allocated up
  * front, outside the parallel region. */
constexpr std::size_t max_listed = std::size_t{1} << 16;

/** What one thread found; cache-line aligned so that threads do not share lines. */
struct alignas (64) ThreadFindings
{
  std::size_t count = 0;
  std::vector<std::pair<std::size_t, std::size_t>> listed;
};

/** Per-block sums, added in block order afterwards so that the totals do not depend
  * on the number of threads. */
struct BlockSums
{
  double volume = 0.0, min_angle = 0.0;
  std::size_t faces = 0, below_10 = 0, collinear = 0;
};

class Geometry
{
public:
  Geometry (const Points3& vertices,
            const Triangles& triangles,
            const MeshCheckOptions& options,
            MeshReport& report)
    : vertices_ (vertices), triangles_ (triangles), options_ (options),
      report_ (report), threads_ (threadCount (options))
  {
  }

  void
  run ()
  {
    measureFaces ();
    if (options_.check_self_intersections)
      findSelfIntersections ();
  }

private:
  /** Per-face metrics and projection axes; faces touching a non-finite vertex keep
    * axis -1 and are left out of the geometry. */
  void
  measureFaces ()
  {
    const std::size_t n = vertices_.size ();
    std::vector<char> finite (n, 1);
    std::vector<char> used (n, 0);
    for (const Triangle& tri : triangles_)
      if (classify (tri, n) == TriangleKind::Face)
        for (pcl::index_t v : tri)
          used[v] = 1;
    Vector3 centroid = Vector3::Zero ();
    std::size_t finite_used = 0;
    for (std::size_t v = 0; v < n; ++v) {
      if (!used[v])
        continue;
      finite[v] = vertices_[v].allFinite ();
      if (finite[v]) {
        centroid += vertices_[v];
        ++finite_used;
      }
      else
        ++report_.non_finite_vertices;
    }
    if (finite_used > 0)
      centroid /= static_cast<double> (finite_used);

    axis_.assign (triangles_.size (), -1);
    constexpr std::size_t block_size = 4096;
    std::vector<BlockSums> blocks ((triangles_.size () + block_size - 1) / block_size);
    const double threshold = 10.0 * pi / 180.0;
    parallelRanges (triangles_.size (), block_size, threads_,
                    [&] (std::size_t begin, std::size_t end, int) {
                      BlockSums& sums = blocks[begin / block_size];
                      for (std::size_t t = begin; t < end; ++t) {
                        const Triangle& tri = triangles_[t];
                        if (classify (tri, n) != TriangleKind::Face ||
                            !finite[tri[0]] || !finite[tri[1]] || !finite[tri[2]])
                          continue;
                        const Vector3& p = vertices_[tri[0]];
                        const Vector3& q = vertices_[tri[1]];
                        const Vector3& r = vertices_[tri[2]];
                        axis_[t] = static_cast<std::int8_t> (projectionAxis (p, q, r));
                        if (axis_[t] < 0)
                          ++sums.collinear;
                        // Measured from the centroid the terms stay small, so a mesh
                        // far from the origin loses no precision to cancellation.
                        sums.volume +=
                            (p - centroid).dot ((q - centroid).cross (r - centroid)) /
                            6.0;
                        const double angle = smallestAngle (p, q, r);
                        sums.min_angle += angle;
                        sums.below_10 += angle < threshold ? 1 : 0;
                        ++sums.faces;
                      }
                    });
    BlockSums total;
    for (const BlockSums& sums : blocks) {
      total.volume += sums.volume;
      total.min_angle += sums.min_angle;
      total.faces += sums.faces;
      total.below_10 += sums.below_10;
      total.collinear += sums.collinear;
    }
    report_.degenerate_triangles += total.collinear;
    report_.signed_volume = total.volume;
    if (total.faces > 0) {
      report_.mean_min_angle_deg =
          total.min_angle / static_cast<double> (total.faces) * 180.0 / pi;
      report_.share_min_angle_below_10 =
          static_cast<double> (total.below_10) / static_cast<double> (total.faces);
    }
  }

  void
  findSelfIntersections ()
  {
    std::vector<std::uint32_t> order;
    for (std::size_t t = 0; t < triangles_.size (); ++t)
      if (axis_[t] >= 0)
        order.push_back (static_cast<std::uint32_t> (t));
    std::vector<Box> boxes = sortedBoxes (order);
    const BoxTree tree (std::move (boxes));
    const PairTester tester (vertices_, triangles_, axis_);

    // Each thread counts on its own and keeps its smallest pairs, trimmed whenever the
    // buffer fills, so the union holds the overall smallest ones; the buffers never
    // reallocate.
    const std::size_t keep = std::min (options_.max_listed_intersections, max_listed);
    std::vector<ThreadFindings> findings (static_cast<std::size_t> (threads_));
    for (ThreadFindings& own : findings)
      own.listed.reserve (keep > 0 ? 4 * keep : 0);

    parallelRanges (
        order.size (), 1024, threads_,
        [&] (std::size_t begin, std::size_t end, int thread) {
          ThreadFindings& own = findings[static_cast<std::size_t> (thread)];
          for (std::size_t p = begin; p < end; ++p)
            tree.forEachLaterOverlap (
                static_cast<std::uint32_t> (p), [&] (std::uint32_t q) {
                  const std::size_t f = order[p], g = order[q];
                  if (!tester.intersect (f, g))
                    return;
                  ++own.count;
                  if (keep == 0)
                    return;
                  own.listed.emplace_back (std::min (f, g), std::max (f, g));
                  if (own.listed.size () == own.listed.capacity ()) {
                    std::nth_element (own.listed.begin (), own.listed.begin () + keep,
                                      own.listed.end ());
                    own.listed.resize (keep);
                  }
                });
        });

    report_.self_intersections_checked = true;
    for (const ThreadFindings& own : findings) {
      report_.self_intersecting_pairs += own.count;
      report_.intersecting_pairs.insert (report_.intersecting_pairs.end (),
                                         own.listed.begin (), own.listed.end ());
    }
    std::sort (report_.intersecting_pairs.begin (), report_.intersecting_pairs.end ());
    if (report_.intersecting_pairs.size () > keep)
      report_.intersecting_pairs.resize (keep);
  }

  /** Sorts the faces in `order` along a Morton curve through their box centres and
    * returns their boxes in that order. */
  std::vector<Box>
  sortedBoxes (std::vector<std::uint32_t>& order) const
  {
    std::vector<Box> boxes (order.size ());
    Box bounds{{{std::numeric_limits<float>::infinity (),
                 std::numeric_limits<float>::infinity (),
                 std::numeric_limits<float>::infinity ()}},
               {{-std::numeric_limits<float>::infinity (),
                 -std::numeric_limits<float>::infinity (),
                 -std::numeric_limits<float>::infinity ()}}};
    for (std::size_t i = 0; i < order.size (); ++i) {
      const Triangle& tri = triangles_[order[i]];
      for (int k = 0; k < 3; ++k) {
        const double lo = std::min (
            {vertices_[tri[0]][k], vertices_[tri[1]][k], vertices_[tri[2]][k]});
        const double hi = std::max (
            {vertices_[tri[0]][k], vertices_[tri[1]][k], vertices_[tri[2]][k]});
        boxes[i].lo[k] = toFloat (lo);
        boxes[i].hi[k] = toFloat (hi);
      }
      bounds = merge (bounds, boxes[i]);
    }
    // Codes only steer the grouping; a poor code (say for infinite bounds) costs time,
    // never correctness.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed (order.size ());
    constexpr double cells = (1u << 21) - 1;
    for (std::size_t i = 0; i < order.size (); ++i) {
      std::uint64_t code = 0;
      for (int k = 0; k < 3; ++k) {
        const double extent = static_cast<double> (bounds.hi[k]) - bounds.lo[k];
        const double centre =
            0.5 * (static_cast<double> (boxes[i].lo[k]) + boxes[i].hi[k]);
        double cell = extent > 0.0 ? (centre - bounds.lo[k]) / extent * cells : 0.0;
        cell = cell >= 0.0 ? std::min (cell, cells) : 0.0; // also maps NaN to 0
        code |= spreadBits (static_cast<std::uint64_t> (cell)) << k;
      }
      keyed[i] = {code, static_cast<std::uint32_t> (i)};
    }
    std::sort (keyed.begin (), keyed.end ());
    std::vector<std::uint32_t> sorted_order (order.size ());
    std::vector<Box> sorted_boxes (order.size ());
    for (std::size_t i = 0; i < keyed.size (); ++i) {
      sorted_order[i] = order[keyed[i].second];
      sorted_boxes[i] = boxes[keyed[i].second];
    }
    order.swap (sorted_order);
    return sorted_boxes;
  }

  const Points3& vertices_;
  const Triangles& triangles_;
  const MeshCheckOptions& options_;
  MeshReport& report_;
  const int threads_;
  std::vector<std::int8_t> axis_;
};

// ---------------------------------------------------------------------------
// Summary text.

std::string
counted (std::size_t n, const char* singular, const char* plural)
{
  return std::to_string (n) + " " + (n == 1 ? singular : plural);
}

} // namespace

bool
MeshReport::isManifold () const
{
  return num_triangles > 0 && num_faces == num_triangles && duplicate_triangles == 0 &&
         non_manifold_edges == 0 && non_manifold_vertices == 0;
}

bool
MeshReport::isOriented () const
{
  return inconsistent_edges == 0;
}

bool
MeshReport::isClosedManifold () const
{
  return isManifold () && isOriented () && boundary_edges == 0;
}

bool
MeshReport::isSphereLike () const
{
  return isClosedManifold () && components == 1 && euler_characteristic == 2;
}

bool
MeshReport::isDiscLike () const
{
  return isManifold () && isOriented () && components == 1 && boundary_loops == 1 &&
         euler_characteristic == 1;
}

MeshReport
checkMesh (const Points3& vertices,
           const Triangles& triangles,
           const MeshCheckOptions& options)
{
  MeshReport report;
  report.num_vertices = vertices.size ();
  report.num_triangles = triangles.size ();
  // Vertex, half-edge and corner ids are 32-bit to halve the memory traffic.
  constexpr std::size_t id_limit = std::numeric_limits<std::uint32_t>::max ();
  if (vertices.size () >= id_limit || triangles.size () >= id_limit / 3) {
    report.message = "mesh too large for 32-bit half-edge ids";
    return report;
  }
  try {
    Topology (triangles, vertices.size (), report).run ();
    Geometry (vertices, triangles, options, report).run ();
    report.success = true;
  } catch (const std::exception& e) {
    MeshReport failed;
    failed.num_vertices = vertices.size ();
    failed.num_triangles = triangles.size ();
    failed.message = std::string ("mesh check failed: ") + e.what ();
    return failed;
  }
  return report;
}

std::string
describe (const MeshReport& r)
{
  std::ostringstream out;
  if (!r.success) {
    out << "Mesh of " << counted (r.num_vertices, "vertex", "vertices") << " and "
        << counted (r.num_triangles, "triangle", "triangles")
        << " not checked: " << r.message << ".";
    return out.str ();
  }
  if (r.num_triangles == 0)
    out << "Empty mesh";
  else if (r.isSphereLike ())
    out << "Sphere-like mesh";
  else if (r.isDiscLike ())
    out << "Disc-like mesh";
  else if (r.isClosedManifold ())
    out << "Closed manifold mesh";
  else if (r.isManifold ())
    out << (r.isOriented () ? "Manifold mesh with boundary"
                            : "Inconsistently oriented manifold mesh");
  else
    out << "Non-manifold mesh";
  out << ": " << counted (r.num_vertices, "vertex", "vertices") << " ("
      << r.unused_vertices << " unused), "
      << counted (r.num_triangles, "triangle", "triangles") << ", "
      << counted (r.num_edges, "edge", "edges") << ", "
      << counted (r.components, "component", "components") << ", Euler characteristic "
      << r.euler_characteristic;
  if (r.genus >= 0)
    out << ", genus " << r.genus;
  out << ".";

  std::vector<std::string> defects;
  const auto note = [&defects] (std::size_t n, const char* singular,
                                const char* plural) {
    if (n > 0)
      defects.push_back (counted (n, singular, plural));
  };
  note (r.invalid_triangles, "triangle with an index out of range",
        "triangles with an index out of range");
  note (r.non_finite_vertices, "vertex with non-finite coordinates",
        "vertices with non-finite coordinates");
  if (r.boundary_edges > 0)
    defects.push_back (counted (r.boundary_edges, "boundary edge", "boundary edges") +
                       " in " + counted (r.boundary_loops, "loop", "loops"));
  note (r.non_manifold_edges, "non-manifold edge", "non-manifold edges");
  note (r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices");
  note (r.inconsistent_edges, "inconsistently oriented edge",
        "inconsistently oriented edges");
  note (r.degenerate_triangles, "degenerate triangle", "degenerate triangles");
  note (r.duplicate_triangles, "duplicate triangle", "duplicate triangles");
  if (r.self_intersecting_pairs > 0) {
    std::string text = counted (r.self_intersecting_pairs, "self-intersecting pair",
                                "self-intersecting pairs");
    if (!r.intersecting_pairs.empty ())
      text += " (e.g. triangles " + std::to_string (r.intersecting_pairs[0].first) +
              " and " + std::to_string (r.intersecting_pairs[0].second) + ")";
    defects.push_back (text);
  }
  if (!defects.empty ()) {
    out << " Defects: ";
    for (std::size_t i = 0; i < defects.size (); ++i)
      out << (i > 0 ? ", " : "") << defects[i];
    out << ".";
  }
  if (!r.self_intersections_checked)
    out << " Self-intersections not checked.";
  else if (r.self_intersecting_pairs == 0)
    out << " No self-intersections.";
  out << std::setprecision (4);
  if (r.isClosedManifold ())
    out << " Signed volume " << r.signed_volume << ".";
  out << " Smallest angle: mean " << std::fixed << std::setprecision (1)
      << r.mean_min_angle_deg << " deg, " << 100.0 * r.share_min_angle_below_10
      << "% below 10 deg.";
  return out.str ();
}

} // namespace meshless
} // namespace pcl
