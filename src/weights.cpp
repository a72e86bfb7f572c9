/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/weights.h>

#include "common/threads.h"

#include <algorithm>
#include <cmath>

namespace pcl {
namespace meshless {

namespace {

double
cross (const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x () * b.y () - a.y () * b.x ();
}

/** tan(alpha/2) for the angle alpha from a to b (counter-clockwise, in (0, pi)),
  * in the cancellation-free form |a x b| / (|a||b| + a.b); negative if a and b turn
  * clockwise, not finite at alpha = pi. */
double
tanHalfAngle (const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return cross (a, b) / (a.norm () * b.norm () + a.dot (b));
}

bool
normalise (std::vector<double>& lambda)
{
  double sum = 0.0;
  for (double l : lambda)
    sum += l;
  if (!(sum > 0.0) || !std::isfinite (sum))
    return false;
  for (double& l : lambda)
    l /= sum;
  return true;
}

} // namespace

bool
meanValueWeights (const Points2& ring, std::vector<double>& lambda)
{
  const std::size_t d = ring.size ();
  if (d < 2)
    return false;
  std::vector<double> tangent (d); // tan(alpha_j / 2), alpha_j from ring[j] to ring[j+1]
  for (std::size_t j = 0; j < d; ++j) {
    const Eigen::Vector2d& a = ring[j];
    const Eigen::Vector2d& b = ring[(j + 1) % d];
    if (!(a.squaredNorm () > 0.0) || !(b.squaredNorm () > 0.0))
      return false;
    const double c = cross (a, b);
    // An angle of pi or more (c <= 0 with the pair not pointing the same way) means
    // the origin is not surrounded; identical directions (alpha = 0) are harmless.
    if (c < 0.0 || (c == 0.0 && a.dot (b) < 0.0))
      return false;
    tangent[j] = tanHalfAngle (a, b);
  }
  std::vector<double> w (d);
  for (std::size_t j = 0; j < d; ++j)
    w[j] = (tangent[(j + d - 1) % d] + tangent[j]) / ring[j].norm ();
  if (!normalise (w))
    return false;
  lambda = std::move (w);
  return true;
}

bool
shapePreservingWeights (const Points2& ring, std::vector<double>& lambda)
{
  const std::size_t d = ring.size ();
  if (d < 3)
    return false;
  for (std::size_t j = 0; j < d; ++j) {
    const double c = cross (ring[j], ring[(j + 1) % d]);
    if (!(c > 0.0))
      return false;
  }
  std::vector<double> w (d, 0.0);
  for (std::size_t l = 0; l < d; ++l) {
    // The ray from ring[l] through the origin leaves the star-shaped ring polygon
    // through one segment [ring[r], ring[r+1]]: the one whose end points lie on
    // either side of the line (or the first end point on it).
    const Eigen::Vector2d& p = ring[l];
    bool found = false;
    for (std::size_t k = 1; k + 1 <= d && !found; ++k) {
      const std::size_t r = (l + k) % d;
      const std::size_t r1 = (r + 1) % d;
      if (r1 == l)
        break;
      // Walking counter-clockwise from p, the exit segment is the first one whose
      // start is clockwise of (or on) the ray direction -p and whose end is
      // counter-clockwise of it; gaps below pi make that pair unique.
      const double sr = cross (-p, ring[r]);
      const double sr1 = cross (-p, ring[r1]);
      if (sr <= 0.0 && sr1 >= 0.0 && !(sr == 0.0 && sr1 == 0.0)) {
        // Barycentric coordinates of the origin in triangle (p, ring[r], ring[r1]).
        const Eigen::Vector2d& a = p;
        const Eigen::Vector2d& b = ring[r];
        const Eigen::Vector2d& c = ring[r1];
        const double area = cross (b - a, c - a);
        if (!(area > 0.0))
          return false;
        const double mu_a = cross (b, c) / area;  // area(0, b, c)
        const double mu_b = cross (c, a) / area;  // area(a, 0, c)
        const double mu_c = cross (a, b) / area;  // area(a, b, 0)
        if (mu_a < 0.0 || mu_b < -1e-12 || mu_c < -1e-12)
          return false;
        w[l] += mu_a;
        w[r] += std::max (mu_b, 0.0);
        w[r1] += std::max (mu_c, 0.0);
        found = true;
      }
    }
    if (!found)
      return false;
  }
  if (!normalise (w))
    return false;
  lambda = std::move (w);
  return true;
}

void
reciprocalDistanceWeights (const Points3& points,
                           pcl::index_t v,
                           const pcl::index_t* begin,
                           const pcl::index_t* end,
                           std::vector<double>& lambda)
{
  lambda.clear ();
  // Coincident neighbours would get infinite weight: give them the weight of the
  // smallest positive distance instead, so the combination stays convex.
  double smallest = 0.0;
  for (const pcl::index_t* w = begin; w != end; ++w) {
    const double dist = (points[*w] - points[v]).norm ();
    if (dist > 0.0 && (smallest == 0.0 || dist < smallest))
      smallest = dist;
  }
  for (const pcl::index_t* w = begin; w != end; ++w) {
    const double dist = (points[*w] - points[v]).norm ();
    lambda.push_back (1.0 / (dist > 0.0 ? dist : (smallest > 0.0 ? smallest : 1.0)));
  }
  normalise (lambda);
}

Weights
computeWeights (const Points3& points,
                const CsrGraph& rings,
                const CsrGraph& graph,
                const std::vector<Eigen::Vector3f>& normals,
                const WeightOptions& options)
{
  Weights result;
  const std::size_t n = points.size ();
  const bool ordered =
      options.type == WeightType::MeanValue || options.type == WeightType::ShapePreserving;
  if (graph.size () != n || (ordered && (rings.size () != n || normals.size () != n))) {
    result.message = "weights need one neighbourhood (and for ordered weights one ring and "
                     "one normal) per point";
    return result;
  }

  // Each point's row comes from its ring or, where the ring fails, from the graph.
  // Rows are computed in parallel into per-point slots wide enough for either
  // (no allocation per point), then packed in order.
  std::vector<std::size_t> slot (n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) {
    const auto v_index = static_cast<pcl::index_t> (v);
    const pcl::index_t ring_size = ordered ? rings.degree (v_index) : 0;
    slot[v + 1] = slot[v] + static_cast<std::size_t> (std::max (ring_size, graph.degree (v_index)));
  }
  std::vector<double> slot_values (slot[n]);
  std::vector<char> uses_ring (n, 0);
  std::size_t fallbacks = 0;
#pragma omp parallel num_threads(threadCount (options.num_threads)) reduction(+ : fallbacks)
  {
    Points2 local;
    std::vector<double> lambda;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t sv = 0; sv < static_cast<std::ptrdiff_t> (n); ++sv) {
      const auto v = static_cast<pcl::index_t> (sv);
      bool done = false;
      if (ordered) {
        localCoordinates (points, v, rings.begin (v), rings.end (v), normals[v].cast<double> (),
                          options.plane, local);
        done = options.type == WeightType::MeanValue ? meanValueWeights (local, lambda)
                                                     : shapePreservingWeights (local, lambda);
        if (!done)
          ++fallbacks;
        uses_ring[v] = done;
      }
      if (!done) {
        const std::size_t d = static_cast<std::size_t> (graph.degree (v));
        if (options.type == WeightType::Uniform)
          lambda.assign (d, d > 0 ? 1.0 / static_cast<double> (d) : 0.0);
        else
          reciprocalDistanceWeights (points, v, graph.begin (v), graph.end (v), lambda);
      }
      std::copy (lambda.begin (), lambda.end (), slot_values.begin () + slot[v]);
    }
  }

  CsrGraph& layout = result.neighbours;
  layout.offsets.assign (n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) {
    const CsrGraph& source = uses_ring[v] ? rings : graph;
    const auto v_index = static_cast<pcl::index_t> (v);
    layout.adjacency.insert (layout.adjacency.end (), source.begin (v_index), source.end (v_index));
    result.values.insert (result.values.end (), slot_values.begin () + slot[v],
                          slot_values.begin () + slot[v] + source.degree (v_index));
    layout.offsets[v + 1] = static_cast<pcl::index_t> (layout.adjacency.size ());
  }
  result.num_fallbacks = fallbacks;
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
