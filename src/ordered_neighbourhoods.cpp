/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/features/feature.h> // pcl::solvePlaneParameters
#include <pcl/surface/meshless/ordered_neighbourhoods.h>

#include "common/constants.h"
#include "common/spacing.h"
#include "common/threads.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace pcl {
namespace meshless {

namespace {

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

/** The Gaussian weights' width about `centre`: `width` times the mean distance to
  * its six nearest among the given points; 0 where that is not positive or finite. */
double
gaussianWidth (const Points3& points,
               pcl::index_t centre,
               const pcl::index_t* begin,
               const pcl::index_t* end,
               double width)
{
  std::vector<double> scratch;
  const double sigma = width * nearestSpacing (points, centre, begin, end, scratch);
  return sigma > 0.0 && std::isfinite (sigma) ? sigma : 0.0;
}

/** exp (-(distance / sigma)^2), the weight of a point at that distance. */
double
gaussianWeight (double distance, double sigma)
{
  const double ratio = distance / sigma;
  return std::exp (-ratio * ratio);
}

/** The normal of the plane of least (weighted) squares from the points' moments
  * about the centre: their weighted sum and sum of outer products, over the total
  * weight. */
Eigen::Vector3d
normalOfMoments (const Eigen::Vector3d& sum, const Eigen::Matrix3d& outer, double total)
{
  const Eigen::Vector3d mean = sum / total;
  const Eigen::Matrix3d covariance = outer / total - mean * mean.transpose ();
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
  return normalOfMoments (sum, outer, count);
}

Eigen::Vector3d
weightedLeastSquaresNormal (const Points3& points,
                            pcl::index_t centre,
                            const pcl::index_t* begin,
                            const pcl::index_t* end,
                            bool include_centre,
                            double width)
{
  const std::ptrdiff_t count = end - begin;
  if (count + (include_centre ? 1 : 0) < 3 || !(width > 0.0))
    return Eigen::Vector3d::Zero ();
  const Eigen::Vector3d& origin = points[centre];
  const double sigma = gaussianWidth (points, centre, begin, end, width);
  if (sigma == 0.0)
    return Eigen::Vector3d::Zero ();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero ();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero ();
  double total = include_centre ? 1.0 : 0.0; // the centre contributes a zero vector
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    const Eigen::Vector3d d = points[begin[i]] - origin;
    const double weight = gaussianWeight (d.norm (), sigma);
    sum += weight * d;
    outer += weight * d * d.transpose ();
    total += weight;
  }
  if (!(total > 0.0))
    return Eigen::Vector3d::Zero ();
  return normalOfMoments (sum, outer, total);
}

Eigen::Vector3d
sphereThroughPointNormal (const Points3& points,
                          pcl::index_t centre,
                          const pcl::index_t* begin,
                          const pcl::index_t* end,
                          double width)
{
  const std::ptrdiff_t count = end - begin;
  if (count < 3)
    return Eigen::Vector3d::Zero ();
  const Eigen::Vector3d& origin = points[centre];
  const double sigma = width > 0.0 ? gaussianWidth (points, centre, begin, end, width) : 0.0;
  if (width > 0.0 && sigma == 0.0)
    return Eigen::Vector3d::Zero ();
  // Offsets in units of the largest keep the fourth powers' sums well conditioned.
  double scale = 0.0;
  for (const pcl::index_t* w = begin; w != end; ++w)
    scale = std::max (scale, (points[*w] - origin).norm ());
  if (!(scale > 0.0) || !std::isfinite (scale))
    return Eigen::Vector3d::Zero ();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero ();
  Eigen::Vector3d lifted = Eigen::Vector3d::Zero ();
  double fourth = 0.0;
  for (const pcl::index_t* w = begin; w != end; ++w) {
    const Eigen::Vector3d d = points[*w] - origin;
    const double weight = sigma > 0.0 ? gaussianWeight (d.norm (), sigma) : 1.0;
    const Eigen::Vector3d u = d / scale;
    const double squared = u.squaredNorm ();
    second += weight * u * u.transpose ();
    lifted += weight * squared * u;
    fourth += weight * squared * squared;
  }
  if (!(fourth > 0.0))
    return Eigen::Vector3d::Zero ();
  const Eigen::Matrix3d form = second - lifted * lifted.transpose () / fourth;
  const double trace = form.trace ();
  if (!(trace > 0.0))
    return Eigen::Vector3d::Zero ();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen (form / trace);
  const Eigen::Vector3d normal = eigen.eigenvectors ().col (0);
  const double length = normal.norm ();
  if (eigen.info () != Eigen::Success || !(length > 0.0) || !std::isfinite (length))
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

  // The origin's Voronoi cell is the intersection of the half planes
  // {x : x.q_j <= |q_j|^2 / 2} = {x : x.p_j <= 1} with p_j = 2 q_j / |q_j|^2, the
  // polar set of K = conv({0} and all p_j); a half plane bounds the cell along an
  // edge of positive length iff its p_j is a vertex of K other than the origin. So
  // the ring is K's vertex set, found by a monotone-chain hull in O(d log d) instead
  // of clipping each bisector by every other half plane in O(d^2), which dominated
  // the rings' time on large clouds. A point hidden behind a nearer one in the same
  // direction lies on [0, p_j]; a co-circular fourth point (a zero-length Voronoi
  // edge) on a hull edge: neither is a vertex. Of points at the same place only one
  // can be.
  struct Polar
  {
    Eigen::Vector2d p;
    int index; // into local, -1 for the origin
  };
  // Buffers kept per thread: the rings of a million points are a million calls.
  static thread_local std::vector<Polar> polar;
  static thread_local std::vector<int> hull;
  polar.clear ();
  polar.push_back ({Eigen::Vector2d::Zero (), -1});
  for (int i = 0; i < count; ++i) {
    const double squared = local[i].squaredNorm ();
    if (std::sqrt (squared) > tolerance) // else it projects onto v: no direction
      polar.push_back ({2.0 * local[i] / squared, i});
  }
  std::sort (polar.begin (), polar.end (), [] (const Polar& a, const Polar& b) {
    return a.p.x () < b.p.x () ||
           (a.p.x () == b.p.x () && (a.p.y () < b.p.y () || (a.p.y () == b.p.y () && a.index < b.index)));
  });
  // Turns of less than a relative 1e-12 count as straight (the former clipping's
  // tolerance of 1e-12 of the neighbourhood's extent along the bisector).
  const auto turnsLeft = [] (const Polar& o, const Polar& a, const Polar& b) {
    const Eigen::Vector2d u = a.p - o.p, w = b.p - o.p;
    const double cross = u.x () * w.y () - u.y () * w.x ();
    return cross > 1e-12 * u.norm () * w.norm ();
  };
  const std::size_t m = polar.size ();
  hull.assign (2 * m, 0);
  std::size_t h = 0;
  for (std::size_t i = 0; i < m; ++i) { // lower hull
    while (h >= 2 && !turnsLeft (polar[hull[h - 2]], polar[hull[h - 1]], polar[i]))
      --h;
    hull[h++] = static_cast<int> (i);
  }
  for (std::size_t i = m - 1, lower = h + 1; i-- > 0;) { // upper hull
    while (h >= lower && !turnsLeft (polar[hull[h - 2]], polar[hull[h - 1]], polar[i]))
      --h;
    hull[h++] = static_cast<int> (i);
  }
  if (m > 1)
    --h; // the first point closes the loop
  for (std::size_t k = 0; k < h; ++k)
    if (polar[hull[k]].index >= 0)
      ring.push_back (polar[hull[k]].index);

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
  const double max_sine = std::sin (std::clamp (options.max_neighbour_elevation_deg, 0.0, 90.0) *
                                    pi / 180.0);
  const bool drop_steep = options.max_neighbour_elevation_deg < 90.0;
  const bool weighted = options.plane_weight_width > 0.0;
  const bool sphere = options.normal_fit == NormalFit::SphereThroughPoint;

#pragma omp parallel num_threads(threadCount (options.num_threads))
  {
    Points2 local;
    std::vector<int> ring;
    std::vector<pcl::index_t> flat; // the candidates not too steep, in their order
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t sv = 0; sv < static_cast<std::ptrdiff_t> (n); ++sv) {
      const auto v = static_cast<pcl::index_t> (sv);
      const pcl::index_t* begin = candidates.begin (v);
      const pcl::index_t* end = candidates.end (v);
      const bool with_centre = options.plane == LocalPlane::ProjectOntoFit;
      const auto planeNormal = [&] (const pcl::index_t* from, const pcl::index_t* to) {
        if (sphere && to - from >= min_points_for_sphere_fit)
          return sphereThroughPointNormal (points, v, from, to, options.plane_weight_width);
        return weighted ? weightedLeastSquaresNormal (points, v, from, to, with_centre,
                                                      options.plane_weight_width)
                        : leastSquaresNormal (points, v, from, to, with_centre);
      };
      Eigen::Vector3d normal = planeNormal (begin, end);
      if (normal.isZero ())
        continue;
      if (drop_steep) {
        flat.clear ();
        for (const pcl::index_t* w = begin; w != end; ++w) {
          const Eigen::Vector3d d = points[*w] - points[v];
          if (std::abs (normal.dot (d)) <= max_sine * d.norm ())
            flat.push_back (*w);
        }
        const auto kept = static_cast<std::ptrdiff_t> (flat.size ());
        if (kept >= 4 && kept < end - begin) {
          const Eigen::Vector3d refit = planeNormal (flat.data (), flat.data () + kept);
          if (!refit.isZero ()) {
            normal = refit;
            begin = flat.data ();
            end = flat.data () + kept;
          }
        }
      }
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
