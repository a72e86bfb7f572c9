// Paper §2: least-squares planes and Delaunay-ordered neighbourhoods.
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <meshless_tools/synthetic_clouds.h>

#include "test_support.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>

using namespace pcl::meshless;

namespace {

constexpr double pi = 3.14159265358979323846;


double
cross (const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x () * b.y () - a.y () * b.x ();
}

/** Brute force: q_i is a Delaunay neighbour of the origin iff some triangle
  * (0, q_i, q_j) has an empty circumcircle, or [0, q_i] is a hull edge. */
std::vector<int>
bruteForceDelaunayNeighbours (const Points2& q)
{
  const int n = static_cast<int> (q.size ());
  auto inCircle = [] (const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      const Eigen::Vector2d& c, const Eigen::Vector2d& p) {
    // Lifted orientation of (0, a, b, p): negative iff p lies inside the circle
    // through the origin, a and b (counter-clockwise); c unused for clarity.
    (void) c;
    const double det = a.squaredNorm () * cross (b, p) - b.squaredNorm () * cross (a, p) +
                       p.squaredNorm () * cross (a, b);
    return det < 0.0;
  };
  std::vector<int> result;
  for (int i = 0; i < n; ++i) {
    bool neighbour = false;
    for (int j = 0; j < n && !neighbour; ++j) {
      if (j == i)
        continue;
      const Eigen::Vector2d& a = cross (q[i], q[j]) > 0.0 ? q[i] : q[j];
      const Eigen::Vector2d& b = cross (q[i], q[j]) > 0.0 ? q[j] : q[i];
      if (cross (a, b) == 0.0)
        continue;
      bool empty = true;
      for (int m = 0; m < n && empty; ++m)
        if (m != i && m != j && inCircle (a, b, b, q[m]))
          empty = false;
      neighbour = empty;
    }
    if (!neighbour) { // hull edge [0, q_i]: every other point on one side
      bool left = true, right = true;
      for (int m = 0; m < n; ++m)
        if (m != i) {
          left = left && cross (q[i], q[m]) > 0.0;
          right = right && cross (q[i], q[m]) < 0.0;
        }
      neighbour = left || right;
    }
    if (neighbour)
      result.push_back (i);
  }
  return result;
}

} // namespace

TEST (OrderedNeighbourhoods, RingOfARegularHexagonIsItsSixCorners)
{
  Points2 local;
  for (int j = 0; j < 6; ++j) // hexagon, listed clockwise to test the sorting
    local.emplace_back (std::cos (-j * pi / 3.0 + 0.1), std::sin (-j * pi / 3.0 + 0.1));
  for (int j = 0; j < 6; ++j) // second ring hidden behind the first
    local.emplace_back (2.2 * std::cos (j * pi / 3.0 + 0.1), 2.2 * std::sin (j * pi / 3.0 + 0.1));
  std::vector<int> ring;
  const double gap = delaunayRing (local, ring);
  ASSERT_EQ (ring.size (), 6u);
  for (int r : ring)
    EXPECT_LT (r, 6) << "an outer point is not a Delaunay neighbour";
  for (std::size_t j = 0; j < 6; ++j)
    EXPECT_GT (cross (local[ring[j]], local[ring[(j + 1) % 6]]), 0.0) << "not counter-clockwise";
  EXPECT_NEAR (gap, pi / 3.0, 1e-12);
}

TEST (OrderedNeighbourhoods, RingOfALatticePointIsItsFourAxisNeighbours)
{
  // The diagonal neighbours of a square lattice are co-circular with two axis
  // neighbours: their Voronoi edges with the origin have zero length. Points two
  // steps away are hidden; a repeated axis neighbour joins the ring at most once.
  Points2 local;
  for (int x = -2; x <= 2; ++x)
    for (int y = -2; y <= 2; ++y)
      if (x != 0 || y != 0)
        local.emplace_back (0.01 * x, 0.01 * y);
  local.emplace_back (0.01, 0.0);
  std::vector<int> ring;
  const double gap = delaunayRing (local, ring);
  ASSERT_EQ (ring.size (), 4u);
  for (int r : ring)
    EXPECT_NEAR (local[r].norm (), 0.01, 1e-15) << "not an axis neighbour";
  EXPECT_NEAR (gap, pi / 2.0, 1e-12);
}

TEST (OrderedNeighbourhoods, RingOfAPointOnTheRimOpensTowardsTheOutside)
{
  // All neighbours in one half plane: the cell is unbounded, the ring the two
  // extreme directions and whatever the half ring's Voronoi edges reach.
  Points2 local = {{1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, {0.0, 2.5}, {0.5, 0.5}};
  std::vector<int> ring;
  const double gap = delaunayRing (local, ring);
  std::vector<int> sorted_ring = ring;
  std::sort (sorted_ring.begin (), sorted_ring.end ());
  EXPECT_EQ (sorted_ring, bruteForceDelaunayNeighbours (local));
  EXPECT_NEAR (gap, pi, 1e-12) << "the largest gap is the open side";
}

TEST (OrderedNeighbourhoods, RingMatchesBruteForceDelaunay)
{
  std::mt19937 random (42);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    Points2 local (4 + trial % 16);
    for (auto& q : local)
      q = Eigen::Vector2d (u (random), u (random));
    std::vector<int> ring;
    delaunayRing (local, ring);
    std::vector<int> sorted_ring = ring;
    std::sort (sorted_ring.begin (), sorted_ring.end ());
    EXPECT_EQ (sorted_ring, bruteForceDelaunayNeighbours (local)) << "trial " << trial;
    for (std::size_t j = 0; j + 1 < ring.size (); ++j) {
      const double a0 = std::atan2 (local[ring[j]].y (), local[ring[j]].x ());
      const double a1 = std::atan2 (local[ring[j + 1]].y (), local[ring[j + 1]].x ());
      EXPECT_LT (a0 < 0 ? a0 + 2 * pi : a0, a1 < 0 ? a1 + 2 * pi : a1) << "not ordered";
    }
  }
}

TEST (OrderedNeighbourhoods, SphereRingsAreClosedCounterClockwiseStarsAroundRadialNormals)
{
  const Points3 points = sampleShape (SyntheticShape::Sphere, {3000, 3, 0.0});
  const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
  const OrderedNeighbourhoods ordered = orderNeighbourhoods (points, graph);
  ASSERT_TRUE (ordered.success) << ordered.message;
  ASSERT_EQ (ordered.rings.size (), points.size ());
  Points2 local;
  for (std::size_t v = 0; v < points.size (); ++v) {
    const auto vi = static_cast<pcl::index_t> (v);
    const Eigen::Vector3d n = ordered.normals[v].cast<double> ();
    EXPECT_GT (std::abs (n.dot (points[v].normalized ())), 0.99) << "normal not radial";
    const int d = ordered.rings.degree (vi);
    EXPECT_GE (d, 4);
    EXPECT_LE (d, 10);
    EXPECT_LT (ordered.largest_gap[v], pi) << "an interior point of a closed surface";
    localCoordinates (points, vi, ordered.rings.begin (vi), ordered.rings.end (vi), n,
                      LocalPlane::ProjectOntoFit, local);
    for (int j = 0; j < d; ++j) // cyclic and counter-clockwise, wrapping around
      EXPECT_GT (cross (local[j], local[(j + 1) % d]), 0.0) << "point " << v;
    for (auto w = ordered.rings.begin (vi); w != ordered.rings.end (vi); ++w)
      EXPECT_TRUE (std::binary_search (graph.begin (vi), graph.end (vi), *w))
          << "ring member outside the candidates";
  }
}

TEST (OrderedNeighbourhoods, StableUnderRotationScalingAndBothPlaneVariants)
{
  const Points3 points = sampleShape (SyntheticShape::BumpySphere, {1500, 5, 0.0});
  const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd (0.7, Eigen::Vector3d (1, 2, 3).normalized ()).toRotationMatrix ();
  for (LocalPlane plane : {LocalPlane::ProjectOntoFit, LocalPlane::RotateIntoFit}) {
    const OrderedNeighbourhoods reference = orderNeighbourhoods (points, graph, {plane});
    for (double scale : {1e-4, 1.0, 1e4}) {
      Points3 moved;
      for (const auto& p : points)
        moved.push_back (scale * (rotation * p) + Eigen::Vector3d (3, -2, 5) * scale);
      const OrderedNeighbourhoods result = orderNeighbourhoods (moved, graph, {plane});
      for (std::size_t v = 0; v < points.size (); ++v) {
        std::vector<pcl::index_t> a (reference.rings.begin (v), reference.rings.end (v));
        std::vector<pcl::index_t> b (result.rings.begin (v), result.rings.end (v));
        ASSERT_EQ (a.size (), b.size ()) << "point " << v << " scale " << scale;
        if (a.empty ())
          continue;
        // Same cycle: b is a rotation of a, or of a reversed (the normal's sign is
        // arbitrary).
        auto start = std::find (b.begin (), b.end (), a.front ());
        ASSERT_NE (start, b.end ());
        std::rotate (b.begin (), start, b.end ());
        std::vector<pcl::index_t> reversed (a.size ());
        reversed[0] = a[0];
        std::reverse_copy (a.begin () + 1, a.end (), reversed.begin () + 1);
        EXPECT_TRUE (a == b || reversed == b) << "point " << v << " scale " << scale;
      }
    }
  }
}

TEST (OrderedNeighbourhoods, BoundaryOfAnOpenDiscHasAGapOfAtLeastPi)
{
  const std::size_t n = 2000;
  const Points3 points = sampleShape (SyntheticShape::Disc, {n, 2, 0.0});
  const OrderedNeighbourhoods ordered = orderNeighbourhoods (points, meshless_test::bruteForceKnnGraph (points, 12));
  ASSERT_TRUE (ordered.success);
  const double spacing = std::sqrt (pi / static_cast<double> (n));
  std::vector<double> rim_angles;
  for (std::size_t v = 0; v < n; ++v) {
    if (ordered.largest_gap[v] < pi)
      continue;
    EXPECT_GT (points[v].head<2> ().norm (), 1.0 - 2.0 * spacing)
        << "point " << v << " well inside the disc is not surrounded by its ring";
    rim_angles.push_back (std::atan2 (points[v].y (), points[v].x ()));
  }
  // The flagged points go all the way round the rim.
  ASSERT_GE (rim_angles.size (), 20u);
  std::sort (rim_angles.begin (), rim_angles.end ());
  double widest = 2.0 * pi - (rim_angles.back () - rim_angles.front ());
  for (std::size_t j = 1; j < rim_angles.size (); ++j)
    widest = std::max (widest, rim_angles[j] - rim_angles[j - 1]);
  EXPECT_LT (widest, pi / 8.0);
}

namespace {

/** Twenty random points of the square [-1, 1]^2 in the plane through the origin
  * with normal n, and the indices of all but the first (its neighbourhood). */
Points3
pointsOnAPlane (std::uint32_t seed, const Eigen::Vector3d& n, std::vector<pcl::index_t>& others)
{
  Points3 points;
  std::mt19937 random (seed);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  const Eigen::Vector3d a = n.unitOrthogonal (), b = n.cross (a);
  for (int i = 0; i < 20; ++i)
    points.push_back (u (random) * a + u (random) * b);
  others.clear ();
  for (pcl::index_t i = 1; i < 20; ++i)
    others.push_back (i);
  return points;
}

/** The points on the generated thin limbs' rods (away from the body and the tips)
  * whose normal is more than 45 degrees off the rod's radial direction; `on_rods`
  * counts the points looked at. */
std::size_t
normalsOffTheRods (const Points3& points, const OrderedNeighbourhoods& ordered,
                   std::size_t& on_rods)
{
  std::size_t off = 0;
  on_rods = 0;
  for (std::size_t v = 0; v < points.size (); ++v) {
    // The rods leave the ball of radius 0.5 along the axes and end at 1.5.
    Eigen::Index axis;
    const double along = points[v].cwiseAbs ().maxCoeff (&axis);
    if (points[v].norm () < 0.75 || along > 1.45)
      continue;
    ++on_rods;
    Eigen::Vector3d radial = points[v];
    radial[axis] = 0.0;
    off += std::abs (ordered.normals[v].cast<double> ().dot (radial.normalized ())) <
           std::cos (pi / 4.0);
  }
  return off;
}

} // namespace

TEST (OrderedNeighbourhoods, LeastSquaresNormalOfAPlane)
{
  const Eigen::Vector3d n = Eigen::Vector3d (0.3, -0.5, 0.8).normalized ();
  std::vector<pcl::index_t> others;
  const Points3 points = pointsOnAPlane (1, n, others);
  const Eigen::Vector3d fit =
      leastSquaresNormal (points, 0, others.data (), others.data () + others.size (), true);
  EXPECT_NEAR (std::abs (fit.dot (n)), 1.0, 1e-6);
  EXPECT_TRUE (leastSquaresNormal (points, 0, others.data (), others.data () + 1, true).isZero ());
}

TEST (OrderedNeighbourhoods, RingsOfAThinRodKeepToTheNearSideWhenSteepNeighboursDrop)
{
  // A rod six points around: twelve neighbours reach its far side, whose points
  // project between the near ones. Without the steep neighbours every ring keeps to
  // the near side and its plane is tangent to the rod.
  const int around = 6, rings = 30;
  Points3 points;
  for (int r = 0; r < rings; ++r)
    for (int j = 0; j < around; ++j) {
      const double a = (j + 0.5 * (r % 2)) * 2.0 * pi / around;
      points.emplace_back (std::cos (a), std::sin (a), 0.9 * r);
    }
  const CsrGraph graph = symmetricGraph (meshless_test::bruteForceKnnGraph (points, 12));
  const auto farSideMembers = [&] (const OrderedNeighbourhoods& ordered) {
    std::size_t far = 0;
    for (std::size_t v = around * 4; v < points.size () - around * 4; ++v) {
      const auto vi = static_cast<pcl::index_t> (v);
      const Eigen::Vector2d radial (points[v].x (), points[v].y ());
      for (auto w = ordered.rings.begin (vi); w != ordered.rings.end (vi); ++w)
        far += radial.dot (Eigen::Vector2d (points[*w].x (), points[*w].y ())) < 0.0;
    }
    return far;
  };
  const OrderedNeighbourhoods all = orderNeighbourhoods (points, graph);
  ASSERT_TRUE (all.success);
  EXPECT_GT (farSideMembers (all), 0u) << "the rod is meant to be thin enough to fold rings";

  OrderingOptions near_side;
  near_side.max_neighbour_elevation_deg = 50.0;
  const OrderedNeighbourhoods ordered = orderNeighbourhoods (points, graph, near_side);
  ASSERT_TRUE (ordered.success);
  EXPECT_EQ (farSideMembers (ordered), 0u);
  for (std::size_t v = around * 4; v < points.size () - around * 4; ++v) {
    const Eigen::Vector3d radial (points[v].x (), points[v].y (), 0.0);
    EXPECT_GT (std::abs (ordered.normals[v].cast<double> ().dot (radial)), 0.95) << "point " << v;
    EXPECT_GE (ordered.rings.degree (static_cast<pcl::index_t> (v)), 4);
    EXPECT_LT (ordered.largest_gap[v], pi) << "point " << v;
  }
}

TEST (OrderedNeighbourhoods, WeightedNormalOfAPlaneIsItsNormal)
{
  const Eigen::Vector3d n = Eigen::Vector3d (-0.2, 0.7, 0.4).normalized ();
  std::vector<pcl::index_t> others;
  const Points3 points = pointsOnAPlane (2, n, others);
  const pcl::index_t* begin = others.data ();
  const pcl::index_t* end = begin + others.size ();
  EXPECT_NEAR (std::abs (weightedLeastSquaresNormal (points, 0, begin, end, true, 0.8).dot (n)),
               1.0, 1e-6);
  EXPECT_TRUE (weightedLeastSquaresNormal (points, 0, begin, begin + 1, true, 0.8).isZero ());
  EXPECT_TRUE (weightedLeastSquaresNormal (points, 0, begin, end, true, 0.0).isZero ());
}

TEST (OrderedNeighbourhoods, SphereThroughAPointHasTheSpheresNormalThereAndAPlanesOnAPlane)
{
  const Eigen::Vector3d n = Eigen::Vector3d (0.6, 0.1, -0.7).normalized ();
  std::vector<pcl::index_t> others;
  const Points3 flat = pointsOnAPlane (3, n, others);
  const pcl::index_t* begin = others.data ();
  const pcl::index_t* end = begin + others.size ();
  for (const double width : {0.0, 0.8}) {
    EXPECT_NEAR (std::abs (sphereThroughPointNormal (flat, 0, begin, end, width).dot (n)), 1.0,
                 1e-6);
    EXPECT_TRUE (sphereThroughPointNormal (flat, 0, begin, begin + 2, width).isZero ());
  }
  // The top of a sphere of radius 1e-3 about (0, 0, -1e-3) and points to one side
  // of it on the sphere, 35 to 70 degrees away: the sphere's normal at the top is
  // z, which the plane through them misses.
  Points3 cap (1, Eigen::Vector3d::Zero ());
  std::mt19937 random (4);
  std::uniform_real_distribution<double> polar (0.6, 1.2), azimuth (-0.5, 0.5);
  for (int i = 0; i < 40; ++i) {
    const double p = polar (random), a = azimuth (random);
    cap.emplace_back (1e-3 * Eigen::Vector3d (std::sin (p) * std::cos (a),
                                              std::sin (p) * std::sin (a), std::cos (p) - 1.0));
  }
  std::vector<pcl::index_t> rest (cap.size () - 1);
  std::iota (rest.begin (), rest.end (), 1);
  const pcl::index_t* first = rest.data ();
  const pcl::index_t* last = first + rest.size ();
  for (const double width : {0.0, 0.8})
    EXPECT_NEAR (std::abs (sphereThroughPointNormal (cap, 0, first, last, width).z ()), 1.0,
                 1e-6);
  EXPECT_LT (std::abs (leastSquaresNormal (cap, 0, first, last, true).z ()),
             std::cos (10.0 * pi / 180.0));
}

TEST (OrderedNeighbourhoods, RodsFourPointsAroundKeepTheirNormalsWithASphereFit)
{
  // Generated limbs about four points around: even a weighted plane fitted there
  // takes the rod's slice for a good share of its points; a sphere through the
  // point bends with the rod.
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE ("seed " + std::to_string (seed));
    const Points3 points = sampleShape (SyntheticShape::ThinLimbs, {1000, seed, 0.0});
    const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
    OrderingOptions near_side;
    near_side.max_neighbour_elevation_deg = 50.0;
    near_side.plane_weight_width = 0.8;
    std::size_t on_rods = 0;
    const OrderedNeighbourhoods plane = orderNeighbourhoods (points, graph, near_side);
    ASSERT_TRUE (plane.success);
    const std::size_t off_plane = normalsOffTheRods (points, plane, on_rods);
    near_side.normal_fit = NormalFit::SphereThroughPoint;
    const OrderedNeighbourhoods sphere = orderNeighbourhoods (points, graph, near_side);
    ASSERT_TRUE (sphere.success);
    const std::size_t off_sphere = normalsOffTheRods (points, sphere, on_rods);
    EXPECT_GT (off_plane, on_rods / 5) << "the rods are meant to be that thin";
    EXPECT_LT (off_sphere, on_rods / 40);
  }
}

TEST (OrderedNeighbourhoods, RodsFivePointsAroundNeedAWeightedPlaneForTheirNearSide)
{
  // Generated limbs five to six points around: twelve neighbours span the rod, and
  // their unweighted plane stands across it for a good share of its points; the
  // steep neighbours dropped against that plane are then the near ones. Weights
  // that fall off within a spacing fit the near side's plane, tangent to the rod.
  for (const std::size_t n : {1500u, 1700u})
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
      SCOPED_TRACE (std::to_string (n) + " points, seed " + std::to_string (seed));
      const Points3 points = sampleShape (SyntheticShape::ThinLimbs, {n, seed, 0.0});
      const CsrGraph graph = meshless_test::bruteForceKnnGraph (points, 12);
      OrderingOptions near_side;
      near_side.max_neighbour_elevation_deg = 50.0;
      std::size_t on_rods = 0;
      const OrderedNeighbourhoods plain = orderNeighbourhoods (points, graph, near_side);
      ASSERT_TRUE (plain.success);
      EXPECT_GT (normalsOffTheRods (points, plain, on_rods), on_rods / 8)
          << "the rods are meant to be that thin";
      near_side.plane_weight_width = 0.8;
      const OrderedNeighbourhoods weighted = orderNeighbourhoods (points, graph, near_side);
      ASSERT_TRUE (weighted.success);
      EXPECT_LT (normalsOffTheRods (points, weighted, on_rods), on_rods / 40);
    }
}
