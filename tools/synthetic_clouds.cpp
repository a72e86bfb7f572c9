/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <meshless_tools/synthetic_clouds.h>

#include "common/constants.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace pcl {
namespace meshless {

namespace {

const double golden_angle = pi * (3.0 - std::sqrt (5.0));

/** Radius of the bumpy sphere in direction d: smooth, star-shaped, 0.75 .. 1.25. */
double
bumpRadius (const Eigen::Vector3d& d)
{
  return 1.0 + 0.15 * std::sin (3.0 * d.x () + 1.0) * std::cos (2.0 * d.y ()) +
         0.1 * std::sin (4.0 * d.z ()) * std::cos (3.0 * d.x () - 0.5);
}

double
heightField (double x, double y)
{
  return 0.3 * std::exp (-3.0 * (x * x + y * y)) + 0.05 * std::sin (3.0 * x);
}

/** i-th point of a Fibonacci lattice of n points on the unit sphere, moved in its
  * tangent plane by (jitter_u, jitter_v) times a quarter of the lattice spacing. */
Eigen::Vector3d
fibonacciDirection (std::size_t i, std::size_t n, double jitter_u, double jitter_v)
{
  const double z = 1.0 - 2.0 * (static_cast<double> (i) + 0.5) / static_cast<double> (n);
  const double r = std::sqrt (std::max (0.0, 1.0 - z * z));
  const double phi = golden_angle * static_cast<double> (i);
  const Eigen::Vector3d p (r * std::cos (phi), r * std::sin (phi), z);
  const double step = 0.25 * std::sqrt (4.0 * pi / static_cast<double> (n));
  const Eigen::Vector3d t1 = p.unitOrthogonal ();
  const Eigen::Vector3d t2 = p.cross (t1);
  return (p + step * (jitter_u * t1 + jitter_v * t2)).normalized ();
}

/** i-th of n points spread evenly by area on the ellipsoid with semi-axes 1, 1, 6:
  * a Fibonacci lattice whose heights follow the ellipsoid's area density (the map
  * (x, y, z) -> (x, y, 6z) stretches the sphere's area by
  * 6 sqrt(1 - z^2 (1 - 1/36))), jittered by a quarter of the spacing. */
Eigen::Vector3d
ellipsoidPoint (std::size_t i, std::size_t n, double jitter_u, double jitter_v)
{
  constexpr double c = 6.0;
  auto density = [] (double z) { return std::sqrt (1.0 - z * z * (1.0 - 1.0 / (c * c))); };
  // Invert the cumulative area over z in [-1, 1] by bisection (monotone).
  auto cumulative = [&] (double z) {
    const int steps = 64;
    double sum = 0.0;
    const double h = (z + 1.0) / steps;
    for (int k = 0; k < steps; ++k)
      sum += h * density (-1.0 + (k + 0.5) * h);
    return sum;
  };
  const double total = cumulative (1.0);
  const double target = total * (static_cast<double> (i) + 0.5 + 0.25 * jitter_u) /
                        static_cast<double> (n);
  double lo = -1.0, hi = 1.0;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (cumulative (mid) < target ? lo : hi) = mid;
  }
  const double z = 0.5 * (lo + hi);
  const double r = std::sqrt (std::max (0.0, 1.0 - z * z));
  const double phi = golden_angle * (static_cast<double> (i) + 0.25 * jitter_v);
  return {r * std::cos (phi), r * std::sin (phi), c * z};
}

} // namespace

Points3
sampleShape (SyntheticShape shape, const SyntheticCloudOptions& options)
{
  const std::size_t n = options.num_points;
  std::mt19937 random (options.seed);
  std::uniform_real_distribution<double> jitter (-0.5, 0.5);
  Points3 points;
  points.reserve (n);
  for (std::size_t i = 0; i < n; ++i) {
    const double ju = jitter (random);
    const double jv = jitter (random);
    switch (shape) {
    case SyntheticShape::Sphere:
      points.push_back (fibonacciDirection (i, n, ju, jv));
      break;
    case SyntheticShape::Ellipsoid:
      points.push_back (ellipsoidPoint (i, n, ju, jv));
      break;
    case SyntheticShape::BumpySphere: {
      const Eigen::Vector3d d = fibonacciDirection (i, n, ju, jv);
      points.push_back (bumpRadius (d) * d);
      break;
    }
    case SyntheticShape::Torus: {
      // A 2D Fibonacci lattice on the (u, v) square, jittered by a quarter of the
      // spacing (density varies with the distance from the axis, about 2:1).
      const double big = 1.0, small = 0.35;
      const double step = 0.25 * std::sqrt (4.0 * pi * pi * big * small / static_cast<double> (n));
      const double u = 2.0 * pi * std::fmod (static_cast<double> (i) * 0.6180339887498949, 1.0) +
                       ju * step / big;
      const double v = 2.0 * pi * (static_cast<double> (i) + 0.5) / static_cast<double> (n) +
                       jv * step / small;
      const double ring = big + small * std::cos (v);
      points.emplace_back (ring * std::cos (u), ring * std::sin (u), small * std::sin (v));
      break;
    }
    case SyntheticShape::Disc:
    case SyntheticShape::HeightField: {
      // Sunflower (Vogel) spiral, jittered by a quarter of the spacing, kept inside
      // the unit disc.
      const double r = std::sqrt ((static_cast<double> (i) + 0.5) / static_cast<double> (n));
      const double phi = golden_angle * static_cast<double> (i);
      const double step = 0.25 * std::sqrt (pi / static_cast<double> (n));
      Eigen::Vector2d xy (r * std::cos (phi) + step * ju, r * std::sin (phi) + step * jv);
      if (xy.norm () > 1.0)
        xy.normalize ();
      points.emplace_back (xy.x (), xy.y (),
                           shape == SyntheticShape::Disc ? 0.0 : heightField (xy.x (), xy.y ()));
      break;
    }
    }
  }
  if (options.noise > 0.0 && !points.empty ()) {
    Eigen::Vector3d lo = points.front (), hi = points.front ();
    for (const auto& p : points) {
      lo = lo.cwiseMin (p);
      hi = hi.cwiseMax (p);
    }
    std::normal_distribution<double> gauss (0.0, options.noise * (hi - lo).norm ());
    for (auto& p : points)
      p += Eigen::Vector3d (gauss (random), gauss (random), gauss (random));
  }
  return points;
}

bool
parseSyntheticShape (const std::string& name, SyntheticShape& shape)
{
  static const std::pair<const char*, SyntheticShape> names[] = {
      {"sphere", SyntheticShape::Sphere},           {"ellipsoid", SyntheticShape::Ellipsoid},
      {"bumpy_sphere", SyntheticShape::BumpySphere}, {"torus", SyntheticShape::Torus},
      {"disc", SyntheticShape::Disc},               {"height_field", SyntheticShape::HeightField}};
  for (const auto& entry : names)
    if (name == entry.first) {
      shape = entry.second;
      return true;
    }
  return false;
}

} // namespace meshless
} // namespace pcl
