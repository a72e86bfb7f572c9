/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/edge_swap.h>
#include <pcl/surface/meshless/triangle_intersection.h>

#include <Eigen/Geometry>

#include "common/constants.h"
#include "common/half_edges.h"
#include "common/swap_predicates.h"
#include "common/threads.h"
#include "common/uniform_grid.h"

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

/** A box in single precision, rounded outward so that it contains the box it was
  * made from: half the memory of a Box per triangle slot (2 million slots on a
  * million points), and a query against it misses nothing the exact box would find. */
struct CompactBox
{
  Eigen::Vector3f lo, hi;

  CompactBox () = default;

  explicit CompactBox (const Box& box)
  {
    for (int k = 0; k < 3; ++k) {
      lo[k] = static_cast<float> (box.lo[k]);
      if (static_cast<double> (lo[k]) > box.lo[k])
        lo[k] = std::nextafter (lo[k], -std::numeric_limits<float>::infinity ());
      hi[k] = static_cast<float> (box.hi[k]);
      if (static_cast<double> (hi[k]) < box.hi[k])
        hi[k] = std::nextafter (hi[k], std::numeric_limits<float>::infinity ());
    }
  }

  Box
  widened () const
  {
    return {lo.cast<double> (), hi.cast<double> ()};
  }
};

bool
overlap (const Box& a, const CompactBox& b)
{
  return (a.lo.array () <= b.hi.cast<double> ().array ()).all () &&
         (b.lo.cast<double> ().array () <= a.hi.array ()).all ();
}

/** Triangle slots hashed by the cells of a uniform grid that their bounding boxes
  * cover; hash collisions only add candidates. Queries (forCandidates) only read it,
  * so they may run in parallel, each with its own VisitStamps. */
class TriangleGrid
{
public:
  TriangleGrid (std::size_t triangles, const Vec3& origin, double cell)
    : frame_ (origin, cell, -cell_limit, cell_limit)
  {
    // One bucket per 8 triangles: a triangle covers one to a few cells and a cell
    // holds a few dozen triangles, so buckets of a few cells each cost little (the
    // tags below tell the cells apart), while an empty bucket's 24 bytes add up to
    // the stage's peak; fewer buckets make the queries slower.
    std::size_t buckets = 1;
    while (buckets < triangles / 8)
      buckets *= 2;
    buckets_.resize (buckets);
    // The bits of an entry above the slot carry a tag of its cell, so that a query
    // passes over the other cells of its bucket without touching their triangles
    // (a quarter of the slots visited). Meshes of 2^31 triangles or more go without
    // tags.
    while (slot_bits_ < 32 && (std::uint64_t{1} << slot_bits_) < triangles)
      ++slot_bits_;
    tag_mask_ = slot_bits_ >= 32 ? 0 : ~std::uint32_t{0} << slot_bits_;
  }

  void
  insert (std::int32_t t, const Box& box)
  {
    const CellRange cells = cellsOf (box);
    if (cells.count () > max_cells)
      large_.push_back (t);
    else
      forCells (cells, [&] (const Key& key) { buckets_[key.bucket].push_back (entry (t, key)); });
  }

  void
  remove (std::int32_t t, const Box& box)
  {
    const CellRange cells = cellsOf (box);
    if (cells.count () > max_cells) {
      const auto it = std::find (large_.begin (), large_.end (), t);
      if (it != large_.end ())
        large_.erase (it);
    }
    else
      forCells (cells, [&] (const Key& key) {
        std::vector<std::uint32_t>& bucket = buckets_[key.bucket];
        const auto it = std::find (bucket.begin (), bucket.end (), entry (t, key));
        if (it != bucket.end ())
          bucket.erase (it);
      });
  }

  /** Re-registers slot t, whose box changed from `from` to `to`; nothing to do when
    * both cover the same cells (common: a swapped triangle keeps two corners). */
  void
  move (std::int32_t t, const Box& from, const Box& to)
  {
    if (cellsOf (from) == cellsOf (to))
      return;
    remove (t, from);
    insert (t, to);
  }

  /** Calls visit (t) once for every triangle that may overlap the box: those
    * registered in its cells and the large ones; only for slots t with wanted (t),
    * asked first (cheaper than the marks). */
  template <typename Wanted, typename Visit>
  void
  forCandidates (const Box& box, VisitStamps& marks, Wanted&& wanted, Visit&& visit) const
  {
    marks.startQuery ();
    const auto consider = [&] (std::int32_t t) {
      if (wanted (t) && marks.firstVisit (t))
        visit (t);
    };
    // A box over more cells than there are buckets is cheaper to answer with all.
    const CellRange cells = cellsOf (box);
    if (cells.count () > static_cast<double> (buckets_.size ()))
      for (const auto& bucket : buckets_)
        for (const std::uint32_t e : bucket)
          consider (slotOf (e));
    else
      forCells (cells, [&] (const Key& key) {
        const std::uint32_t tag = key.tag & tag_mask_;
        for (const std::uint32_t e : buckets_[key.bucket])
          if ((e & tag_mask_) == tag)
            consider (slotOf (e));
      });
    for (const std::int32_t t : large_)
      consider (t);
  }

  template <typename Visit>
  void
  forCandidates (const Box& box, VisitStamps& marks, Visit&& visit) const
  {
    forCandidates (box, marks, [] (std::int32_t) { return true; }, std::forward<Visit> (visit));
  }

private:
  /** Boxes over more cells than this go to a list every query scans (long slivers
    * across a fold would otherwise fill thousands of cells). */
  static constexpr double max_cells = 1024;
  /** Cell coordinates are clamped to [-cell_limit, cell_limit]. */
  static constexpr std::int64_t cell_limit = std::int64_t{1} << 19;

  /** A cell's bucket and its tag (in the bits above slot_bits_). */
  struct Key
  {
    std::size_t bucket;
    std::uint32_t tag;
  };

  CellRange
  cellsOf (const Box& box) const
  {
    return frame_.cellsOf (box.lo, box.hi);
  }

  Key
  keyOf (const GridCell& cell) const
  {
    const std::uint64_t h = static_cast<std::uint64_t> (cell[0]) * 73856093ull ^
                            static_cast<std::uint64_t> (cell[1]) * 19349663ull ^
                            static_cast<std::uint64_t> (cell[2]) * 83492791ull;
    const std::uint64_t mixed = h ^ (h >> 29);
    // The tag from bits the bucket index does not use, mixed once more.
    const std::uint64_t other = (mixed * 0x9e3779b97f4a7c15ull) >> 32;
    return {static_cast<std::size_t> (mixed & (buckets_.size () - 1)),
            static_cast<std::uint32_t> (other) << (slot_bits_ >= 32 ? 0 : slot_bits_)};
  }

  std::uint32_t
  entry (std::int32_t t, const Key& key) const
  {
    return static_cast<std::uint32_t> (t) | (key.tag & tag_mask_);
  }

  std::int32_t
  slotOf (std::uint32_t e) const
  {
    return static_cast<std::int32_t> (e & ~tag_mask_);
  }

  template <typename Apply>
  void
  forCells (const CellRange& cells, Apply&& apply) const
  {
    forEachCell (cells, [&] (const GridCell& cell) { apply (keyOf (cell)); });
  }

  GridFrame frame_;
  std::vector<std::vector<std::uint32_t>> buckets_;
  std::vector<std::int32_t> large_;
  int slot_bits_ = 0;
  std::uint32_t tag_mask_ = 0;
};

/** Loops over fewer items than this run on one thread: waking the other threads
  * costs milliseconds on a loaded machine, more than such loops take. */
constexpr std::ptrdiff_t parallel_from = 50000;

/** SwapRules::crease_look_ahead_depth's rounds start only from edges turning by
  * this much or more (radians): sharp creases, not the slight turns of curved parts. */
constexpr double crease_look_ahead_min_dihedral = pi / 4.0;

// ---------------------------------------------------------------------------
// The optimizer: a half-edge structure over the triangle array, the heap, the passes.

/** arctan (t) for t in [-1, 1] within 4e-8 (absolute; relative 7e-7 near 0): an odd
  * polynomial of degree 15 fitted to minimise the largest error on [0, 1]. */
double
arctanUnit (double t)
{
  const double z = t * t;
  return t * (0.99999933557952914 +
              z * (-0.33329860786772125 +
                   z * (0.19946565666955515 +
                        z * (-0.13908629593144803 +
                             z * (0.096421973807665373 +
                                  z * (-0.055912326950487867 +
                                       z * (0.021862957733893691 +
                                            z * -0.0040545671200883466)))))));
}

/** Angle between two (unnormalised) vectors, in [0, pi]; 0 if one vanishes. This is
  * atan2 (|u x v|, u . v) with the arctangent above instead of libm's, which took a
  * third of the optimizer's time (about 10 angles per priced swap). Symmetric in u
  * and v to the last bit (|u x v| and u . v are), so an edge's cost does not depend on
  * which side computes it. */
double
angleBetween (const Vec3& u, const Vec3& v)
{
  const double s = u.cross (v).norm (), c = u.dot (v);
  if (c >= s)
    return c > 0.0 ? arctanUnit (s / c) : 0.0; // c = 0 here means both vanish
  if (c > -s)
    return 0.5 * pi - arctanUnit (c / s);
  return pi - arctanUnit (s / -c);
}

/** The plane of a triangle prepared for many certified side tests: side (x) is +1 or
  * -1 when x is certainly on that side of the plane (the sign of orient3d of the
  * triangle and x), 0 when floating point cannot tell. It settles most pairs of a
  * local intersection query before the exact test: a triangle whose vertices, other
  * than those it shares with this one, all lie strictly on one side can meet it only
  * in what they share. */
class PlaneFilter
{
public:
  PlaneFilter () = default;

  PlaneFilter (const Vec3& a, const Vec3& b, const Vec3& c) : origin_ (a)
  {
    const Vec3 u = b - a, v = c - a;
    normal_ = u.cross (v);
    // Per normal component, the sum of the magnitudes of its two products.
    magnitude_ = Vec3 (std::abs (u.y () * v.z ()) + std::abs (u.z () * v.y ()),
                       std::abs (u.z () * v.x ()) + std::abs (u.x () * v.z ()),
                       std::abs (u.x () * v.y ()) + std::abs (u.y () * v.x ()));
  }

  int
  side (const Vec3& x) const
  {
    const Vec3 w = x - origin_;
    const Vec3 magnitude_w = w.cwiseAbs ();
    const double det = normal_.dot (w);
    const double permanent = magnitude_w.dot (magnitude_);
    // The triple product (u x v) . w with every input a rounded difference: each term
    // passes through at most 8 roundings, so the error is below 8 units of roundoff
    // times the permanent; twice that for margin, as orient3dIfCertain does, plus
    // room for products in u x v that underflowed, scaled by |w|. Huge permanents
    // are not certified.
    const double bound =
        16.0 * 0x1p-53 * permanent + (magnitude_w.sum () + 1.0) * 0x1p-1000;
    if (permanent < 1e300 && std::abs (det) > bound)
      return det > 0.0 ? 1 : -1;
    return 0;
  }

  /** Whether triangle t (vertex indices into p) certainly meets the plane's triangle
    * `own` at most in the vertices they share. */
  bool
  separates (const Points3& p, const Triangle& own, const Triangle& t) const
  {
    int first = 0;
    for (const pcl::index_t v : t) {
      if (v == own[0] || v == own[1] || v == own[2])
        continue;
      const int s = side (p[v]);
      if (s == 0 || (first != 0 && s != first))
        return false;
      first = s;
    }
    return first != 0;
  }

private:
  Vec3 origin_, normal_, magnitude_;
};

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
      cos_fold_ (std::cos (std::clamp (options.max_fold_angle_deg, 0.0, 180.0) * pi / 180.0)),
      min_dihedral_ (std::clamp (options.descent_min_dihedral_deg, 0.0, 180.0) * pi / 180.0),
      threads_ (threadCount (options.num_threads)),
      rewritten_ (options.rewritten && options.rewritten->size () == tri.size () ? options.rewritten
                                                                               : nullptr)
  {}

  /** Numbers the edge of the half-edges [first, last) and pairs them as twins;
    * false with message_ set if they are more than two or run the same way. */
  bool
  pairHalfEdges (const HalfEdgeGroups::Entry* first, const HalfEdgeGroups::Entry* last)
  {
    if (last - first > 2) {
      message_ = "the mesh has an edge shared by more than two triangles";
      return false;
    }
    const std::int32_t h = first->second;
    const auto e = static_cast<std::int32_t> (edge_he_.size ());
    edge_he_.push_back (h);
    edge_of_[h] = e;
    if (last - first == 2) {
      const std::int32_t g = first[1].second;
      if (from (h) == from (g)) {
        message_ = "the triangles are not consistently oriented";
        return false;
      }
      opp_[h] = g;
      opp_[g] = h;
      edge_of_[g] = e;
    }
    return true;
  }

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
    // Edges numbered in the order of (smaller, larger) vertex.
    const HalfEdgeGroups groups = groupHalfEdges (tri_, p_.size ());
    opp_.assign (nh, -1);
    edge_of_.assign (nh, -1);
    bool valid = true;
    forEachEdge (groups, [&] (std::size_t, const HalfEdgeGroups::Entry* first,
                              const HalfEdgeGroups::Entry* last) {
      if (valid)
        valid = pairHalfEdges (first, last);
    });
    if (!valid)
      return false;
    unit_normal_.resize (tri_.size ());
    for (std::size_t t = 0; t < tri_.size (); ++t)
      updateNormal (t);
    if (perEdge ()) {
      term_.resize (edge_he_.size ());
      const auto edges = static_cast<std::ptrdiff_t> (edge_he_.size ());
#pragma omp parallel for schedule(static, 4096) num_threads(threads_) if (edges >= parallel_from)
      for (std::ptrdiff_t e = 0; e < edges; ++e)
        term_[e] = edgeTerm (static_cast<std::int32_t> (e));
    }
    // A vertex is manifold when one walk around it meets all its outgoing half-edges.
    vert_he_.assign (p_.size (), -1);
    std::vector<std::int32_t> outgoing (p_.size (), 0);
    for (std::size_t h = 0; h < nh; ++h) {
      ++outgoing[from (h)];
      if (vert_he_[from (h)] < 0)
        vert_he_[from (h)] = static_cast<std::int32_t> (h);
    }
    // Each vertex on its own: read-only, so in parallel.
    const auto vertices = static_cast<std::ptrdiff_t> (p_.size ());
    bool manifold = true;
#pragma omp parallel num_threads(threads_) if (vertices >= parallel_from) reduction(&& : manifold)
    {
      Link link;
#pragma omp for schedule(static, 4096)
      for (std::ptrdiff_t v = 0; v < vertices; ++v)
        if (vert_he_[v] >= 0) {
          gatherLink (static_cast<std::int32_t> (v), link);
          const std::size_t fan = link.closed ? link.w.size () : link.w.size () - 1;
          manifold = manifold && fan == static_cast<std::size_t> (outgoing[v]);
        }
    }
    if (!manifold) {
      message_ = "the mesh has a non-manifold vertex";
      return false;
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
      if (terms_stale_)
        for (std::size_t e = 0; e < term_.size (); ++e)
          term_[e] = edgeTerm (static_cast<std::int32_t> (e));
      terms_stale_ = false;
      for (const double term : term_)
        sum += term;
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
    // Cells of three mean edge lengths: a swap's query box (its quad) then spans one
    // or two cells along each axis. Each cell a query visits is a cache miss in the
    // buckets; the cells' other triangles are passed over by their tags and boxes.
    // Smaller cells make the swaps slower, larger ones no faster.
    grid_ = std::make_unique<TriangleGrid> (tri_.size (), tri_.empty () ? Vec3::Zero () : p_[tri_[0][0]],
                                            3.0 * std::max (length, 1e-300));
    // The per-triangle data in parallel, the grid entries in order.
    const auto slots = static_cast<std::ptrdiff_t> (tri_.size ());
#pragma omp parallel for schedule(static, 4096) num_threads(threads_) if (slots >= parallel_from)
    for (std::ptrdiff_t t = 0; t < slots; ++t) {
      Slot slot;
      prepare (tri_[t], slot, true); // every axis now: the parallel queries only read
      axis_[t] = static_cast<std::int8_t> (slot.axis);
      box_[t] = CompactBox (slot.box);
    }
    for (std::size_t t = 0; t < tri_.size (); ++t)
      grid_->insert (static_cast<std::int32_t> (t), box_[t].widened ());
    marks_ = std::make_unique<VisitStamps> (tri_.size ());
    partners_.assign (tri_.size (), 0);
    intersections_ = 0;
    if (options_.input_free_of_intersections)
      return 0;

    // Every pair once (the partner with the larger slot is tested from the smaller),
    // the slots split among the threads; the pairs are few, so they are collected per
    // thread and counted afterwards, which keeps the counts independent of the threads.
    std::vector<std::pair<std::int32_t, std::int32_t>> found;
    const auto count = static_cast<std::ptrdiff_t> (tri_.size ());
#pragma omp parallel num_threads(threads_) if (count >= parallel_from)
    {
      VisitStamps marks (tri_.size ());
      std::vector<std::pair<std::int32_t, std::int32_t>> own;
#pragma omp for schedule(dynamic, 1024) nowait
      for (std::ptrdiff_t t = 0; t < count; ++t) {
        const auto s = static_cast<std::int32_t> (t);
        forEachIntersecting (
            tri_[s], axis_[s], marks, [&] (std::int32_t x) { return x > s; },
            [this] (std::int32_t x) { return static_cast<int> (axis_[x]); },
            [&] (std::int32_t x) { own.emplace_back (s, x); });
      }
#pragma omp critical(meshless_edge_swap_pairs)
      found.insert (found.end (), own.begin (), own.end ());
    }
    for (const auto& [s, x] : found) {
      ++partners_[s];
      ++partners_[x];
    }
    intersections_ = found.size ();
    return intersections_;
  }

  std::size_t
  intersections () const
  {
    return intersections_;
  }

  /** The median over the interior edges of the angle (radians) between the normals
    * of their two triangles; 0 without interior edges. */
  double
  medianDihedral () const
  {
    std::vector<double> angles;
    angles.reserve (edge_he_.size ());
    for (std::size_t e = 0; e < edge_he_.size (); ++e) {
      const std::int32_t h = edge_he_[e];
      if (opp_[h] < 0)
        continue;
      // The per-edge costs have it cached, times the edge's weight.
      const double weight = perEdge () ? weightOf (static_cast<std::int32_t> (e)) : 0.0;
      angles.push_back (weight > 0.0
                            ? term_[e] / weight
                            : angleBetween (normal (h / 3), normal (opp_[h] / 3)));
    }
    if (angles.empty ())
      return 0.0;
    const auto middle = angles.begin () + static_cast<std::ptrdiff_t> (angles.size () / 2);
    std::nth_element (angles.begin (), middle, angles.end ());
    return *middle;
  }

  /** Turns on the noisy-input rule of the descent (see
    * EdgeSwapOptions::noisy_median_dihedral_deg). */
  void
  keepCloseToPoints ()
  {
    offset_.assign (p_.size (), Vec3::Zero ());
    Link link;
    for (std::size_t v = 0; v < p_.size (); ++v)
      if (vert_he_[v] >= 0) {
        gatherLink (static_cast<std::int32_t> (v), link);
        Vec3 mean = p_[v];
        for (const std::int32_t w : link.w)
          mean += p_[w];
        offset_[v] = p_[v] - mean / static_cast<double> (link.w.size () + 1);
      }
  }

  std::size_t
  swaps () const
  {
    return swaps_;
  }

  bool
  swapLimitReached () const
  {
    return options_.max_swaps != 0 && swaps_ >= options_.max_swaps;
  }

  /** Greedy descent: pops the best swap until none lowers the cost. */
  void
  descend ()
  {
    heap_live_ = true;
    if (terms_stale_)
      totalCost (); // refreshes the terms
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
      if (perEdge ()) {
        // Every edge priced at once, in parallel; the heap is then built in linear
        // time. Its order (by change, then edge) does not depend on the threads.
        const auto count = static_cast<std::ptrdiff_t> (edge_he_.size ());
        std::vector<double> change (edge_he_.size ());
        std::vector<char> admissible (edge_he_.size ());
#pragma omp parallel for schedule(static, 4096) num_threads(threads_) if (count >= parallel_from)
        for (std::ptrdiff_t e = 0; e < count; ++e)
          admissible[e] = price (static_cast<std::int32_t> (e), change[e]);
        std::vector<Entry> entries;
        for (std::ptrdiff_t e = 0; e < count; ++e) {
          heap_stamp_[e] = 1;
          if (admissible[e])
            entries.push_back ({change[e], static_cast<std::int32_t> (e), 1});
        }
        heap_ = std::priority_queue<Entry> (std::less<Entry> (), std::move (entries));
      }
      else
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
    * locally Delaunay in quads turning less than the bound, under the same
    * admissibility rules and without adding intersecting pairs; with
    * `unfold_steep`, also in steeper quads where the swap makes them turn less.
    * Bounded by a number of swaps proportional to the mesh (on a plane it ends by
    * itself; curved quads could cycle). */
  void
  improveAngles (double max_dihedral_deg, bool unfold_steep)
  {
    const double cos_flat = std::cos (max_dihedral_deg * pi / 180.0);
    // The descent is over: keeping its heap up to date would cost more than the
    // swaps themselves (each swap re-prices about 13 edges).
    heap_live_ = false;
    heap_ = {};
    heap_stamp_.clear (); // a later descent prices everything afresh
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
      if (!oppositeAnglesExceedPi (a, b, c, d))
        continue;
      const Vec3 n0 = normal (a, d, c), n1 = normal (d, b, c);
      const double new_length = n0.norm () * n1.norm ();
      const double old_turn = normal (q.t0).dot (normal (q.t1)); // 0 if degenerate
      const double new_turn = new_length > 0.0 ? n0.dot (n1) / new_length : -1.0;
      const bool flat = old_turn >= cos_flat && new_turn >= cos_flat;
      if ((!flat && !(unfold_steep && new_turn > old_turn)) || !feasible (q))
        continue;
      if (!swapUnlessMoreIntersections (q))
        continue;
      --budget;
      for (const std::int32_t h : {3 * q.t0, 3 * q.t0 + 1, 3 * q.t1, 3 * q.t1 + 1})
        work.push_back (edge_of_[h]);
    }
  }

  /** One round of the look-ahead (SwapRules::look_ahead_depth and
    * crease_look_ahead_depth): sequences of up to `depth` swaps, each on an outer
    * edge of the two triangles the one before made, that lower the cost together
    * although their first swap alone does not (the greedy descent stops where a few
    * swaps must change together: a crease crossed by fans instead of followed),
    * starting from edges turning by `min_dihedral` or more. The first round starts
    * from all of them, later ones from those at the triangles the last round and the
    * descent rewrote. Each step must be admissible; a sequence found is made again
    * under the intersection bookkeeping and undone if it adds pairs. Per-edge costs
    * only. Returns whether a sequence was kept; the next descent prices every edge
    * afresh. */
  bool
  lookAhead (std::size_t depth, double min_dihedral)
  {
    if (!perEdge () || depth < 2)
      return false;
    heap_live_ = false;
    heap_ = {};
    heap_stamp_.clear ();
    if (terms_stale_)
      totalCost ();
    terms_live_ = true;
    const bool everywhere = changed_.empty ();
    std::vector<char> start;
    start.swap (changed_);
    changed_.assign (tri_.size (), 0);
    bool any = false;
    const auto edges = static_cast<std::int32_t> (edge_he_.size ());
    for (std::int32_t e = 0; e < edges; ++e) {
      // A sequence and its replay add at most 2 depth swaps before they settle.
      if (options_.max_swaps != 0 && swaps_ + 2 * depth > options_.max_swaps)
        break;
      if (term_[e] < min_dihedral * weightOf (e))
        continue;
      const std::int32_t h = edge_he_[e];
      if (!everywhere && !start[h / 3] && !(opp_[h] >= 0 && start[opp_[h] / 3]))
        continue;
      exploring_ = true;
      const bool found = explore (h, depth, 0.0, 0.0);
      exploring_ = false;
      if (found && keepPath ())
        any = true;
      path_.clear ();
      saved_.clear ();
    }
    terms_live_ = false;
    return any;
  }

  /** The next lookAhead starts from every edge again, not only where the last
    * round and the descent rewrote triangles. */
  void
  lookAheadEverywhere ()
  {
    changed_.clear ();
  }

  double
  minDihedral () const
  {
    return min_dihedral_;
  }

private:
  /** What a swap writes, put back exactly by restore (same triangle slots, which
    * the intersection grid is keyed by, same half-edges). */
  struct Saved
  {
    std::int32_t t0, t1;
    std::array<Triangle, 2> triangle;
    std::array<std::int32_t, 6> opp, edge_of;
    std::array<std::pair<std::int32_t, std::int32_t>, 4> twin_opp;
    std::array<std::pair<std::int32_t, std::int32_t>, 5> edge_he;
    std::array<std::pair<std::int32_t, std::int32_t>, 4> vert_he;
    std::array<Vec3, 2> normal;
    std::array<double, 5> term;
  };

  /** One step of lookAhead: swaps the edge of h (outside the intersection
    * bookkeeping) and stops if the sequence so far lowers the cost; else tries the
    * new triangles' outer edges; else puts the quad back. `scale` sums the costs
    * the steps acted on, the scale of the rounding tolerance. */
  bool
  explore (std::int32_t h, std::size_t remaining, double so_far, double scale)
  {
    Quad q;
    if (!quadOf (h, q) || q.c == q.d)
      return false;
    double local = 0.0;
    const double change = so_far + edgeCostChange (q, local);
    scale += local;
    const bool lower = change < -1e-9 * scale;
    // A first swap that lowers the cost alone is one the descent's rules refused.
    if ((path_.empty () && lower) || (remaining == 1 && !lower) || !feasible (q))
      return false;
    saved_.emplace_back ();
    save (q, saved_.back ());
    applySwap (q, 0);
    path_.push_back ({q.a, q.b, q.c, q.d});
    if (lower)
      return true;
    // The outer edges of the new triangles (c, a, d) and (d, b, c); a step tried
    // below and not kept is put back into the same slots.
    for (const std::int32_t side : {3 * q.t0, 3 * q.t0 + 1, 3 * q.t1, 3 * q.t1 + 1})
      if (explore (side, remaining - 1, change, scale))
        return true;
    path_.pop_back ();
    restore (saved_.back ());
    saved_.pop_back ();
    return false;
  }

  void
  save (const Quad& q, Saved& s) const
  {
    s.t0 = q.t0;
    s.t1 = q.t1;
    s.triangle = {tri_[q.t0], tri_[q.t1]};
    for (int i = 0; i < 3; ++i) {
      s.opp[i] = opp_[3 * q.t0 + i];
      s.opp[3 + i] = opp_[3 * q.t1 + i];
      s.edge_of[i] = edge_of_[3 * q.t0 + i];
      s.edge_of[3 + i] = edge_of_[3 * q.t1 + i];
    }
    const std::array<std::size_t, 4> outer{prev (q.h), next (q.h), prev (q.g), next (q.g)};
    for (int i = 0; i < 4; ++i) {
      const std::int32_t twin = opp_[outer[i]];
      s.twin_opp[i] = {twin, twin >= 0 ? opp_[twin] : -1};
      const std::int32_t e = edge_of_[outer[i]];
      s.edge_he[i] = {e, edge_he_[e]};
      s.term[i] = term_[e];
    }
    const std::int32_t inner = edge_of_[q.h];
    s.edge_he[4] = {inner, edge_he_[inner]};
    s.term[4] = term_[inner];
    int k = 0;
    for (const std::int32_t v : {q.a, q.b, q.c, q.d})
      s.vert_he[k++] = {v, vert_he_[v]};
    s.normal = {unit_normal_[q.t0], unit_normal_[q.t1]};
  }

  void
  restore (const Saved& s)
  {
    tri_[s.t0] = s.triangle[0];
    tri_[s.t1] = s.triangle[1];
    for (int i = 0; i < 3; ++i) {
      opp_[3 * s.t0 + i] = s.opp[i];
      opp_[3 * s.t1 + i] = s.opp[3 + i];
      edge_of_[3 * s.t0 + i] = s.edge_of[i];
      edge_of_[3 * s.t1 + i] = s.edge_of[3 + i];
    }
    for (const auto& [twin, value] : s.twin_opp)
      if (twin >= 0)
        opp_[twin] = value;
    for (int i = 0; i < 5; ++i) {
      edge_he_[s.edge_he[i].first] = s.edge_he[i].second;
      term_[s.edge_he[i].first] = s.term[i];
    }
    for (const auto& [v, h] : s.vert_he)
      vert_he_[v] = h;
    unit_normal_[s.t0] = s.normal[0];
    unit_normal_[s.t1] = s.normal[1];
    --swaps_;
  }

  /** The sequence explore found, put back and made again under the intersection
    * bookkeeping; undone if it adds intersecting pairs on balance. Returns whether
    * it was kept. */
  bool
  keepPath ()
  {
    for (auto saved = saved_.rbegin (); saved != saved_.rend (); ++saved)
      restore (*saved);
    std::ptrdiff_t added = 0;
    for (const auto& [a, b, c, d] : path_) {
      const Quad q = quadBetween (a, b);
      added += applyCounted (q);
      changed_[q.t0] = changed_[q.t1] = 1;
    }
    if (added <= 0)
      return true;
    for (auto step = path_.rbegin (); step != path_.rend (); ++step)
      applyCounted (quadBetween ((*step)[2], (*step)[3]));
    return false;
  }

  /** Makes the admissible swap q whatever it does to the intersecting pairs, and
    * returns the change in their number (0 without intersection bookkeeping). */
  std::ptrdiff_t
  applyCounted (const Quad& q)
  {
    std::size_t pairs = 0;
    std::ptrdiff_t change = 0;
    if (grid_) {
      const auto [before, after] = intersectionChange (q);
      change = static_cast<std::ptrdiff_t> (after) - static_cast<std::ptrdiff_t> (before);
      intersections_ = intersections_ + after - before;
      pairs = after;
    }
    applySwap (q, pairs);
    return change;
  }

  /** The quad whose diagonal is the edge u-w. keepPath replays swaps from the
    * states explore made them in, so the edge is there and interior. */
  Quad
  quadBetween (std::int32_t u, std::int32_t w) const
  {
    std::int32_t found = -1;
    forEachOutgoing (u, [&] (std::size_t h) {
      if (to (h) == w)
        found = static_cast<std::int32_t> (h);
    });
    Quad q;
    quadOf (found, q);
    return q;
  }

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

  /** The cost term of edge e for the per-edge costs: its weight times the angle
    * between the normals of its two triangles; 0 on the boundary. */
  double
  edgeTerm (std::int32_t e) const
  {
    const std::int32_t h = edge_he_[e];
    return opp_[h] < 0 ? 0.0 : weightOf (e) * angleBetween (normal (h / 3), normal (opp_[h] / 3));
  }

  double
  edgeWeight (std::int32_t u, std::int32_t w) const
  {
    return options_.cost == SwapCost::AngleBetweenNormals ? 1.0 : 1.5 * (p_[u] - p_[w]).norm ();
  }

  /** The weight of edge e. Computed when asked: a cache per edge could lift the
    * stage's peak above the patches'. */
  double
  weightOf (std::int32_t e) const
  {
    const std::int32_t h = edge_he_[e];
    return edgeWeight (from (h), to (h));
  }

  /** Whether u-w is an edge. */
  bool
  adjacent (std::int32_t u, std::int32_t w) const
  {
    // Each triangle (u, x, y) at u shows both its neighbours x and y: one walk around
    // the fan, counter-clockwise from any half-edge, then clockwise if it was open.
    const std::int32_t start = vert_he_[u];
    for (std::int32_t h = start;;) {
      if (to (h) == w || from (prev (h)) == w)
        return true;
      const std::int32_t back = opp_[prev (h)];
      if (back == start)
        return false;
      if (back < 0)
        break;
      h = back;
    }
    for (std::int32_t h = start;;) {
      const std::int32_t g = opp_[h];
      if (g < 0)
        return false;
      h = static_cast<std::int32_t> (next (g));
      if (to (h) == w || from (prev (h)) == w)
        return true;
    }
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
  feasible (const Quad& q) const
  {
    if (q.c == q.d)
      return false;
    if (adjacent (q.c, q.d))
      return false;
    const Vec3 &a = p_[q.a], &b = p_[q.b], &c = p_[q.c], &d = p_[q.d];
    const Vec3 n0 = normal (a, d, c), n1 = normal (d, b, c);
    if (nearlyDegenerateTriangle (n0, a, d, c) || nearlyDegenerateTriangle (n1, d, b, c))
      return false;
    // Turns are allowed up to the bound, or up to the old quad's turn if that is
    // larger: a swap may leave a fold it cannot open, never deepen it. (A degenerate
    // old triangle has a zero normal and constrains nothing.)
    const Vec3& o0 = normal (q.t0);
    const Vec3& o1 = normal (q.t1);
    const double old_cos = std::min (cos_fold_, o0.dot (o1));
    if (!normalsWithin (n0, n1, old_cos))
      return false;
    return (normalsWithin (n0, o0, old_cos) || normalsWithin (n0, o1, old_cos)) &&
           (normalsWithin (n1, o0, old_cos) || normalsWithin (n1, o1, old_cos));
  }

  /** Cost change of swapping q (negative is better) for the per-edge costs; `local`
    * receives the part of the cost the swap acts on, the scale for the rounding
    * tolerance. Only the five terms after the swap are computed: the ones before are
    * cached (term_). */
  double
  edgeCostChange (const Quad& q, double& local) const
  {
    // angleBetween needs no unit vectors.
    const Vec3 n0 = normal (p_[q.a], p_[q.d], p_[q.c]);
    const Vec3 n1 = normal (p_[q.d], p_[q.b], p_[q.c]);
    local = term_[edge_of_[q.h]];
    double after = edgeWeight (q.c, q.d) * angleBetween (n0, n1);
    // Outer edges: the new triangle at each, and the old half-edge.
    const std::array<std::pair<const Vec3*, std::size_t>, 4> outer{
        std::make_pair (&n1, next (q.h)),  // b->c
        std::make_pair (&n0, prev (q.h)),  // c->a
        std::make_pair (&n0, next (q.g)),  // a->d
        std::make_pair (&n1, prev (q.g))}; // d->b
    for (const auto& [new_n, he] : outer) {
      const std::int32_t across = opp_[he];
      if (across < 0)
        continue;
      const std::int32_t e = edge_of_[he];
      local += term_[e];
      after += weightOf (e) * angleBetween (*new_n, normal (across / 3));
    }
    return after - local;
  }

  /** The same for the per-vertex costs (not thread-safe: uses scratch_). */
  double
  costChange (const Quad& q, double& local)
  {
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

  /** Whether swapping edge e is admissible and lowers the cost by more than the
    * threshold; then `change` is the (negative) cost change. Read-only for the
    * per-edge costs, so edges can be priced in parallel. */
  bool
  price (std::int32_t e, double& change)
  {
    Quad q;
    if (!quadOf (edge_he_[e], q) || q.c == q.d)
      return false;
    // Edges across which the surface is nearly flat are the angle pass's: the
    // curvature cost there rewards slivers along the least curved direction, which
    // the angle pass would flip back (see EdgeSwapOptions::descent_min_dihedral_deg).
    if ((perEdge () ? term_[e] < min_dihedral_ * weightOf (e)
                    : angleBetween (normal (q.t0), normal (q.t1)) < min_dihedral_) &&
        !(grid_ && (partners_[q.t0] > 0 || partners_[q.t1] > 0)))
      return false;
    if (!offset_.empty ()) {
      // Noisy input: the new edge's midpoint must not lie farther from the local
      // average of the points than the old one's (EdgeSwapOptions::noisy_median_dihedral_deg).
      const Vec3 n = normal (q.t0) + normal (q.t1);
      if (std::abs ((offset_[q.c] + offset_[q.d]).dot (n)) > std::abs ((offset_[q.a] + offset_[q.b]).dot (n)))
        return false;
    }
    double local = 0.0;
    change = perEdge () ? edgeCostChange (q, local) : costChange (q, local);
    // Changes within rounding of the local cost do not count as decreases: this keeps
    // the descent finite. Most edges stop here, before the dearer feasibility test.
    return change < -1e-12 * local && feasible (q) && keepsLongestEdge (q);
  }

  /** Whether the new diagonal c-d is no longer than the longest of the quad's four
    * sides and its old diagonal (EdgeSwapOptions::descent_keeps_longest_edge). */
  bool
  keepsLongestEdge (const Quad& q) const
  {
    if (!options_.descent_keeps_longest_edge)
      return true;
    const Vec3 &a = p_[q.a], &b = p_[q.b], &c = p_[q.c], &d = p_[q.d];
    const double longest =
        std::max ({(a - b).squaredNorm (), (a - c).squaredNorm (), (b - c).squaredNorm (),
                   (a - d).squaredNorm (), (b - d).squaredNorm ()});
    return (c - d).squaredNorm () <= longest;
  }

  void
  push (std::int32_t e)
  {
    ++heap_stamp_[e];
    double change;
    if (price (e, change))
      heap_.push ({change, e, heap_stamp_[e]});
  }

  /** Intersecting pairs of the quad's triangles before and after the swap. */
  std::pair<std::size_t, std::size_t>
  intersectionChange (const Quad& q)
  {
    // The pair t0, t1 itself is counted in both partner counts.
    const std::size_t inner =
        partners_[q.t0] > 0 && partners_[q.t1] > 0 && slotsIntersect (q.t0, q.t1) ? 1 : 0;
    const std::size_t before = partners_[q.t0] + partners_[q.t1] - inner;
    // The new triangles as applySwap will store them, prepared once for the query
    // and kept for place ().
    pending_.quad = q;
    pending_.triangle = {Triangle{q.c, q.a, q.d}, Triangle{q.d, q.b, q.c}};
    for (int k = 0; k < 2; ++k)
      prepare (pending_.triangle[k], pending_.slot[k]);
    Slot& s0 = pending_.slot[0];
    Slot& s1 = pending_.slot[1];
    // The new pair shares edge c-d: certainly apart when b is off the first's plane.
    std::size_t after = 0;
    if (!s0.plane.separates (p_, pending_.triangle[0], pending_.triangle[1]) &&
        exactAxis (pending_.triangle[0], s0) >= 0 && exactAxis (pending_.triangle[1], s1) >= 0 &&
        trianglesIntersect (p_, pending_.triangle[0], s0.axis, pending_.triangle[1], s1.axis))
      after = 1;
    // One query for both: their boxes nearly coincide.
    const Box both{s0.box.lo.cwiseMin (s1.box.lo), s0.box.hi.cwiseMax (s1.box.hi)};
    grid_->forCandidates (both, *marks_, [&] (std::int32_t x) {
      if (x == q.t0 || x == q.t1 || axis_[x] == -1 || !overlap (both, box_[x]))
        return;
      for (int k = 0; k < 2; ++k) {
        Slot& s = pending_.slot[k];
        const Triangle& t = pending_.triangle[k];
        if (s.axis != -1 && overlap (s.box, box_[x]) && !s.plane.separates (p_, t, tri_[x]) &&
            !slotPlane (x).separates (p_, tri_[x], t) && exactAxis (t, s) >= 0 &&
            slotAxis (x) >= 0 && trianglesIntersect (p_, t, s.axis, tri_[x], axis_[x]))
          ++after;
      }
    });
    return {before, after};
  }

  /** What the intersection queries keep per triangle slot. */
  struct Slot
  {
    /** projectionAxis, -1 for an exactly degenerate triangle, -2 not computed yet:
      * only the rare pairs the plane filters cannot settle need it. */
    int axis = -2;
    Box box;
    PlaneFilter plane;
  };

  void
  prepare (const Triangle& t, Slot& slot, bool with_axis = false) const
  {
    slot.axis = with_axis ? projectionAxis (p_[t[0]], p_[t[1]], p_[t[2]]) : -2;
    slot.box = boxOf (p_, t);
    slot.plane = PlaneFilter (p_[t[0]], p_[t[1]], p_[t[2]]);
  }

  static int
  exactAxis (const Points3& p, const Triangle& t, int& axis)
  {
    if (axis == -2)
      axis = projectionAxis (p[t[0]], p[t[1]], p[t[2]]);
    return axis;
  }

  int
  exactAxis (const Triangle& t, Slot& slot) const
  {
    return exactAxis (p_, t, slot.axis);
  }

  /** The projection axis of slot t, computed on first use. */
  int
  slotAxis (std::int32_t t)
  {
    if (axis_[t] == -2)
      axis_[t] = static_cast<std::int8_t> (projectionAxis (p_[tri_[t][0]], p_[tri_[t][1]], p_[tri_[t][2]]));
    return axis_[t];
  }

  /** Whether the triangles in slots s and t intersect (as checkMesh counts). */
  bool
  slotsIntersect (std::int32_t s, std::int32_t t)
  {
    return slotAxis (s) >= 0 && slotAxis (t) >= 0 &&
           trianglesIntersect (p_, tri_[s], axis_[s], tri_[t], axis_[t]);
  }

  /** Records slot t's query data (prepared for its current triangle) and moves its
    * entry in the grid. */
  void
  place (std::int32_t t, const Slot& slot)
  {
    axis_[t] = static_cast<std::int8_t> (slot.axis);
    const CompactBox box (slot.box);
    grid_->move (t, box_[t].widened (), box.widened ());
    box_[t] = box;
  }

  /** The plane filter of slot t's triangle. Made when asked, not kept per slot (72
    * bytes each): only candidates whose box overlaps and which the other plane did
    * not settle need it. */
  PlaneFilter
  slotPlane (std::int32_t t) const
  {
    const Triangle& x = tri_[t];
    return PlaneFilter (p_[x[0]], p_[x[1]], p_[x[2]]);
  }

  /** Calls visit (x) for the triangles x of the mesh for which consider (x) holds
    * that intersect triangle t (projection axis `axis`). Read-only: may run in
    * parallel with separate marks. */
  template <typename Consider, typename AxisOf, typename Visit>
  void
  forEachIntersecting (const Triangle& t, int axis, VisitStamps& marks, Consider&& consider,
                       AxisOf&& axis_of, Visit&& visit) const
  {
    // Exactly degenerate faces (axis -1) are left out, as checkMesh does.
    if (axis < 0)
      return;
    const Box box = boxOf (p_, t);
    const PlaneFilter plane (p_[t[0]], p_[t[1]], p_[t[2]]);
    grid_->forCandidates (box, marks, consider, [&] (std::int32_t x) {
      if (axis_[x] != -1 && overlap (box, box_[x]) &&
          !plane.separates (p_, t, tri_[x]) && !slotPlane (x).separates (p_, tri_[x], t) &&
          axis_of (x) >= 0 && trianglesIntersect (p_, t, axis, tri_[x], axis_[x]))
        visit (x);
    });
  }

  /** The same for every triangle but slots skip0 and skip1 (single-threaded: fills
    * in projection axes on the way). */
  template <typename Visit>
  void
  forEachIntersecting (const Triangle& t, int axis, std::int32_t skip0, std::int32_t skip1, Visit&& visit)
  {
    forEachIntersecting (
        t, axis, *marks_, [&] (std::int32_t x) { return x != skip0 && x != skip1; },
        [this] (std::int32_t x) { return slotAxis (x); }, std::forward<Visit> (visit));
  }

  /** Takes the quad's triangles out of the grid and their pairs out of the partner
    * counts. */
  void
  leaveGrid (const Quad& q)
  {
    for (const std::int32_t t : {q.t0, q.t1})
      if (partners_[t] > 0)
        forEachIntersecting (tri_[t], slotAxis (t), q.t0, q.t1, [this] (std::int32_t x) { --partners_[x]; });
  }

  /** Enters the swapped triangles; `pairs` is the number of intersecting pairs they
    * take part in (from intersectionChange), so the usual 0 needs no search. */
  void
  enterGrid (const Quad& q, std::size_t pairs)
  {
    // intersectionChange prepared the new triangles unless the swap came without it.
    const bool prepared = pending_.quad.t0 == q.t0 && pending_.quad.t1 == q.t1 &&
                          pending_.triangle[0] == tri_[q.t0] && pending_.triangle[1] == tri_[q.t1];
    for (int k = 0; k < 2; ++k) {
      const std::int32_t t = k == 0 ? q.t0 : q.t1;
      if (!prepared)
        prepare (tri_[t], pending_.slot[k]);
      place (t, pending_.slot[k]);
    }
    pending_.quad.t0 = -1;
    partners_[q.t0] = partners_[q.t1] = 0;
    if (pairs == 0)
      return;
    if (slotsIntersect (q.t0, q.t1)) {
      ++partners_[q.t0];
      ++partners_[q.t1];
    }
    for (const std::int32_t t : {q.t0, q.t1})
      forEachIntersecting (tri_[t], slotAxis (t), q.t0, q.t1, [&] (std::int32_t x) {
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
    if (grid_ && !exploring_)
      leaveGrid (q);
    // New triangles (c, a, d) and (d, b, c): half-edges c->a, a->d, d->c and
    // d->b, b->c, c->d.
    tri_[q.t0] = {q.c, q.a, q.d};
    tri_[q.t1] = {q.d, q.b, q.c};
    if (rewritten_ && !exploring_)
      (*rewritten_)[q.t0] = (*rewritten_)[q.t1] = 1;
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
    if (grid_ && !exploring_)
      enterGrid (q, pairs);
    ++swaps_;
    if (perEdge () && (heap_live_ || terms_live_)) {
      term_[inner] = edgeTerm (inner);
      for (const std::int32_t e : edge)
        term_[e] = edgeTerm (e);
    }
    if (!heap_live_) {
      if (!terms_live_)
        terms_stale_ = true; // only totalCost reads them now: refreshed there, once
      return;
    }
    if (!changed_.empty ()) // the descent's swaps: the next look-ahead round starts there too
      changed_[q.t0] = changed_[q.t1] = 1;
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
  /** EdgeSwapOptions::descent_min_dihedral_deg in radians. */
  const double min_dihedral_;
  const int threads_;
  /** EdgeSwapOptions::rewritten, if it fits. */
  std::vector<char>* rewritten_ = nullptr;
  std::string message_;

  std::vector<std::int32_t> opp_, edge_of_, edge_he_, vert_he_;
  std::vector<Vec3> unit_normal_;
  std::vector<double> vertex_cost_;
  /** Per edge, for the per-edge costs: edgeWeight and edgeTerm, kept up to date by
    * applySwap (a swap's cost change then needs only the five terms after it). */
  std::vector<double> term_;
  /** Per vertex, on noisy input only: its offset from the mean of itself and its
    * neighbours in the input mesh, a local estimate of where the surface is. */
  std::vector<Vec3> offset_;
  /** Whether applySwap re-prices the edges around a swap (during the descent). */
  bool heap_live_ = false;
  /** Per triangle, after a look-ahead round: rewritten since (by a kept sequence or
    * the descent). Empty before the first round. */
  std::vector<char> changed_;
  /** Whether applySwap keeps term_ current without a heap (the look-ahead). */
  bool terms_live_ = false;
  /** Whether explore is trying swaps: applySwap leaves the grid and `rewritten`
    * alone, and restore puts the triangles back exactly. */
  bool exploring_ = false;
  /** The swaps explore has made, as (a, b, c, d) of their quads, and what each
    * overwrote. */
  std::vector<std::array<std::int32_t, 4>> path_;
  std::vector<Saved> saved_;
  /** Whether term_ lags behind swaps made outside the descent. */
  bool terms_stale_ = false;
  std::priority_queue<Entry> heap_;
  std::vector<std::uint32_t> heap_stamp_, seen_;
  std::uint32_t round_ = 0;
  Link scratch_;
  std::size_t swaps_ = 0;

  std::unique_ptr<TriangleGrid> grid_;
  std::unique_ptr<VisitStamps> marks_;
  /** The new triangles of the last swap intersectionChange looked at. */
  struct
  {
    Quad quad{-1, -1, -1, -1, -1, -1, -1, -1};
    std::array<Triangle, 2> triangle;
    std::array<Slot, 2> slot;
  } pending_;
  std::vector<std::int8_t> axis_;
  std::vector<CompactBox> box_;
  /** Per triangle slot: the number of triangles it intersects. */
  std::vector<std::int32_t> partners_;
  std::size_t intersections_ = 0;
};

/** Whether every one of n vertices is a corner of some triangle. */
bool
allVerticesUsed (std::size_t n, const Triangles& triangles)
{
  std::vector<char> used (n, 0);
  std::size_t count = 0;
  for (const Triangle& t : triangles)
    for (const pcl::index_t v : t)
      if (!used[v]) {
        used[v] = 1;
        ++count;
      }
  return count == n;
}

} // namespace

// Decided on the sine and cosine of the excess (from dot and cross products), which
// is more accurate than adding two angles and needs no arctangent.
bool
oppositeAnglesExceedPi (const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c,
                        const Eigen::Vector3d& d)
{
  const Eigen::Vector3d ca = a - c, cb = b - c, db = b - d, da = a - d;
  const double cos_c = ca.dot (cb), sin_c = ca.cross (cb).norm ();
  const double cos_d = db.dot (da), sin_d = db.cross (da).norm ();
  // Both scaled by the four edge lengths: sin and cos of (angle c + angle d - pi).
  const double sine = -(sin_c * cos_d + cos_c * sin_d);
  const double cosine = -(cos_c * cos_d - sin_c * sin_d);
  // atan2 (sine, cosine) > 1e-9, with tan (1e-9) = 1e-9 in double precision.
  if (sine > 0.0)
    return cosine <= 0.0 || sine > 1e-9 * cosine;
  return sine == 0.0 && cosine < 0.0;
}

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
    // The used vertices renumbered, on copies, in the order the triangles first use
    // them unless the caller's order is coherent already
    // (EdgeSwapOptions::renumber_vertices); without renumbering the swaps work on
    // the caller's triangles themselves (one copy of the mesh less), which
    // build () only reads: an invalid mesh fails untouched, and a swap writes both
    // of its triangles before anything that allocates, so running out of memory
    // leaves the valid triangulation of the swaps made so far.
    const bool renumber = options.renumber_vertices || !allVerticesUsed (points.size (), triangles);
    std::vector<pcl::index_t> original;
    Triangles copy;
    Points3 renumbered_points;
    if (renumber) {
      copy = triangles;
      std::vector<pcl::index_t> renumbered (points.size (), -1);
      for (Triangle& t : copy)
        for (pcl::index_t& v : t) {
          if (renumbered[v] < 0) {
            renumbered[v] = static_cast<pcl::index_t> (original.size ());
            original.push_back (v);
          }
          v = renumbered[v];
        }
      renumbered_points.resize (original.size ());
      for (std::size_t v = 0; v < original.size (); ++v)
        renumbered_points[v] = points[original[v]];
    }
    const Points3& local = renumber ? renumbered_points : points;
    Triangles& work = renumber ? copy : triangles;
    Optimizer optimizer (local, work, options);
    if (!optimizer.build ()) {
      result.message = optimizer.message ();
      return result;
    }
    result.cost_before = optimizer.totalCost ();
    result.median_dihedral_deg = optimizer.medianDihedral () * 180.0 / pi;
    result.noisy = result.median_dihedral_deg > options.noisy_median_dihedral_deg;
    if (result.noisy)
      optimizer.keepCloseToPoints ();
    if (options.remove_self_intersections)
      result.self_intersections_before = optimizer.initIntersections ();
    std::size_t mark = 0;
    const auto count = [&] (std::size_t& into) {
      into += optimizer.swaps () - mark;
      mark = optimizer.swaps ();
    };
    optimizer.descend ();
    count (result.descent_swaps);
    const std::array<std::pair<std::size_t, double>, 2> look_ahead_phases{
        std::make_pair (options.look_ahead_depth, optimizer.minDihedral ()),
        std::make_pair (options.crease_look_ahead_depth, crease_look_ahead_min_dihedral)};
    for (const auto& [depth, min_dihedral] : look_ahead_phases) {
      optimizer.lookAheadEverywhere ();
      // Each kept sequence strictly lowers the cost, so this ends.
      while (!result.noisy && !optimizer.swapLimitReached ()) {
        const bool kept = optimizer.lookAhead (depth, min_dihedral);
        count (result.look_ahead_swaps); // sequences undone count too
        if (!kept)
          break;
        optimizer.descend ();
        count (result.descent_swaps);
      }
    }
    // Each round of targeted swaps strictly lowers the number of intersecting pairs
    // and the descent never raises it, so this ends.
    while (options.remove_self_intersections && optimizer.removeIntersections ()) {
      count (result.intersection_swaps);
      optimizer.descend ();
      count (result.descent_swaps);
    }
    if (options.improve_angles) {
      optimizer.improveAngles (options.angle_pass_max_dihedral_deg,
                               options.angle_pass_unfolds_steep_quads && !result.noisy);
      count (result.angle_swaps);
    }
    result.cost_after = optimizer.totalCost ();
    result.self_intersections_after = optimizer.intersections ();
    result.swaps = optimizer.swaps ();
    if (renumber) {
      for (Triangle& t : copy)
        for (pcl::index_t& v : t)
          v = original[v];
      triangles.swap (copy);
    }
    result.success = true;
  }
  catch (const std::bad_alloc&) {
    result.message = "out of memory";
  }
  return result;
}

} // namespace meshless
} // namespace pcl
