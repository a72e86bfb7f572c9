// The project's own generated clouds: deterministic, on their shapes, evenly spread.
#include <meshless_tools/synthetic_clouds.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>

#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <vector>

using namespace pcl::meshless;

TEST (SyntheticClouds, SameSeedSameCloudOtherSeedOtherCloud)
{
  const Points3 a = sampleShape (SyntheticShape::BumpySphere, {500, 1, 0.0});
  const Points3 b = sampleShape (SyntheticShape::BumpySphere, {500, 1, 0.0});
  const Points3 c = sampleShape (SyntheticShape::BumpySphere, {500, 2, 0.0});
  ASSERT_EQ (a.size (), 500u);
  EXPECT_EQ (a, b);
  EXPECT_NE (a, c);
}

TEST (SyntheticClouds, PointsLieOnTheirShapes)
{
  for (const auto& p : sampleShape (SyntheticShape::Sphere, {1000, 1, 0.0}))
    EXPECT_NEAR (p.norm (), 1.0, 1e-12);
  for (const auto& p : sampleShape (SyntheticShape::Ellipsoid, {1000, 1, 0.0}))
    EXPECT_NEAR (p.x () * p.x () + p.y () * p.y () + p.z () * p.z () / 36.0, 1.0, 1e-12);
  for (const auto& p : sampleShape (SyntheticShape::Torus, {1000, 1, 0.0})) {
    const double ring = std::hypot (p.x (), p.y ()) - 1.0;
    EXPECT_NEAR (std::hypot (ring, p.z ()), 0.35, 1e-12);
  }
  for (const auto& p : sampleShape (SyntheticShape::Disc, {1000, 1, 0.0})) {
    EXPECT_EQ (p.z (), 0.0);
    EXPECT_LE (p.head<2> ().norm (), 1.0);
  }
  for (const auto& p : sampleShape (SyntheticShape::BumpySphere, {1000, 1, 0.0})) {
    EXPECT_GT (p.norm (), 0.74);
    EXPECT_LT (p.norm (), 1.26);
  }
}

TEST (SyntheticClouds, SpacingIsEvenOnTheSphere)
{
  const std::size_t n = 2000;
  const Points3 points = sampleShape (SyntheticShape::Sphere, {n, 4, 0.0});
  const double expected = std::sqrt (4.0 * 3.14159265358979 / static_cast<double> (n));
  for (std::size_t i = 0; i < n; ++i) {
    double nearest = 1e9;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i)
        nearest = std::min (nearest, (points[i] - points[j]).norm ());
    EXPECT_GT (nearest, 0.2 * expected) << "point " << i;
    EXPECT_LT (nearest, 1.5 * expected) << "point " << i;
  }
}

TEST (SyntheticClouds, NoiseMovesPointsOffTheShape)
{
  const Points3 points = sampleShape (SyntheticShape::Sphere, {2000, 1, 0.01});
  double sum_sq = 0.0;
  for (const auto& p : points)
    sum_sq += (p.norm () - 1.0) * (p.norm () - 1.0);
  const double rms = std::sqrt (sum_sq / 2000.0);
  // sigma = 1% of the diagonal (2 sqrt 3) in each coordinate: radial rms ~ sigma.
  EXPECT_NEAR (rms, 0.01 * 2.0 * std::sqrt (3.0), 0.01);
  std::string bad = "cube";
  SyntheticShape shape;
  EXPECT_FALSE (parseSyntheticShape (bad, shape));
  EXPECT_TRUE (parseSyntheticShape ("bumpy_sphere", shape));
  EXPECT_EQ (shape, SyntheticShape::BumpySphere);
}

namespace {

const double tube_radius = 0.3;

/** The (2, 3) torus knot the KnottedTube is built around, as documented. */
Eigen::Vector3d
knot (double t)
{
  const double h = 2.0 + std::cos (3.0 * t);
  return {h * std::cos (2.0 * t), h * std::sin (2.0 * t), std::sin (3.0 * t)};
}

/** Distance from p to the whole knot: a dense scan, refined by ternary search. */
double
distanceToKnot (const Eigen::Vector3d& p)
{
  const int steps = 4000;
  const double step = 2.0 * M_PI / steps;
  int best = 0;
  for (int i = 1; i < steps; ++i)
    if ((knot (i * step) - p).squaredNorm () < (knot (best * step) - p).squaredNorm ())
      best = i;
  double lo = (best - 2) * step, hi = (best + 2) * step;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double a = lo + (hi - lo) / 3.0, b = hi - (hi - lo) / 3.0;
    if ((knot (a) - p).squaredNorm () < (knot (b) - p).squaredNorm ())
      hi = b;
    else
      lo = a;
  }
  return (knot (0.5 * (lo + hi)) - p).norm ();
}

/** Distance to the DoubleTorus to first order: |f| / |grad f|. */
double
distanceToDoubleTorus (const Eigen::Vector3d& p)
{
  const double x = p.x (), y = p.y (), z = p.z ();
  const double q = x * x + y * y;
  const double g = q * q - x * x + y * y;
  const Eigen::Vector3d gradient (2.0 * g * (4.0 * q * x - 2.0 * x),
                                  2.0 * g * (4.0 * q * y + 2.0 * y), 2.0 * z);
  return std::abs (g * g + z * z - 0.01) / gradient.norm ();
}

double
torusDistance (const Eigen::Vector3d& p, double small)
{
  return std::abs (std::hypot (std::hypot (p.x (), p.y ()) - 1.0, p.z ()) - small);
}

/** 95th over 5th percentile of the nearest-neighbour distances (brute force). */
double
spacingSpread (const Points3& points)
{
  std::vector<double> nearest (points.size (), 1e300);
  for (std::size_t i = 0; i < points.size (); ++i)
    for (std::size_t j = 0; j < points.size (); ++j)
      if (j != i)
        nearest[i] = std::min (nearest[i], (points[i] - points[j]).norm ());
  std::sort (nearest.begin (), nearest.end ());
  return nearest[nearest.size () * 95 / 100] / nearest[nearest.size () * 5 / 100];
}

const SyntheticShape new_shapes[] = {SyntheticShape::ThinTorus, SyntheticShape::FatTorus,
                                     SyntheticShape::DoubleTorus, SyntheticShape::KnottedTube,
                                     SyntheticShape::ThinLimbs};

} // namespace

TEST (SyntheticClouds, NewShapesPointsLieOnTheirSurfaces)
{
  const SyntheticCloudOptions options{3000, 5, 0.0};
  for (const auto& p : sampleShape (SyntheticShape::ThinTorus, options))
    ASSERT_LT (torusDistance (p, 0.15), 1e-9 * 0.15);
  for (const auto& p : sampleShape (SyntheticShape::FatTorus, options))
    ASSERT_LT (torusDistance (p, 0.6), 1e-9 * 0.6);
  for (const auto& p : sampleShape (SyntheticShape::DoubleTorus, options))
    ASSERT_LT (distanceToDoubleTorus (p), 1e-9 * 0.1);
  // The distance to the whole knot, not only to the point the tube was built from:
  // were the tube to touch itself, points would lie closer to another strand.
  for (const auto& p : sampleShape (SyntheticShape::KnottedTube, options))
    ASSERT_NEAR (distanceToKnot (p), tube_radius, 1e-9 * tube_radius);
  // Beyond the ball and its rounded joins (0.7 from the centre), a point lies on a
  // rod: at 0.05 from an axis, or on a rod's end cap.
  for (const auto& p : sampleShape (SyntheticShape::ThinLimbs, options)) {
    if (p.norm () < 0.7)
      continue;
    double nearest = std::numeric_limits<double>::infinity ();
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3d off_axis = p;
      off_axis[axis] -= std::clamp (p[axis], -1.5, 1.5);
      nearest = std::min (nearest, off_axis.norm ());
    }
    ASSERT_NEAR (nearest, 0.05, 1e-9);
  }
}

TEST (SyntheticClouds, NewShapesSameSeedSameCloudOtherSeedOtherCloud)
{
  for (const SyntheticShape shape : new_shapes) {
    const Points3 a = sampleShape (shape, {800, 1, 0.0});
    ASSERT_EQ (a.size (), 800u);
    EXPECT_EQ (a, sampleShape (shape, {800, 1, 0.0}));
    EXPECT_NE (a, sampleShape (shape, {800, 2, 0.0}));
    SyntheticCloudOptions uneven{800, 1, 0.0};
    uneven.uneven = 10.0;
    EXPECT_EQ (sampleShape (shape, uneven), sampleShape (shape, uneven));
  }
}

TEST (SyntheticClouds, NewShapesSpacingIsEven)
{
  for (const SyntheticShape shape : new_shapes) {
    const double spread = spacingSpread (sampleShape (shape, {3000, 7, 0.0}));
    std::cout << "nearest-neighbour distance, 95th / 5th percentile, shape "
              << static_cast<int> (shape) << ": " << spread << "\n";
    EXPECT_LT (spread, 1.6);
  }
}

TEST (SyntheticClouds, UnevenDensityFollowsTheRatioOnEveryClosedShape)
{
  const double ratio = 10.0;
  for (int s = 0; s <= static_cast<int> (SyntheticShape::ThinLimbs); ++s) {
    const auto shape = static_cast<SyntheticShape> (s);
    if (syntheticGenus (shape) < 0)
      continue;
    const Points3 uniform = sampleShape (shape, {20000, 3, 0.0});
    SyntheticCloudOptions options{20000, 3, 0.0};
    options.uneven = ratio;
    const Points3 uneven = sampleShape (shape, options);
    ASSERT_EQ (uneven.size (), 20000u);
    Eigen::Vector3d lo = uniform.front (), hi = uniform.front ();
    for (const auto& p : uniform) {
      lo = lo.cwiseMin (p);
      hi = hi.cwiseMax (p);
    }
    int axis = 0; // the first of the longest axes, as the generator picks it
    while ((hi - lo)[axis] < 0.99 * (hi - lo).maxCoeff ())
      ++axis;
    // Points in the sparse and the dense end slabs, each against the uniform cloud's
    // count there, so that the slabs' areas cancel.
    auto counts = [&] (const Points3& points) {
      std::pair<double, double> ends{0.0, 0.0};
      for (const auto& p : points) {
        const double t = (p[axis] - lo[axis]) / (hi[axis] - lo[axis]);
        ends.first += t < 0.15;
        ends.second += t > 0.85;
      }
      return ends;
    };
    const auto base = counts (uniform), skewed = counts (uneven);
    const double measured = (skewed.second / base.second) / (skewed.first / base.first);
    std::cout << "density ratio asked " << ratio << ", measured " << measured << ", shape " << s
              << "\n";
    EXPECT_GT (measured, ratio / 1.5) << "shape " << s;
    EXPECT_LT (measured, ratio * 1.5) << "shape " << s;
  }
}

TEST (SyntheticClouds, GenusIsDocumented)
{
  EXPECT_EQ (syntheticGenus (SyntheticShape::Sphere), 0);
  EXPECT_EQ (syntheticGenus (SyntheticShape::Ellipsoid), 0);
  EXPECT_EQ (syntheticGenus (SyntheticShape::BumpySphere), 0);
  EXPECT_EQ (syntheticGenus (SyntheticShape::Torus), 1);
  EXPECT_EQ (syntheticGenus (SyntheticShape::ThinTorus), 1);
  EXPECT_EQ (syntheticGenus (SyntheticShape::FatTorus), 1);
  EXPECT_EQ (syntheticGenus (SyntheticShape::KnottedTube), 1);
  EXPECT_EQ (syntheticGenus (SyntheticShape::DoubleTorus), 2);
  EXPECT_EQ (syntheticGenus (SyntheticShape::ThinLimbs), 0);
  EXPECT_EQ (syntheticGenus (SyntheticShape::Disc), -1);
  EXPECT_EQ (syntheticGenus (SyntheticShape::HeightField), -1);
  const std::pair<const char*, SyntheticShape> names[] = {
      {"thin_torus", SyntheticShape::ThinTorus},
      {"fat_torus", SyntheticShape::FatTorus},
      {"double_torus", SyntheticShape::DoubleTorus},
      {"knotted_tube", SyntheticShape::KnottedTube},
      {"thin_limbs", SyntheticShape::ThinLimbs}};
  for (const auto& [name, expected] : names) {
    SyntheticShape shape = SyntheticShape::Sphere;
    EXPECT_TRUE (parseSyntheticShape (name, shape)) << name;
    EXPECT_EQ (shape, expected) << name;
  }
}

TEST (SyntheticClouds, KnottedTubeDoesNotTouchItself)
{
  // Strands of the knot far apart along it (more than three tube diameters of arc)
  // keep more than a diameter between their axes, and the tube never folds on its
  // inner side (radius times curvature below 1).
  const int steps = 3000;
  const double step = 2.0 * M_PI / steps;
  std::vector<double> arc (steps + 1, 0.0);
  for (int i = 0; i < steps; ++i)
    arc[i + 1] = arc[i] + (knot ((i + 1) * step) - knot (i * step)).norm ();
  const double length = arc[steps];
  double closest = 1e300, largest_curvature = 0.0;
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector3d a = knot ((i - 1) * step), b = knot (i * step), c = knot ((i + 1) * step);
    // Curvature from the circle through three neighbouring points.
    largest_curvature = std::max (largest_curvature, 2.0 * (b - a).cross (c - b).norm () /
                                                         ((b - a).norm () * (c - b).norm () *
                                                          (c - a).norm ()));
    for (int j = i + 1; j < steps; ++j) {
      const double along = std::min (arc[j] - arc[i], length - (arc[j] - arc[i]));
      if (along > 6.0 * tube_radius)
        closest = std::min (closest, (knot (j * step) - b).norm ());
    }
  }
  std::cout << "knot: closest far strands " << closest << ", largest curvature "
            << largest_curvature << "\n";
  EXPECT_GT (closest, 2.0 * tube_radius + 0.1);
  EXPECT_LT (tube_radius * largest_curvature, 0.9);
}

TEST (SyntheticClouds, ClustersFallApartAtTwelveNeighbours)
{
  // Clusters of 16 and 32 points: the 12 nearest neighbours of every point stay in
  // its cluster, so the 12-nearest-neighbour graph has one piece per cluster; on the
  // shape, same seed same cloud.
  for (const std::size_t size : {16u, 32u}) {
    SyntheticCloudOptions options{3200, 5, 0.0};
    options.cluster_size = size;
    const Points3 points = sampleShape (SyntheticShape::Sphere, options);
    EXPECT_EQ (points, sampleShape (SyntheticShape::Sphere, options));
    ASSERT_EQ (points.size (), 3200 / size * size);
    for (const auto& p : points)
      EXPECT_NEAR (p.norm (), 1.0, 1e-12);
    std::vector<pcl::index_t> labels;
    const std::size_t pieces = pcl::meshless::connectedComponents (
        pcl::meshless::symmetricGraph (meshless_test::bruteForceKnn (points, 12)), labels);
    EXPECT_GT (pieces, 3200 / size / 2) << "cluster size " << size;
  }
}

TEST (SyntheticClouds, LatticesAreSquareGridsAndHolesDropPoints)
{
  // On a lattice every point's nearest neighbour lies one step away, four of them
  // inside the outline; each further hole drops more points.
  for (const SyntheticShape shape : {SyntheticShape::Disc, SyntheticShape::HeightField}) {
    SyntheticCloudOptions options{2000, 3, 0.0};
    options.lattice = true;
    const Points3 grid = sampleShape (shape, options);
    EXPECT_NEAR (static_cast<double> (grid.size ()), 2000.0, 100.0);
    const double step = std::sqrt (3.141592653589793 / 2000.0);
    const CsrGraph near = meshless_test::bruteForceKnn (grid, 4);
    std::size_t four_at_one_step = 0;
    for (std::size_t v = 0; v < grid.size (); ++v) {
      std::size_t at_step = 0;
      for (const pcl::index_t* w = near.begin (v); w != near.end (v); ++w) {
        const Eigen::Vector2d d = (grid[*w] - grid[v]).head<2> ();
        at_step += std::abs (d.norm () - step) < 1e-9 ? 1 : 0;
      }
      EXPECT_GE (at_step, 1u) << "point " << v;
      four_at_one_step += at_step == 4 ? 1 : 0;
    }
    EXPECT_GT (four_at_one_step, grid.size () * 8 / 10);

    std::size_t previous = grid.size ();
    for (const std::size_t holes : {1u, 3u, 5u}) {
      options.holes = holes;
      const Points3 holed = sampleShape (shape, options);
      EXPECT_LT (holed.size (), previous) << holes << " holes";
      previous = holed.size ();
    }
  }
}

TEST (SyntheticClouds, RowsLeaveEmptySlabsStretchTimesTheSpacingApart)
{
  // In rows `stretch` spacings apart, sorted along the rows' axis the points leave
  // gaps wider than two nearest-neighbour distances between the rows, about stretch
  // of them wide (less a row's width); an even sample leaves none along any axis.
  struct Slabs
  {
    int count = 0;
    double median_width = 0.0; // in median nearest-neighbour distances
  };
  const auto emptySlabs = [] (const Points3& points) {
    if (points.empty ())
      return Slabs{-1, 0.0}; // fails both the even and the rows expectations
    const CsrGraph nearest = meshless_test::bruteForceKnn (points, 1);
    std::vector<double> d;
    for (std::size_t v = 0; v < points.size (); ++v)
      d.push_back ((points[*nearest.begin (v)] - points[v]).norm ());
    std::nth_element (d.begin (), d.begin () + d.size () / 2, d.end ());
    const double spacing = d[d.size () / 2];
    Slabs most; // along the axis with the most of them: the rows' axis
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> x;
      for (const auto& p : points)
        x.push_back (p[axis]);
      std::sort (x.begin (), x.end ());
      std::vector<double> widths;
      for (std::size_t i = 1; i < x.size (); ++i)
        if (x[i] - x[i - 1] > 2.0 * spacing)
          widths.push_back ((x[i] - x[i - 1]) / spacing);
      if (static_cast<int> (widths.size ()) > most.count) {
        std::nth_element (widths.begin (), widths.begin () + widths.size () / 2, widths.end ());
        most = {static_cast<int> (widths.size ()), widths[widths.size () / 2]};
      }
    }
    return most;
  };
  for (const SyntheticShape shape : {SyntheticShape::Sphere, SyntheticShape::Torus,
                                     SyntheticShape::ThinLimbs}) {
    SCOPED_TRACE (static_cast<int> (shape));
    SyntheticCloudOptions options{2000, 2, 0.0};
    EXPECT_EQ (emptySlabs (sampleShape (shape, options)).count, 0);
    for (const double stretch : {3.0, 4.0}) {
      SCOPED_TRACE (stretch);
      options.stretch = stretch;
      const Points3 rows = sampleShape (shape, options);
      EXPECT_NEAR (static_cast<double> (rows.size ()), 2000.0, 20.0);
      EXPECT_EQ (rows, sampleShape (shape, options));
      if (shape == SyntheticShape::Sphere)
        for (const auto& p : rows)
          EXPECT_NEAR (p.norm (), 1.0, 1e-12);
      const Slabs slabs = emptySlabs (rows);
      EXPECT_GE (slabs.count, 5);
      EXPECT_GT (slabs.median_width, 0.75 * stretch);
      EXPECT_LT (slabs.median_width, 1.15 * stretch);
    }
  }
}
