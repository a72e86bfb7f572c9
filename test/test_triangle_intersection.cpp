// Exact predicates and the exact triangle-pair intersection test, on their contract.
#include <pcl/surface/meshless/triangle_intersection.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <tuple>

using namespace pcl::meshless;

namespace {

using Int128 = __int128;

int
sign (Int128 x)
{
  return (x > 0) - (x < 0);
}

/** The orientations as plain floating-point determinants, to show where they fail. */
int
naiveOrient2d (const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c)
{
  const double det = (b.x () - a.x ()) * (c.y () - a.y ()) - (b.y () - a.y ()) * (c.x () - a.x ());
  return (det > 0.0) - (det < 0.0);
}

int
naiveOrient3d (const Eigen::Vector3d& a,
               const Eigen::Vector3d& b,
               const Eigen::Vector3d& c,
               const Eigen::Vector3d& d)
{
  const double det = (b - a).dot ((c - a).cross (d - a));
  return (det > 0.0) - (det < 0.0);
}

/** Exact references on integer coordinates (below 2^30 in magnitude). */
int
exactOrient2d (const std::array<std::int64_t, 2>& a,
               const std::array<std::int64_t, 2>& b,
               const std::array<std::int64_t, 2>& c)
{
  return sign (Int128 (b[0] - a[0]) * (c[1] - a[1]) - Int128 (b[1] - a[1]) * (c[0] - a[0]));
}

int
exactOrient3d (const std::array<std::int64_t, 3>& a,
               const std::array<std::int64_t, 3>& b,
               const std::array<std::int64_t, 3>& c,
               const std::array<std::int64_t, 3>& d)
{
  const Int128 ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const Int128 vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const Int128 wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
  return sign (ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx));
}

Eigen::Vector3d
toVector (const std::array<std::int64_t, 3>& p)
{
  return {static_cast<double> (p[0]), static_cast<double> (p[1]), static_cast<double> (p[2])};
}

/** The test through every valid pair of projection axes and both argument orders:
  * the contract says the answer depends on neither. Checks that they agree and
  * returns the answer. */
bool
intersectAnyWay (const Points3& v, const Triangle& s, const Triangle& t)
{
  const bool answer = trianglesIntersect (v, s, t);
  EXPECT_EQ (trianglesIntersect (v, t, s), answer) << "order matters";
  for (int axis_s = 0; axis_s < 3; ++axis_s)
    for (int axis_t = 0; axis_t < 3; ++axis_t) {
      const auto flat = [&v] (const Triangle& x, int axis) {
        const auto project = [axis] (const Eigen::Vector3d& p) {
          return Eigen::Vector2d (p[(axis + 1) % 3], p[(axis + 2) % 3]);
        };
        return orient2d (project (v[x[0]]), project (v[x[1]]), project (v[x[2]])) == 0;
      };
      if (flat (s, axis_s) || flat (t, axis_t))
        continue; // not a valid projection axis for that triangle
      EXPECT_EQ (trianglesIntersect (v, s, axis_s, t, axis_t), answer)
          << "axes " << axis_s << " " << axis_t;
    }
  return answer;
}

const Points3 base = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};

/** base as triangle 0, 1, 2 and the given corners as triangle 3, 4, 5. */
bool
pairIntersects (const Points3& corners)
{
  Points3 v = base;
  v.insert (v.end (), corners.begin (), corners.end ());
  return intersectAnyWay (v, {0, 1, 2}, {3, 4, 5});
}

} // namespace

TEST (TriangleIntersection, ProjectionAxis)
{
  const Points3 v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 0, 0}, {0, 0, 0}};
  EXPECT_EQ (projectionAxis (v, {0, 1, 2}), 2); // in z = 0: drop z
  EXPECT_EQ (projectionAxis (v, {0, 2, 3}), 0); // in x = 0: drop x
  EXPECT_EQ (projectionAxis (v, {0, 1, 4}), -1); // collinear
  EXPECT_EQ (projectionAxis (v, {0, 1, 5}), -1); // two coincident points
  // Tilted: the dominant normal component is z.
  EXPECT_EQ (projectionAxis ({0, 0, 0}, {4, 0, 1}, {0, 4, 1}), 2);
}

TEST (TriangleIntersection, DisjointAndCrossing)
{
  // Parallel planes.
  EXPECT_FALSE (pairIntersects ({{0, 0, 1}, {2, 0, 1}, {0, 2, 1}}));
  // Piercing the interior at (0.5, 0.5, 0).
  EXPECT_TRUE (pairIntersects ({{0.5, 0.5, -1}, {0.5, 0.5, 1}, {3, 3, 0}}));
  // The same triangle lifted above the plane.
  EXPECT_FALSE (pairIntersects ({{0.5, 0.5, 1}, {0.5, 0.5, 2}, {3, 3, 1.5}}));
  // Crossing the plane beside the triangle (the boxes overlap).
  EXPECT_FALSE (pairIntersects ({{1.5, 1.5, -1}, {1.5, 1.5, 1}, {3, 3, 0}}));
  // Two edges crossing in their interiors, planes perpendicular.
  EXPECT_TRUE (pairIntersects ({{1, -1, 0}, {1, 1, 0}, {1, 0, 1}}));
  // Coplanar and disjoint, closer than their bounding boxes.
  EXPECT_FALSE (pairIntersects ({{1.1, 1.1, 0}, {3, 1, 0}, {1, 3, 0}}));
  // Coplanar, one inside the other; coplanar, edges crossing.
  EXPECT_TRUE (pairIntersects ({{0.2, 0.2, 0}, {0.5, 0.2, 0}, {0.2, 0.5, 0}}));
  EXPECT_TRUE (pairIntersects ({{1, -1, 0}, {1, 3, 0}, {3, 1, 0}}));
}

TEST (TriangleIntersection, TouchingAtAPointIntersects)
{
  // A vertex on the other's edge, coplanar and not.
  EXPECT_TRUE (pairIntersects ({{1, 0, 0}, {2, -1, 0}, {3, -1, 0}}));
  EXPECT_TRUE (pairIntersects ({{1, 0, 0}, {1, -1, 1}, {1, -1, -1}}));
  // A vertex on the other's interior, from above.
  EXPECT_TRUE (pairIntersects ({{0.5, 0.5, 0}, {1, 0.5, 1}, {0.5, 1, 1}}));
  // The same vertex lifted by the smallest positive double: apart.
  const double tiny = std::nextafter (0.0, 1.0);
  EXPECT_FALSE (pairIntersects ({{0.5, 0.5, tiny}, {1, 0.5, 1}, {0.5, 1, 1}}));
  // Coincident vertices under different indices.
  EXPECT_TRUE (pairIntersects ({{2, 0, 0}, {3, 0, 1}, {3, 1, 0}}));
  // Edges touching at one point, perpendicular and not coplanar.
  EXPECT_TRUE (pairIntersects ({{1, 1, 0}, {2, 2, 1}, {2, 2, -1}}));
}

TEST (TriangleIntersection, SharedVertexOnly)
{
  const Points3 v = {{0, 0, 0},    {2, 0, 0},      {0, 2, 0},   {-1, 0, 0.5},
                     {0, -1, 0.5}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {1, 0.2, 0},
                     {3, 1, 0},    {-1, -0.1, 0},  {-0.1, -1, 0}, {1, 0, 0}};
  // Only the shared vertex in common.
  EXPECT_FALSE (intersectAnyWay (v, {0, 1, 2}, {0, 3, 4}));
  // Through the other's interior from the shared vertex.
  EXPECT_TRUE (intersectAnyWay (v, {0, 1, 2}, {0, 5, 6}));
  // Coplanar, corners overlapping beyond the vertex.
  EXPECT_TRUE (intersectAnyWay (v, {0, 1, 2}, {0, 7, 8}));
  // Coplanar, corners touching only at the vertex.
  EXPECT_FALSE (intersectAnyWay (v, {0, 1, 2}, {0, 9, 10}));
  // An edge of one along an edge of the other beyond the vertex (different planes):
  // they have a segment in common, more than the vertex.
  EXPECT_TRUE (intersectAnyWay (v, {0, 1, 2}, {0, 11, 4}));
  // Orientation of the triangles does not matter.
  EXPECT_TRUE (intersectAnyWay (v, {0, 2, 1}, {0, 8, 7}));
  EXPECT_FALSE (intersectAnyWay (v, {0, 2, 1}, {0, 4, 3}));
}

TEST (TriangleIntersection, SharedEdge)
{
  const Points3 v = {{0, 0, 0},      {1, 0, 0},   {0, 1, 0},     {0.3, 0.5, 0},
                     {0.3, -0.5, 0}, {0.5, 0, 1}, {0.3, 0.5, 1e-9}};
  // Coplanar, the third vertices on the same side: a fold-over, whichever way round.
  EXPECT_TRUE (intersectAnyWay (v, {0, 1, 2}, {1, 0, 3}));
  EXPECT_TRUE (intersectAnyWay (v, {0, 1, 2}, {0, 1, 3}));
  // Coplanar, on opposite sides: only the edge in common.
  EXPECT_FALSE (intersectAnyWay (v, {0, 1, 2}, {1, 0, 4}));
  EXPECT_FALSE (intersectAnyWay (v, {0, 1, 2}, {0, 1, 4}));
  // Different planes: a sharp fold or a right angle is legal.
  EXPECT_FALSE (intersectAnyWay (v, {0, 1, 2}, {1, 0, 5}));
  EXPECT_FALSE (intersectAnyWay (v, {0, 1, 2}, {1, 0, 6}));
  // The same three indices: coinciding faces.
  EXPECT_TRUE (intersectAnyWay (v, {0, 1, 2}, {2, 1, 0}));
}

TEST (TriangleIntersection, DegenerateTrianglesAreLeftOut)
{
  const Points3 v = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0, 0}, {0.5, 0.5, 0}};
  EXPECT_FALSE (trianglesIntersect (v, {0, 1, 2}, {0, 1, 3})); // collinear
  EXPECT_FALSE (trianglesIntersect (v, {0, 1, 2}, {4, 4, 1})); // repeated index
}

TEST (TriangleIntersection, Orient2dExactWhereFloatingPointFails)
{
  // Integer points at lattice distance -2 .. 2 from the line through a and b (twice
  // the triangle's area is s in {-2, ..., 2}), with products of coordinate
  // differences near 2^60: the plain determinant, off by up to about 2^8, gets such
  // signs wrong; orient2d must not.
  std::mt19937_64 random (3);
  std::uniform_int_distribution<std::int64_t> coordinate (-(1 << 28), 1 << 28), step (-2, 2);
  int naive_wrong = 0, collinear = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const std::array<std::int64_t, 2> a{coordinate (random), coordinate (random)};
    const std::array<std::int64_t, 2> d{coordinate (random), coordinate (random)};
    // Extended Euclid: u d0 + v d1 = gcd; with gcd 1, w = (-v, u) has cross (d, w) = 1.
    std::int64_t r0 = d[0], r1 = d[1], u0 = 1, u1 = 0, v0 = 0, v1 = 1;
    while (r1 != 0) {
      const std::int64_t q = r0 / r1;
      std::tie (r0, r1) = std::make_tuple (r1, r0 - q * r1);
      std::tie (u0, u1) = std::make_tuple (u1, u0 - q * u1);
      std::tie (v0, v1) = std::make_tuple (v1, v0 - q * v1);
    }
    if (r0 != 1 && r0 != -1)
      continue;
    const std::array<std::int64_t, 2> w{-v0 * r0, u0 * r0};
    const std::int64_t s = step (random);
    const std::array<std::int64_t, 2> b{a[0] + d[0], a[1] + d[1]};
    const std::array<std::int64_t, 2> c{a[0] + 2 * d[0] + s * w[0], a[1] + 2 * d[1] + s * w[1]};
    const int expected = exactOrient2d (a, b, c);
    ASSERT_EQ (expected, (s > 0) - (s < 0));
    const Eigen::Vector2d pa (a[0], a[1]), pb (b[0], b[1]), pc (c[0], c[1]);
    ASSERT_EQ (orient2d (pa, pb, pc), expected) << "trial " << trial;
    ASSERT_EQ (orient2d (pb, pc, pa), expected) << "trial " << trial;
    ASSERT_EQ (orient2d (pb, pa, pc), -expected) << "trial " << trial;
    naive_wrong += naiveOrient2d (pa, pb, pc) != expected ? 1 : 0;
    collinear += expected == 0 ? 1 : 0;
  }
  EXPECT_GT (collinear, 1000);
  EXPECT_GT (naive_wrong, 1000) << "the configurations should defeat plain floating point";
  // Tiny coordinates: the products underflow, the sign must still be exact.
  const double tiny = std::ldexp (1.0, -1070);
  EXPECT_EQ (orient2d ({0, 0}, {tiny, 0}, {0, tiny}), 1);
  EXPECT_EQ (orient2d ({0, 0}, {0, tiny}, {tiny, 0}), -1);
  EXPECT_EQ (orient2d ({0, 0}, {2 * tiny, 2 * tiny}, {tiny, tiny}), 0);
}

TEST (TriangleIntersection, Orient3dExactOnNearCoplanarIntegerPoints)
{
  // Integer points on or next to the tilted plane z = x + y (2^29 range, so the
  // products exceed 2^53): plain floating point sees coplanar points off the plane.
  std::mt19937_64 random (5);
  std::uniform_int_distribution<std::int64_t> coordinate (-(1 << 29), 1 << 29), offset (-1, 1);
  int naive_wrong = 0, coplanar = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::array<std::array<std::int64_t, 3>, 4> p;
    for (auto& x : p) {
      x[0] = coordinate (random);
      x[1] = coordinate (random);
      x[2] = x[0] + x[1];
    }
    p[3][2] += offset (random);
    const int expected = exactOrient3d (p[0], p[1], p[2], p[3]);
    const Eigen::Vector3d a = toVector (p[0]), b = toVector (p[1]), c = toVector (p[2]),
                          d = toVector (p[3]);
    ASSERT_EQ (orient3d (a, b, c, d), expected) << "trial " << trial;
    const int certain = orient3dIfCertain (a, b, c, d);
    ASSERT_TRUE (certain == 0 || certain == expected) << "trial " << trial;
    naive_wrong += naiveOrient3d (a, b, c, d) != expected ? 1 : 0;
    coplanar += expected == 0 ? 1 : 0;
  }
  EXPECT_GT (coplanar, 1000);
  EXPECT_GT (naive_wrong, 100) << "the configurations should defeat plain floating point";
}

TEST (TriangleIntersection, NearDegenerateCoplanarIntegerConfigurations)
{
  // Triangles with integer vertices exactly on z = x + y: the plain determinant sees
  // them off the plane, which would turn a coplanar fold-over into a legal fold.
  std::mt19937_64 random (11);
  std::uniform_int_distribution<std::int64_t> coordinate (-(1 << 29), 1 << 29);
  int folds = 0, naive_off_plane = 0, overlapping_corners = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::array<std::array<std::int64_t, 3>, 5> p;
    for (auto& x : p) {
      x[0] = coordinate (random);
      x[1] = coordinate (random);
      x[2] = x[0] + x[1];
    }
    Points3 v;
    for (const auto& x : p)
      v.push_back (toVector (x));
    const auto side = [&p] (int from, int to, int k) {
      return exactOrient2d ({p[from][0], p[from][1]}, {p[to][0], p[to][1]},
                            {p[k][0], p[k][1]});
    };
    if (side (0, 1, 2) == 0 || side (0, 1, 3) == 0 || side (0, 3, 4) == 0)
      continue;
    naive_off_plane += naiveOrient3d (v[0], v[1], v[2], v[3]) != 0 ? 1 : 0;

    // Shared edge 0-1: a fold-over iff 2 and 3 lie on the same side of it.
    const bool fold = side (0, 1, 2) == side (0, 1, 3);
    folds += fold ? 1 : 0;
    ASSERT_EQ (intersectAnyWay (v, {0, 1, 2}, {1, 0, 3}), fold) << "trial " << trial;

    // Shared vertex 0: the corners at 0 overlap beyond it iff a ray of one lies in
    // the other's (closed) corner; each corner is narrower than pi.
    const auto inCorner = [&side] (int a, int b, int x) {
      const int turn = side (0, a, b);
      return side (0, a, x) * turn >= 0 && side (0, x, b) * turn >= 0;
    };
    const bool overlap = inCorner (1, 2, 3) || inCorner (1, 2, 4) || inCorner (3, 4, 1) ||
                         inCorner (3, 4, 2);
    overlapping_corners += overlap ? 1 : 0;
    ASSERT_EQ (intersectAnyWay (v, {0, 1, 2}, {0, 3, 4}), overlap) << "trial " << trial;
  }
  EXPECT_GT (folds, 500);
  EXPECT_GT (overlapping_corners, 500);
  EXPECT_GT (naive_off_plane, 500) << "the configurations should defeat plain floating point";
}

TEST (TriangleIntersection, AnswerIndependentOfAxesAndOrderOnSmallGrid)
{
  // Few points on a small grid: coplanar, touching and shared-index pairs of every
  // kind; intersectAnyWay checks that axes and argument order do not matter.
  std::mt19937 random (7);
  std::uniform_int_distribution<int> coordinate (0, 2), pick (0, 6);
  std::array<int, 4> tested{}, intersecting{};
  for (int trial = 0; trial < 20000; ++trial) {
    Points3 v;
    for (int i = 0; i < 7; ++i)
      v.emplace_back (coordinate (random), coordinate (random), coordinate (random));
    const Triangle s{pick (random), pick (random), pick (random)};
    const Triangle t{pick (random), pick (random), pick (random)};
    if (projectionAxis (v, s) < 0 || projectionAxis (v, t) < 0 || s[0] == s[1] ||
        s[1] == s[2] || s[2] == s[0] || t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      continue;
    int shared = 0;
    for (pcl::index_t i : s)
      for (pcl::index_t j : t)
        shared += i == j ? 1 : 0;
    const bool answer = intersectAnyWay (v, s, t);
    ++tested[shared];
    intersecting[shared] += answer ? 1 : 0;
    if (::testing::Test::HasFailure ())
      FAIL () << "trial " << trial;
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT (intersecting[k], 50) << k;
    EXPECT_GT (tested[k] - intersecting[k], 50) << k;
  }
  EXPECT_EQ (intersecting[3], tested[3]);
}
