/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/edge_swap.h>
#include <pcl/surface/meshless/triangle_intersection.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <queue>
#include <tuple>
#include <utility>

namespace pcl {
namespace meshless {

namespace {

using Vec3 = Eigen::Vector3d;

constexpr double pi = 3.14159265358979323846;

// ---------------------------------------------------------------------------
// Broad phase for local intersection queries: a hashed uniform grid of triangle
// bounding boxes that follows the swaps.

struct Box
{
  Vec3 lo, hi;
};

Box
boxOf (const Points3& p, const Triangle& t)
{
  Box b{p[t[0]], p[t[0]]};
  for (int i = 1; i < 3; ++i) {
    b.lo = b.lo.cwiseMin (p[t[i]]);
    b.hi = b.hi.cwiseMax (p[t[i]]);
  }
  return b;
}

bool
overlap (const Box& a, const Box& b)
{
  return (a.lo.array () <= b.hi.array ()).all () && (b.lo.array () <= a.hi.array ()).all ();
}

/** Triangle slots hashed by the cells of a uniform grid that their bounding boxes
  * cover; hash collisions only add candidates. */
class TriangleGrid
{
public:
  TriangleGrid (std::size_t triangles, const Vec3& origin, double cell)
    : inverse_cell_ (1.0 / cell), origin_ (origin), mark_ (triangles, 0)
  {
    std::size_t buckets = 1;
    while (buckets < triangles)
      buckets *= 2;
    buckets_.resize (buckets);
  }

  void
  insert (std::int32_t t, const Box& box)
  {
    if (cellCount (box) > max_cells)
      large_.push_back (t);
    else
      forCells (box, [&] (std::vector<std::int32_t>& bucket) { bucket.push_back (t); });
  }

  void
  remove (std::int32_t t, const Box& box)
  {
    const auto erase = [t] (std::vector<std::int32_t>& bucket) {
      const auto it = std::find (bucket.begin (), bucket.end (), t);
      if (it != bucket.end ())
        bucket.erase (it);
    };
    if (cellCount (box) > max_cells)
      erase (large_);
    else
      forCells (box, erase);
  }

  /** Calls visit (t) once for every triangle that may overlap the box: those
    * registered in its cells and the large ones. */
  template <typename Visit>
  void
  forCandidates (const Box& box, Visit&& visit)
  {
    if (++stamp_ == 0) {
      std::fill (mark_.begin (), mark_.end (), 0);
      stamp_ = 1;
    }
    const auto scan = [&] (const std::vector<std::int32_t>& bucket) {
      for (const std::int32_t t : bucket)
        if (mark_[t] != stamp_) {
          mark_[t] = stamp_;
          visit (t);
        }
    };
    // A box over more cells than there are buckets is cheaper to answer with all.
    if (cellCount (box) > static_cast<std::int64_t> (buckets_.size ()))
      for (const auto& bucket : buckets_)
        scan (bucket);
    else
      forCells (box, scan);
    scan (large_);
  }

private:
  /** Boxes over more cells than this go to a list every query scans (long slivers
    * across a fold would otherwise fill thousands of cells). */
  static constexpr std::int64_t max_cells = 1024;

  std::array<std::int64_t, 3>
  cellOf (const Vec3& x) const
  {
    // Clamped, so the conversion is defined and box cell counts fit; the mapping stays
    // monotone, so boxes that overlap still share a cell.
    constexpr double limit = 1 << 19;
    std::array<std::int64_t, 3> cell;
    for (int k = 0; k < 3; ++k)
      cell[k] = static_cast<std::int64_t> (std::clamp (std::floor ((x[k] - origin_[k]) * inverse_cell_), -limit, limit));
    return cell;
  }

  std::int64_t
  cellCount (const Box& box) const
  {
    const auto lo = cellOf (box.lo), hi = cellOf (box.hi);
    return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  }

  template <typename Apply>
  void
  forCells (const Box& box, Apply&& apply)
  {
    const auto lo = cellOf (box.lo), hi = cellOf (box.hi);
    const std::uint64_t mask = buckets_.size () - 1;
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
          const std::uint64_t h = static_cast<std::uint64_t> (x) * 73856093ull ^
                                  static_cast<std::uint64_t> (y) * 19349663ull ^
                                  static_cast<std::uint64_t> (z) * 83492791ull;
          apply (buckets_[(h ^ (h >> 29)) & mask]);
        }
  }

  double inverse_cell_;
  Vec3 origin_;
  std::vector<std::vector<std::int32_t>> buckets_;
  std::vector<std::int32_t> large_;
  std::vector<std::uint32_t> mark_;
  std::uint32_t stamp_ = 0;
};

// ---------------------------------------------------------------------------
// The optimizer: a half-edge structure over the triangle array, the heap, the passes.

/** Angle between two (unnormalised) vectors; 0 if one vanishes. */
double
angleBetween (const Vec3& u, const Vec3& v)
{
  return std::atan2 (u.cross (v).norm (), u.dot (v));
}

/** The link of a vertex v: its neighbours w_0, w_1, ... in counter-clockwise order,
  * its triangles being (v, w_j, w_j+1); `closed` when the last wraps to the first. */
struct Link
{
  std::vector<std::int32_t> w;
  bool closed = true;
};

/** The swap of edge a-b in triangles (a, b, c), (b, a, d) to (a, d, c), (d, b, c). */
struct Quad
{
  std::int32_t h, g;       // half-edges a->b and b->a
  std::int32_t a, b, c, d; // vertices
  std::int32_t t0, t1;     // triangles of h and g
};

class Optimizer
{
public:
  Optimizer (const Points3& points, Triangles& tri, const EdgeSwapOptions& options)
    : p_ (points), tri_ (tri), options_ (options),
      cos_fold_ (std::cos (std::clamp (options.max_fold_angle_deg, 0.0, 180.0) * pi / 180.0))
  {}

  /** Builds the half-edge structure; false with message_ set if the input is not a
    * manifold, consistently oriented mesh. */
  bool
  build ()
  {
    const std::size_t nh = 3 * tri_.size ();
    if (nh >= static_cast<std::size_t> (std::numeric_limits<std::int32_t>::max ())) {
      message_ = "too many triangles for 32-bit half-edge indices";
      return false;
    }
    std::vector<std::pair<std::uint64_t, std::int32_t>> keyed (nh);
    for (std::size_t h = 0; h < nh; ++h) {
      const auto u = static_cast<std::uint64_t> (from (h)), v = static_cast<std::uint64_t> (to (h));
      keyed[h] = {std::min (u, v) << 32 | std::max (u, v), static_cast<std::int32_t> (h)};
    }
    std::sort (keyed.begin (), keyed.end ());
    opp_.assign (nh, -1);
    edge_of_.assign (nh, -1);
    for (std::size_t i = 0; i < nh;) {
      std::size_t j = i + 1;
      while (j < nh && keyed[j].first == keyed[i].first)
        ++j;
      if (j - i > 2) {
        message_ = "the mesh has an edge shared by more than two triangles";
        return false;
      }
      const std::int32_t h = keyed[i].second;
      const auto e = static_cast<std::int32_t> (edge_he_.size ());
      edge_he_.push_back (h);
      edge_of_[h] = e;
      if (j - i == 2) {
        const std::int32_t g = keyed[i + 1].second;
        if (from (h) == from (g)) {
          message_ = "the triangles are not consistently oriented";
          return false;
        }
        opp_[h] = g;
        opp_[g] = h;
        edge_of_[g] = e;
      }
      i = j;
    }
    unit_normal_.resize (tri_.size ());
    for (std::size_t t = 0; t < tri_.size (); ++t)
      updateNormal (t);
    // A vertex is manifold when one walk around it meets all its outgoing half-edges.
    vert_he_.assign (p_.size (), -1);
    std::vector<std::int32_t> outgoing (p_.size (), 0);
    for (std::size_t h = 0; h < nh; ++h) {
      ++outgoing[from (h)];
      if (vert_he_[from (h)] < 0)
        vert_he_[from (h)] = static_cast<std::int32_t> (h);
    }
    Link link;
    for (std::size_t v = 0; v < p_.size (); ++v)
      if (vert_he_[v] >= 0) {
        gatherLink (static_cast<std::int32_t> (v), link);
        const std::size_t fan = link.closed ? link.w.size () : link.w.size () - 1;
        if (fan != static_cast<std::size_t> (outgoing[v])) {
          message_ = "the mesh has a non-manifold vertex";
          return false;
        }
      }
    return true;
  }

  const std::string&
  message () const
  {
    return message_;
  }

  double
  totalCost ()
  {
    double sum = 0.0;
    if (perEdge ()) {
      for (const std::int32_t h : edge_he_)
        if (opp_[h] >= 0)
          sum += edgeWeight (from (h), to (h)) * angleBetween (normal (h / 3), normal (opp_[h] / 3));
      return sum;
    }
    Link link;
    for (std::size_t v = 0; v < p_.size (); ++v)
      if (vert_he_[v] >= 0) {
        gatherLink (static_cast<std::int32_t> (v), link);
        sum += vertexCost (static_cast<std::int32_t> (v), link);
      }
    return sum;
  }

  /** Sets up the intersection bookkeeping and returns the number of intersecting
    * pairs. */
  std::size_t
  initIntersections ()
  {
    double length = 0.0;
    for (const std::int32_t h : edge_he_)
      length += (p_[to (h)] - p_[from (h)]).norm ();
    length = edge_he_.empty () ? 1.0 : length / static_cast<double> (edge_he_.size ());
    axis_.resize (tri_.size ());
    box_.resize (tri_.size ());
    grid_ = std::make_unique<TriangleGrid> (tri_.size (), tri_.empty () ? Vec3::Zero () : p_[tri_[0][0]],
                                            1.5 * std::max (length, 1e-300));
    for (std::size_t t = 0; t < tri_.size (); ++t)
      place (static_cast<std::int32_t> (t));
    partners_.assign (tri_.size (), 0);
    std::size_t pairs = 0;
    for (std::size_t t = 0; t < tri_.size (); ++t) {
      const auto s = static_cast<std::int32_t> (t);
      forEachIntersecting (tri_[t], axis_[t], s, -1, [&] (std::int32_t x) {
        if (x > s) {
          ++partners_[s];
          ++partners_[x];
          ++pairs;
        }
      });
    }
    intersections_ = pairs;
    return pairs;
  }

  std::size_t
  intersections () const
  {
    return intersections_;
  }

  std::size_t
  swaps () const
  {
    return swaps_;
  }

  /** Greedy descent: pops the best swap until none lowers the cost. */
  void
  descend ()
  {
    if (heap_stamp_.empty ()) {
      heap_stamp_.assign (edge_he_.size (), 0);
      seen_.assign (edge_he_.size (), 0);
      if (!perEdge ()) {
        vertex_cost_.assign (p_.size (), 0.0);
        Link link;
        for (std::size_t v = 0; v < p_.size (); ++v)
          if (vert_he_[v] >= 0) {
            gatherLink (static_cast<std::int32_t> (v), link);
            vertex_cost_[v] = vertexCost (static_cast<std::int32_t> (v), link);
          }
      }
      for (std::size_t e = 0; e < edge_he_.size (); ++e)
        push (static_cast<std::int32_t> (e));
    }
    while (!heap_.empty () && !swapLimitReached ()) {
      const Entry top = heap_.top ();
      heap_.pop ();
      if (top.stamp != heap_stamp_[top.edge])
        continue;
      Quad q;
      if (quadOf (edge_he_[top.edge], q) && feasible (q))
        swapUnlessMoreIntersections (q);
    }
  }

  /** Makes the admissible swap q unless its new triangles would take part in more
    * intersecting pairs than the old ones (without intersection bookkeeping it
    * always swaps); returns whether it swapped. */
  bool
  swapUnlessMoreIntersections (const Quad& q)
  {
    std::size_t pairs = 0;
    if (grid_) {
      const auto [before, after] = intersectionChange (q);
      if (after > before)
        return false;
      intersections_ -= before - after;
      pairs = after;
    }
    applySwap (q, pairs);
    return true;
  }

  /** Swaps edges of triangles in intersecting pairs while that strictly lowers the
    * number of pairs; returns whether any swap was made. */
  bool
  removeIntersections ()
  {
    bool any = false;
    std::vector<std::int32_t> work;
    // Popped from the back: in increasing order.
    for (auto t = static_cast<std::int32_t> (tri_.size ()) - 1; t >= 0; --t)
      if (partners_[t] > 0)
        work.push_back (t);
    while (!work.empty () && !swapLimitReached ()) {
      const std::int32_t t = work.back ();
      work.pop_back ();
      if (partners_[t] == 0)
        continue;
      Quad best;
      std::size_t best_before = 0, best_after = 0;
      bool found = false;
      for (int i = 0; i < 3; ++i) {
        Quad q;
        if (!quadOf (3 * t + i, q) || !feasible (q))
          continue;
        const auto [before, after] = intersectionChange (q);
        if (after < before && (!found || before - after > best_before - best_after)) {
          best = q;
          best_before = before;
          best_after = after;
          found = true;
        }
      }
      if (!found)
        continue;
      intersections_ -= best_before - best_after;
      applySwap (best, best_after);
      any = true;
      // Both new triangles may still take part in pairs: look at them again.
      if (best_after > 0) {
        work.push_back (best.t1);
        work.push_back (best.t0);
      }
    }
    return any;
  }

  /** The angle pass (EdgeSwapOptions::improve_angles): swaps edges that are not
    * locally Delaunay in nearly flat quads, under the same admissibility rules and
    * without adding intersecting pairs. Bounded by a number of swaps proportional
    * to the mesh (on a plane it ends by itself; curved quads could cycle). */
  void
  improveAngles (double max_dihedral_deg)
  {
    constexpr double pi = 3.14159265358979323846;
    const double cos_flat = std::cos (max_dihedral_deg * pi / 180.0);
    std::vector<std::int32_t> work;
    for (auto e = static_cast<std::int32_t> (edge_he_.size ()) - 1; e >= 0; --e)
      work.push_back (e);
    std::size_t budget = 10 * tri_.size ();
    while (!work.empty () && !swapLimitReached () && budget > 0) {
      const std::int32_t e = work.back ();
      work.pop_back ();
      Quad q;
      if (!quadOf (edge_he_[e], q))
        continue;
      const Vec3 &a = p_[q.a], &b = p_[q.b], &c = p_[q.c], &d = p_[q.d];
      if (angleBetween (a - c, b - c) + angleBetween (b - d, a - d) <= pi + 1e-9)
        continue;
      if (normal (q.t0).dot (normal (q.t1)) < cos_flat || !feasible (q))
        continue;
      const Vec3 n0 = normal (a, d, c), n1 = normal (d, b, c);
      if (n0.dot (n1) < cos_flat * n0.norm () * n1.norm ())
        continue;
      if (!swapUnlessMoreIntersections (q))
        continue;
      --budget;
      for (const std::int32_t h : {3 * q.t0, 3 * q.t0 + 1, 3 * q.t1, 3 * q.t1 + 1})
        work.push_back (edge_of_[h]);
    }
  }

private:
  struct Entry
  {
    double delta;
    std::int32_t edge;
    std::uint32_t stamp;
    bool
    operator< (const Entry& other) const
    {
      // std::priority_queue is a max-heap: the most negative change (then the lowest
      // edge id, for determinism) must compare greatest.
      return std::tie (other.delta, other.edge) < std::tie (delta, edge);
    }
  };

  static std::size_t
  next (std::size_t h)
  {
    return h % 3 == 2 ? h - 2 : h + 1;
  }

  static std::size_t
  prev (std::size_t h)
  {
    return h % 3 == 0 ? h + 2 : h - 1;
  }

  std::int32_t
  from (std::size_t h) const
  {
    return tri_[h / 3][h % 3];
  }

  std::int32_t
  to (std::size_t h) const
  {
    return tri_[h / 3][(h + 1) % 3];
  }

  Vec3
  normal (const Vec3& a, const Vec3& b, const Vec3& c) const
  {
    return (b - a).cross (c - a);
  }

  /** The unit normal of triangle t (zero if degenerate), cached. */
  const Vec3&
  normal (std::size_t t) const
  {
    return unit_normal_[t];
  }

  void
  updateNormal (std::size_t t)
  {
    const Vec3 n = normal (p_[tri_[t][0]], p_[tri_[t][1]], p_[tri_[t][2]]);
    const double length = n.norm ();
    unit_normal_[t] = length > 0.0 ? Vec3 (n / length) : Vec3::Zero ();
  }

  /** ABN and the integrated mean curvature are sums over edges: summed over the
    * vertices, (3/4) |e| beta_e counts each interior edge at both of its ends. */
  bool
  perEdge () const
  {
    return options_.cost == SwapCost::AngleBetweenNormals ||
           options_.cost == SwapCost::IntegratedMeanCurvature;
  }

  double
  edgeWeight (std::int32_t u, std::int32_t w) const
  {
    return options_.cost == SwapCost::AngleBetweenNormals ? 1.0 : 1.5 * (p_[u] - p_[w]).norm ();
  }

  /** Whether u-w is an edge. */
  bool
  adjacent (std::int32_t u, std::int32_t w) const
  {
    bool found = false;
    forEachOutgoing (u, [&] (std::size_t h) {
      found = found || to (h) == w || (opp_[prev (h)] < 0 && from (prev (h)) == w);
    });
    return found;
  }

  bool
  swapLimitReached () const
  {
    return options_.max_swaps != 0 && swaps_ >= options_.max_swaps;
  }

  /** Calls visit (h) for the outgoing half-edges h of v in counter-clockwise order,
    * starting at the boundary if v is on it; returns whether the fan is closed. */
  template <typename Visit>
  bool
  forEachOutgoing (std::int32_t v, Visit&& visit) const
  {
    std::int32_t start = vert_he_[v];
    // Walk clockwise to the boundary half-edge, if there is one.
    for (std::int32_t h = start;;) {
      const std::int32_t g = opp_[h];
      if (g < 0) {
        start = h;
        break;
      }
      h = static_cast<std::int32_t> (next (g));
      if (h == start)
        break;
    }
    for (std::int32_t h = start;;) {
      visit (static_cast<std::size_t> (h));
      const std::int32_t back = opp_[prev (h)]; // twin of w_j+1 -> v
      if (back < 0)
        return false;
      h = back;
      if (h == start)
        return true;
    }
  }

  /** Collects the link of v. */
  void
  gatherLink (std::int32_t v, Link& link) const
  {
    link.w.clear ();
    std::size_t last = 0;
    link.closed = forEachOutgoing (v, [&] (std::size_t h) {
      link.w.push_back (to (h));
      last = h;
    });
    if (!link.closed)
      link.w.push_back (from (prev (last)));
  }

  /** The cost of vertex v with the given link (squared mean and total absolute
    * curvature). */
  double
  vertexCost (std::int32_t v, const Link& link) const
  {
    const std::size_t k = link.w.size ();
    const std::size_t fans = link.closed ? k : k - 1;
    const Vec3& pv = p_[v];
    double area = 0.0, angles = 0.0, integrated_mean = 0.0;
    Vec3 first_normal, last_normal;
    for (std::size_t j = 0; j < fans; ++j) {
      const Vec3 e1 = p_[link.w[j]] - pv, e2 = p_[link.w[(j + 1) % k]] - pv;
      const Vec3 n = e1.cross (e2);
      area += 0.5 * n.norm ();
      angles += angleBetween (e1, e2);
      if (j == 0)
        first_normal = n;
      else
        integrated_mean += e1.norm () * angleBetween (last_normal, n);
      last_normal = n;
    }
    if (link.closed)
      integrated_mean += (p_[link.w[0]] - pv).norm () * angleBetween (last_normal, first_normal);
    integrated_mean *= 0.75;              // |H| A
    const double defect = 3.0 * ((link.closed ? 2.0 * pi : pi) - angles); // K A
    if (options_.cost == SwapCost::SquaredMeanCurvature)
      return area > 0.0 ? integrated_mean * integrated_mean / area : 0.0;
    // Total absolute curvature: (|k1| + |k2|) A with H A and K A.
    if (defect >= 0.0)
      return 2.0 * integrated_mean;
    return 2.0 * std::sqrt (integrated_mean * integrated_mean - defect * area);
  }

  /** The quad of an interior half-edge; false on the boundary. */
  bool
  quadOf (std::int32_t h, Quad& q) const
  {
    const std::int32_t g = opp_[h];
    if (g < 0)
      return false;
    q.h = h;
    q.g = g;
    q.a = from (h);
    q.b = to (h);
    q.c = from (prev (h));
    q.d = from (prev (g));
    q.t0 = h / 3;
    q.t1 = g / 3;
    return true;
  }

  /** Combinatorial and geometric admissibility of swapping q. */
  bool
  feasible (const Quad& q)
  {
    if (q.c == q.d)
      return false;
    if (adjacent (q.c, q.d))
      return false;
    const Vec3 &a = p_[q.a], &b = p_[q.b], &c = p_[q.c], &d = p_[q.d];
    const Vec3 n0 = normal (a, d, c), n1 = normal (d, b, c);
    // Degenerate: sine of the smallest angle below about 1e-8.
    const auto degenerate = [] (const Vec3& n, const Vec3& x, const Vec3& y, const Vec3& z) {
      const double longest = std::max ({(x - y).squaredNorm (), (y - z).squaredNorm (), (z - x).squaredNorm ()});
      return !(n.norm () > 1e-8 * longest);
    };
    if (degenerate (n0, a, d, c) || degenerate (n1, d, b, c))
      return false;
    // Turns are allowed up to the bound, or up to the old quad's turn if that is
    // larger: a swap may leave a fold it cannot open, never deepen it. (A degenerate
    // old triangle has a zero normal and constrains nothing.)
    const Vec3& o0 = normal (q.t0);
    const Vec3& o1 = normal (q.t1);
    const double old_cos = std::min (cos_fold_, o0.dot (o1));
    const auto within = [old_cos] (const Vec3& u, const Vec3& v) {
      return u.dot (v) >= old_cos * u.norm () * v.norm ();
    };
    if (!within (n0, n1))
      return false;
    return (within (n0, o0) || within (n0, o1)) && (within (n1, o0) || within (n1, o1));
  }

  /** Cost change of swapping q (negative is better); `local` receives the part of the
    * cost the swap acts on, the scale for the rounding tolerance. */
  double
  costChange (const Quad& q, double& local)
  {
    if (perEdge ()) {
      const Vec3& o0 = normal (q.t0);
      const Vec3& o1 = normal (q.t1);
      const Vec3 n0 = normal (p_[q.a], p_[q.d], p_[q.c]).normalized ();
      const Vec3 n1 = normal (p_[q.d], p_[q.b], p_[q.c]).normalized ();
      local = edgeWeight (q.a, q.b) * angleBetween (o0, o1);
      double after = edgeWeight (q.c, q.d) * angleBetween (n0, n1);
      // Outer edges: the old and the new triangle at them, the old half-edge.
      const std::array<std::tuple<const Vec3*, const Vec3*, std::size_t>, 4> outer{
          std::make_tuple (&o0, &n1, next (q.h)),  // b->c
          std::make_tuple (&o0, &n0, prev (q.h)),  // c->a
          std::make_tuple (&o1, &n0, next (q.g)),  // a->d
          std::make_tuple (&o1, &n1, prev (q.g))}; // d->b
      for (const auto& [old_n, new_n, he] : outer) {
        const std::int32_t across = opp_[he];
        if (across < 0)
          continue;
        const Vec3& m = normal (across / 3);
        const double weight = edgeWeight (from (he), to (he));
        local += weight * angleBetween (*old_n, m);
        after += weight * angleBetween (*new_n, m);
      }
      return after - local;
    }
    local = 0.0;
    double after = 0.0;
    const std::array<std::pair<std::int32_t, std::int32_t>, 4> edits{
        std::make_pair (q.a, -q.b - 1), std::make_pair (q.b, -q.a - 1),
        std::make_pair (q.c, q.d), std::make_pair (q.d, q.c)};
    for (const auto& [v, edit] : edits) {
      gatherLink (v, scratch_);
      auto& w = scratch_.w;
      if (edit < 0) // remove the swapped edge's other end from the link
        w.erase (std::find (w.begin (), w.end (), -edit - 1));
      else {
        // Insert the new neighbour between the two old ends: c's link has a, b and
        // d's has b, a consecutively (cyclically).
        const std::int32_t before = v == q.c ? q.a : q.b;
        const auto it = std::find (w.begin (), w.end (), before);
        w.insert (it + 1, edit);
      }
      local += vertex_cost_[v];
      after += vertexCost (v, scratch_);
    }
    return after - local;
  }

  void
  push (std::int32_t e)
  {
    ++heap_stamp_[e];
    Quad q;
    if (!quadOf (edge_he_[e], q) || q.c == q.d)
      return;
    double local = 0.0;
    const double change = costChange (q, local);
    // Changes within rounding of the local cost do not count as decreases: this keeps
    // the descent finite. Most edges stop here, before the dearer feasibility test.
    if (change < -1e-12 * local && feasible (q))
      heap_.push ({change, e, heap_stamp_[e]});
  }

  /** Intersecting pairs of the quad's triangles before and after the swap. */
  std::pair<std::size_t, std::size_t>
  intersectionChange (const Quad& q)
  {
    // The pair t0, t1 itself is counted in both partner counts.
    const std::size_t inner = pairIntersects (tri_[q.t0], axis_[q.t0], tri_[q.t1], axis_[q.t1]) ? 1 : 0;
    const std::size_t before = partners_[q.t0] + partners_[q.t1] - inner;
    const Triangle n0{q.a, q.d, q.c}, n1{q.d, q.b, q.c};
    const int x0 = projectionAxis (p_[q.a], p_[q.d], p_[q.c]);
    const int x1 = projectionAxis (p_[q.d], p_[q.b], p_[q.c]);
    std::size_t after = pairIntersects (n0, x0, n1, x1) ? 1 : 0;
    const auto count = [&after] (std::int32_t) { ++after; };
    forEachIntersecting (n0, x0, q.t0, q.t1, count);
    forEachIntersecting (n1, x1, q.t0, q.t1, count);
    return {before, after};
  }

  /** Records triangle t's projection axis and box and enters it in the grid. */
  void
  place (std::int32_t t)
  {
    const Triangle& v = tri_[t];
    axis_[t] = static_cast<std::int8_t> (projectionAxis (p_[v[0]], p_[v[1]], p_[v[2]]));
    box_[t] = boxOf (p_, v);
    grid_->insert (t, box_[t]);
  }

  /** Exactly degenerate faces (axis -1) are left out, as checkMesh does. */
  bool
  pairIntersects (const Triangle& s, int axis_s, const Triangle& t, int axis_t) const
  {
    return axis_s >= 0 && axis_t >= 0 && trianglesIntersect (p_, s, axis_s, t, axis_t);
  }

  /** Calls visit (x) for the triangles x of the mesh other than slots skip0 and skip1
    * that intersect triangle t (projection axis `axis`). */
  template <typename Visit>
  void
  forEachIntersecting (const Triangle& t, int axis, std::int32_t skip0, std::int32_t skip1, Visit&& visit)
  {
    if (axis < 0)
      return;
    const Box box = boxOf (p_, t);
    grid_->forCandidates (box, [&] (std::int32_t x) {
      if (x != skip0 && x != skip1 && axis_[x] >= 0 && overlap (box, box_[x]) &&
          trianglesIntersect (p_, t, axis, tri_[x], axis_[x]))
        visit (x);
    });
  }

  /** Takes the quad's triangles out of the grid and their pairs out of the partner
    * counts. */
  void
  leaveGrid (const Quad& q)
  {
    for (const std::int32_t t : {q.t0, q.t1}) {
      if (partners_[t] > 0)
        forEachIntersecting (tri_[t], axis_[t], q.t0, q.t1, [this] (std::int32_t x) { --partners_[x]; });
      grid_->remove (t, box_[t]);
    }
  }

  /** Enters the swapped triangles; `pairs` is the number of intersecting pairs they
    * take part in (from intersectionChange), so the usual 0 needs no search. */
  void
  enterGrid (const Quad& q, std::size_t pairs)
  {
    place (q.t0);
    place (q.t1);
    partners_[q.t0] = partners_[q.t1] = 0;
    if (pairs == 0)
      return;
    if (pairIntersects (tri_[q.t0], axis_[q.t0], tri_[q.t1], axis_[q.t1])) {
      ++partners_[q.t0];
      ++partners_[q.t1];
    }
    for (const std::int32_t t : {q.t0, q.t1})
      forEachIntersecting (tri_[t], axis_[t], q.t0, q.t1, [&] (std::int32_t x) {
        ++partners_[x];
        ++partners_[t];
      });
  }

  /** Writes the swap of q into the triangles and the half-edge structure and updates
    * everything that depends on them; `pairs` as for enterGrid (ignored without
    * intersection bookkeeping). */
  void
  applySwap (const Quad& q, std::size_t pairs)
  {
    // Old outer half-edges and their twins and edges, by their new place.
    const std::array<std::size_t, 4> outer{prev (q.h), next (q.g), prev (q.g), next (q.h)};
    std::array<std::int32_t, 4> twin, edge;
    for (int i = 0; i < 4; ++i) {
      twin[i] = opp_[outer[i]];
      edge[i] = edge_of_[outer[i]];
    }
    const std::int32_t inner = edge_of_[q.h];
    if (grid_)
      leaveGrid (q);
    // New triangles (c, a, d) and (d, b, c): half-edges c->a, a->d, d->c and
    // d->b, b->c, c->d.
    tri_[q.t0] = {q.c, q.a, q.d};
    tri_[q.t1] = {q.d, q.b, q.c};
    const std::array<std::int32_t, 4> slot{3 * q.t0, 3 * q.t0 + 1, 3 * q.t1, 3 * q.t1 + 1};
    for (int i = 0; i < 4; ++i) {
      opp_[slot[i]] = twin[i];
      if (twin[i] >= 0)
        opp_[twin[i]] = slot[i];
      edge_of_[slot[i]] = edge[i];
      edge_he_[edge[i]] = slot[i];
    }
    opp_[3 * q.t0 + 2] = 3 * q.t1 + 2;
    opp_[3 * q.t1 + 2] = 3 * q.t0 + 2;
    edge_of_[3 * q.t0 + 2] = edge_of_[3 * q.t1 + 2] = inner;
    edge_he_[inner] = 3 * q.t0 + 2;
    // Outgoing half-edges of the quad vertices that were rewritten.
    const auto keep = [&] (std::int32_t v, std::int32_t h) {
      if (vert_he_[v] / 3 == q.t0 || vert_he_[v] / 3 == q.t1)
        vert_he_[v] = h;
    };
    keep (q.c, 3 * q.t0);
    keep (q.a, 3 * q.t0 + 1);
    keep (q.d, 3 * q.t1);
    keep (q.b, 3 * q.t1 + 1);
    updateNormal (q.t0);
    updateNormal (q.t1);
    if (grid_)
      enterGrid (q, pairs);
    ++swaps_;
    if (heap_stamp_.empty ())
      return;
    ++round_;
    const auto update = [this] (std::size_t h) {
      const std::int32_t e = edge_of_[h];
      if (seen_[e] != round_) {
        seen_[e] = round_;
        push (e);
      }
    };
    if (perEdge ()) {
      // An edge's swap cost depends on its two triangles and their neighbours: update
      // the edges of the new triangles and of their neighbours.
      for (const std::int32_t t : {q.t0, q.t1})
        for (std::size_t h = 3 * static_cast<std::size_t> (t); h < 3 * static_cast<std::size_t> (t) + 3; ++h) {
          update (h);
          if (opp_[h] >= 0)
            for (const std::size_t x : {static_cast<std::size_t> (opp_[h]), next (opp_[h]), prev (opp_[h])})
              update (x);
        }
      // Removing a-b admits the swap of edges whose quad has a and b as apexes.
      forEachOutgoing (q.a, [&] (std::size_t h) {
        const std::int32_t g = opp_[next (h)];
        if (g >= 0 && from (prev (g)) == q.b)
          update (next (h));
      });
      return;
    }
    for (const std::int32_t v : {q.a, q.b, q.c, q.d}) {
      gatherLink (v, scratch_);
      vertex_cost_[v] = vertexCost (v, scratch_);
    }
    // A vertex cost depends on the vertex's fan: every edge of a triangle at a quad
    // vertex has the vertex in its own quad, so its swap cost may have changed.
    for (const std::int32_t v : {q.a, q.b, q.c, q.d})
      forEachOutgoing (v, [&] (std::size_t h) {
        update (h);
        update (next (h));
        update (prev (h));
      });
  }

  const Points3& p_;
  Triangles& tri_;
  const EdgeSwapOptions& options_;
  const double cos_fold_;
  std::string message_;

  std::vector<std::int32_t> opp_, edge_of_, edge_he_, vert_he_;
  std::vector<Vec3> unit_normal_;
  std::vector<double> vertex_cost_;
  std::priority_queue<Entry> heap_;
  std::vector<std::uint32_t> heap_stamp_, seen_;
  std::uint32_t round_ = 0;
  Link scratch_;
  std::size_t swaps_ = 0;

  std::unique_ptr<TriangleGrid> grid_;
  std::vector<std::int8_t> axis_;
  std::vector<Box> box_;
  /** Per triangle slot: the number of triangles it intersects. */
  std::vector<std::int32_t> partners_;
  std::size_t intersections_ = 0;
};

} // namespace

EdgeSwapResult
optimizeBySwaps (const Points3& points, Triangles& triangles, const EdgeSwapOptions& options)
{
  EdgeSwapResult result;
  for (const Triangle& t : triangles)
    for (int i = 0; i < 3; ++i) {
      if (t[i] < 0 || static_cast<std::size_t> (t[i]) >= points.size ()) {
        result.message = "a triangle index is out of range";
        return result;
      }
      if (t[i] == t[(i + 1) % 3]) {
        result.message = "a triangle repeats a vertex";
        return result;
      }
      if (!points[t[i]].allFinite ()) {
        result.message = "a vertex has a non-finite coordinate";
        return result;
      }
    }
  try {
    // Work on a copy so that no failure can leave a half-done mesh behind.
    Triangles work = triangles;
    Optimizer optimizer (points, work, options);
    if (!optimizer.build ()) {
      result.message = optimizer.message ();
      return result;
    }
    result.cost_before = optimizer.totalCost ();
    if (options.remove_self_intersections)
      result.self_intersections_before = optimizer.initIntersections ();
    optimizer.descend ();
    // Each round of targeted swaps strictly lowers the number of intersecting pairs
    // and the descent never raises it, so this ends.
    while (options.remove_self_intersections && optimizer.removeIntersections ())
      optimizer.descend ();
    if (options.improve_angles)
      optimizer.improveAngles (options.angle_pass_max_dihedral_deg);
    result.cost_after = optimizer.totalCost ();
    result.self_intersections_after = optimizer.intersections ();
    result.swaps = optimizer.swaps ();
    triangles.swap (work);
    result.success = true;
  }
  catch (const std::bad_alloc&) {
    result.message = "out of memory";
  }
  return result;
}

} // namespace meshless
} // namespace pcl
