/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/features/feature.h> // pcl::solvePlaneParameters
#include <pcl/surface/meshless/ordered_neighbourhoods.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace pcl {
namespace meshless {

namespace {

constexpr double two_pi = 6.283185307179586476925286766559;

/** A right-handed orthonormal frame (e1, e2, n) chosen from n alone, so that the
  * same normal always gives the same frame. */
void
planeFrame (const Eigen::Vector3d& n, Eigen::Vector3d& e1, Eigen::Vector3d& e2)
{
  Eigen::Index smallest;
  n.cwiseAbs ().minCoeff (&smallest);
  Eigen::Vector3d axis = Eigen::Vector3d::Zero ();
  axis[smallest] = 1.0;
  e1 = axis.cross (n).normalized ();
  e2 = n.cross (e1);
}

} // namespace

Eigen::Vector3d
leastSquaresNormal (const Points3& points,
                    pcl::index_t centre,
                    const pcl::index_t* begin,
                    const pcl::index_t* end,
                    bool include_centre)
{
  const Eigen::Vector3d& origin = points[centre];
  Eigen::Vector3d sum = Eigen::Vector3d::Zero ();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero ();
  int count = include_centre ? 1 : 0; // the centre contributes a zero vector
  for (const pcl::index_t* w = begin; w != end; ++w) {
    const Eigen::Vector3d d = points[*w] - origin;
    sum += d;
    outer += d * d.transpose ();
    ++count;
  }
  if (count < 3)
    return Eigen::Vector3d::Zero ();
  const Eigen::Vector3d mean = sum / count;
  const Eigen::Matrix3d covariance = outer / count - mean * mean.transpose ();
  // Scale to unit trace: the eigenvector is unchanged and float stays accurate for
  // clouds in any unit (1e-4 or 1e4).
  const double trace = covariance.trace ();
  if (!(trace > 0.0))
    return Eigen::Vector3d::Zero ();
  float nx, ny, nz, curvature;
  pcl::solvePlaneParameters (Eigen::Matrix3f ((covariance / trace).cast<float> ()), nx, ny,
                             nz, curvature);
  Eigen::Vector3d normal (nx, ny, nz);
  const double length = normal.norm ();
  if (!(length > 0.0) || !std::isfinite (length))
    return Eigen::Vector3d::Zero ();
  return normal / length;
}

void
localCoordinates (const Points3& points,
                  pcl::index_t v,
                  const pcl::index_t* begin,
                  const pcl::index_t* end,
                  const Eigen::Vector3d& normal,
                  LocalPlane plane,
                  Points2& local)
{
  Eigen::Vector3d e1, e2;
  planeFrame (normal, e1, e2);
  local.resize (static_cast<std::size_t> (end - begin));
  std::size_t i = 0;
  for (const pcl::index_t* w = begin; w != end; ++w, ++i) {
    const Eigen::Vector3d d = points[*w] - points[v];
    Eigen::Vector2d q (d.dot (e1), d.dot (e2));
    if (plane == LocalPlane::RotateIntoFit) {
      // Rotate about v into the plane: keep the direction of the projection and
      // the full distance |w - v|.
      const double projected = q.norm ();
      if (projected > 0.0)
        q *= d.norm () / projected;
    }
    local[i] = q;
  }
}

double
delaunayRing (const Points2& local, std::vector<int>& ring)
{
  ring.clear ();
  const int count = static_cast<int> (local.size ());
  double scale = 0.0;
  for (const auto& q : local)
    scale = std::max (scale, q.cwiseAbs ().maxCoeff ());
  if (!(scale > 0.0))
    return two_pi;
  const double tolerance = 1e-12 * scale;

  // q_i is a Delaunay neighbour of the origin iff the bisector of [0, q_i] keeps a
  // piece of positive length inside every other half plane {x : x.q_j <= |q_j|^2/2}
  // (the Voronoi cell of the origin). The bisector is x = q_i/2 + t d_i, |d_i| = 1.
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector2d& qi = local[i];
    const double length = qi.norm ();
    if (!(length > tolerance))
      continue; // projects onto v: no direction to order it by
    const Eigen::Vector2d mid = 0.5 * qi;
    const Eigen::Vector2d dir (-qi.y () / length, qi.x () / length);
    double lo = -std::numeric_limits<double>::infinity ();
    double hi = std::numeric_limits<double>::infinity ();
    for (int j = 0; j < count && hi - lo > tolerance; ++j) {
      if (j == i)
        continue;
      const Eigen::Vector2d& qj = local[j];
      const double a = dir.dot (qj);
      const double b = 0.5 * qj.squaredNorm () - mid.dot (qj);
      if (std::abs (a) <= 1e-15 * scale) {
        if (b < -tolerance * scale)
          hi = lo; // q_j lies between the origin and q_i on one line: q_i is hidden
      }
      else if (a > 0.0)
        hi = std::min (hi, b / a);
      else
        lo = std::max (lo, b / a);
    }
    if (hi - lo > tolerance)
      ring.push_back (i);
  }

  std::vector<double> angle (count, 0.0);
  for (int i : ring) {
    double a = std::atan2 (local[i].y (), local[i].x ());
    angle[i] = a < 0.0 ? a + two_pi : a;
  }
  std::stable_sort (ring.begin (), ring.end (),
                    [&] (int a, int b) { return angle[a] < angle[b]; });
  if (ring.size () < 2)
    return two_pi;
  double largest = two_pi - (angle[ring.back ()] - angle[ring.front ()]);
  for (std::size_t j = 1; j < ring.size (); ++j)
    largest = std::max (largest, angle[ring[j]] - angle[ring[j - 1]]);
  return largest;
}

OrderedNeighbourhoods
orderNeighbourhoods (const Points3& points,
                     const CsrGraph& candidates,
                     const OrderingOptions& options)
{
  OrderedNeighbourhoods result;
  const std::size_t n = points.size ();
  if (candidates.size () != n) {
    result.message = "the neighbourhood graph and the point array differ in size";
    return result;
  }
  result.normals.assign (n, Eigen::Vector3f::Zero ());
  result.largest_gap.assign (n, static_cast<float> (two_pi));

  // Rings are computed independently per point into per-point slots of the
  // candidate layout (a ring is a subset of the candidates), then compacted.
  std::vector<pcl::index_t> slots (candidates.numEntries ());
  std::vector<pcl::index_t> ring_size (n, 0);

#pragma omp parallel
  {
    Points2 local;
    std::vector<int> ring;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t sv = 0; sv < static_cast<std::ptrdiff_t> (n); ++sv) {
      const auto v = static_cast<pcl::index_t> (sv);
      const pcl::index_t* begin = candidates.begin (v);
      const pcl::index_t* end = candidates.end (v);
      const bool with_centre = options.plane == LocalPlane::ProjectOntoFit;
      const Eigen::Vector3d normal = leastSquaresNormal (points, v, begin, end, with_centre);
      if (normal.isZero ())
        continue;
      result.normals[v] = normal.cast<float> ();
      localCoordinates (points, v, begin, end, normal, options.plane, local);
      result.largest_gap[v] = static_cast<float> (delaunayRing (local, ring));
      pcl::index_t* out = slots.data () + candidates.offsets[v];
      for (int r : ring)
        *out++ = begin[r];
      ring_size[v] = static_cast<pcl::index_t> (ring.size ());
    }
  }

  CsrGraph& rings = result.rings;
  rings.offsets.assign (n + 1, 0);
  for (std::size_t v = 0; v < n; ++v)
    rings.offsets[v + 1] = rings.offsets[v] + ring_size[v];
  rings.adjacency.resize (rings.offsets[n]);
  for (std::size_t v = 0; v < n; ++v)
    std::copy_n (slots.begin () + candidates.offsets[v], ring_size[v],
                 rings.adjacency.begin () + rings.offsets[v]);
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
