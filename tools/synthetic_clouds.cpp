/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <meshless_tools/synthetic_clouds.h>

#include "common/constants.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <random>
#include <unordered_map>
#include <utility>
#include <vector>

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

/** n points of a jittered lattice on one of the shapes the lattices cover. */
Points3
sampleLattice (SyntheticShape shape, std::size_t n, std::mt19937& random)
{
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
    default:
      break;
    }
  }
  return points;
}

struct BoundingBox
{
  Eigen::Vector3d lo, hi;
};

BoundingBox
boundingBox (const Points3& points)
{
  BoundingBox box{points.front (), points.front ()};
  for (const auto& p : points) {
    box.lo = box.lo.cwiseMin (p);
    box.hi = box.hi.cwiseMax (p);
  }
  return box;
}

/** The first bounding-box axis within 1% of the longest: near-equal extents (a
  * sphere, a torus) differ by sampling. */
int
longestAxis (const Points3& points)
{
  const BoundingBox box = boundingBox (points);
  const Eigen::Vector3d extents = box.hi - box.lo;
  int axis = 0;
  while (extents[axis] < 0.99 * extents.maxCoeff ())
    ++axis;
  return axis;
}

using Crowding = std::vector<std::vector<std::pair<std::uint32_t, double>>>;

/** Points binned in cubic cells, to visit those in the 27 cells around a position
  * (all within one cell size of it, and some farther). Positions searched must not
  * lie below `origin` on any axis. */
class CellGrid
{
public:
  CellGrid (const Points3& points, double cell, const Eigen::Vector3d& origin)
    : origin_ (origin), cell_ (cell)
  {
    for (std::size_t i = 0; i < points.size (); ++i)
      cells_[keyOf (cellOf (points[i]))].push_back (static_cast<std::uint32_t> (i));
  }

  template <typename Visit>
  void
  forEachNear (const Eigen::Vector3d& p, Visit visit) const
  {
    anyNear (p, [&visit] (std::uint32_t j) {
      visit (j);
      return false;
    });
  }

  /** Whether `test` holds for a point in the 27 cells around p; stops at the first. */
  template <typename Test>
  bool
  anyNear (const Eigen::Vector3d& p, Test test) const
  {
    const Eigen::Array<std::int64_t, 3, 1> c = cellOf (p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto found = cells_.find (keyOf (c + Eigen::Array<std::int64_t, 3, 1> (dx, dy, dz)));
          if (found != cells_.end ())
            for (const std::uint32_t j : found->second)
              if (test (j))
                return true;
        }
    return false;
  }

private:
  Eigen::Array<std::int64_t, 3, 1>
  cellOf (const Eigen::Vector3d& p) const
  {
    return ((p - origin_) / cell_).array ().floor ().cast<std::int64_t> ();
  }

  // Cells count from 0 at the box's corner, their neighbours from -1: shift by one so
  // that keys stay non-negative (fewer than 2^21 cells per axis).
  static std::int64_t
  keyOf (const Eigen::Array<std::int64_t, 3, 1>& c)
  {
    return ((c.x () + 1) << 42) | ((c.y () + 1) << 21) | (c.z () + 1);
  }

  Eigen::Vector3d origin_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

/** For every point, its neighbours closer than reach with the weights
  * (1 - d / reach)^8 they crowd it by. */
Crowding
crowdingNeighbours (const Points3& points, double reach)
{
  const CellGrid grid (points, reach, boundingBox (points).lo);
  Crowding crowding (points.size ());
  for (std::size_t i = 0; i < points.size (); ++i)
    grid.forEachNear (points[i], [&] (std::uint32_t j) {
      const double d = (points[i] - points[j]).norm ();
      if (j != i && d < reach)
        crowding[i].emplace_back (j, std::pow (1.0 - d / reach, 8.0));
    });
  return crowding;
}

/** Keeps n of the candidates, removing one at a time the one most crowded by its
  * neighbours within twice the radius of n discs packed on the area (Yuksel's
  * weighted sample elimination): a random cloud becomes evenly spaced, yet
  * irregular. The survivors keep their order. */
Points3
eliminateCrowded (const Points3& candidates, std::size_t n, double area)
{
  const std::size_t m = candidates.size ();
  if (n >= m)
    return candidates;
  const double reach = 2.0 * std::sqrt (area / (2.0 * std::sqrt (3.0) * static_cast<double> (n)));
  const Crowding crowding = crowdingNeighbours (candidates, reach);
  std::vector<double> weight (m, 0.0);
  for (std::size_t i = 0; i < m; ++i)
    for (const auto& neighbour : crowding[i])
      weight[i] += neighbour.second;
  std::priority_queue<std::pair<double, std::uint32_t>> most_crowded;
  for (std::size_t i = 0; i < m; ++i)
    most_crowded.emplace (weight[i], static_cast<std::uint32_t> (i));
  std::vector<bool> removed (m, false);
  for (std::size_t left = m; left > n;) {
    const auto [w, i] = most_crowded.top ();
    most_crowded.pop ();
    if (removed[i] || w != weight[i])
      continue; // a stale entry: the weight fell since it was queued
    removed[i] = true;
    --left;
    for (const auto& [j, wij] : crowding[i])
      if (!removed[j]) {
        weight[j] -= wij;
        most_crowded.emplace (weight[j], j);
      }
  }
  Points3 kept;
  kept.reserve (n);
  for (std::size_t i = 0; i < m; ++i)
    if (!removed[i])
      kept.push_back (candidates[i]);
  return kept;
}

/** The (2, 3) torus knot of the KnottedTube, with its first two derivatives. */
void
torusKnot (double t, Eigen::Vector3d& c, Eigen::Vector3d& d1, Eigen::Vector3d& d2)
{
  const double h = 2.0 + std::cos (3.0 * t), h1 = -3.0 * std::sin (3.0 * t),
               h2 = -9.0 * std::cos (3.0 * t);
  const double cu = std::cos (2.0 * t), su = std::sin (2.0 * t);
  c = {h * cu, h * su, std::sin (3.0 * t)};
  d1 = {h1 * cu - 2.0 * h * su, h1 * su + 2.0 * h * cu, 3.0 * std::cos (3.0 * t)};
  d2 = {h2 * cu - 4.0 * h1 * su - 4.0 * h * cu, h2 * su + 4.0 * h1 * cu - 4.0 * h * su,
        -9.0 * std::sin (3.0 * t)};
}

/** Point (u, v) in [0, 2 pi)^2 of a parametric shape: tori in (around the axis,
  * around the tube), the knotted tube in (along the knot, around it, Frenet frame). */
Eigen::Vector3d
parametricPoint (SyntheticShape shape, double u, double v)
{
  if (shape == SyntheticShape::KnottedTube) {
    Eigen::Vector3d c, d1, d2;
    torusKnot (u, c, d1, d2);
    const Eigen::Vector3d tangent = d1.normalized ();
    const Eigen::Vector3d binormal = d1.cross (d2).normalized ();
    const Eigen::Vector3d normal = binormal.cross (tangent);
    return c + 0.3 * (std::cos (v) * normal + std::sin (v) * binormal);
  }
  const double small = shape == SyntheticShape::ThinTorus ? 0.15 : 0.6;
  const double ring = 1.0 + small * std::cos (v);
  return {ring * std::cos (u), ring * std::sin (u), small * std::sin (v)};
}

/** Area element |X_u x X_v| of a parametric shape, by central differences. */
double
areaElement (SyntheticShape shape, double u, double v)
{
  const double h = 1e-5;
  const Eigen::Vector3d xu =
      (parametricPoint (shape, u + h, v) - parametricPoint (shape, u - h, v)) / (2.0 * h);
  const Eigen::Vector3d xv =
      (parametricPoint (shape, u, v + h) - parametricPoint (shape, u, v - h)) / (2.0 * h);
  return xu.cross (xv).norm ();
}

/** m points uniform per area on a parametric shape: parameters drawn uniformly and
  * kept with probability area element / its maximum. Sets the shape's area. */
Points3
sampleParametric (SyntheticShape shape, std::size_t m, std::mt19937& random, double& area)
{
  const int steps = 256;
  double largest = 0.0, sum = 0.0;
  for (int i = 0; i < steps; ++i)
    for (int j = 0; j < steps; ++j) {
      const double element = areaElement (shape, 2.0 * pi * i / steps, 2.0 * pi * j / steps);
      largest = std::max (largest, element);
      sum += element;
    }
  area = 4.0 * pi * pi * sum / (steps * steps);
  largest *= 1.05; // the grid may miss the peak between its nodes
  std::uniform_real_distribution<double> angle (0.0, 2.0 * pi), unit (0.0, 1.0);
  Points3 points;
  points.reserve (m);
  while (points.size () < m) {
    const double u = angle (random), v = angle (random);
    if (unit (random) * largest < areaElement (shape, u, v))
      points.push_back (parametricPoint (shape, u, v));
  }
  return points;
}

/** The DoubleTorus' implicit function and its gradient. */
double
doubleTorusFunction (const Eigen::Vector3d& p, Eigen::Vector3d& gradient)
{
  const double x = p.x (), y = p.y (), z = p.z ();
  const double q = x * x + y * y;
  const double g = q * q - x * x + y * y;
  gradient = {2.0 * g * (4.0 * q * x - 2.0 * x), 2.0 * g * (4.0 * q * y + 2.0 * y), 2.0 * z};
  return g * g + z * z - 0.01;
}

/** Union of a and b with the join rounded over a width of about `width`. */
double
smoothMinimum (double a, double b, double width)
{
  const double h = std::max (width - std::abs (a - b), 0.0) / width;
  return std::min (a, b) - 0.25 * h * h * width;
}

/** The ThinLimbs' signed distance (nearly: the rounded joins are not exact). */
double
thinLimbsDistance (const Eigen::Vector3d& p)
{
  double f = p.norm () - 0.5;
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d off_axis = p;
    off_axis[axis] -= std::clamp (p[axis], -1.5, 1.5);
    f = smoothMinimum (f, off_axis.norm () - 0.05, 0.1);
  }
  return f;
}

/** The ThinLimbs' function and its gradient by central differences; far from the
  * surface, where the sampler only rejects, a unit vector stands in for the gradient. */
double
thinLimbsFunction (const Eigen::Vector3d& p, Eigen::Vector3d& gradient)
{
  const double f = thinLimbsDistance (p);
  gradient = Eigen::Vector3d::UnitX ();
  if (std::abs (f) > 0.1)
    return f;
  const double h = 1e-7;
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d step = Eigen::Vector3d::Zero ();
    step[axis] = h;
    gradient[axis] = (thinLimbsDistance (p + step) - thinLimbsDistance (p - step)) / (2.0 * h);
  }
  return f;
}

/** m points close to uniform per area on the zero set of `function` inside the box
  * of half extents `half`: uniform points of the box within a shell of half width
  * `shell` around it (by first-order distance), projected onto it by Newton steps
  * along the gradient. Sets the shape's area (shell volume / width). */
template <typename Function>
Points3
sampleImplicit (const Function& function,
                const Eigen::Vector3d& half,
                double shell,
                std::size_t m,
                std::mt19937& random,
                double& area)
{
  std::uniform_real_distribution<double> unit (-1.0, 1.0);
  Points3 points;
  points.reserve (m);
  std::size_t tried = 0;
  while (points.size () < m) {
    ++tried;
    Eigen::Vector3d p (half.x () * unit (random), half.y () * unit (random),
                       half.z () * unit (random));
    Eigen::Vector3d gradient;
    double f = function (p, gradient);
    if (std::abs (f) >= shell * gradient.norm ())
      continue;
    for (int step = 0; step < 50 && std::abs (f) > 1e-15 * gradient.norm (); ++step) {
      p -= f * gradient / gradient.squaredNorm ();
      f = function (p, gradient);
    }
    points.push_back (p);
  }
  area = 8.0 * half.prod () * static_cast<double> (m) / static_cast<double> (tried) /
         (2.0 * shell);
  return points;
}

/** The shapes sampled on a jittered lattice (sampleLattice), not by elimination. */
bool
onALattice (SyntheticShape shape)
{
  switch (shape) {
  case SyntheticShape::ThinTorus:
  case SyntheticShape::FatTorus:
  case SyntheticShape::KnottedTube:
  case SyntheticShape::DoubleTorus:
  case SyntheticShape::ThinLimbs:
    return false;
  default:
    return true;
  }
}

/** `count` candidates uniform per area: random points on the shapes sampled through
  * a function (their area returned), the jittered lattice on the others (area 0). */
Points3
uniformCandidates (SyntheticShape shape, std::size_t count, std::mt19937& random, double& area)
{
  area = 0.0;
  if (onALattice (shape))
    return sampleLattice (shape, count, random);
  switch (shape) {
  case SyntheticShape::ThinTorus:
  case SyntheticShape::FatTorus:
  case SyntheticShape::KnottedTube:
    return sampleParametric (shape, count, random, area);
  case SyntheticShape::DoubleTorus:
    return sampleImplicit (doubleTorusFunction, {1.2, 0.6, 0.15}, 0.005, count, random, area);
  case SyntheticShape::ThinLimbs:
    return sampleImplicit (thinLimbsFunction, {1.6, 1.6, 1.6}, 0.02, count, random, area);
  default: // a shape onALattice does not know yet: the lattice, as for the others
    return sampleLattice (shape, count, random);
  }
}

/** n points evenly spread on a shape, uniform per area. */
Points3
sampleUniformly (SyntheticShape shape, std::size_t n, std::mt19937& random)
{
  if (n == 0)
    return {};
  if (onALattice (shape))
    return sampleLattice (shape, n, random);
  double area = 0.0;
  const Points3 candidates = uniformCandidates (shape, 5 * n, random, area);
  return eliminateCrowded (candidates, n, area);
}

/** n points whose density grows smoothly by the factor ratio along the longest axis
  * of the shape's box: a shuffled uniform cloud, each point kept with probability
  * proportional to the density there, until n are kept (a larger cloud if too few). */
Points3
sampleUnevenly (SyntheticShape shape, std::size_t n, double ratio, std::mt19937& random)
{
  if (n == 0)
    return {};
  std::uniform_real_distribution<double> unit (0.0, 1.0);
  for (std::size_t m = n + n / 2 + n;; m *= 2) {
    Points3 uniform = sampleUniformly (shape, m, random);
    std::shuffle (uniform.begin (), uniform.end (), random);
    const BoundingBox box = boundingBox (uniform);
    const int axis = longestAxis (uniform);
    const double extent = box.hi[axis] - box.lo[axis];
    Points3 kept;
    kept.reserve (n);
    for (const auto& p : uniform) {
      const double s = (p[axis] - box.lo[axis]) / extent;
      const double density = 1.0 + (ratio - 1.0) * 0.5 * (1.0 - std::cos (pi * s));
      if (unit (random) * ratio < density)
        kept.push_back (p);
      if (kept.size () == n)
        return kept;
    }
  }
}

/** Clusters of `size` points: the points of a sample eight times as dense nearest to
  * each point of an even sample of n / size centres. */
Points3
sampleInClusters (SyntheticShape shape, std::size_t n, std::size_t size, std::mt19937& random)
{
  const std::size_t centres = std::max<std::size_t> (1, n / size);
  const Points3 centre = sampleUniformly (shape, centres, random);
  const Points3 dense = sampleUniformly (shape, 8 * centres * size, random);
  std::vector<std::vector<std::pair<double, std::size_t>>> nearest (centre.size ());
  for (std::size_t i = 0; i < dense.size (); ++i) {
    std::size_t best = 0;
    for (std::size_t c = 1; c < centre.size (); ++c)
      if ((dense[i] - centre[c]).squaredNorm () < (dense[i] - centre[best]).squaredNorm ())
        best = c;
    nearest[best].emplace_back ((dense[i] - centre[best]).squaredNorm (), i);
  }
  Points3 points;
  points.reserve (centres * size);
  for (auto& members : nearest) {
    const std::size_t keep = std::min (size, members.size ());
    std::partial_sort (members.begin (), members.begin () + keep, members.end ());
    for (std::size_t j = 0; j < keep; ++j)
      points.push_back (dense[members[j].second]);
  }
  return points;
}

/** Points per unit area of a sample spread over a surface: the mean count within
  * four median nearest-neighbour distances (at most the grid's cell) of every 16th
  * point, over that disc's area. */
double
areaDensity (const Points3& points)
{
  const BoundingBox box = boundingBox (points);
  const double cell =
      4.0 * (box.hi - box.lo).norm () / std::sqrt (static_cast<double> (points.size ()));
  const CellGrid grid (points, cell, box.lo);
  std::vector<std::vector<double>> distances;
  std::vector<double> nearest;
  for (std::size_t i = 0; i < points.size (); i += 16) {
    std::vector<double> d;
    grid.forEachNear (points[i], [&] (std::uint32_t j) {
      if (j != i)
        d.push_back ((points[j] - points[i]).norm ());
    });
    nearest.push_back (d.empty () ? cell : *std::min_element (d.begin (), d.end ()));
    distances.push_back (std::move (d));
  }
  std::nth_element (nearest.begin (), nearest.begin () + nearest.size () / 2, nearest.end ());
  const double reach = std::min (cell, 4.0 * nearest[nearest.size () / 2]);
  double count = 0.0;
  for (const auto& d : distances)
    count += 1.0 + static_cast<double> (
                       std::count_if (d.begin (), d.end (), [&] (double x) { return x < reach; }));
  return count / static_cast<double> (distances.size ()) / (pi * reach * reach);
}

/** n points in rows (fewer only if the candidates are): the shape cut by planes
  * across its longest axis, `stretch` times the spacing along a row apart, at an
  * offset set by the seed; in each cut the candidates within a quarter of that
  * spacing of its plane. Where the surface turns across the axis (a sphere's poles)
  * the cuts lie far apart along it: the candidates farther than three quarters of
  * the rows' gap from every cut fill it. All are thinned to the spacing
  * (eliminateCrowded; from a stretch of about 2.5 the rows lie farther apart than
  * its reach, below it neighbouring rows crowd each other too). */
Points3
sampleInRows (SyntheticShape shape, std::size_t n, double stretch, std::mt19937& random)
{
  if (n == 0)
    return {};
  // Ten times as many candidates per row gap as points, so that a quarter-spacing
  // strip around each cut still holds several times the points it keeps.
  const auto m = static_cast<std::size_t> (10.0 * std::ceil (stretch) * static_cast<double> (n));
  double area = 0.0;
  const Points3 candidates = uniformCandidates (shape, m, random, area);
  if (onALattice (shape))
    area = static_cast<double> (candidates.size ()) / areaDensity (candidates);
  // n points on rows of total length area / (stretch spacing), spacing apart.
  const double spacing = std::sqrt (area / (stretch * static_cast<double> (n)));
  const double gap = stretch * spacing;
  const double even_area = 2.0 * std::sqrt (3.0) * static_cast<double> (n) * spacing * spacing;
  const int axis = longestAxis (candidates);
  const double offset = std::uniform_real_distribution<double> (0.0, gap) (random);
  Points3 rows_and_caps;
  for (const auto& p : candidates)
    if (std::abs (std::remainder (p[axis] - offset, gap)) < 0.25 * spacing)
      rows_and_caps.push_back (p);
  if (rows_and_caps.empty ()) // rows wider apart than the shape
    return eliminateCrowded (candidates, n, even_area);
  const CellGrid cut_points (rows_and_caps, 0.75 * gap, boundingBox (candidates).lo);
  Points3 far_from_cuts;
  for (const auto& p : candidates)
    if (!cut_points.anyNear (p, [&] (std::uint32_t j) {
          return (rows_and_caps[j] - p).norm () <= 0.75 * gap;
        }))
      far_from_cuts.push_back (p);
  rows_and_caps.insert (rows_and_caps.end (), far_from_cuts.begin (), far_from_cuts.end ());
  // eliminateCrowded's reach, 2 sqrt (area / (2 sqrt 3 n)), is then twice the spacing.
  return eliminateCrowded (rows_and_caps, n, even_area);
}

/** The open shapes' square grid over the unit disc, turned and shifted at random. */
Points3
sampleOnLattice (SyntheticShape shape, std::size_t n, std::mt19937& random)
{
  std::uniform_real_distribution<double> unit (0.0, 1.0);
  const double step = std::sqrt (pi / static_cast<double> (std::max<std::size_t> (n, 1)));
  const double turn = 0.5 * pi * unit (random);
  const Eigen::Vector2d shift (step * unit (random), step * unit (random));
  const Eigen::Rotation2Dd rotation (turn);
  const int reach = static_cast<int> (std::ceil (1.5 / step));
  Points3 points;
  for (int i = -reach; i <= reach; ++i)
    for (int j = -reach; j <= reach; ++j) {
      const Eigen::Vector2d xy = rotation * (Eigen::Vector2d (i * step, j * step) + shift);
      if (xy.norm () <= 1.0)
        points.emplace_back (xy.x (), xy.y (),
                             shape == SyntheticShape::Disc ? 0.0 : heightField (xy.x (), xy.y ()));
    }
  return points;
}

} // namespace

int
syntheticGenus (SyntheticShape shape)
{
  switch (shape) {
  case SyntheticShape::Sphere:
  case SyntheticShape::Ellipsoid:
  case SyntheticShape::BumpySphere:
  case SyntheticShape::ThinLimbs:
    return 0;
  case SyntheticShape::Torus:
  case SyntheticShape::ThinTorus:
  case SyntheticShape::FatTorus:
  case SyntheticShape::KnottedTube:
    return 1;
  case SyntheticShape::DoubleTorus:
    return 2;
  case SyntheticShape::Disc:
  case SyntheticShape::HeightField:
    break;
  }
  return -1;
}

Points3
sampleShape (SyntheticShape shape, const SyntheticCloudOptions& options)
{
  std::mt19937 random (options.seed);
  const bool open = shape == SyntheticShape::Disc || shape == SyntheticShape::HeightField;
  Points3 points =
      options.uneven > 1.0 ? sampleUnevenly (shape, options.num_points, options.uneven, random)
      : options.cluster_size > 1
          ? sampleInClusters (shape, options.num_points, options.cluster_size, random)
      : options.lattice && open ? sampleOnLattice (shape, options.num_points, random)
      : options.stretch > 1.0 && std::isfinite (options.stretch)
          ? sampleInRows (shape, options.num_points, options.stretch, random)
          : sampleUniformly (shape, options.num_points, random);
  if (open && options.holes > 0) {
    const double radius = 0.15;
    std::uniform_real_distribution<double> unit (0.0, 1.0);
    std::vector<Eigen::Vector2d> centres;
    for (int tries = 0; centres.size () < std::min<std::size_t> (options.holes, 5) && tries < 10000;
         ++tries) {
      const double r = 0.65 * std::sqrt (unit (random)), phi = 2.0 * pi * unit (random);
      const Eigen::Vector2d c (r * std::cos (phi), r * std::sin (phi));
      if (std::all_of (centres.begin (), centres.end (),
                       [&] (const Eigen::Vector2d& o) { return (o - c).norm () >= 3.0 * radius; }))
        centres.push_back (c);
    }
    points.erase (std::remove_if (points.begin (), points.end (),
                                  [&] (const Eigen::Vector3d& p) {
                                    return std::any_of (centres.begin (), centres.end (),
                                                        [&] (const Eigen::Vector2d& c) {
                                                          return (p.head<2> () - c).norm () < radius;
                                                        });
                                  }),
                  points.end ());
  }
  if (options.noise > 0.0 && !points.empty ()) {
    const BoundingBox box = boundingBox (points);
    std::normal_distribution<double> gauss (0.0, options.noise * (box.hi - box.lo).norm ());
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
      {"disc", SyntheticShape::Disc},               {"height_field", SyntheticShape::HeightField},
      {"thin_torus", SyntheticShape::ThinTorus},     {"fat_torus", SyntheticShape::FatTorus},
      {"double_torus", SyntheticShape::DoubleTorus}, {"knotted_tube", SyntheticShape::KnottedTube},
      {"thin_limbs", SyntheticShape::ThinLimbs}};
  for (const auto& entry : names)
    if (name == entry.first) {
      shape = entry.second;
      return true;
    }
  return false;
}

} // namespace meshless
} // namespace pcl
