// Mesh-to-mesh distance: point-triangle distance, the nearest-triangle index against
// brute force, sampled distances between meshes whose distances are known, and edge
// comparison with a reference on hand-built cubes.
#include <meshless_tools/mesh_distance.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace pcl::meshless;

namespace {

constexpr double pi = 3.14159265358979323846;

struct Mesh
{
  Points3 vertices;
  Triangles triangles;
};

/** The unit square [0, w] x [0, 1] in the plane z = slope * x + height, two triangles
  * counter-clockwise seen from +z. */
Mesh
square (double height, double slope = 0.0, double width = 1.0)
{
  auto z = [&] (double x) { return height + slope * x; };
  return {{{0, 0, z (0)}, {width, 0, z (width)}, {width, 1, z (width)}, {0, 1, z (0)}},
          {{0, 1, 2}, {0, 2, 3}}};
}

Mesh
tetrahedron (const Eigen::Vector3d& shift = Eigen::Vector3d::Zero ())
{
  return {{shift, Eigen::Vector3d (1, 0, 0) + shift, Eigen::Vector3d (0, 1, 0) + shift,
           Eigen::Vector3d (0, 0, 1) + shift},
          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

MeshDistanceReport
compare (const Mesh& mesh, const Mesh& reference, std::size_t samples = 100000)
{
  MeshDistanceOptions options;
  options.samples = samples;
  return compareToReference (mesh.vertices, mesh.triangles, reference.vertices,
                             reference.triangles, options);
}

} // namespace

TEST (ClosestPointOnTriangle, EveryVoronoiRegion)
{
  const Eigen::Vector3d a (0, 0, 0), b (2, 0, 0), c (0, 2, 0);
  auto expect = [&] (const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    EXPECT_LT ((closestPointOnTriangle (p, a, b, c) - q).norm (), 1e-12)
        << p.transpose ();
  };
  expect ({0.5, 0.5, 3}, {0.5, 0.5, 0}); // face
  expect ({-1, -1, 1}, a);               // vertex regions
  expect ({3, -1, 0}, b);
  expect ({-1, 3, -2}, c);
  expect ({1, -1, 1}, {1, 0, 0}); // edge ab
  expect ({-1, 1, 0}, {0, 1, 0}); // edge ca
  expect ({2, 2, 0}, {1, 1, 0});  // edge bc
  // Zero area: the segment from a to b (c in between).
  EXPECT_LT ((closestPointOnTriangle ({3, 1, 0}, a, b, {1, 0, 0}) - b).norm (), 1e-12);
}

TEST (TriangleDistanceIndex, MatchesBruteForceWithLargeAndSmallTriangles)
{
  // A soup of small triangles next to large ones: the nearest triangle is often not
  // the one with the nearest centroid.
  std::mt19937 generator (7);
  std::uniform_real_distribution<double> coordinate (-1.0, 1.0), size (0.001, 1.5);
  Mesh soup;
  for (int t = 0; t < 400; ++t) {
    const Eigen::Vector3d centre (coordinate (generator), coordinate (generator),
                                  coordinate (generator));
    const double s = t % 10 == 0 ? size (generator) * 3.0 : size (generator) * 0.1;
    for (int k = 0; k < 3; ++k)
      soup.vertices.push_back (centre + s * Eigen::Vector3d (coordinate (generator),
                                                             coordinate (generator),
                                                             coordinate (generator)));
    soup.triangles.push_back ({3 * t, 3 * t + 1, 3 * t + 2});
  }
  soup.triangles.push_back ({0, 1, 5000}); // out of range: ignored
  const TriangleDistanceIndex index (soup.vertices, soup.triangles);
  EXPECT_EQ (index.size (), 400u);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p (2 * coordinate (generator), 2 * coordinate (generator),
                             2 * coordinate (generator));
    double best = std::numeric_limits<double>::infinity ();
    for (std::size_t t = 0; t < 400; ++t) {
      const Triangle& tri = soup.triangles[t];
      best = std::min (
          best, (closestPointOnTriangle (p, soup.vertices[tri[0]],
                                         soup.vertices[tri[1]], soup.vertices[tri[2]]) -
                 p)
                    .norm ());
    }
    const ClosestPoint found = index.closest (p);
    ASSERT_EQ (found.distance, best) << "query " << i;
    EXPECT_NEAR ((found.point - p).norm (), best, 1e-15);
  }
}

TEST (TriangleDistanceIndex, EmptyMesh)
{
  const Points3 vertices;
  const Triangles triangles;
  const TriangleDistanceIndex index (vertices, triangles);
  EXPECT_TRUE (std::isinf (index.closest (Eigen::Vector3d::Zero ()).distance));
}

TEST (CompareToReference, MeshAgainstItselfIsZero)
{
  const Mesh tet = tetrahedron ();
  const MeshDistanceReport report = compare (tet, tet);
  ASSERT_TRUE (report.success) << report.message;
  EXPECT_DOUBLE_EQ (report.diagonal, std::sqrt (3.0));
  EXPECT_LT (report.two_sided.max, 1e-12);
  // acos near 1 turns a rounding error of 1e-16 into 1e-8 radians.
  EXPECT_NEAR (report.normal_deviation_deg, 0.0, 1e-5);
}

TEST (CompareToReference, ParallelPlanesAtDistanceD)
{
  const double d = 0.25;
  const MeshDistanceReport report = compare (square (d), square (0.0), 20000);
  ASSERT_TRUE (report.success) << report.message;
  const double relative = d / std::sqrt (2.0);
  for (const DistanceStatistics* s :
       {&report.to_reference, &report.from_reference, &report.two_sided}) {
    EXPECT_NEAR (s->mean, relative, 1e-12);
    EXPECT_NEAR (s->p99, relative, 1e-12);
    EXPECT_NEAR (s->max, relative, 1e-12);
  }
  EXPECT_NEAR (report.normal_deviation_deg, 0.0, 1e-5);
}

TEST (CompareToReference, LatticeFindsTheApexThatSamplesMiss)
{
  // A pyramid of height h over the unit square: the mesh is farthest from the
  // square at its apex, a single point a random sample all but never hits.
  const double h = 0.3;
  const Mesh pyramid{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, h}},
                     {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}};
  MeshDistanceOptions options;
  options.samples = 200;
  const MeshDistanceReport sampled = compareToReference (
      pyramid.vertices, pyramid.triangles, square (0.0).vertices, square (0.0).triangles, options);
  options.lattice_for_max = 3; // the apex is a lattice point of every face
  const MeshDistanceReport lattice = compareToReference (
      pyramid.vertices, pyramid.triangles, square (0.0).vertices, square (0.0).triangles, options);
  ASSERT_TRUE (sampled.success && lattice.success);
  const double apex = h / std::sqrt (2.0);
  EXPECT_LT (sampled.to_reference.max, 0.99 * apex);
  EXPECT_NEAR (lattice.to_reference.max, apex, 1e-12);
  EXPECT_NEAR (lattice.two_sided.max, apex, 1e-12);
  // Every point of the square lies within h of the pyramid; the lattice can only
  // raise the sampled maximum.
  EXPECT_LE (lattice.from_reference.max, apex + 1e-12);
  EXPECT_GE (lattice.from_reference.max, sampled.from_reference.max);
  // The means do not change.
  EXPECT_EQ (lattice.to_reference.mean, sampled.to_reference.mean);
  EXPECT_EQ (lattice.two_sided.p99, sampled.two_sided.p99);
}

TEST (CompareToReference, HalfOfTheSurfaceMissing)
{
  // The mesh covers x in [0, 0.5] of the reference square: nothing strays, but the
  // other half of the reference is x - 0.5 away. Distances in units of sqrt(2).
  const MeshDistanceReport report = compare (square (0.0, 0.0, 0.5), square (0.0));
  ASSERT_TRUE (report.success) << report.message;
  const double unit = std::sqrt (2.0);
  EXPECT_LT (report.to_reference.max, 1e-12);
  // x uniform on [0, 1]: mean of max (0, x - 0.5) is 1/8, its max 1/2.
  EXPECT_NEAR (report.from_reference.mean * unit, 0.125, 0.002);
  EXPECT_NEAR (report.from_reference.max * unit, 0.5, 0.001);
  EXPECT_NEAR (report.from_reference.p99 * unit, 0.49, 0.002);
  // Pooled with as many zeros: mean 1/16, and P(D <= t) = 0.75 + t / 2 gives p99 0.48.
  EXPECT_NEAR (report.two_sided.mean * unit, 0.0625, 0.001);
  EXPECT_NEAR (report.two_sided.p99 * unit, 0.48, 0.002);
}

TEST (CompareToReference, TiltedPlaneDeviatesByItsAngle)
{
  const double angle = 20.0;
  const MeshDistanceReport report =
      compare (square (0.5, std::tan (angle * pi / 180.0)), square (0.5), 1000);
  ASSERT_TRUE (report.success) << report.message;
  EXPECT_NEAR (report.normal_deviation_deg, angle, 1e-5);
  // Planes, not orientations: the same square turned over deviates by 0 degrees.
  Mesh flipped = square (0.5);
  for (Triangle& t : flipped.triangles)
    std::swap (t[1], t[2]);
  EXPECT_NEAR (compare (flipped, square (0.5), 1000).normal_deviation_deg, 0.0, 1e-5);
}

TEST (CompareToReference, TetrahedronAgainstShiftedCopy)
{
  // Shifted up by delta: the bottom face of the original lies exactly delta below the
  // copy's bottom face, and no point is farther than delta from the copy (p + shift
  // is on it). The bottom face is a fifth of the area, so p99 and max are delta.
  // Every face's centroid is nearest to the parallel face of the copy.
  const double delta = 0.05;
  const MeshDistanceReport report =
      compare (tetrahedron (), tetrahedron (Eigen::Vector3d (0, 0, delta)));
  ASSERT_TRUE (report.success) << report.message;
  const double relative = delta / std::sqrt (3.0);
  EXPECT_NEAR (report.to_reference.max, relative, 1e-12);
  EXPECT_NEAR (report.to_reference.p99, relative, 1e-12);
  EXPECT_NEAR (report.two_sided.max, relative, 1e-12);
  EXPECT_GT (report.two_sided.mean, 0.0);
  EXPECT_LT (report.two_sided.mean, relative);
  EXPECT_NEAR (report.normal_deviation_deg, 0.0, 1e-5);
}

TEST (CompareToReference, DeterministicAcrossThreadCounts)
{
  MeshDistanceOptions one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  const Mesh mesh = tetrahedron (Eigen::Vector3d (0.01, 0.02, 0.03));
  const Mesh reference = tetrahedron ();
  const MeshDistanceReport a = compareToReference (
      mesh.vertices, mesh.triangles, reference.vertices, reference.triangles, one);
  const MeshDistanceReport b = compareToReference (
      mesh.vertices, mesh.triangles, reference.vertices, reference.triangles, two);
  EXPECT_EQ (a.two_sided.mean, b.two_sided.mean);
  EXPECT_EQ (a.two_sided.p99, b.two_sided.p99);
  EXPECT_EQ (a.normal_deviation_deg, b.normal_deviation_deg);
}

TEST (CompareToReference, FailsWithoutTriangles)
{
  const Mesh tet = tetrahedron ();
  const MeshDistanceReport report =
      compareToReference (tet.vertices, {}, tet.vertices, tet.triangles);
  EXPECT_FALSE (report.success);
  EXPECT_EQ (report.message, "the mesh has no triangle of positive area");
}

namespace {

/** The unit cube, vertex x + 2y + 4z at (x, y, z), each face split into two
  * counter-clockwise triangles: 12 feature edges (90 degrees), 6 flat diagonals. */
Mesh
cube ()
{
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back (i & 1, (i >> 1) & 1, (i >> 2) & 1);
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

/** The same mesh with its vertices stored in reverse order. */
Mesh
reversed (const Mesh& m)
{
  const auto n = static_cast<pcl::index_t> (m.vertices.size ());
  Mesh r;
  r.vertices.assign (m.vertices.rbegin (), m.vertices.rend ());
  for (const Triangle& t : m.triangles)
    r.triangles.push_back ({n - 1 - t[0], n - 1 - t[1], n - 1 - t[2]});
  return r;
}

EdgeComparison
compareCube (const Mesh& mesh, const Mesh& reference = cube ())
{
  return compareEdges (mesh.vertices, mesh.triangles, reference.vertices,
                       reference.triangles);
}

} // namespace

TEST (MatchVerticesByPosition, ExactPositionsInAnyOrderSmallestIndexFirst)
{
  const Eigen::Vector3d p (0.1, 0.2, 0.3), q (-1, 0, 2);
  const Points3 reference{p, q, p};
  const double nan = std::numeric_limits<double>::quiet_NaN ();
  const Points3 points{q, p, {0.1, 0.2, std::nextafter (0.3, 1.0)}, {nan, 0, 0}};
  const std::vector<pcl::index_t> match = matchVerticesByPosition (points, reference);
  EXPECT_EQ (match, (std::vector<pcl::index_t>{1, 0, -1, -1}));
}

TEST (CompareEdges, SameMeshInAnotherVertexOrder)
{
  const EdgeComparison c = compareCube (reversed (cube ()));
  ASSERT_TRUE (c.success) << c.message;
  EXPECT_EQ (c.edges, 18u);
  EXPECT_EQ (c.unmatched_vertices, 0u);
  EXPECT_EQ (c.reference_edges, 18u);
  EXPECT_DOUBLE_EQ (c.reference_edge_fraction, 1.0);
  EXPECT_EQ (c.sharp_edges, 12u); // the cube's edges, not the face diagonals
  EXPECT_EQ (c.sharp_edges_found, 12u);
  EXPECT_DOUBLE_EQ (c.sharp_edge_fraction, 1.0);
}

TEST (CompareEdges, FlippedDiagonalKeepsTheFeatureEdges)
{
  Mesh mesh = cube ();
  // Bottom face: diagonal 0-3 becomes 1-2.
  mesh.triangles[0] = {0, 2, 1};
  mesh.triangles[1] = {2, 3, 1};
  const EdgeComparison c = compareCube (reversed (mesh));
  EXPECT_EQ (c.edges, 18u);
  EXPECT_EQ (c.reference_edges, 17u);
  EXPECT_EQ (c.sharp_edges_found, 12u);
}

TEST (CompareEdges, SwappedFeatureEdgeIsMissing)
{
  Mesh mesh = cube ();
  // Feature edge 0-1 of triangles (0, 1, 5) and (1, 0, 3) becomes 3-5, across the
  // corner.
  mesh.triangles[1] = {0, 3, 5};
  mesh.triangles[4] = {3, 1, 5};
  const EdgeComparison c = compareCube (mesh);
  EXPECT_EQ (c.edges, 18u);
  EXPECT_EQ (c.reference_edges, 17u);
  EXPECT_EQ (c.sharp_edges, 12u);
  EXPECT_EQ (c.sharp_edges_found, 11u);
  EXPECT_NEAR (c.sharp_edge_fraction, 11.0 / 12.0, 1e-15);
  ASSERT_EQ (c.missing_sharp_edges.size (), 1u);
  EXPECT_EQ (c.missing_sharp_edges[0], (std::array<pcl::index_t, 2>{0, 1}));
}

TEST (CompareEdges, MovedVertexMatchesNothing)
{
  Mesh mesh = cube ();
  mesh.vertices[0].x () = std::nextafter (0.0, -1.0);
  const EdgeComparison c = compareCube (mesh);
  EXPECT_EQ (c.unmatched_vertices, 1u);
  EXPECT_EQ (c.reference_edges, 18u - 6u); // vertex 0 has six edges
  EXPECT_EQ (c.sharp_edges_found, 12u - 3u);
}

TEST (CompareEdges, ReferenceSeamsAreJoined)
{
  // The reference's left face uses a copy (vertex 8) of corner 0: its edges still
  // count, and the edge 0-2 between the bottom and the left face is still sharp.
  Mesh reference = cube ();
  reference.vertices.push_back (reference.vertices[0]);
  reference.triangles[8] = {8, 4, 6};
  reference.triangles[9] = {8, 6, 2};
  const EdgeComparison c = compareCube (cube (), reference);
  EXPECT_EQ (c.reference_edges, 18u);
  EXPECT_EQ (c.sharp_edges, 12u);
  EXPECT_EQ (c.sharp_edges_found, 12u);
}
