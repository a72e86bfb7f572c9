/*
 * Software License Agreement (BSD License)
 *
 *  pcl_spherical_meshless: meshless triangulation of point clouds with spherical
 *  topology (Hormann and Reimers 2003) for the Point Cloud Library.
 */
#include <pcl/surface/meshless/delaunay_2d.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace {

using boost::multiprecision::cpp_int;
using pcl::index_t;
using pcl::meshless::delaunay2D;
using pcl::meshless::Delaunay2DOptions;
using pcl::meshless::Delaunay2DResult;
using pcl::meshless::Points2;
using pcl::meshless::Triangle;
using pcl::meshless::Triangles;

/** \brief Exact orientation and incircle tests on the input doubles themselves.
  *
  * Written independently of the library (which works on snapped integers): every
  * coordinate is an integer multiple of 2^min_exponent_, so scaling by its inverse
  * turns the points into big integers. A loose floating-point filter skips the big
  * integers when the sign is obvious.
  */
class ExactPredicates
{
public:
  explicit ExactPredicates (const Points2& points)
  {
    for (const auto& p : points)
      for (const double v : {p.x (), p.y ()})
        if (v != 0.0)
          min_exponent_ = std::min (min_exponent_, decompose (v).second);
  }

  int orient (const Eigen::Vector2d& a, const Eigen::Vector2d& b,
              const Eigen::Vector2d& c) const
  {
    const double l = (b.x () - a.x ()) * (c.y () - a.y ());
    const double r = (b.y () - a.y ()) * (c.x () - a.x ());
    if (std::abs (l - r) > kFilter * (std::abs (l) + std::abs (r)))
      return l > r ? 1 : -1;
    const cpp_int ax = exact (a.x ()), ay = exact (a.y ());
    const cpp_int det = (exact (b.x ()) - ax) * (exact (c.y ()) - ay) -
                        (exact (b.y ()) - ay) * (exact (c.x ()) - ax);
    return det.sign ();
  }

  /** \brief +1 if d is strictly inside the circle through counter-clockwise a, b, c. */
  int incircle (const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                const Eigen::Vector2d& c, const Eigen::Vector2d& d) const
  {
    const Eigen::Vector2d ad = a - d, bd = b - d, cd = c - d;
    const double ta = ad.squaredNorm () * (bd.x () * cd.y () - bd.y () * cd.x ());
    const double tb = bd.squaredNorm () * (cd.x () * ad.y () - cd.y () * ad.x ());
    const double tc = cd.squaredNorm () * (ad.x () * bd.y () - ad.y () * bd.x ());
    const double permanent =
        ad.squaredNorm () *
            (std::abs (bd.x () * cd.y ()) + std::abs (bd.y () * cd.x ())) +
        bd.squaredNorm () *
            (std::abs (cd.x () * ad.y ()) + std::abs (cd.y () * ad.x ())) +
        cd.squaredNorm () *
            (std::abs (ad.x () * bd.y ()) + std::abs (ad.y () * bd.x ()));
    const double det = ta + tb + tc;
    if (std::abs (det) > kFilter * permanent)
      return det > 0 ? 1 : -1;
    const cpp_int dx = exact (d.x ()), dy = exact (d.y ());
    const cpp_int adx = exact (a.x ()) - dx, ady = exact (a.y ()) - dy;
    const cpp_int bdx = exact (b.x ()) - dx, bdy = exact (b.y ()) - dy;
    const cpp_int cdx = exact (c.x ()) - dx, cdy = exact (c.y ()) - dy;
    const cpp_int exact_det = (adx * adx + ady * ady) * (bdx * cdy - bdy * cdx) +
                              (bdx * bdx + bdy * bdy) * (cdx * ady - cdy * adx) +
                              (cdx * cdx + cdy * cdy) * (adx * bdy - ady * bdx);
    return exact_det.sign ();
  }

private:
  /** \brief Far above the ~11 ulp a double evaluation can be off by. */
  static constexpr double kFilter = 1e-10;

  /** \brief v = mantissa * 2^exponent with an odd integer mantissa. */
  static std::pair<std::int64_t, int> decompose (double v)
  {
    int e = 0;
    auto mantissa = static_cast<std::int64_t> (std::ldexp (std::frexp (v, &e), 53));
    e -= 53;
    while (mantissa % 2 == 0) {
      mantissa /= 2;
      ++e;
    }
    return {mantissa, e};
  }

  cpp_int exact (double v) const
  {
    if (v == 0.0)
      return 0;
    const auto [mantissa, e] = decompose (v);
    cpp_int result = mantissa;
    result <<= (e - min_exponent_);
    return result;
  }

  int min_exponent_ = std::numeric_limits<int>::max ();
};

/** \brief Checks the whole contract of a successful result; returns "" or the first
  * violation found.
  */
std::string
checkTriangulation (const Points2& points, const Delaunay2DResult& result)
{
  if (!result.success)
    return "failed: " + result.message;
  const std::size_t n = points.size ();
  const ExactPredicates exact (points);

  // Duplicates: earlier, themselves vertices, at most a grid spacing away.
  if (result.duplicate_of.size () != n)
    return "duplicate_of has the wrong size";
  std::size_t num_duplicates = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const index_t d = result.duplicate_of[i];
    if (d == -1)
      continue;
    ++num_duplicates;
    if (d < 0 || static_cast<std::size_t> (d) >= i || result.duplicate_of[d] != -1)
      return "bad duplicate_of[" + std::to_string (i) + "]";
    if ((points[i] - points[d]).cwiseAbs ().maxCoeff () > result.grid_spacing)
      return "duplicate " + std::to_string (i) + " is not at its representative";
  }
  if (num_duplicates != result.num_duplicates)
    return "num_duplicates disagrees with duplicate_of";

  // Every distinct point is a vertex, no duplicate is.
  std::vector<bool> used (n, false);
  for (const Triangle& t : result.triangles)
    for (const index_t v : t) {
      if (v < 0 || static_cast<std::size_t> (v) >= n)
        return "vertex index out of range";
      used[v] = true;
    }
  for (std::size_t i = 0; i < n; ++i)
    if (used[i] != (result.duplicate_of[i] == -1))
      return "point " + std::to_string (i) +
             (used[i] ? " is a duplicate but a vertex" : " is not a vertex");

  // Euler: 2n - 2 - h triangles.
  const std::size_t distinct = n - num_duplicates;
  const std::size_t h = result.hull.size ();
  if (result.triangles.size () + 2 + h != 2 * distinct)
    return "expected 2n - 2 - h = " + std::to_string (2 * distinct - 2 - h) +
           " triangles, got " + std::to_string (result.triangles.size ());

  // Strictly counter-clockwise triangles.
  for (const Triangle& t : result.triangles)
    if (exact.orient (points[t[0]], points[t[1]], points[t[2]]) <= 0)
      return "triangle (" + std::to_string (t[0]) + ", " + std::to_string (t[1]) +
             ", " + std::to_string (t[2]) + ") is not counter-clockwise";

  // Directed edges: each at most once; interior ones (with a reverse) locally Delaunay.
  std::unordered_map<std::uint64_t, index_t> third_vertex;
  const auto key = [n] (index_t a, index_t b) {
    return static_cast<std::uint64_t> (a) * n + static_cast<std::uint64_t> (b);
  };
  third_vertex.reserve (3 * result.triangles.size ());
  for (const Triangle& t : result.triangles)
    for (int i = 0; i < 3; ++i)
      if (!third_vertex.emplace (key (t[i], t[(i + 1) % 3]), t[(i + 2) % 3]).second)
        return "a directed edge occurs twice";
  std::size_t boundary_edges = 0;
  for (const Triangle& t : result.triangles)
    for (int i = 0; i < 3; ++i) {
      const index_t a = t[i], b = t[(i + 1) % 3], c = t[(i + 2) % 3];
      const auto reverse = third_vertex.find (key (b, a));
      if (reverse == third_vertex.end ())
        ++boundary_edges;
      else if (a < b && exact.incircle (points[a], points[b], points[c],
                                        points[reverse->second]) > 0)
        return "edge (" + std::to_string (a) + ", " + std::to_string (b) +
               ") is not Delaunay";
    }

  // The hull: its edges are the boundary edges, it is convex and holds all points.
  if (boundary_edges != h)
    return "the boundary has " + std::to_string (boundary_edges) + " edges, the hull " +
           std::to_string (h);
  double hull_area = 0.0;
  for (std::size_t i = 0; i < h; ++i) {
    const index_t a = result.hull[i], b = result.hull[(i + 1) % h];
    const index_t c = result.hull[(i + 2) % h];
    if (third_vertex.count (key (a, b)) == 0 || third_vertex.count (key (b, a)) != 0)
      return "hull edge (" + std::to_string (a) + ", " + std::to_string (b) +
             ") is not a boundary edge";
    if (exact.orient (points[a], points[b], points[c]) < 0)
      return "the hull is not convex at " + std::to_string (b);
    hull_area +=
        0.5 * (points[a].x () * points[b].y () - points[b].x () * points[a].y ());
  }
  // Duplicates may lie up to a grid spacing outside; their vertex stands for them.
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < h && result.duplicate_of[i] == -1; ++k)
      if (exact.orient (points[result.hull[k]], points[result.hull[(k + 1) % h]],
                        points[i]) < 0)
        return "point " + std::to_string (i) + " lies outside the hull";

  // The triangles tile the hull.
  double area = 0.0;
  for (const Triangle& t : result.triangles) {
    const Eigen::Vector2d u = points[t[1]] - points[t[0]],
                          v = points[t[2]] - points[t[0]];
    area += 0.5 * (u.x () * v.y () - u.y () * v.x ());
  }
  if (std::abs (area - hull_area) > 1e-9 * hull_area)
    return "the triangle areas sum to " + std::to_string (area) +
           ", the hull area is " + std::to_string (hull_area);
  return "";
}

Points2
uniformPoints (std::size_t n, std::uint64_t seed)
{
  std::mt19937_64 random (seed);
  std::uniform_real_distribution<double> coordinate (0.0, 1.0);
  Points2 points (n);
  for (auto& p : points) {
    const double x = coordinate (random);
    p = Eigen::Vector2d (x, coordinate (random));
  }
  return points;
}

/** \brief Radii exp(-strength U): the clustering of meshless parameter points. */
Points2
clusteredPoints (std::size_t n, double strength, std::uint64_t seed)
{
  std::mt19937_64 random (seed);
  std::uniform_real_distribution<double> uniform (0.0, 1.0);
  Points2 points (n);
  for (auto& p : points) {
    const double r = std::exp (-strength * uniform (random));
    const double angle = 2.0 * EIGEN_PI * uniform (random);
    p = Eigen::Vector2d (r * std::cos (angle), r * std::sin (angle));
  }
  return points;
}

/** \brief Triangles as a sorted list of index triples, each rotated to start at its
  * smallest index, so that equal triangulations compare equal.
  */
Triangles
canonical (Triangles triangles)
{
  for (Triangle& t : triangles)
    std::rotate (t.begin (), std::min_element (t.begin (), t.end ()), t.end ());
  std::sort (triangles.begin (), triangles.end ());
  return triangles;
}

void
expectFailure (const Points2& points)
{
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_FALSE (result.success);
  EXPECT_FALSE (result.message.empty ());
  EXPECT_TRUE (result.triangles.empty ());
}

TEST (Delaunay2D, UniformThousand)
{
  const Points2 points = uniformPoints (1000, 1);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (0u, result.num_duplicates);
}

TEST (Delaunay2D, UniformHundredThousand)
{
  const Points2 points = uniformPoints (100000, 2);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (0u, result.num_duplicates);
}

TEST (Delaunay2D, ClusteredStrength12)
{
  const Points2 points = clusteredPoints (100000, 12.0, 3);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (0u, result.num_duplicates);
}

TEST (Delaunay2D, ClusteredStrength25)
{
  const Points2 points = clusteredPoints (100000, 25.0, 4);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (0u, result.num_duplicates);
}

TEST (Delaunay2D, ClusteredStrength40)
{
  // Radii down to 4e-18, a few spacings of a 64-bit snapping grid (8.7e-19).
  const Points2 points = clusteredPoints (100000, 40.0, 13);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (0u, result.num_duplicates);
}

TEST (Delaunay2D, RegularGrid)
{
  // Every grid square is cocircular, every row and column collinear.
  const int nx = 60, ny = 45;
  Points2 points;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      points.emplace_back (0.25 * i - 3.0, 0.5 * j + 1.0);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (static_cast<std::size_t> (2 * (nx + ny) - 4), result.hull.size ());
  EXPECT_EQ (static_cast<std::size_t> (2 * (nx - 1) * (ny - 1)),
             result.triangles.size ());
  EXPECT_EQ (0, result.hull.front ()); // the lowest of the leftmost points
}

TEST (Delaunay2D, PointsOnACircle)
{
  // All integer points on the circle of radius 5525 = 5^2 13 17: exactly cocircular.
  const std::int64_t radius = 5525;
  Points2 points;
  for (std::int64_t x = -radius; x <= radius; ++x) {
    const std::int64_t y2 = radius * radius - x * x;
    const auto y = static_cast<std::int64_t> (std::llround (std::sqrt (double (y2))));
    if (y * y == y2) {
      points.emplace_back (double (x), double (y));
      if (y != 0)
        points.emplace_back (double (x), double (-y));
    }
  }
  ASSERT_GT (points.size (), 100u);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (points.size (), result.hull.size ());
  EXPECT_EQ (points.size () - 2, result.triangles.size ());
}

TEST (Delaunay2D, PointsOnHullEdges)
{
  std::mt19937_64 random (5);
  std::uniform_real_distribution<double> uniform (0.0, 1.0);
  Points2 points = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
  for (int k = 0; k < 40; ++k) {
    const double s = uniform (random), t = k / 40.0 + 1.0 / 80.0;
    points.emplace_back (s, 0.0);
    points.emplace_back (1.0, s);
    points.emplace_back (t, 1.0);
    points.emplace_back (0.0, t);
  }
  const std::size_t num_boundary = points.size ();
  for (int k = 0; k < 500; ++k) {
    const double x = uniform (random);
    points.emplace_back (x, uniform (random));
  }
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  std::vector<index_t> hull = result.hull;
  std::sort (hull.begin (), hull.end ());
  std::vector<index_t> expected (num_boundary);
  for (std::size_t i = 0; i < num_boundary; ++i)
    expected[i] = static_cast<index_t> (i);
  EXPECT_EQ (expected, hull);
}

TEST (Delaunay2D, CollinearPointsAndOneApex)
{
  // All but one point on the hull edge opposite the apex: a fan of n - 2 triangles.
  Points2 points;
  for (int i = 0; i < 100; ++i)
    points.emplace_back (i * 0.37, i * 0.37 * 2.0 + 1.0);
  points.emplace_back (5.0, -3.0);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (points.size (), result.hull.size ());
  EXPECT_EQ (points.size () - 2, result.triangles.size ());
}

TEST (Delaunay2D, ExactDuplicates)
{
  std::mt19937_64 random (6);
  Points2 points = uniformPoints (1000, 7);
  // Copies of random points at random positions, some copied several times.
  for (int k = 0; k < 400; ++k) {
    const std::size_t source = random () % points.size ();
    const std::size_t target = random () % (points.size () + 1);
    const Eigen::Vector2d copy = points[source];
    points.insert (points.begin () + target, copy);
  }
  std::vector<index_t> expected (points.size (), -1);
  std::size_t expected_count = 0;
  for (std::size_t i = 0; i < points.size (); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (points[j] == points[i]) {
        expected[i] = static_cast<index_t> (j);
        ++expected_count;
        break;
      }
  ASSERT_EQ (400u, expected_count);

  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_EQ (expected_count, result.num_duplicates);
  EXPECT_EQ (expected, result.duplicate_of);
}

TEST (Delaunay2D, PointsCloserThanTheGridMerge)
{
  // Documented: distinct points closer than the snapping grid (near the origin, about
  // 1e-36 here) are one vertex and reported as duplicates.
  Points2 points = uniformPoints (100, 8);
  points.emplace_back (0.0, 0.0);
  points.emplace_back (1e-40, -1e-40);
  const Delaunay2DResult result = delaunay2D (points);
  EXPECT_EQ ("", checkTriangulation (points, result));
  EXPECT_GT (result.grid_spacing, 0.0);
  EXPECT_LE (result.grid_spacing, std::ldexp (1.0, -119));
  EXPECT_EQ (1u, result.num_duplicates);
  EXPECT_EQ (100, result.duplicate_of[101]);
}

TEST (Delaunay2D, SmallCases)
{
  // Clockwise input comes back counter-clockwise.
  const Points2 triangle = {{0.0, 0.0}, {0.0, 1.0}, {1.0, 0.0}};
  const Delaunay2DResult one = delaunay2D (triangle);
  EXPECT_EQ ("", checkTriangulation (triangle, one));
  EXPECT_EQ (1u, one.triangles.size ());

  const Points2 square = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
  const Delaunay2DResult two = delaunay2D (square);
  EXPECT_EQ ("", checkTriangulation (square, two));
  EXPECT_EQ (2u, two.triangles.size ());
  EXPECT_EQ ((std::vector<index_t>{0, 1, 2, 3}), two.hull);
}

TEST (Delaunay2D, DegenerateInputFails)
{
  expectFailure ({});
  expectFailure ({{1.0, 2.0}});
  expectFailure ({{1.0, 2.0}, {3.0, 4.0}});
  expectFailure ({{1.0, 2.0}, {1.0, 2.0}, {1.0, 2.0}});
  expectFailure ({{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}});
  expectFailure ({{1.0, 2.0}, {3.0, 4.0}, {1.0, 2.0}, {3.0, 4.0}});

  Points2 line;
  for (int i = 0; i < 50; ++i)
    line.emplace_back (3.0 * i - 7.0, -2.0 * i + 5.0);
  expectFailure (line);

  Points2 with_nan = uniformPoints (20, 9);
  with_nan[7].y () = std::numeric_limits<double>::quiet_NaN ();
  expectFailure (with_nan);
  Points2 with_inf = uniformPoints (20, 10);
  with_inf[3].x () = -std::numeric_limits<double>::infinity ();
  expectFailure (with_inf);
}

TEST (Delaunay2D, InvariantUnderScalingAndTranslation)
{
  const Points2 points = uniformPoints (10000, 11);
  const Delaunay2DResult reference = delaunay2D (points);
  ASSERT_TRUE (reference.success);
  const Triangles expected = canonical (reference.triangles);

  struct Transform
  {
    double scale;
    Eigen::Vector2d offset;
  };
  for (const Transform& transform :
       {Transform{1e-8, {0.0, 0.0}}, Transform{1e8, {0.0, 0.0}},
        Transform{1.0, {1000.0, -2000.0}}, Transform{1e-8, {3e-6, 5e-7}},
        Transform{1e8, {-1e9, 2e8}}, Transform{1e200, {0.0, 0.0}}}) {
    Points2 moved (points.size ());
    for (std::size_t i = 0; i < points.size (); ++i)
      moved[i] = transform.scale * points[i] + transform.offset;
    const Delaunay2DResult result = delaunay2D (moved);
    ASSERT_TRUE (result.success) << result.message;
    EXPECT_EQ (expected, canonical (result.triangles)) << "scale " << transform.scale;
    EXPECT_EQ (reference.hull, result.hull) << "scale " << transform.scale;
  }
}

TEST (Delaunay2D, SeedOnlyAffectsCocircularChoices)
{
  const Points2 points = clusteredPoints (20000, 25.0, 12);
  Delaunay2DOptions options;
  options.random_seed = 12345;
  const Delaunay2DResult a = delaunay2D (points);
  const Delaunay2DResult b = delaunay2D (points, options);
  ASSERT_TRUE (a.success && b.success);
  EXPECT_EQ (canonical (a.triangles), canonical (b.triangles));

  Points2 grid;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j)
      grid.emplace_back (i, j);
  EXPECT_EQ ("", checkTriangulation (grid, delaunay2D (grid, options)));
}

} // namespace
