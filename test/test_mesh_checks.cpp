// Mesh invariant checks: topology counts, orientation, exact self-intersection tests.
#include <pcl/surface/meshless/mesh_checks.h>

#include <gtest/gtest.h>

#include "test_support.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <iostream>
#include <map>
#include <random>

using namespace pcl::meshless;
using meshless_test::geodesicSphere;
using meshless_test::Mesh;

namespace {

constexpr double pi = 3.14159265358979323846;


Mesh
tetrahedron ()
{
  // Counter-clockwise seen from outside; enclosed volume 1/6.
  return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

Mesh
cube ()
{
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back (i & 1, (i >> 1) & 1, (i >> 2) & 1);
  // Two outward triangles per face; the last face is the top (z = 1).
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {0, 1, 5}, {0, 5, 4}, {0, 4, 6}, {0, 6, 2},
                 {1, 3, 7}, {1, 7, 5}, {2, 6, 7}, {2, 7, 3}, {4, 5, 7}, {4, 7, 6}};
  return m;
}

void
flipAll (Mesh& m)
{
  for (Triangle& t : m.triangles)
    std::swap (t[1], t[2]);
}

/** nu x nv quad grid on a torus (radii 2 and 0.7), each quad split in two. */
Mesh
gridTorus (int nu, int nv)
{
  Mesh m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double theta = 2 * pi * i / nu, phi = 2 * pi * j / nv;
      const double rho = 2.0 + 0.7 * std::cos (phi);
      m.vertices.emplace_back (rho * std::cos (theta), rho * std::sin (theta),
                               0.7 * std::sin (phi));
    }
  const auto id = [nu, nv] (int i, int j) {
    return ((i + nu) % nu) * nv + (j + nv) % nv;
  };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back ({id (i, j), id (i + 1, j), id (i + 1, j + 1)});
      m.triangles.push_back ({id (i, j), id (i + 1, j + 1), id (i, j + 1)});
    }
  return m;
}


/** Two separate triangles t and u given by their corners. */
MeshReport
checkPair (const Points3& t, const Points3& u)
{
  Points3 vertices = t;
  vertices.insert (vertices.end (), u.begin (), u.end ());
  return checkMesh (vertices, {{0, 1, 2}, {3, 4, 5}});
}

// Reference for the intersection tests on small integer coordinates, by a different
// method: closed convex sets are disjoint iff some axis separates their projections
// strictly; for triangles and segments the face normals, the cross products of edge
// directions and the in-plane edge normals are enough candidates.
using Int3 = std::array<long long, 3>;

Int3
sub (const Int3& a, const Int3& b)
{
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

Int3
cross (const Int3& a, const Int3& b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
          a[0] * b[1] - a[1] * b[0]};
}

long long
dot (const Int3& a, const Int3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/** Closed polygons (a segment or a non-degenerate triangle) p and q meet. */
bool
convexMeet (const std::vector<Int3>& p, const std::vector<Int3>& q)
{
  std::vector<Int3> edges, normals;
  for (const auto* s : {&p, &q}) {
    for (std::size_t i = 0; i + 1 < s->size () || (s->size () == 3 && i < 3); ++i)
      edges.push_back (sub ((*s)[(i + 1) % s->size ()], (*s)[i]));
    if (s->size () == 3)
      normals.push_back (cross (sub ((*s)[1], (*s)[0]), sub ((*s)[2], (*s)[0])));
  }
  std::vector<Int3> axes = normals;
  for (const Int3& e : edges) {
    for (const Int3& f : edges)
      axes.push_back (cross (e, f));
    for (const Int3& n : normals)
      axes.push_back (cross (n, e));
  }
  for (const Int3& axis : axes) {
    const auto range = [&axis] (const std::vector<Int3>& s) {
      long long lo = dot (axis, s[0]), hi = lo;
      for (const Int3& x : s) {
        lo = std::min (lo, dot (axis, x));
        hi = std::max (hi, dot (axis, x));
      }
      return std::make_pair (lo, hi);
    };
    const auto rp = range (p), rq = range (q);
    if (rp.second < rq.first || rq.second < rp.first)
      return false;
  }
  return true;
}

/** Whether faces s and t over `points` meet beyond what their shared indices allow. */
bool
referenceIntersect (const std::vector<Int3>& points,
                    const Triangle& s,
                    const Triangle& t)
{
  std::vector<int> only_s, only_t, shared;
  for (pcl::index_t i : s)
    (std::find (t.begin (), t.end (), i) != t.end () ? shared : only_s).push_back (i);
  for (pcl::index_t i : t)
    if (std::find (s.begin (), s.end (), i) == s.end ())
      only_t.push_back (i);
  const auto pts = [&points] (std::initializer_list<int> ids) {
    std::vector<Int3> r;
    for (int i : ids)
      r.push_back (points[i]);
    return r;
  };
  switch (shared.size ()) {
  case 0:
    return convexMeet (pts ({s[0], s[1], s[2]}), pts ({t[0], t[1], t[2]}));
  case 1: // beyond the vertex iff an edge opposite it meets the other face
    return convexMeet (pts ({only_s[0], only_s[1]}), pts ({t[0], t[1], t[2]})) ||
           convexMeet (pts ({only_t[0], only_t[1]}), pts ({s[0], s[1], s[2]}));
  case 2: { // beyond the edge iff coplanar and on the same side of it
    const Int3 u = points[shared[0]], e = sub (points[shared[1]], u);
    const Int3 na = cross (e, sub (points[only_s[0]], u));
    const Int3 nb = cross (e, sub (points[only_t[0]], u));
    return dot (cross (na, nb), cross (na, nb)) == 0 && dot (na, nb) > 0;
  }
  default:
    return true;
  }
}

const Points3 base_triangle = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};

/** The geometric figures of two reports of the same mesh agree exactly (pairs,
  * their list, volume, mean smallest angle). */
void
expectSameGeometry (const MeshReport& a, const MeshReport& b)
{
  EXPECT_EQ (a.self_intersecting_pairs, b.self_intersecting_pairs);
  EXPECT_EQ (a.intersecting_pairs, b.intersecting_pairs);
  EXPECT_EQ (a.signed_volume, b.signed_volume);
  EXPECT_EQ (a.mean_min_angle_deg, b.mean_min_angle_deg);
}

} // namespace

TEST (MeshChecks, Tetrahedron)
{
  Mesh m = tetrahedron ();
  const MeshReport r = checkMesh (m.vertices, m.triangles);
  ASSERT_TRUE (r.success) << r.message;
  EXPECT_EQ (r.num_vertices, 4u);
  EXPECT_EQ (r.num_triangles, 4u);
  EXPECT_EQ (r.num_faces, 4u);
  EXPECT_EQ (r.used_vertices, 4u);
  EXPECT_EQ (r.unused_vertices, 0u);
  EXPECT_EQ (r.num_edges, 6u);
  EXPECT_EQ (r.boundary_edges, 0u);
  EXPECT_EQ (r.boundary_loops, 0u);
  EXPECT_EQ (r.non_manifold_edges, 0u);
  EXPECT_EQ (r.non_manifold_vertices, 0u);
  EXPECT_EQ (r.inconsistent_edges, 0u);
  EXPECT_EQ (r.components, 1u);
  EXPECT_EQ (r.euler_characteristic, 2);
  EXPECT_EQ (r.genus, 0);
  EXPECT_EQ (r.degenerate_triangles, 0u);
  EXPECT_EQ (r.duplicate_triangles, 0u);
  EXPECT_TRUE (r.self_intersections_checked);
  EXPECT_EQ (r.self_intersecting_pairs, 0u);
  EXPECT_NEAR (r.signed_volume, 1.0 / 6.0, 1e-15);
  // Three right isosceles faces (45 deg) and one equilateral face (60 deg).
  EXPECT_NEAR (r.mean_min_angle_deg, (3 * 45.0 + 60.0) / 4.0, 1e-9);
  EXPECT_EQ (r.share_min_angle_below_10, 0.0);
  EXPECT_TRUE (r.isClosedManifold ());
  EXPECT_TRUE (r.isSphereLike ());
  EXPECT_FALSE (r.isDiscLike ());
  EXPECT_NE (describe (r).find ("Sphere-like"), std::string::npos) << describe (r);

  flipAll (m);
  const MeshReport flipped = checkMesh (m.vertices, m.triangles);
  EXPECT_NEAR (flipped.signed_volume, -1.0 / 6.0, 1e-15);
  EXPECT_TRUE (flipped.isSphereLike ()); // orientation is consistent, just inward
}

TEST (MeshChecks, TetrahedronWithOneFlippedTriangle)
{
  Mesh m = tetrahedron ();
  std::swap (m.triangles[3][1], m.triangles[3][2]);
  const MeshReport r = checkMesh (m.vertices, m.triangles);
  EXPECT_EQ (r.inconsistent_edges, 3u); // every edge of the flipped face
  EXPECT_EQ (r.boundary_edges, 0u);
  EXPECT_EQ (r.non_manifold_edges, 0u);
  EXPECT_EQ (r.euler_characteristic, 2);
  EXPECT_EQ (r.genus, -1);
  EXPECT_TRUE (r.isManifold ());
  EXPECT_FALSE (r.isOriented ());
  EXPECT_FALSE (r.isClosedManifold ());
  EXPECT_FALSE (r.isSphereLike ());
  EXPECT_EQ (r.self_intersecting_pairs, 0u);
}

TEST (MeshChecks, CubeWithOneFaceMissingIsDiscLike)
{
  Mesh m = cube ();
  const MeshReport closed = checkMesh (m.vertices, m.triangles);
  EXPECT_TRUE (closed.isSphereLike ());
  EXPECT_EQ (closed.num_edges, 18u);
  EXPECT_NEAR (closed.signed_volume, 1.0, 1e-15);
  EXPECT_EQ (closed.self_intersecting_pairs, 0u); // coplanar neighbours on each face

  m.triangles.resize (10); // drop the top face
  const MeshReport r = checkMesh (m.vertices, m.triangles);
  EXPECT_EQ (r.num_edges, 17u);
  EXPECT_EQ (r.boundary_edges, 4u);
  EXPECT_EQ (r.boundary_loops, 1u);
  EXPECT_EQ (r.euler_characteristic, 1);
  EXPECT_EQ (r.genus, 0);
  EXPECT_EQ (r.components, 1u);
  EXPECT_EQ (r.inconsistent_edges, 0u);
  EXPECT_EQ (r.non_manifold_vertices, 0u);
  EXPECT_TRUE (r.isDiscLike ());
  EXPECT_FALSE (r.isClosedManifold ());
  EXPECT_EQ (r.self_intersecting_pairs, 0u);
}

TEST (MeshChecks, TwoTrianglesSharingAnEdgeTheSameWayRound)
{
  const Points3 v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  const MeshReport r = checkMesh (v, {{0, 1, 2}, {0, 1, 3}});
  EXPECT_EQ (r.inconsistent_edges, 1u);
  EXPECT_EQ (r.num_edges, 5u);
  EXPECT_EQ (r.boundary_edges, 4u);
  EXPECT_EQ (r.boundary_loops, 1u);
  EXPECT_FALSE (r.isDiscLike ());
  EXPECT_EQ (r.self_intersecting_pairs, 0u); // coplanar, on opposite sides of the edge

  const MeshReport fixed = checkMesh (v, {{0, 1, 2}, {1, 0, 3}});
  EXPECT_EQ (fixed.inconsistent_edges, 0u);
  EXPECT_TRUE (fixed.isDiscLike ());
}

TEST (MeshChecks, CrossingTriangles)
{
  // The second triangle pierces the first at (0.5, 0.5, 0).
  const MeshReport r =
      checkPair (base_triangle, {{0.5, 0.5, -1}, {0.5, 0.5, 1}, {3, 3, 0}});
  EXPECT_EQ (r.self_intersecting_pairs, 1u);
  ASSERT_EQ (r.intersecting_pairs.size (), 1u);
  EXPECT_EQ (r.intersecting_pairs[0], std::make_pair (std::size_t{0}, std::size_t{1}));
  EXPECT_EQ (r.components, 2u);

  const MeshReport apart =
      checkPair (base_triangle, {{0.5, 0.5, 1}, {0.5, 0.5, 2}, {3, 3, 1.5}});
  EXPECT_EQ (apart.self_intersecting_pairs, 0u);
}

TEST (MeshChecks, TouchingCountsAsIntersecting)
{
  // A vertex on the other's edge, both in the plane z = 0.
  EXPECT_EQ (checkPair (base_triangle, {{1, 0, 0}, {2, -1, 0}, {3, -1, 0}})
                 .self_intersecting_pairs,
             1u);
  // A vertex on the other's interior, from above.
  EXPECT_EQ (checkPair (base_triangle, {{0.5, 0.5, 0}, {1, 0.5, 1}, {0.5, 1, 1}})
                 .self_intersecting_pairs,
             1u);
  // The same vertex lifted by the smallest positive double: apart.
  const double tiny = std::nextafter (0.0, 1.0);
  EXPECT_EQ (checkPair (base_triangle, {{0.5, 0.5, tiny}, {1, 0.5, 1}, {0.5, 1, 1}})
                 .self_intersecting_pairs,
             0u);
  // Coincident vertices with different indices touch.
  EXPECT_EQ (checkPair (base_triangle, {{2, 0, 0}, {3, 0, 1}, {3, 1, 0}})
                 .self_intersecting_pairs,
             1u);
  // Coplanar and disjoint, separated by less than the bounding boxes.
  EXPECT_EQ (checkPair (base_triangle, {{1.1, 1.1, 0}, {3, 1, 0}, {1, 3, 0}})
                 .self_intersecting_pairs,
             0u);
  // Coplanar, one inside the other.
  EXPECT_EQ (checkPair (base_triangle, {{0.2, 0.2, 0}, {0.5, 0.2, 0}, {0.2, 0.5, 0}})
                 .self_intersecting_pairs,
             1u);
}

TEST (MeshChecks, TrianglesSharingOnlyAVertex)
{
  const Points3 v = {{0, 0, 0},    {2, 0, 0},      {0, 2, 0},    {-1, 0, 0.5},
                     {0, -1, 0.5}, {0.5, 0.5, -1}, {0.5, 0.5, 1}};
  const MeshReport touching = checkMesh (v, {{0, 1, 2}, {0, 3, 4}});
  EXPECT_EQ (touching.self_intersecting_pairs, 0u);
  EXPECT_EQ (touching.non_manifold_vertices, 1u); // two fans at vertex 0
  // A triangle from the shared vertex through the other one's interior.
  const MeshReport crossing = checkMesh (v, {{0, 1, 2}, {0, 5, 6}});
  EXPECT_EQ (crossing.self_intersecting_pairs, 1u);
  // Coplanar, sectors at the shared vertex overlapping.
  const Points3 w = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0.2, 0}, {3, 1, 0}};
  EXPECT_EQ (checkMesh (w, {{0, 1, 2}, {0, 3, 4}}).self_intersecting_pairs, 1u);
  // Coplanar, sectors only touching at the shared vertex.
  const Points3 u = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {-1, -0.1, 0}, {-0.1, -1, 0}};
  EXPECT_EQ (checkMesh (u, {{0, 1, 2}, {0, 3, 4}}).self_intersecting_pairs, 0u);
}

TEST (MeshChecks, FoldedOverEdgeIsAnIntersection)
{
  // Second triangle on the same side of the shared edge, in the same plane, oriented
  // consistently: only geometry can tell.
  const Points3 v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.5, 0}};
  const MeshReport r = checkMesh (v, {{0, 1, 2}, {1, 0, 3}});
  EXPECT_EQ (r.inconsistent_edges, 0u);
  EXPECT_EQ (r.self_intersecting_pairs, 1u);
  // Lifted off the plane, it is a legal (sharp) fold.
  const Points3 lifted = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.5, 1e-9}};
  EXPECT_EQ (checkMesh (lifted, {{0, 1, 2}, {1, 0, 3}}).self_intersecting_pairs, 0u);
}

TEST (MeshChecks, ExactPredicatesOnNearlyCollinearPoints)
{
  // Folds across an edge in the tilted plane z = x, decided by on which side of the
  // line y = x the point p = (0.5 + i u, 0.5 + j u) lies (above iff j > i); u is one
  // unit in the last place of 0.5. Floating-point orientation tests get such
  // decisions wrong in a scattered pattern (Kettner et al.); exact ones may not.
  const double u = std::ldexp (1.0, -53);
  const Eigen::Vector3d q (12, 12, 12), r (18, 18, 18), a (0, 10, 0);
  for (int i = -40; i <= 40; ++i)
    for (int j = -40; j <= 40; ++j) {
      const Eigen::Vector3d p (0.5 + i * u, 0.5 + j * u, 0.5 + i * u);
      // Edge q-r, p opposite it: a fold iff p is above the line, like a.
      const MeshReport across = checkMesh ({q, r, a, p}, {{0, 1, 2}, {1, 0, 3}});
      EXPECT_EQ (across.degenerate_triangles, i == j ? 1u : 0u) << i << " " << j;
      EXPECT_EQ (across.self_intersecting_pairs, j > i ? 1u : 0u) << i << " " << j;
      // Edge p-r, q opposite it: q is above the line p-r iff p is below y = x.
      const MeshReport along = checkMesh ({p, r, a, q}, {{0, 1, 2}, {1, 0, 3}});
      EXPECT_EQ (along.degenerate_triangles, i == j ? 1u : 0u) << i << " " << j;
      EXPECT_EQ (along.self_intersecting_pairs, j < i ? 1u : 0u) << i << " " << j;
    }
}

TEST (MeshChecks, IntersectionsAgreeWithSeparatingAxisReference)
{
  // Few points on a small grid: coplanar, touching and shared-vertex configurations
  // of every kind are frequent.
  std::mt19937 random (7);
  std::uniform_int_distribution<int> coordinate (0, 3), pick (0, 7);
  MeshCheckOptions options;
  options.num_threads = 1;
  std::array<std::size_t, 4> tested{}, intersecting{};
  for (int trial = 0; trial < 100000; ++trial) {
    std::vector<Int3> points (8);
    Points3 vertices;
    for (Int3& p : points) {
      p = {coordinate (random), coordinate (random), coordinate (random)};
      vertices.emplace_back (p[0], p[1], p[2]);
    }
    const Triangle s{pick (random), pick (random), pick (random)};
    const Triangle t{pick (random), pick (random), pick (random)};
    const auto flat = [&points] (const Triangle& x) {
      const Int3 n =
          cross (sub (points[x[1]], points[x[0]]), sub (points[x[2]], points[x[0]]));
      return x[0] == x[1] || x[1] == x[2] || x[2] == x[0] || dot (n, n) == 0;
    };
    if (flat (s) || flat (t))
      continue;
    const bool expected = referenceIntersect (points, s, t);
    std::size_t shared = 0;
    for (pcl::index_t i : s)
      shared += std::count (t.begin (), t.end (), i);
    ++tested[shared];
    intersecting[shared] += expected ? 1 : 0;
    const MeshReport r = checkMesh (vertices, {s, t}, options);
    ASSERT_EQ (r.self_intersecting_pairs, expected ? 1u : 0u)
        << "trial " << trial << ", " << shared << " shared";
  }
  // Every kind of pair occurred, both intersecting and not.
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_GT (intersecting[k], 100u) << k;
    EXPECT_GT (tested[k] - intersecting[k], 100u) << k;
  }
}

TEST (MeshChecks, ExactPredicatesOnTiltedCoplanarPoints)
{
  // Points exactly on the plane z = x + y with 29-bit coordinates: floating-point
  // orientation tests round and see them off the plane. A face folded across a shared
  // edge onto the same side must still count, one on the other side must not.
  std::mt19937_64 random (11);
  const auto coordinate = [&random] {
    return static_cast<long long> (random () >> 35);
  };
  const double scale = std::ldexp (1.0, -40);
  std::size_t folds = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::array<std::array<long long, 2>, 4> xy;
    Points3 v;
    for (auto& p : xy) {
      p = {coordinate (), coordinate ()};
      v.emplace_back (p[0] * scale, p[1] * scale, (p[0] + p[1]) * scale);
    }
    const auto side = [&xy] (int k) {
      const long long ex = xy[1][0] - xy[0][0], ey = xy[1][1] - xy[0][1];
      const long long dx = xy[k][0] - xy[0][0], dy = xy[k][1] - xy[0][1];
      const long long c = ex * dy - ey * dx; // below 2^61: exact
      return (c > 0) - (c < 0);
    };
    if (side (2) == 0 || side (3) == 0)
      continue;
    const bool fold = side (2) == side (3);
    folds += fold ? 1 : 0;
    const MeshReport r = checkMesh (v, {{0, 1, 2}, {1, 0, 3}});
    ASSERT_EQ (r.self_intersecting_pairs, fold ? 1u : 0u) << "trial " << trial;
  }
  EXPECT_GT (folds, 100u);
}

TEST (MeshChecks, BowtieVertex)
{
  const Points3 v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  const MeshReport r = checkMesh (v, {{0, 1, 2}, {0, 3, 4}});
  EXPECT_EQ (r.non_manifold_vertices, 1u);
  EXPECT_EQ (r.non_manifold_edges, 0u);
  EXPECT_EQ (r.components, 1u);     // connected through the shared vertex
  EXPECT_EQ (r.boundary_loops, 1u); // the two loops touch at the vertex
  EXPECT_EQ (r.euler_characteristic, 1);
  EXPECT_EQ (r.genus, -1);
  EXPECT_FALSE (r.isManifold ());
  EXPECT_FALSE (r.isDiscLike ());
  EXPECT_EQ (r.self_intersecting_pairs, 0u);
}

TEST (MeshChecks, ThreeTrianglesOnOneEdge)
{
  const Points3 v = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  const MeshReport r = checkMesh (v, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_EQ (r.non_manifold_edges, 1u);
  EXPECT_EQ (r.non_manifold_vertices, 0u); // reported through the edge instead
  EXPECT_EQ (r.inconsistent_edges, 0u);    // only edges with two faces are judged
  EXPECT_EQ (r.num_edges, 7u);
  EXPECT_EQ (r.boundary_edges, 6u);
  EXPECT_FALSE (r.isManifold ());
  EXPECT_EQ (r.self_intersecting_pairs, 0u);
}

TEST (MeshChecks, GridTorusHasGenusOne)
{
  for (const auto& size : {std::make_pair (4, 4), std::make_pair (24, 12)}) {
    const Mesh m = gridTorus (size.first, size.second);
    const MeshReport r = checkMesh (m.vertices, m.triangles);
    const std::size_t n = static_cast<std::size_t> (size.first * size.second);
    EXPECT_EQ (r.used_vertices, n);
    EXPECT_EQ (r.num_edges, 3 * n);
    EXPECT_EQ (r.euler_characteristic, 0);
    EXPECT_EQ (r.genus, 1);
    EXPECT_EQ (r.components, 1u);
    EXPECT_TRUE (r.isClosedManifold ());
    EXPECT_FALSE (r.isSphereLike ());
    EXPECT_EQ (r.self_intersecting_pairs, 0u);
    EXPECT_GT (r.signed_volume, 0.0);
  }
  const Mesh fine = gridTorus (24, 12);
  // Two disjoint tori: genus adds up, components too.
  Mesh two = fine;
  for (const auto& p : fine.vertices)
    two.vertices.push_back (p + Eigen::Vector3d (10, 0, 0));
  const auto offset = static_cast<pcl::index_t> (fine.vertices.size ());
  for (const Triangle& t : fine.triangles)
    two.triangles.push_back ({t[0] + offset, t[1] + offset, t[2] + offset});
  const MeshReport r = checkMesh (two.vertices, two.triangles);
  EXPECT_EQ (r.components, 2u);
  EXPECT_EQ (r.genus, 2);
}

TEST (MeshChecks, UnusedDegenerateDuplicateAndInvalid)
{
  Mesh m = tetrahedron ();
  // 4, 5, 6 collinear; 7 and 8 unused.
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d (2, 0, 0), Eigen::Vector3d (3, 0, 0), Eigen::Vector3d (4, 0, 0),
        Eigen::Vector3d (9, 9, 9), Eigen::Vector3d (10, 10, 10)})
    m.vertices.push_back (p);
  m.triangles.push_back ({0, 0, 1});  // repeated index
  m.triangles.push_back ({4, 5, 6});  // zero area
  m.triangles.push_back ({1, 2, 3});  // duplicate, same orientation
  m.triangles.push_back ({0, 3, 1});  // duplicate of {0, 1, 3}, flipped
  m.triangles.push_back ({0, 1, 99}); // out of range
  m.triangles.push_back ({-1, 0, 1}); // out of range
  const MeshReport r = checkMesh (m.vertices, m.triangles);
  ASSERT_TRUE (r.success);
  EXPECT_EQ (r.num_vertices, 9u);
  EXPECT_EQ (r.num_triangles, 10u);
  EXPECT_EQ (r.invalid_triangles, 2u);
  EXPECT_EQ (r.num_faces, 7u);
  EXPECT_EQ (r.used_vertices, 7u);
  EXPECT_EQ (r.unused_vertices, 2u);
  EXPECT_EQ (r.degenerate_triangles, 2u);
  EXPECT_EQ (r.duplicate_triangles, 2u);
  EXPECT_EQ (r.num_edges, 9u);
  EXPECT_EQ (r.non_manifold_edges, 5u); // all tetrahedron edges but 0-2
  EXPECT_EQ (r.boundary_edges, 3u);     // the zero-area face's
  EXPECT_EQ (r.components, 2u);
  EXPECT_EQ (r.euler_characteristic, 7 - 9 + 7);
  EXPECT_EQ (r.self_intersecting_pairs, 2u); // each duplicate overlaps its original
  EXPECT_FALSE (r.isManifold ());
  EXPECT_EQ (r.genus, -1);

  // Coincident vertices make a degenerate face too; a non-finite vertex is counted
  // and its faces are left out of the geometry.
  Mesh n = tetrahedron ();
  n.vertices.push_back (n.vertices[0]);
  n.vertices.push_back ({std::nan (""), 0, 0});
  n.triangles.push_back ({4, 0, 1});
  n.triangles.push_back ({5, 1, 2});
  const MeshReport s = checkMesh (n.vertices, n.triangles);
  EXPECT_EQ (s.non_finite_vertices, 1u);
  EXPECT_EQ (s.degenerate_triangles, 1u);
}

TEST (MeshChecks, GeodesicSphereAndAVertexPushedThrough)
{
  Mesh m = geodesicSphere (64);
  ASSERT_EQ (m.triangles.size (), 81920u);
  const MeshReport r = checkMesh (m.vertices, m.triangles);
  EXPECT_EQ (r.used_vertices, 40962u);
  EXPECT_EQ (r.euler_characteristic, 2);
  EXPECT_TRUE (r.isSphereLike ());
  EXPECT_EQ (r.self_intersecting_pairs, 0u);
  EXPECT_EQ (r.degenerate_triangles, 0u);
  EXPECT_NEAR (r.signed_volume, 4.0 / 3.0 * pi, 1e-2);
  EXPECT_GT (r.mean_min_angle_deg, 45.0);

  // A dent is fine.
  m.vertices[1000] *= 0.99;
  EXPECT_EQ (checkMesh (m.vertices, m.triangles).self_intersecting_pairs, 0u);

  // Pushed through the far side, its fan crosses the surface there.
  m.vertices[1000] *= -1.2;
  MeshCheckOptions single;
  single.num_threads = 1;
  const MeshReport pierced = checkMesh (m.vertices, m.triangles, single);
  EXPECT_TRUE (pierced.isSphereLike ()); // topology is untouched
  EXPECT_GT (pierced.self_intersecting_pairs, 0u);
  ASSERT_FALSE (pierced.intersecting_pairs.empty ());

  // The same report, pair list included, with any number of threads.
  MeshCheckOptions several;
  several.num_threads = 3;
  const MeshReport again = checkMesh (m.vertices, m.triangles, several);
  expectSameGeometry (again, pierced);
}

TEST (MeshChecks, TopologyBesideGeometryGivesTheSameReport)
{
  // Large enough for the topology to run beside the geometry with several
  // threads (concurrent_from); with one thread they run one after the other.
  Mesh m = geodesicSphere (80);
  ASSERT_GE (m.triangles.size (), 100000u);
  m.vertices[1000] *= -1.2;   // a fan through the far side: pairs to find
  m.triangles.push_back (m.triangles[5]); // a duplicate: topology and geometry both count
  m.triangles.push_back ({7, 7, 8});      // a repeated index (topology's degenerate)
  MeshCheckOptions single;
  single.num_threads = 1;
  single.max_listed_intersections = 64;
  MeshCheckOptions two = single;
  two.num_threads = 2;
  const MeshReport a = checkMesh (m.vertices, m.triangles, single);
  const MeshReport b = checkMesh (m.vertices, m.triangles, two);
  ASSERT_TRUE (a.success && b.success);
  EXPECT_GT (a.self_intersecting_pairs, 0u);
  EXPECT_FALSE (a.intersecting_pairs.empty ());
  EXPECT_EQ (a.degenerate_triangles, 1u);
  EXPECT_EQ (a.duplicate_triangles, 1u);
  EXPECT_GT (a.signed_volume, 3.0);
  EXPECT_GT (a.mean_min_angle_deg, 40.0);
  EXPECT_EQ (describe (a), describe (b));
  EXPECT_EQ (a.num_faces, b.num_faces);
  EXPECT_EQ (a.num_edges, b.num_edges);
  EXPECT_EQ (a.degenerate_triangles, b.degenerate_triangles);
  EXPECT_EQ (a.duplicate_triangles, b.duplicate_triangles);
  EXPECT_EQ (a.non_manifold_edges, b.non_manifold_edges);
  EXPECT_EQ (a.euler_characteristic, b.euler_characteristic);
  expectSameGeometry (a, b);
  EXPECT_EQ (a.share_min_angle_below_10, b.share_min_angle_below_10);
}

TEST (MeshChecks, PairsKnownApartAreNotTestedAndTheRestAreAllFound)
{
  // The pierced geodesic sphere, checked again after an earlier check: what the
  // earlier one found and what changed since must be tested, the rest need not.
  Mesh m = geodesicSphere (48);
  m.vertices[1000] *= -1.2; // a fan through the far side
  MeshCheckOptions full;
  full.max_listed_intersections = 65536;
  const MeshReport reference = checkMesh (m.vertices, m.triangles, full);
  ASSERT_GT (reference.self_intersecting_pairs, 0u);
  ASSERT_EQ (reference.intersecting_pairs.size (), reference.self_intersecting_pairs);

  // Everything known apart but the triangles of the pairs: the same report.
  std::vector<char> known (m.triangles.size (), 1);
  for (const auto& [s, t] : reference.intersecting_pairs)
    known[s] = known[t] = 0;
  MeshCheckOptions masked = full;
  masked.known_apart = &known;
  const MeshReport same = checkMesh (m.vertices, m.triangles, masked);
  EXPECT_EQ (same.self_intersecting_pairs, reference.self_intersecting_pairs);
  EXPECT_EQ (same.intersecting_pairs, reference.intersecting_pairs);
  EXPECT_EQ (describe (same), describe (reference));

  // Only the fan's side of each pair left to test (the far side known apart from
  // the rest): still all found, since each pair has a triangle to test.
  std::vector<char> fan_only (m.triangles.size (), 1);
  for (std::size_t t = 0; t < m.triangles.size (); ++t)
    for (const pcl::index_t v : m.triangles[t])
      if (v == 1000)
        fan_only[t] = 0;
  masked.known_apart = &fan_only;
  EXPECT_EQ (checkMesh (m.vertices, m.triangles, masked).intersecting_pairs,
             reference.intersecting_pairs);

  // The caller vouches: pairs of two triangles it marks are not tested at all.
  std::vector<char> all (m.triangles.size (), 1);
  masked.known_apart = &all;
  const MeshReport vouched = checkMesh (m.vertices, m.triangles, masked);
  EXPECT_EQ (vouched.self_intersecting_pairs, 0u);
  EXPECT_TRUE (vouched.isSphereLike ()); // topology in full all the same

  // A mask of the wrong size is ignored.
  std::vector<char> short_mask (10, 1);
  masked.known_apart = &short_mask;
  EXPECT_EQ (checkMesh (m.vertices, m.triangles, masked).self_intersecting_pairs,
             reference.self_intersecting_pairs);
}

TEST (MeshChecks, EmptyAndUncheckedIntersections)
{
  const MeshReport empty = checkMesh ({}, {});
  EXPECT_TRUE (empty.success);
  EXPECT_FALSE (empty.isManifold ());
  EXPECT_EQ (empty.genus, -1);
  EXPECT_FALSE (describe (empty).empty ());

  const Mesh m = tetrahedron ();
  MeshCheckOptions options;
  options.check_self_intersections = false;
  const MeshReport r = checkMesh (m.vertices, m.triangles, options);
  EXPECT_FALSE (r.self_intersections_checked);
  EXPECT_NE (describe (r).find ("not checked"), std::string::npos) << describe (r);
}

TEST (MeshChecks, LargeSpherePerformance)
{
  const Mesh m = geodesicSphere (316);
  ASSERT_EQ (m.triangles.size (), 1997120u);
  const auto start = std::chrono::steady_clock::now ();
  const MeshReport r = checkMesh (m.vertices, m.triangles);
  const double seconds =
      std::chrono::duration<double> (std::chrono::steady_clock::now () - start)
          .count ();
  EXPECT_TRUE (r.isSphereLike ());
  EXPECT_EQ (r.self_intersecting_pairs, 0u);
  std::cout << "checkMesh on " << m.triangles.size () << " triangles: " << seconds
            << " s\n"
            << describe (r) << "\n";
  RecordProperty ("seconds", std::to_string (seconds));
}

TEST (MeshChecks, AreaFacingAgainstNormals)
{
  Mesh m = tetrahedron ();
  // Normals from the centroid out: every face agrees with them.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
  for (const auto& p : m.vertices)
    centroid += p / 4.0;
  std::vector<Eigen::Vector3f> outward;
  for (const auto& p : m.vertices)
    outward.push_back ((p - centroid).template cast<float> ());
  EXPECT_DOUBLE_EQ (areaFacingAgainstNormals (m.vertices, m.triangles, outward), 0.0);

  std::vector<Eigen::Vector3f> inward;
  for (const auto& n : outward)
    inward.push_back (-n);
  EXPECT_DOUBLE_EQ (areaFacingAgainstNormals (m.vertices, m.triangles, inward), 1.0);

  // One face turned round: exactly its share of the area.
  Mesh flipped = m;
  std::swap (flipped.triangles[0][1], flipped.triangles[0][2]);
  double total = 0.0;
  for (const auto& t : m.triangles)
    total += (m.vertices[t[1]] - m.vertices[t[0]]).cross (m.vertices[t[2]] - m.vertices[t[0]]).norm ();
  const auto& t0 = m.triangles[0];
  const double first =
      (m.vertices[t0[1]] - m.vertices[t0[0]]).cross (m.vertices[t0[2]] - m.vertices[t0[0]]).norm ();
  EXPECT_NEAR (areaFacingAgainstNormals (flipped.vertices, flipped.triangles, outward), first / total,
               1e-12);
  EXPECT_DOUBLE_EQ (areaFacingAgainstNormals ({}, {}, {}), 0.0);
}

TEST (MeshChecks, DistantIntersectingPairsTellFoldsFromCrossings)
{
  Mesh m = geodesicSphere (8);
  const std::size_t n = m.vertices.size ();
  MeshCheckOptions all;
  all.max_listed_intersections = 65536;
  ASSERT_EQ (checkMesh (m.vertices, m.triangles, all).self_intersecting_pairs, 0u);

  // A local fold: vertex 100 moved past its neighbour, so its fan folds over the
  // triangles around that neighbour.
  Mesh folded = m;
  pcl::index_t neighbour = -1;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] == 100)
        neighbour = t[(k + 1) % 3];
  ASSERT_GE (neighbour, 0);
  const Eigen::Vector3d step = m.vertices[neighbour] - m.vertices[100];
  folded.vertices[100] = (m.vertices[neighbour] + 0.6 * step).normalized ();
  const MeshReport fold = checkMesh (folded.vertices, folded.triangles, all);
  ASSERT_GT (fold.self_intersecting_pairs, 0u);
  ASSERT_EQ (fold.intersecting_pairs.size (), fold.self_intersecting_pairs);
  EXPECT_EQ (distantIntersectingPairs (n, folded.triangles, fold.intersecting_pairs, 2), 0u);

  // A crossing: the same vertex pushed through the far side of the sphere, its fan
  // cuts the surface about half a circumference (some 20 edges) away.
  Mesh pierced = m;
  pierced.vertices[100] *= -1.2;
  const MeshReport cross = checkMesh (pierced.vertices, pierced.triangles, all);
  ASSERT_GT (cross.self_intersecting_pairs, 0u);
  const std::size_t far = distantIntersectingPairs (n, pierced.triangles, cross.intersecting_pairs, 8);
  EXPECT_GT (far, 0u);
  EXPECT_LE (far, cross.self_intersecting_pairs);
  // Every triangle of the sphere is within a few dozen edges of every other.
  EXPECT_EQ (distantIntersectingPairs (n, pierced.triangles, cross.intersecting_pairs, 100), 0u);

  // Pairs or triangles out of range are ignored, not read.
  Triangles broken = pierced.triangles;
  broken.push_back ({0, 1, static_cast<pcl::index_t> (n)});
  const std::vector<std::pair<std::size_t, std::size_t>> bad{
      {0, broken.size () + 5}, {broken.size () - 1, 0}};
  EXPECT_EQ (distantIntersectingPairs (n, broken, bad, 0), 0u);
  EXPECT_EQ (distantIntersectingPairs (0, {}, {}, 3), 0u);
}

TEST (MeshChecks, NeighboursSeparatedByTheMeshShowAHandleCutThrough)
{
  // A torus meshed faithfully keeps every point's nearest neighbours within a few
  // edges. Cut through its tube and capped at both ends, it is a closed genus-0
  // mesh through the same points without any intersection, and the neighbours
  // across the cut lie a whole loop apart.
  const int nu = 48, nv = 12;
  const Mesh torus = gridTorus (nu, nv);
  std::vector<Eigen::Vector3f> normals;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double theta = 2 * pi * i / nu, phi = 2 * pi * j / nv;
      normals.emplace_back (static_cast<float> (std::cos (theta) * std::cos (phi)),
                            static_cast<float> (std::sin (theta) * std::cos (phi)),
                            static_cast<float> (std::sin (phi)));
    }
  const CsrGraph neighbours = meshless_test::bruteForceKnn (torus.vertices, 8);
  EXPECT_EQ (neighboursSeparatedByTheMesh (torus.vertices, torus.triangles, neighbours, normals, 16),
             0u);

  Mesh capped = torus;
  capped.triangles.clear ();
  const auto id = [] (int i, int j) { return static_cast<pcl::index_t> (i * nv + j); };
  for (int i = 0; i + 1 < nu; ++i) // every quad but those from the last ring to the first
    for (int j = 0; j < nv; ++j) {
      capped.triangles.push_back ({id (i, j), id (i + 1, j), id (i + 1, (j + 1) % nv)});
      capped.triangles.push_back ({id (i, j), id (i + 1, (j + 1) % nv), id (i, (j + 1) % nv)});
    }
  for (int j = 1; j + 1 < nv; ++j) { // a fan over each end, turned outwards
    capped.triangles.push_back ({id (0, 0), id (0, j), id (0, j + 1)});
    capped.triangles.push_back ({id (nu - 1, 0), id (nu - 1, j + 1), id (nu - 1, j)});
  }
  const MeshReport report = checkMesh (capped.vertices, capped.triangles);
  ASSERT_TRUE (report.isSphereLike ()) << describe (report);
  const std::size_t cut =
      neighboursSeparatedByTheMesh (capped.vertices, capped.triangles, neighbours, normals, 16);
  EXPECT_GE (cut, static_cast<std::size_t> (2 * nv)) << "both ends' points see the other end";
  // Within 48 hops the way round the other side is found.
  EXPECT_EQ (neighboursSeparatedByTheMesh (capped.vertices, capped.triangles, neighbours, normals, 48),
             0u);
  // Where the normals point apart (the two sides of a thin part), nothing counts:
  // the last rings turned, as far as the first ring's neighbours reach.
  std::vector<Eigen::Vector3f> apart = normals;
  for (int i = nu - 4; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
      apart[id (i, j)] = -apart[id (i, j)];
  EXPECT_EQ (neighboursSeparatedByTheMesh (capped.vertices, capped.triangles, neighbours, apart, 16),
             0u);
  // Points without a normal are skipped.
  std::vector<Eigen::Vector3f> unknown = normals;
  for (int i = nu - 4; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
      unknown[id (i, j)] = Eigen::Vector3f::Zero ();
  EXPECT_EQ (neighboursSeparatedByTheMesh (capped.vertices, capped.triangles, neighbours, unknown, 16),
             0u);
  // Sizes that do not match the points give 0.
  EXPECT_EQ (neighboursSeparatedByTheMesh (capped.vertices, capped.triangles, neighbours, {}, 16),
             0u);
}
