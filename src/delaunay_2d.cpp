/*
 * Software License Agreement (BSD License)
 *
 *  pcl_spherical_meshless: meshless triangulation of point clouds with spherical
 *  topology (Hormann and Reimers 2003) for the Point Cloud Library.
 */
#include <pcl/surface/meshless/delaunay_2d.h>

#include <boost/config.hpp>
#include <boost/multiprecision/cpp_int.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#ifndef BOOST_HAS_INT128
#error "delaunay_2d.cpp needs a compiler with 128-bit integers (GCC or Clang)"
#endif

namespace pcl {
namespace meshless {
namespace {

using Int128 = boost::int128_type;
using Int256 = boost::multiprecision::int256_t;
using Int512 = boost::multiprecision::int512_t;

/** \brief Snapped coordinates are below 2^kGridBits in magnitude, which leaves the
  * headroom the exact predicates below are sized for.
  */
constexpr int kGridBits = 120;

/** \brief Corner indices (3 per triangle) must fit an int: 2n triangles, 6n corners. */
constexpr std::size_t kMaxPoints = std::numeric_limits<int>::max () / 6;

/** \brief Unit roundoff of double precision, 2^-53. */
constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon () / 2.0;

/** \brief A point on the integer grid and the input index it came from.
  *
  * The grid coordinates are integers below 2^kGridBits, stored as doubles: each is
  * either the input coordinate scaled by a power of two (if that is already integral)
  * or an integer below 2^53, so the doubles hold them exactly. Floating-point filters
  * thus start from exact values, and the exact fallbacks convert them to 128 bits
  * without loss.
  */
struct GridPoint
{
  double x;
  double y;
  pcl::index_t index;
};

bool
sameNode (const GridPoint& a, const GridPoint& b)
{
  return a.x == b.x && a.y == b.y;
}

Int128
exactDifference (double a, double b)
{
  return static_cast<Int128> (a) - static_cast<Int128> (b);
}

/** \brief Sign of the orientation of (a, b, c): +1 counter-clockwise, 0 collinear.
  *
  * Differences take 121 bits, so the determinant needs 243: it is evaluated in double
  * precision and, if that cannot be trusted, in 256-bit integers.
  */
int
orient (const GridPoint& a, const GridPoint& b, const GridPoint& c)
{
  const double left = (b.x - a.x) * (c.y - a.y);
  const double right = (b.y - a.y) * (c.x - a.x);
  const double det = left - right;
  // Each product passes through 4 roundings (two differences, the product, the final
  // difference), so the error is below 4u (|left| + |right|) up to second order terms.
  // The values are integers below 2^243: no underflow or overflow.
  const double bound = 5.0 * kUnitRoundoff * (std::abs (left) + std::abs (right));
  if (det > bound)
    return 1;
  if (det < -bound)
    return -1;
  // A zero bound means both products are exactly zero: common for axis-parallel edges.
  if (bound == 0.0)
    return 0;
  return (Int256 (exactDifference (b.x, a.x)) * Int256 (exactDifference (c.y, a.y)) -
          Int256 (exactDifference (b.y, a.y)) * Int256 (exactDifference (c.x, a.x)))
      .sign ();
}

/** \brief True if p, collinear with a and b, lies strictly between them. */
bool
strictlyBetween (const GridPoint& a, const GridPoint& b, const GridPoint& p)
{
  // Collinear: p is strictly between iff it is strictly between in x, or in y for
  // vertical segments.
  if (a.x != b.x)
    return (a.x < p.x && p.x < b.x) || (b.x < p.x && p.x < a.x);
  return (a.y < p.y && p.y < b.y) || (b.y < p.y && p.y < a.y);
}

/** \brief Sign of the incircle test: +1 if d lies strictly inside the circle through
  * the counter-clockwise a, b, c, 0 if on it, -1 outside.
  */
int
incircle (const GridPoint& a, const GridPoint& b, const GridPoint& c,
          const GridPoint& d)
{
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det =
      alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
  // Each monomial of the determinant passes through at most 11 roundings: its 4
  // factors' differences, square, lift sum, product, minor difference, lift times minor
  // and two additions. Its relative error is therefore below 11u and the absolute error
  // below 11u times the permanent (the determinant with all terms made positive), which
  // itself is computed with a relative error far below 1/11. 12u covers both; the
  // values (integers below 2^489) can neither overflow nor underflow.
  const double permanent = (std::abs (bdxcdy) + std::abs (cdxbdy)) * alift +
                           (std::abs (cdxady) + std::abs (adxcdy)) * blift +
                           (std::abs (adxbdy) + std::abs (bdxady)) * clift;
  const double bound = 12.0 * kUnitRoundoff * permanent;
  if (det > bound)
    return 1;
  if (det < -bound)
    return -1;

  // Exact: differences take 121 bits, lifts and 2x2 minors 243, their products 486, the
  // sum 488.
  const Int512 eadx = exactDifference (a.x, d.x), eady = exactDifference (a.y, d.y);
  const Int512 ebdx = exactDifference (b.x, d.x), ebdy = exactDifference (b.y, d.y);
  const Int512 ecdx = exactDifference (c.x, d.x), ecdy = exactDifference (c.y, d.y);
  const Int512 exact = (eadx * eadx + eady * eady) * (ebdx * ecdy - ebdy * ecdx) +
                       (ebdx * ebdx + ebdy * ebdy) * (ecdx * eady - ecdy * eadx) +
                       (ecdx * ecdx + ecdy * ecdy) * (eadx * ebdy - eady * ebdx);
  return exact.sign ();
}

/** \brief Moves the median of [first, last) along `axis` (ascending or descending) to
  * the middle, the elements that come earlier in that order before it, and returns the
  * middle.
  */
GridPoint*
medianSplit (GridPoint* first, GridPoint* last, int axis, bool ascending)
{
  GridPoint* middle = first + (last - first) / 2;
  std::nth_element (
      first, middle, last, [axis, ascending] (const GridPoint& a, const GridPoint& b) {
        const double key_a = axis == 0 ? a.x : a.y, key_b = axis == 0 ? b.x : b.y;
        return ascending ? key_a < key_b : key_b < key_a;
      });
  return middle;
}

/** \brief Orders [first, last) along a Hilbert curve.
  *
  * The curve traverses four quadrants: the first half along `axis` (in the direction
  * `ascending`) ascending along the other axis if `ascending_other`, then the second
  * half in the opposite direction along the other axis. The first and last quadrants
  * traverse transposed (and for the last, reversed) copies of the curve so that
  * consecutive quadrants meet. Quadrants split at medians instead of at box midpoints,
  * so the recursion depth is logarithmic however strongly the points cluster.
  */
void
hilbertSort (GridPoint* first, GridPoint* last, int axis, bool ascending,
             bool ascending_other)
{
  if (last - first < 2)
    return;
  const int other = 1 - axis;
  GridPoint* const m2 = medianSplit (first, last, axis, ascending);
  GridPoint* const m1 = medianSplit (first, m2, other, ascending_other);
  GridPoint* const m3 = medianSplit (m2, last, other, !ascending_other);
  hilbertSort (first, m1, other, ascending_other, ascending);
  hilbertSort (m1, m2, axis, ascending, ascending_other);
  hilbertSort (m2, m3, axis, ascending, ascending_other);
  hilbertSort (m3, last, other, !ascending_other, !ascending);
}

/** \brief Biased randomized insertion order: after a random shuffle, the last half of
  * the points forms the last round, the quarter before it the round before, and so on;
  * each round is Hilbert sorted. The randomness bounds the expected work of the
  * incremental construction, the sorting keeps consecutive insertions close together.
  */
void
brioOrder (std::vector<GridPoint>& points, std::uint32_t seed)
{
  constexpr std::size_t kFirstRound = 64;
  std::mt19937 random (seed);
  std::shuffle (points.begin (), points.end (), random);
  std::size_t end = points.size ();
  while (end > 0) {
    const std::size_t begin = end <= kFirstRound ? 0 : end / 2;
    hilbertSort (points.data () + begin, points.data () + end, 0, true, true);
    end = begin;
  }
}

/** \brief Incremental Delaunay triangulation of the plane closed by an infinite vertex.
  *
  * Triangles are stored as corners: corner c = 3 t + i is the i-th vertex of triangle
  * t, counter-clockwise. `opposite_[c]` is the corner of the neighbouring triangle that
  * faces c across the edge opposite c, so walking and relinking need no searches. Ghost
  * triangles contain the infinite vertex; a ghost (u, v, inf) lies across the hull edge
  * whose finite triangle traverses it as v -> u.
  */
class DelaunayBuilder
{
public:
  /** \param[in] points the points in insertion order; the first three are distinct and
    * not collinear
    */
  explicit DelaunayBuilder (const std::vector<GridPoint>& points)
      : points_ (points), infinite_ (static_cast<int> (points.size ())),
        duplicate_of_ (points.size (), -1), triangle_at_ (points.size () + 1)
  {
    const std::size_t max_triangles = 2 * points.size ();
    vertex_.reserve (3 * max_triangles);
    opposite_.reserve (3 * max_triangles);
    stamp_.reserve (max_triangles);

    // Two points: two ghosts glued along all three edges, which closes the plane.
    const int t0 = newTriangle (), t1 = newTriangle ();
    setVertices (t0, 0, 1, infinite_);
    setVertices (t1, 1, 0, infinite_);
    link (3 * t0 + 0, 3 * t1 + 1);
    link (3 * t0 + 1, 3 * t1 + 0);
    link (3 * t0 + 2, 3 * t1 + 2);
    // The third point lies strictly outside one of the two (coinciding) hull edges.
    insert (2, orient (points_[0], points_[1], points_[2]) > 0 ? t0 : t1);

    for (int p = 3; p < infinite_; ++p) {
      const int t = locate (p);
      const int twin = coincidentVertex (t, p);
      if (twin >= 0)
        duplicate_of_[p] = twin;
      else
        insert (p, t);
    }
  }

  /** \brief Writes triangles, hull and duplicates (indices of the input points). */
  void extract (Delaunay2DResult& result) const
  {
    // Each vertex is represented by the smallest input index at its grid node.
    std::vector<pcl::index_t> representative (points_.size ());
    for (std::size_t p = 0; p < points_.size (); ++p)
      representative[p] = points_[p].index;
    for (std::size_t p = 0; p < points_.size (); ++p)
      if (duplicate_of_[p] >= 0)
        representative[duplicate_of_[p]] =
            std::min (representative[duplicate_of_[p]], points_[p].index);

    result.duplicate_of.assign (points_.size (), -1);
    result.num_duplicates = 0;
    for (std::size_t p = 0; p < points_.size (); ++p) {
      const int vertex =
          duplicate_of_[p] >= 0 ? duplicate_of_[p] : static_cast<int> (p);
      if (representative[vertex] != points_[p].index) {
        result.duplicate_of[points_[p].index] = representative[vertex];
        ++result.num_duplicates;
      }
    }

    const int num_triangles = static_cast<int> (stamp_.size ());
    int ghost = -1;
    result.triangles.clear ();
    result.triangles.reserve (num_triangles);
    for (int t = 0; t < num_triangles; ++t) {
      if (isGhost (t))
        ghost = t;
      else
        result.triangles.push_back ({representative[vertex_[3 * t]],
                                     representative[vertex_[3 * t + 1]],
                                     representative[vertex_[3 * t + 2]]});
    }

    // Walk the ghosts around the hull: in ghost (u, v, inf) the hull runs v -> u, and
    // the next ghost lies across the edge (inf, u), which is opposite v.
    std::vector<int> hull;
    int t = ghost;
    do {
      const int inf_corner = cornerOf (t, infinite_);
      const int v_corner = prev (inf_corner);
      hull.push_back (vertex_[v_corner]);
      t = opposite_[v_corner] / 3;
    } while (t != ghost);
    const auto first =
        std::min_element (hull.begin (), hull.end (), [this] (int a, int b) {
          return std::make_pair (points_[a].x, points_[a].y) <
                 std::make_pair (points_[b].x, points_[b].y);
        });
    std::rotate (hull.begin (), first, hull.end ());
    result.hull.clear ();
    result.hull.reserve (hull.size ());
    for (const int v : hull)
      result.hull.push_back (representative[v]);
  }

private:
  struct BoundaryEdge
  {
    int a;
    int b;
    int outer_corner;
  };

  static int next (int c) { return c % 3 == 2 ? c - 2 : c + 1; }

  static int prev (int c) { return c % 3 == 0 ? c + 2 : c - 1; }

  int newTriangle ()
  {
    vertex_.resize (vertex_.size () + 3);
    opposite_.resize (opposite_.size () + 3);
    stamp_.push_back (0);
    return static_cast<int> (stamp_.size ()) - 1;
  }

  void setVertices (int t, int a, int b, int c)
  {
    vertex_[3 * t] = a;
    vertex_[3 * t + 1] = b;
    vertex_[3 * t + 2] = c;
  }

  void link (int c, int d)
  {
    opposite_[c] = d;
    opposite_[d] = c;
  }

  bool isGhost (int t) const
  {
    return vertex_[3 * t] == infinite_ || vertex_[3 * t + 1] == infinite_ ||
           vertex_[3 * t + 2] == infinite_;
  }

  int cornerOf (int t, int v) const
  {
    return vertex_[3 * t] == v       ? 3 * t
           : vertex_[3 * t + 1] == v ? 3 * t + 1
                                     : 3 * t + 2;
  }

  /** \brief Orientation of point p with respect to the edge opposite corner c. */
  int orientEdge (int c, int p) const
  {
    return orient (points_[vertex_[next (c)]], points_[vertex_[prev (c)]], points_[p]);
  }

  /** \brief True if inserting p destroys triangle t (see the file documentation). */
  bool inConflict (int t, int p) const
  {
    const GridPoint& q = points_[p];
    for (int i = 0; i < 3; ++i) {
      const int c = 3 * t + i;
      if (vertex_[c] == infinite_) {
        const GridPoint& u = points_[vertex_[next (c)]];
        const GridPoint& v = points_[vertex_[prev (c)]];
        const int side = orient (u, v, q);
        return side > 0 || (side == 0 && strictlyBetween (u, v, q));
      }
    }
    return incircle (points_[vertex_[3 * t]], points_[vertex_[3 * t + 1]],
                     points_[vertex_[3 * t + 2]], q) > 0;
  }

  /** \brief Finds a finite triangle containing p (closed) or a ghost whose hull edge
    * has p strictly outside; either is in conflict with p unless p coincides with a
    * vertex.
    *
    * Visibility walk from the last insertion: leave through an edge that has p strictly
    * on its far side. A fixed order of testing the edges is only known to terminate in
    * Delaunay triangulations without cocircular points; starting at a random edge makes
    * the walk terminate in any triangulation.
    */
  int locate (int p)
  {
    int t = last_finite_;
    int entry = -1; // the corner facing the edge we came through; p is not beyond it
    for (;;) {
      random_ ^= random_ << 13;
      random_ ^= random_ >> 17;
      random_ ^= random_ << 5;
      const int start = static_cast<int> (random_ % 3);
      int exit = -1;
      for (int k = 0; k < 3 && exit < 0; ++k) {
        const int c = 3 * t + (start + k) % 3;
        if (c != entry && orientEdge (c, p) < 0)
          exit = c;
      }
      if (exit < 0)
        return t;
      entry = opposite_[exit];
      t = entry / 3;
      if (isGhost (t))
        return t;
    }
  }

  /** \brief The vertex of t at the grid node of p, or -1. */
  int coincidentVertex (int t, int p) const
  {
    for (int i = 0; i < 3; ++i) {
      const int v = vertex_[3 * t + i];
      if (v != infinite_ && sameNode (points_[v], points_[p]))
        return v;
    }
    return -1;
  }

  /** \brief Bowyer-Watson step: removes the triangles in conflict with p, which form a
    * region star-shaped from p that contains t, and fans its boundary to p.
    */
  void insert (int p, int t)
  {
    ++current_stamp_;
    cavity_.assign (1, t);
    stack_.assign (1, t);
    stamp_[t] = current_stamp_;
    boundary_.clear ();
    while (!stack_.empty ()) {
      const int s = stack_.back ();
      stack_.pop_back ();
      for (int c = 3 * s; c < 3 * s + 3; ++c) {
        const int outer = opposite_[c];
        const int u = outer / 3;
        if (stamp_[u] == current_stamp_)
          continue;
        if (inConflict (u, p)) {
          stamp_[u] = current_stamp_;
          cavity_.push_back (u);
          stack_.push_back (u);
        }
        else
          boundary_.push_back ({vertex_[next (c)], vertex_[prev (c)], outer});
      }
    }

    // The boundary has two edges more than the cavity has triangles: reuse the cavity's
    // slots and append two. New triangle (p, a, b) sits on boundary edge a -> b.
    while (cavity_.size () < boundary_.size ())
      cavity_.push_back (newTriangle ());
    for (std::size_t k = 0; k < boundary_.size (); ++k) {
      const int n = cavity_[k];
      setVertices (n, p, boundary_[k].a, boundary_[k].b);
      link (3 * n, boundary_[k].outer_corner);
      triangle_at_[boundary_[k].a] = n;
    }
    // Neighbours around p: (p, a, b) meets (p, b, c) along p-b, opposite a and c.
    for (std::size_t k = 0; k < boundary_.size (); ++k) {
      const int n = cavity_[k];
      link (3 * n + 1, 3 * triangle_at_[vertex_[3 * n + 2]] + 2);
      if (!isGhost (n))
        last_finite_ = n;
    }
  }

  const std::vector<GridPoint>& points_;
  /** \brief Index of the infinite vertex: one past the last point. */
  const int infinite_;
  std::vector<int> vertex_;
  std::vector<int> opposite_;
  /** \brief Per triangle: the insertion that put it into the cavity last. */
  std::vector<std::uint32_t> stamp_;
  std::uint32_t current_stamp_ = 0;
  /** \brief Per point: the vertex at the same grid node, or -1. */
  std::vector<int> duplicate_of_;
  /** \brief Per vertex (and the infinite one): new triangle starting at it, scratch. */
  std::vector<int> triangle_at_;
  std::vector<int> cavity_;
  std::vector<int> stack_;
  std::vector<BoundaryEdge> boundary_;
  int last_finite_ = 0;
  std::uint32_t random_ = 2463534242u;
};

Delaunay2DResult
failure (std::string message)
{
  Delaunay2DResult result;
  result.message = "delaunay2D: " + std::move (message);
  return result;
}

Delaunay2DResult
triangulate (const Points2& points, const Delaunay2DOptions& options)
{
  const std::size_t n = points.size ();
  if (n < 3)
    return failure ("needs at least 3 points, got " + std::to_string (n) + ".");
  if (n > kMaxPoints)
    return failure ("more than " + std::to_string (kMaxPoints) + " points.");

  double max_abs = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite (points[i].x ()) || !std::isfinite (points[i].y ()))
      return failure ("point " + std::to_string (i) + " has a non-finite coordinate.");
    max_abs =
        std::max ({max_abs, std::abs (points[i].x ()), std::abs (points[i].y ())});
  }
  if (max_abs == 0.0)
    return failure ("all points coincide.");

  // Largest power of two 2^e with max_abs 2^e < 2^kGridBits: ldexp by it is exact, and
  // rounding changes only values below 2^52 (see GridPoint).
  const int exponent = kGridBits - 1 - std::ilogb (max_abs);
  const auto snap = [exponent] (double v) {
    return std::round (std::ldexp (v, exponent));
  };
  std::vector<GridPoint> order (n);
  for (std::size_t i = 0; i < n; ++i)
    order[i] = {snap (points[i].x ()), snap (points[i].y ()),
                static_cast<pcl::index_t> (i)};

  brioOrder (order, options.random_seed);

  // The construction starts from two distinct points and a third one off their line.
  std::size_t second = 1;
  while (second < n && sameNode (order[second], order[0]))
    ++second;
  if (second == n)
    return failure ("all points coincide.");
  std::swap (order[1], order[second]);
  std::size_t third = 2;
  while (third < n && orient (order[0], order[1], order[third]) == 0)
    ++third;
  if (third == n)
    return failure ("all points are collinear.");
  std::swap (order[2], order[third]);

  Delaunay2DResult result;
  DelaunayBuilder (order).extract (result);
  result.grid_spacing = std::ldexp (1.0, -exponent);
  result.success = true;
  return result;
}

} // namespace

Delaunay2DResult
delaunay2D (const Points2& points, const Delaunay2DOptions& options)
{
  // Only allocation can throw; the contract is to report, not to throw.
  try {
    return triangulate (points, options);
  } catch (const std::exception& e) {
    return failure (std::string ("out of resources: ") + e.what ());
  }
}

} // namespace meshless
} // namespace pcl
