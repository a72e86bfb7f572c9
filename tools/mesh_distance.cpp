/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <meshless_tools/mesh_distance.h>

#include <Eigen/Geometry>

#include "common/constants.h"
#include "common/threads.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <random>
#include <tuple>

namespace pcl {
namespace meshless {

namespace {

using Vector3 = Eigen::Vector3d;

constexpr std::uint32_t leaf_size = 4;

Vector3
closestPointOnSegment (const Vector3& p, const Vector3& a, const Vector3& b)
{
  const Vector3 ab = b - a;
  const double length2 = ab.squaredNorm ();
  if (!(length2 > 0.0))
    return a;
  const double t = std::clamp ((p - a).dot (ab) / length2, 0.0, 1.0);
  return a + t * ab;
}

bool
isFace (const Points3& vertices, const Triangle& t)
{
  const auto n = static_cast<pcl::index_t> (vertices.size ());
  for (const pcl::index_t v : t)
    if (v < 0 || v >= n || !vertices[v].allFinite ())
      return false;
  return true;
}

/** Twice the area vector of a triangle. */
Vector3
areaVector (const Points3& vertices, const Triangle& t)
{
  return (vertices[t[1]] - vertices[t[0]]).cross (vertices[t[2]] - vertices[t[0]]);
}

/** Uniform double in [0, 1) from the top 53 bits, so the samples do not depend on
  * the standard library's distribution implementation. */
double
unit (std::mt19937_64& generator)
{
  return static_cast<double> (generator () >> 11) * 0x1.0p-53;
}

/** Points uniformly distributed by area over the faces of positive area. */
Points3
samplePoints (const Points3& vertices, const Triangles& triangles, std::size_t count,
              std::uint64_t seed)
{
  std::vector<double> cumulative;
  std::vector<std::size_t> faces;
  double total = 0.0;
  for (std::size_t t = 0; t < triangles.size (); ++t) {
    if (!isFace (vertices, triangles[t]))
      continue;
    const double area = 0.5 * areaVector (vertices, triangles[t]).norm ();
    if (!(area > 0.0) || !std::isfinite (area))
      continue;
    total += area;
    cumulative.push_back (total);
    faces.push_back (t);
  }
  Points3 samples;
  if (faces.empty ())
    return samples;
  samples.reserve (count);
  std::mt19937_64 generator (seed);
  for (std::size_t i = 0; i < count; ++i) {
    const auto at = std::upper_bound (cumulative.begin (), cumulative.end (),
                                      unit (generator) * total);
    const Triangle& t = triangles[faces[std::min<std::size_t> (at - cumulative.begin (),
                                                               faces.size () - 1)]];
    // The square root makes the density uniform over the triangle's area.
    const double r1 = std::sqrt (unit (generator));
    const double r2 = unit (generator);
    samples.push_back ((1.0 - r1) * vertices[t[0]] + r1 * (1.0 - r2) * vertices[t[1]] +
                       r1 * r2 * vertices[t[2]]);
  }
  return samples;
}

/** Distances of every sample to the indexed mesh, computed in parallel (each entry
  * is independent, so the result does not depend on the thread count). */
std::vector<double>
distancesTo (const TriangleDistanceIndex& index, const Points3& samples, int threads)
{
  std::vector<double> distances (samples.size ());
  const auto count = static_cast<std::ptrdiff_t> (samples.size ());
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
  for (std::ptrdiff_t i = 0; i < count; ++i)
    distances[i] = index.closest (samples[i]).distance;
  return distances;
}

DistanceStatistics
statistics (std::vector<double> distances, double unit_length)
{
  DistanceStatistics s;
  if (distances.empty ())
    return s;
  double sum = 0.0;
  for (const double d : distances)
    sum += d;
  s.mean = sum / static_cast<double> (distances.size ()) / unit_length;
  s.max = *std::max_element (distances.begin (), distances.end ()) / unit_length;
  // Nearest rank: the smallest value with at least 99 % of the samples at or below it.
  const auto rank = static_cast<std::size_t> (
      std::ceil (0.99 * static_cast<double> (distances.size ())) - 1.0);
  std::nth_element (distances.begin (), distances.begin () + rank, distances.end ());
  s.p99 = distances[rank] / unit_length;
  return s;
}

} // namespace

Vector3
closestPointOnTriangle (const Vector3& p, const Vector3& a, const Vector3& b,
                        const Vector3& c)
{
  // Ericson, Real-Time Collision Detection, 5.1.5: find the Voronoi region of p
  // (vertex, edge or face) from the signs of dot products, then project.
  const Vector3 ab = b - a, ac = c - a, ap = p - a;
  if (!(ab.cross (ac).squaredNorm () > 0.0)) {
    // Zero area: the triangle is a segment, the closest point is on one of its edges.
    const Vector3 candidates[3] = {closestPointOnSegment (p, a, b),
                                   closestPointOnSegment (p, b, c),
                                   closestPointOnSegment (p, c, a)};
    return *std::min_element (std::begin (candidates), std::end (candidates),
                              [&] (const Vector3& u, const Vector3& v) {
                                return (u - p).squaredNorm () < (v - p).squaredNorm ();
                              });
  }
  const double d1 = ab.dot (ap), d2 = ac.dot (ap);
  if (d1 <= 0.0 && d2 <= 0.0)
    return a;
  const Vector3 bp = p - b;
  const double d3 = ab.dot (bp), d4 = ac.dot (bp);
  if (d3 >= 0.0 && d4 <= d3)
    return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
    return a + d1 / (d1 - d3) * ab;
  const Vector3 cp = p - c;
  const double d5 = ab.dot (cp), d6 = ac.dot (cp);
  if (d6 >= 0.0 && d5 <= d6)
    return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
    return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = va + vb + vc;
  return a + (vb / denominator) * ab + (vc / denominator) * ac;
}

TriangleDistanceIndex::TriangleDistanceIndex (const Points3& vertices,
                                              const Triangles& triangles)
    : vertices_ (vertices), triangles_ (triangles)
{
  for (std::size_t t = 0; t < triangles.size (); ++t)
    if (isFace (vertices, triangles[t]))
      faces_.push_back (static_cast<std::uint32_t> (t));
  if (faces_.empty ())
    return;
  nodes_.reserve (2 * faces_.size () / ((leaf_size + 1) / 2) + 1);
  build (0, static_cast<std::uint32_t> (faces_.size ()));
}

std::uint32_t
TriangleDistanceIndex::build (std::uint32_t begin, std::uint32_t end)
{
  const auto self = static_cast<std::uint32_t> (nodes_.size ());
  Node node;
  node.lo = Vector3::Constant (std::numeric_limits<double>::infinity ());
  node.hi = -node.lo;
  Vector3 centre_lo = node.lo, centre_hi = node.hi;
  for (std::uint32_t i = begin; i < end; ++i) {
    const Triangle& t = triangles_[faces_[i]];
    Vector3 centre = Vector3::Zero ();
    for (const pcl::index_t v : t) {
      node.lo = node.lo.cwiseMin (vertices_[v]);
      node.hi = node.hi.cwiseMax (vertices_[v]);
      centre += vertices_[v];
    }
    centre_lo = centre_lo.cwiseMin (centre);
    centre_hi = centre_hi.cwiseMax (centre);
  }
  node.begin = begin;
  node.end = end;
  node.right = 0;
  nodes_.push_back (node);
  if (end - begin <= leaf_size)
    return self;
  int axis;
  (centre_hi - centre_lo).maxCoeff (&axis);
  auto centre = [&] (std::uint32_t f) {
    const Triangle& t = triangles_[f];
    return vertices_[t[0]][axis] + vertices_[t[1]][axis] + vertices_[t[2]][axis];
  };
  // Median split by centroid along the widest axis; the index breaks ties so the tree
  // (and with it the choice among equidistant triangles) is deterministic.
  const std::uint32_t middle = begin + (end - begin) / 2;
  std::nth_element (faces_.begin () + begin, faces_.begin () + middle,
                    faces_.begin () + end, [&] (std::uint32_t f, std::uint32_t g) {
                      const double cf = centre (f), cg = centre (g);
                      return cf < cg || (cf == cg && f < g);
                    });
  build (begin, middle);
  const std::uint32_t right = build (middle, end);
  nodes_[self].right = right;
  return self;
}

ClosestPoint
TriangleDistanceIndex::closest (const Vector3& p) const
{
  ClosestPoint best;
  if (nodes_.empty ())
    return best;
  double best2 = std::numeric_limits<double>::infinity ();
  auto boxDistance2 = [&] (const Node& node) {
    return (node.lo - p).cwiseMax (p - node.hi).cwiseMax (0.0).squaredNorm ();
  };
  // Median splits keep the depth below 32; each level leaves at most one entry behind.
  std::array<std::uint32_t, 64> stack;
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t at = stack[--top];
    const Node& node = nodes_[at];
    // Equal distances are not pruned, so the smallest index among ties is found.
    if (boxDistance2 (node) > best2)
      continue;
    if (node.right == 0) {
      for (std::uint32_t i = node.begin; i < node.end; ++i) {
        const std::size_t f = faces_[i];
        const Triangle& t = triangles_[f];
        const Vector3 q = closestPointOnTriangle (p, vertices_[t[0]], vertices_[t[1]],
                                                  vertices_[t[2]]);
        const double d2 = (q - p).squaredNorm ();
        if (d2 < best2 || (d2 == best2 && f < best.triangle)) {
          best2 = d2;
          best.triangle = f;
          best.point = q;
        }
      }
      continue;
    }
    // The nearer child goes on top so that it shrinks best2 before the other is tried.
    const std::uint32_t left = at + 1;
    const bool left_first =
        boxDistance2 (nodes_[left]) <= boxDistance2 (nodes_[node.right]);
    stack[top++] = left_first ? node.right : left;
    stack[top++] = left_first ? left : node.right;
  }
  best.distance = std::sqrt (best2);
  return best;
}

namespace {

/** The largest distance to `index` over the points of a barycentric lattice of
  * step 1 / steps on every face. */
double
latticeMax (const Points3& vertices, const Triangles& triangles,
            const TriangleDistanceIndex& index, int steps, int threads)
{
  double largest = 0.0;
  const auto count = static_cast<std::ptrdiff_t> (triangles.size ());
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) reduction(max : largest)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    const Triangle& t = triangles[i];
    if (!isFace (vertices, t))
      continue;
    for (int a = 0; a <= steps; ++a)
      for (int b = 0; a + b <= steps; ++b) {
        const double u = static_cast<double> (a) / steps, v = static_cast<double> (b) / steps;
        const Vector3 x = u * vertices[t[0]] + v * vertices[t[1]] + (1.0 - u - v) * vertices[t[2]];
        largest = std::max (largest, index.closest (x).distance);
      }
  }
  return largest;
}

} // namespace

MeshDistanceReport
compareToReference (const Points3& vertices, const Triangles& triangles,
                    const Points3& reference_vertices,
                    const Triangles& reference_triangles,
                    const MeshDistanceOptions& options)
{
  MeshDistanceReport report;
  // The index numbers triangles with 32 bits.
  constexpr std::size_t max_triangles = std::numeric_limits<std::uint32_t>::max ();
  if (triangles.size () > max_triangles || reference_triangles.size () > max_triangles) {
    report.message = "more than 2^32 - 1 triangles";
    return report;
  }
  try {
    const int threads = threadCount (options.num_threads);
    const Points3 samples =
        samplePoints (vertices, triangles, options.samples, options.seed);
    // A different stream for the reference, so the two sample sets are independent.
    const Points3 reference_samples =
        samplePoints (reference_vertices, reference_triangles, options.samples,
                      ~static_cast<std::uint64_t> (options.seed));
    if (samples.empty () || reference_samples.empty ()) {
      report.message =
          std::string (samples.empty () ? "the mesh" : "the reference mesh") +
          " has no triangle of positive area";
      return report;
    }

    Vector3 lo = Vector3::Constant (std::numeric_limits<double>::infinity ());
    Vector3 hi = -lo;
    for (const Triangle& t : reference_triangles)
      if (isFace (reference_vertices, t))
        for (const pcl::index_t v : t) {
          lo = lo.cwiseMin (reference_vertices[v]);
          hi = hi.cwiseMax (reference_vertices[v]);
        }
    report.diagonal = (hi - lo).norm ();

    const TriangleDistanceIndex mesh_index (vertices, triangles);
    const TriangleDistanceIndex reference_index (reference_vertices,
                                                 reference_triangles);
    std::vector<double> forward = distancesTo (reference_index, samples, threads);
    std::vector<double> backward = distancesTo (mesh_index, reference_samples, threads);
    report.to_reference = statistics (forward, report.diagonal);
    report.from_reference = statistics (backward, report.diagonal);
    forward.insert (forward.end (), backward.begin (), backward.end ());
    report.two_sided = statistics (std::move (forward), report.diagonal);
    if (options.lattice_for_max > 0) {
      const double to = latticeMax (vertices, triangles, reference_index,
                                    options.lattice_for_max, threads) / report.diagonal;
      const double from = latticeMax (reference_vertices, reference_triangles, mesh_index,
                                      options.lattice_for_max, threads) / report.diagonal;
      report.to_reference.max = std::max (report.to_reference.max, to);
      report.from_reference.max = std::max (report.from_reference.max, from);
      report.two_sided.max =
          std::max (report.to_reference.max, report.from_reference.max);
    }

    // Angles in parallel into one slot per triangle, summed in order afterwards, so
    // the mean does not depend on the thread count.
    std::vector<double> weighted_angle (triangles.size (), 0.0);
    std::vector<double> weight (triangles.size (), 0.0);
    const auto count = static_cast<std::ptrdiff_t> (triangles.size ());
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      const Triangle& t = triangles[i];
      if (!isFace (vertices, t))
        continue;
      const Vector3 normal = areaVector (vertices, t);
      const double area = 0.5 * normal.norm ();
      if (!(area > 0.0) || !std::isfinite (area))
        continue;
      const Vector3 centroid = (vertices[t[0]] + vertices[t[1]] + vertices[t[2]]) / 3.0;
      const Vector3 reference_normal =
          areaVector (reference_vertices,
                      reference_triangles[reference_index.closest (centroid).triangle]);
      const double length = reference_normal.norm ();
      if (!(length > 0.0))
        continue;
      const double cosine = std::min (1.0, std::abs (normal.dot (reference_normal)) /
                                               (2.0 * area * length));
      weighted_angle[i] = area * std::acos (cosine) * 180.0 / pi;
      weight[i] = area;
    }
    double angle_sum = 0.0, weight_sum = 0.0;
    for (std::size_t i = 0; i < triangles.size (); ++i) {
      angle_sum += weighted_angle[i];
      weight_sum += weight[i];
    }
    report.normal_deviation_deg = weight_sum > 0.0 ? angle_sum / weight_sum : 0.0;
    report.success = true;
  } catch (const std::exception& e) {
    report = MeshDistanceReport ();
    report.message = std::string ("mesh comparison failed: ") + e.what ();
  }
  return report;
}

std::vector<pcl::index_t>
matchVerticesByPosition (const Points3& vertices, const Points3& reference_vertices)
{
  // Reference indices sorted by coordinates, then by index, so that the first of
  // equal positions is the smallest index. Non-finite vertices are left out: a NaN
  // would break the ordering, and nothing can match it.
  const auto less = [&reference_vertices] (pcl::index_t i, pcl::index_t j) {
    const Vector3 &p = reference_vertices[i], &q = reference_vertices[j];
    return std::tie (p[0], p[1], p[2], i) < std::tie (q[0], q[1], q[2], j);
  };
  std::vector<pcl::index_t> order;
  order.reserve (reference_vertices.size ());
  for (std::size_t r = 0; r < reference_vertices.size (); ++r)
    if (reference_vertices[r].allFinite ())
      order.push_back (static_cast<pcl::index_t> (r));
  std::sort (order.begin (), order.end (), less);

  std::vector<pcl::index_t> match (vertices.size (), -1);
  for (std::size_t v = 0; v < vertices.size (); ++v) {
    const Vector3& p = vertices[v];
    if (!p.allFinite ())
      continue;
    const auto at = std::lower_bound (
        order.begin (), order.end (), p, [&reference_vertices] (pcl::index_t r, const Vector3& x) {
          const Vector3& q = reference_vertices[r];
          return std::tie (q[0], q[1], q[2]) < std::tie (x[0], x[1], x[2]);
        });
    if (at != order.end () && reference_vertices[*at] == p)
      match[v] = *at;
  }
  return match;
}

EdgeComparison
compareEdges (const Points3& vertices, const Triangles& triangles,
              const Points3& reference_vertices, const Triangles& reference_triangles,
              const EdgeComparisonOptions& options)
{
  EdgeComparison result;
  const auto key = [] (pcl::index_t u, pcl::index_t w) {
    const auto lo = static_cast<std::uint64_t> (std::min (u, w));
    const auto hi = static_cast<std::uint64_t> (std::max (u, w));
    return lo << 32 | hi;
  };
  const auto inRange = [] (const Triangle& t, std::size_t n) {
    for (const pcl::index_t v : t)
      if (v < 0 || static_cast<std::size_t> (v) >= n)
        return false;
    return true;
  };
  try {
    // Reference vertices at one position become one vertex (the smallest index), so
    // that a reference with split seams still has its edges across them.
    const std::vector<pcl::index_t> canonical =
        matchVerticesByPosition (reference_vertices, reference_vertices);

    // Reference half-edges in canonical indices, grouped by undirected edge; the
    // direction says how to orient the triangle's normal when the reference is not
    // consistently oriented.
    struct HalfEdge
    {
      std::uint64_t edge;
      bool forward;
      std::uint32_t triangle;
    };
    std::vector<HalfEdge> half_edges;
    half_edges.reserve (3 * reference_triangles.size ());
    for (std::size_t t = 0; t < reference_triangles.size (); ++t) {
      const Triangle& tri = reference_triangles[t];
      if (!inRange (tri, reference_vertices.size ()))
        continue;
      for (int i = 0; i < 3; ++i) {
        const pcl::index_t u = canonical[tri[i]], w = canonical[tri[(i + 1) % 3]];
        if (u >= 0 && w >= 0 && u != w)
          half_edges.push_back ({key (u, w), u < w, static_cast<std::uint32_t> (t)});
      }
    }
    std::sort (half_edges.begin (), half_edges.end (),
               [] (const HalfEdge& a, const HalfEdge& b) {
                 return std::tie (a.edge, a.triangle) < std::tie (b.edge, b.triangle);
               });
    std::vector<std::uint64_t> reference_edges, sharp_edges;
    const double cos_sharp = std::cos (options.sharp_angle_deg * pi / 180.0);
    for (std::size_t i = 0; i < half_edges.size ();) {
      std::size_t j = i + 1;
      while (j < half_edges.size () && half_edges[j].edge == half_edges[i].edge)
        ++j;
      reference_edges.push_back (half_edges[i].edge);
      if (j - i == 2) {
        // A consistently oriented pair uses the edge in opposite directions; if not,
        // one normal is turned so that the angle is the fold of the surface.
        Vector3 n0 = areaVector (reference_vertices, reference_triangles[half_edges[i].triangle]);
        Vector3 n1 = areaVector (reference_vertices, reference_triangles[half_edges[i + 1].triangle]);
        if (half_edges[i].forward == half_edges[i + 1].forward)
          n1 = -n1;
        const double l0 = n0.norm (), l1 = n1.norm ();
        if (l0 > 0.0 && l1 > 0.0 && n0.dot (n1) < cos_sharp * l0 * l1)
          sharp_edges.push_back (half_edges[i].edge);
      }
      i = j;
    }
    result.sharp_edges = sharp_edges.size ();

    // The mesh's edges, once each, in its own indices and in the reference's.
    const std::vector<pcl::index_t> match =
        matchVerticesByPosition (vertices, reference_vertices);
    std::vector<std::uint64_t> edges;
    edges.reserve (3 * triangles.size ());
    std::vector<bool> used (vertices.size (), false);
    for (const Triangle& t : triangles) {
      if (!inRange (t, vertices.size ()))
        continue;
      for (int i = 0; i < 3; ++i) {
        used[t[i]] = true;
        if (t[i] != t[(i + 1) % 3])
          edges.push_back (key (t[i], t[(i + 1) % 3]));
      }
    }
    std::sort (edges.begin (), edges.end ());
    edges.erase (std::unique (edges.begin (), edges.end ()), edges.end ());
    for (std::size_t v = 0; v < vertices.size (); ++v)
      if (used[v] && match[v] < 0)
        ++result.unmatched_vertices;
    result.edges = edges.size ();

    std::vector<std::uint64_t> mapped;
    mapped.reserve (edges.size ());
    for (const std::uint64_t e : edges) {
      const pcl::index_t u = match[e >> 32], w = match[e & 0xffffffffu];
      if (u >= 0 && w >= 0 && u != w)
        mapped.push_back (key (u, w));
    }
    std::sort (mapped.begin (), mapped.end ());
    for (const std::uint64_t e : mapped)
      if (std::binary_search (reference_edges.begin (), reference_edges.end (), e))
        ++result.reference_edges;
    for (const std::uint64_t e : sharp_edges) {
      if (std::binary_search (mapped.begin (), mapped.end (), e))
        ++result.sharp_edges_found;
      else
        result.missing_sharp_edges.push_back (
            {static_cast<pcl::index_t> (e >> 32), static_cast<pcl::index_t> (e & 0xffffffffu)});
    }
    if (result.edges > 0)
      result.reference_edge_fraction =
          static_cast<double> (result.reference_edges) / static_cast<double> (result.edges);
    if (result.sharp_edges > 0)
      result.sharp_edge_fraction = static_cast<double> (result.sharp_edges_found) /
                                   static_cast<double> (result.sharp_edges);
    result.success = true;
  } catch (const std::exception& e) {
    result = EdgeComparison ();
    result.message = std::string ("edge comparison failed: ") + e.what ();
  }
  return result;
}

} // namespace meshless
} // namespace pcl
