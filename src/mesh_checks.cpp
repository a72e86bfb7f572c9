/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/mesh_checks.h>
#include "common/spatial_order.h"
#include <pcl/surface/meshless/triangle_intersection.h>

#include <Eigen/Geometry>

#include "common/constants.h"
#include "common/half_edges.h"
#include "common/threads.h"
#include "common/union_find.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <system_error>
#include <thread>

namespace pcl {
namespace meshless {

namespace {

using Vector3 = Eigen::Vector3d;

// ---------------------------------------------------------------------------
// Broad phase: a bounding-volume hierarchy over the faces in Morton order.

/** Closed axis-aligned box in single precision. */
struct Box
{
  std::array<float, 3> lo, hi;
};

/** Rounds to the nearest float, out-of-range values to infinity (a plain conversion
  * would be undefined there). The rounding is monotone, so the boxes of two faces with
  * a common point keep a common point: no candidate pair is lost. */
float
toFloat (double x)
{
  constexpr double largest = std::numeric_limits<float>::max ();
  if (x > largest)
    return std::numeric_limits<float>::infinity ();
  if (x < -largest)
    return -std::numeric_limits<float>::infinity ();
  return static_cast<float> (x);
}

bool
overlap (const Box& a, const Box& b)
{
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k])
      return false;
  return true;
}

Box
merge (const Box& a, const Box& b)
{
  Box m;
  for (int k = 0; k < 3; ++k) {
    m.lo[k] = std::min (a.lo[k], b.lo[k]);
    m.hi[k] = std::max (a.hi[k], b.hi[k]);
  }
  return m;
}

/** Binary tree over boxes; the boxes are stored in an order in which near boxes are
  * near each other (Morton order), and every node covers a contiguous range of that
  * order, the left child's before the right child's. Overlapping pairs are found by
  * walking pairs of nodes (a node with itself, then its children against each
  * other) rather than one query per box from the root: on a surface mesh nearly
  * all the nodes a box's own query visits are its ancestors and their siblings,
  * which each pair walk visits once. */
class BoxTree
{
public:
  /** \param[in] boxes in the order the tree splits them
    * \param[in] changed optional, per box: pairs of two boxes not marked are not
    *            visited (empty: every pair is) */
  explicit BoxTree (std::vector<Box> boxes, std::vector<char> changed = {})
      : boxes_ (std::move (boxes)), changed_ (std::move (changed))
  {
    if (boxes_.empty ())
      return;
    if (changed_.size () != boxes_.size ())
      changed_.assign (boxes_.size (), 1);
    // Median splits leave at least (leaf_size + 1) / 2 boxes per leaf, and a binary
    // tree has fewer than twice as many nodes as leaves.
    nodes_.reserve (2 * (boxes_.size () / ((leaf_size + 1) / 2)) + 1);
    node_changed_.reserve (nodes_.capacity ());
    build (0, static_cast<std::uint32_t> (boxes_.size ()));
  }

  /** Calls visit (p, q, thread) once for every pair p < q of overlapping boxes, the
    * work split among `threads` threads (run (tasks, body) runs body (i, thread)
    * for i in [0, tasks)). */
  template <typename Run, typename Visit>
  void
  forEachOverlappingPair (Run&& run, Visit&& visit) const
  {
    if (nodes_.empty ())
      return;
    // Independent tasks from the top of the walk: enough of them to balance the
    // threads, each a node with itself (a == b) or two nodes whose ranges are
    // apart, a's before b's.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> tasks{{0, 0}}, next;
    for (int level = 0; level < 12 && tasks.size () < 256; ++level) {
      next.clear ();
      for (const auto& [a, b] : tasks) {
        const Node& na = nodes_[a];
        const Node& nb = nodes_[b];
        if (!node_changed_[a] && !node_changed_[b])
          continue; // no pair there to visit
        if (a == b) {
          if (na.right == 0)
            next.emplace_back (a, a);
          else {
            next.emplace_back (a + 1, a + 1);
            next.emplace_back (na.right, na.right);
            next.emplace_back (a + 1, na.right);
          }
        }
        else if (!overlap (na.box, nb.box))
          continue;
        else if (na.right == 0 && nb.right == 0)
          next.emplace_back (a, b);
        else if (nb.right == 0 || (na.right != 0 && na.end - na.begin >= nb.end - nb.begin)) {
          next.emplace_back (a + 1, b);
          next.emplace_back (na.right, b);
        }
        else {
          next.emplace_back (a, b + 1);
          next.emplace_back (a, nb.right);
        }
      }
      tasks.swap (next);
    }
    run (tasks.size (), [&] (std::size_t i, int thread) {
      const auto [a, b] = tasks[i];
      const auto at = [&] (std::uint32_t p, std::uint32_t q) { visit (p, q, thread); };
      if (a == b)
        self (a, at);
      else
        cross (a, b, at);
    });
  }

private:
  static constexpr std::uint32_t leaf_size = 8;

  struct Node
  {
    Box box;
    std::uint32_t begin, end;
    /** Index of the right child (the left one follows its parent), 0 for a leaf. */
    std::uint32_t right;
  };

  /** The pairs within node a. */
  template <typename Visit>
  void
  self (std::uint32_t a, Visit& visit) const
  {
    const Node& node = nodes_[a];
    if (!node_changed_[a])
      return;
    if (node.right == 0) {
      for (std::uint32_t p = node.begin; p < node.end; ++p)
        for (std::uint32_t q = p + 1; q < node.end; ++q)
          if ((changed_[p] || changed_[q]) && overlap (boxes_[p], boxes_[q]))
            visit (p, q);
      return;
    }
    self (a + 1, visit);
    self (node.right, visit);
    cross (a + 1, node.right, visit);
  }

  /** The pairs between node a and node b, whose range follows a's; the larger
    * node is split first. */
  template <typename Visit>
  void
  cross (std::uint32_t a, std::uint32_t b, Visit& visit) const
  {
    const Node& na = nodes_[a];
    const Node& nb = nodes_[b];
    if ((!node_changed_[a] && !node_changed_[b]) || !overlap (na.box, nb.box))
      return;
    if (na.right == 0 && nb.right == 0) {
      for (std::uint32_t p = na.begin; p < na.end; ++p) {
        if ((!changed_[p] && !node_changed_[b]) || !overlap (boxes_[p], nb.box))
          continue;
        for (std::uint32_t q = nb.begin; q < nb.end; ++q)
          if ((changed_[p] || changed_[q]) && overlap (boxes_[p], boxes_[q]))
            visit (p, q);
      }
      return;
    }
    if (nb.right == 0 || (na.right != 0 && na.end - na.begin >= nb.end - nb.begin)) {
      cross (a + 1, b, visit);
      cross (na.right, b, visit);
    }
    else {
      cross (a, b + 1, visit);
      cross (a, nb.right, visit);
    }
  }

  std::uint32_t
  build (std::uint32_t begin, std::uint32_t end)
  {
    const auto index = static_cast<std::uint32_t> (nodes_.size ());
    nodes_.push_back ({boxes_[begin], begin, end, 0});
    node_changed_.push_back (changed_[begin]);
    if (end - begin <= leaf_size) {
      for (std::uint32_t i = begin + 1; i < end; ++i) {
        nodes_[index].box = merge (nodes_[index].box, boxes_[i]);
        node_changed_[index] = static_cast<char> (node_changed_[index] | changed_[i]);
      }
      return index;
    }
    const std::uint32_t middle = begin + (end - begin) / 2;
    build (begin, middle);
    const std::uint32_t right = build (middle, end);
    nodes_[index].right = right;
    nodes_[index].box = merge (nodes_[index + 1].box, nodes_[right].box);
    node_changed_[index] = static_cast<char> (node_changed_[index + 1] | node_changed_[right]);
    return index;
  }

  std::vector<Box> boxes_;
  /** Per box and per node: whether it (or a box below it) takes part in the pairs to
    * visit (all, unless the caller knows some pairs apart). */
  std::vector<char> changed_;
  std::vector<Node> nodes_;
  std::vector<char> node_changed_;
};

// ---------------------------------------------------------------------------
// Topology.

enum class TriangleKind {
  Invalid,       // an index out of range
  RepeatedIndex, // in range, but not three distinct vertices
  Face
};

TriangleKind
classify (const Triangle& t, std::size_t num_vertices)
{
  for (pcl::index_t i : t)
    if (i < 0 || static_cast<std::size_t> (i) >= num_vertices)
      return TriangleKind::Invalid;
  if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
    return TriangleKind::RepeatedIndex;
  return TriangleKind::Face;
}

class Topology
{
public:
  Topology (const Triangles& triangles, std::size_t num_vertices, MeshReport& report)
    : triangles_ (triangles), n_ (num_vertices), report_ (report)
  {
  }

  void
  run ()
  {
    std::vector<char> used (n_, 0);
    DisjointSets<std::uint32_t> components (n_);
    for (std::size_t t = 0; t < triangles_.size (); ++t) {
      const Triangle& tri = triangles_[t];
      switch (classify (tri, n_)) {
      case TriangleKind::Invalid:
        ++report_.invalid_triangles;
        break;
      case TriangleKind::RepeatedIndex:
        ++report_.degenerate_triangles;
        break;
      case TriangleKind::Face:
        ++report_.num_faces;
        for (pcl::index_t v : tri)
          used[v] = 1;
        components.join (tri[0], tri[1]);
        components.join (tri[1], tri[2]);
        break;
      }
    }
    for (std::size_t v = 0; v < n_; ++v)
      if (used[v]) {
        ++report_.used_vertices;
        if (components.isRoot (static_cast<std::uint32_t> (v)))
          ++report_.components;
      }
    report_.unused_vertices = n_ - report_.used_vertices;

    scanEdges ();

    report_.euler_characteristic = static_cast<long> (report_.used_vertices) -
                                   static_cast<long> (report_.num_edges) +
                                   static_cast<long> (report_.num_faces);
    if (report_.isManifold () && report_.isOriented ()) {
      const long twice_genus = 2 * static_cast<long> (report_.components) -
                               report_.euler_characteristic -
                               static_cast<long> (report_.boundary_loops);
      report_.genus = twice_genus >= 0 && twice_genus % 2 == 0 ? twice_genus / 2 : -1;
    }
  }

private:
  std::uint32_t
  from (std::uint32_t id) const
  {
    return static_cast<std::uint32_t> (triangles_[id / 3][id % 3]);
  }

  std::uint32_t
  opposite (std::uint32_t id) const
  {
    return static_cast<std::uint32_t> (triangles_[id / 3][(id % 3 + 2) % 3]);
  }

  /** Corner id (3 * t + j) of vertex x, an end of half-edge id, in id's triangle. */
  std::uint32_t
  corner (std::uint32_t id, std::uint32_t x) const
  {
    return from (id) == x ? id : id - id % 3 + (id % 3 + 1) % 3;
  }

  /** Groups the half-edges of the faces by undirected edge and derives every
    * edge-based count from the groups. */
  void
  scanEdges ()
  {
    const HalfEdgeGroups groups = groupHalfEdges (
        triangles_, n_, [this] (std::size_t t) { return classify (triangles_[t], n_) == TriangleKind::Face; });
    DisjointSets<std::uint32_t> corners (3 * triangles_.size ()); // joined across manifold edges
    DisjointSets<std::uint32_t> boundary (n_);                    // joined along boundary edges
    std::vector<char> on_boundary (n_, 0), on_non_manifold_edge (n_, 0);
    std::vector<std::uint32_t> apexes; // of a non-manifold edge's triangles
    forEachEdge (groups, [&] (std::size_t smaller, const HalfEdgeGroups::Entry* run,
                              const HalfEdgeGroups::Entry* run_end) {
      const auto low = static_cast<std::uint32_t> (smaller);
      const auto high = static_cast<std::uint32_t> (run->first);
      const auto id = [] (const HalfEdgeGroups::Entry* e) { return static_cast<std::uint32_t> (e->second); };
      ++report_.num_edges;
      const std::size_t uses = static_cast<std::size_t> (run_end - run);
      if (uses == 1) {
        ++report_.boundary_edges;
        boundary.join (low, high);
        on_boundary[low] = on_boundary[high] = 1;
      }
      else if (uses == 2) {
        if ((from (id (run)) == low) == (from (id (run + 1)) == low))
          ++report_.inconsistent_edges;
        corners.join (corner (id (run), low), corner (id (run + 1), low));
        corners.join (corner (id (run), high), corner (id (run + 1), high));
        // A face is counted as a duplicate once, in the group of its two smallest
        // vertices (there its opposite vertex is above `high`).
        const std::uint32_t apex = opposite (id (run));
        if (apex > high && apex == opposite (id (run + 1)))
          ++report_.duplicate_triangles;
      }
      else {
        ++report_.non_manifold_edges;
        on_non_manifold_edge[low] = on_non_manifold_edge[high] = 1;
        // The same count; the opposite vertices sorted put duplicates side by side.
        apexes.clear ();
        for (const HalfEdgeGroups::Entry* e = run; e != run_end; ++e)
          apexes.push_back (opposite (id (e)));
        std::sort (apexes.begin (), apexes.end ());
        for (std::size_t k = 0; k + 1 < apexes.size (); ++k)
          if (apexes[k] > high && apexes[k] == apexes[k + 1])
            ++report_.duplicate_triangles;
      }
    });

    for (std::uint32_t v = 0; v < n_; ++v)
      if (on_boundary[v] && boundary.isRoot (v))
        ++report_.boundary_loops;

    // Faces around a vertex joined through manifold edges form its fans; every fan
    // has exactly one root corner.
    std::vector<std::uint32_t> fans (n_, 0);
    for (std::size_t t = 0; t < triangles_.size (); ++t)
      if (classify (triangles_[t], n_) == TriangleKind::Face)
        for (int j = 0; j < 3; ++j)
          if (corners.isRoot (static_cast<std::uint32_t> (3 * t + j)))
            ++fans[triangles_[t][j]];
    for (std::size_t v = 0; v < n_; ++v)
      if (fans[v] > 1 && !on_non_manifold_edge[v])
        ++report_.non_manifold_vertices;
  }

  const Triangles& triangles_;
  const std::size_t n_;
  MeshReport& report_;
};

// ---------------------------------------------------------------------------
// Geometry.

/** Calls body (begin, end, thread) on the ranges [k * grain, (k + 1) * grain) covering
  * [0, n), in parallel if there is more than one (a team costs more than a small mesh,
  * all the more on busy cores). An exception leaving a parallel region would terminate
  * the program, so the first one is carried out of the region and rethrown. */
template <typename Body>
void
parallelRanges (std::size_t n, std::size_t grain, int threads, Body&& body)
{
  const auto ranges = static_cast<std::ptrdiff_t> ((n + grain - 1) / grain);
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic) num_threads(threads) if (ranges > 1)
  for (std::ptrdiff_t k = 0; k < ranges; ++k) {
    const std::size_t begin = static_cast<std::size_t> (k) * grain;
    try {
      body (begin, std::min (n, begin + grain), threadIndex ());
    } catch (...) {
#pragma omp critical(meshless_mesh_checks_failure)
      if (!failure)
        failure = std::current_exception ();
    }
  }
  if (failure)
    std::rethrow_exception (failure);
}

/** Smallest interior angle in radians: the one opposite the shortest edge. */
double
smallestAngle (const Vector3& a, const Vector3& b, const Vector3& c)
{
  const double la = (c - b).squaredNorm (), lb = (a - c).squaredNorm (),
               lc = (b - a).squaredNorm ();
  const Vector3* apex = &a;
  const Vector3 *p = &b, *q = &c;
  if (lb < la && lb <= lc) {
    apex = &b;
    p = &c;
    q = &a;
  }
  else if (lc < la && lc < lb) {
    apex = &c;
    p = &a;
    q = &b;
  }
  const Vector3 u = *p - *apex, v = *q - *apex;
  // atan2 stays accurate for tiny and for nearly straight angles, unlike acos.
  return std::atan2 (u.cross (v).norm (), u.dot (v));
}

/** Meshes of at least this many triangles are checked with the topology and the
  * geometry side by side (a thread costs more than a small mesh's check). */
constexpr std::size_t concurrent_from = 100000;

/** Cap on MeshCheckOptions::max_listed_intersections: the buffers are allocated up
  * front, outside the parallel region. */
constexpr std::size_t max_listed = std::size_t{1} << 16;

/** What one thread found; cache-line aligned so that threads do not share lines. */
struct alignas (64) ThreadFindings
{
  std::size_t count = 0;
  std::vector<std::pair<std::size_t, std::size_t>> listed;
};

/** Per-block sums, added in block order afterwards so that the totals do not depend
  * on the number of threads. */
struct BlockSums
{
  double volume = 0.0, min_angle = 0.0;
  std::size_t faces = 0, below_10 = 0, collinear = 0;
};

class Geometry
{
public:
  Geometry (const Points3& vertices,
            const Triangles& triangles,
            const MeshCheckOptions& options,
            MeshReport& report)
    : vertices_ (vertices), triangles_ (triangles), options_ (options),
      report_ (report), threads_ (threadCount (options.num_threads))
  {
  }

  void
  run ()
  {
    measureFaces ();
    if (options_.check_self_intersections)
      findSelfIntersections ();
  }

private:
  /** Per-face metrics and projection axes; faces touching a non-finite vertex keep
    * axis -1 and are left out of the geometry. */
  void
  measureFaces ()
  {
    const std::size_t n = vertices_.size ();
    std::vector<char> finite (n, 1);
    std::vector<char> used (n, 0);
    for (const Triangle& tri : triangles_)
      if (classify (tri, n) == TriangleKind::Face)
        for (pcl::index_t v : tri)
          used[v] = 1;
    Vector3 centroid = Vector3::Zero ();
    std::size_t finite_used = 0;
    for (std::size_t v = 0; v < n; ++v) {
      if (!used[v])
        continue;
      finite[v] = vertices_[v].allFinite ();
      if (finite[v]) {
        centroid += vertices_[v];
        ++finite_used;
      }
      else
        ++report_.non_finite_vertices;
    }
    if (finite_used > 0)
      centroid /= static_cast<double> (finite_used);

    axis_.assign (triangles_.size (), -1);
    constexpr std::size_t block_size = 4096;
    std::vector<BlockSums> blocks ((triangles_.size () + block_size - 1) / block_size);
    const double threshold = 10.0 * pi / 180.0;
    parallelRanges (triangles_.size (), block_size, threads_,
                    [&] (std::size_t begin, std::size_t end, int) {
                      BlockSums& sums = blocks[begin / block_size];
                      for (std::size_t t = begin; t < end; ++t) {
                        const Triangle& tri = triangles_[t];
                        if (classify (tri, n) != TriangleKind::Face ||
                            !finite[tri[0]] || !finite[tri[1]] || !finite[tri[2]])
                          continue;
                        const Vector3& p = vertices_[tri[0]];
                        const Vector3& q = vertices_[tri[1]];
                        const Vector3& r = vertices_[tri[2]];
                        axis_[t] = static_cast<std::int8_t> (projectionAxis (p, q, r));
                        if (axis_[t] < 0)
                          ++sums.collinear;
                        // Measured from the centroid the terms stay small, so a mesh
                        // far from the origin loses no precision to cancellation.
                        sums.volume +=
                            (p - centroid).dot ((q - centroid).cross (r - centroid)) /
                            6.0;
                        const double angle = smallestAngle (p, q, r);
                        sums.min_angle += angle;
                        sums.below_10 += angle < threshold ? 1 : 0;
                        ++sums.faces;
                      }
                    });
    BlockSums total;
    for (const BlockSums& sums : blocks) {
      total.volume += sums.volume;
      total.min_angle += sums.min_angle;
      total.faces += sums.faces;
      total.below_10 += sums.below_10;
      total.collinear += sums.collinear;
    }
    report_.degenerate_triangles += total.collinear;
    report_.signed_volume = total.volume;
    if (total.faces > 0) {
      report_.mean_min_angle_deg =
          total.min_angle / static_cast<double> (total.faces) * 180.0 / pi;
      report_.share_min_angle_below_10 =
          static_cast<double> (total.below_10) / static_cast<double> (total.faces);
    }
  }

  void
  findSelfIntersections ()
  {
    std::vector<std::uint32_t> order;
    for (std::size_t t = 0; t < triangles_.size (); ++t)
      if (axis_[t] >= 0)
        order.push_back (static_cast<std::uint32_t> (t));
    std::vector<Box> boxes = sortedBoxes (order);
    // Pairs of triangles the caller knows apart are not visited (see
    // MeshCheckOptions::known_apart).
    std::vector<char> changed;
    const std::vector<char>* known = options_.known_apart;
    if (known && known->size () == triangles_.size ()) {
      changed.resize (order.size ());
      for (std::size_t p = 0; p < order.size (); ++p)
        changed[p] = !(*known)[order[p]];
    }
    const BoxTree tree (std::move (boxes), std::move (changed));

    // Each thread counts on its own and keeps its smallest pairs, trimmed whenever the
    // buffer fills, so the union holds the overall smallest ones; the buffers never
    // reallocate.
    const std::size_t keep = std::min (options_.max_listed_intersections, max_listed);
    std::vector<ThreadFindings> findings (static_cast<std::size_t> (threads_));
    for (ThreadFindings& own : findings)
      own.listed.reserve (keep > 0 ? 4 * keep : 0);

    const auto run = [&] (std::size_t tasks, const auto& body) {
      parallelRanges (tasks, 1, threads_, [&] (std::size_t begin, std::size_t end, int thread) {
        for (std::size_t i = begin; i < end; ++i)
          body (i, thread);
      });
    };
    tree.forEachOverlappingPair (run, [&] (std::uint32_t p, std::uint32_t q, int thread) {
      ThreadFindings& own = findings[static_cast<std::size_t> (thread)];
      const std::size_t f = order[p], g = order[q];
      if (!trianglesIntersect (vertices_, triangles_[f], axis_[f], triangles_[g], axis_[g]))
        return;
      ++own.count;
      if (keep == 0)
        return;
      own.listed.emplace_back (std::min (f, g), std::max (f, g));
      if (own.listed.size () == own.listed.capacity ()) {
        std::nth_element (own.listed.begin (), own.listed.begin () + keep, own.listed.end ());
        own.listed.resize (keep);
      }
    });

    report_.self_intersections_checked = true;
    for (const ThreadFindings& own : findings) {
      report_.self_intersecting_pairs += own.count;
      report_.intersecting_pairs.insert (report_.intersecting_pairs.end (),
                                         own.listed.begin (), own.listed.end ());
    }
    std::sort (report_.intersecting_pairs.begin (), report_.intersecting_pairs.end ());
    if (report_.intersecting_pairs.size () > keep)
      report_.intersecting_pairs.resize (keep);
  }

  /** Sorts the faces in `order` along a Morton curve through their box centres and
    * returns their boxes in that order. */
  std::vector<Box>
  sortedBoxes (std::vector<std::uint32_t>& order) const
  {
    std::vector<Box> boxes (order.size ());
    Box bounds{{{std::numeric_limits<float>::infinity (),
                 std::numeric_limits<float>::infinity (),
                 std::numeric_limits<float>::infinity ()}},
               {{-std::numeric_limits<float>::infinity (),
                 -std::numeric_limits<float>::infinity (),
                 -std::numeric_limits<float>::infinity ()}}};
    for (std::size_t i = 0; i < order.size (); ++i) {
      const Triangle& tri = triangles_[order[i]];
      for (int k = 0; k < 3; ++k) {
        const double lo = std::min (
            {vertices_[tri[0]][k], vertices_[tri[1]][k], vertices_[tri[2]][k]});
        const double hi = std::max (
            {vertices_[tri[0]][k], vertices_[tri[1]][k], vertices_[tri[2]][k]});
        boxes[i].lo[k] = toFloat (lo);
        boxes[i].hi[k] = toFloat (hi);
      }
      bounds = merge (bounds, boxes[i]);
    }
    // Codes only steer the grouping; a poor code (say for infinite bounds) costs time,
    // never correctness.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed (order.size ());
    constexpr double cells = (1u << 21) - 1;
    for (std::size_t i = 0; i < order.size (); ++i) {
      std::uint64_t cell_of[3];
      for (int k = 0; k < 3; ++k) {
        const double extent = static_cast<double> (bounds.hi[k]) - bounds.lo[k];
        const double centre =
            0.5 * (static_cast<double> (boxes[i].lo[k]) + boxes[i].hi[k]);
        double cell = extent > 0.0 ? (centre - bounds.lo[k]) / extent * cells : 0.0;
        cell = cell >= 0.0 ? std::min (cell, cells) : 0.0; // also maps NaN to 0
        cell_of[k] = static_cast<std::uint64_t> (cell);
      }
      keyed[i] = {mortonKey (cell_of[0], cell_of[1], cell_of[2]), static_cast<std::uint32_t> (i)};
    }
    std::sort (keyed.begin (), keyed.end ());
    std::vector<std::uint32_t> sorted_order (order.size ());
    std::vector<Box> sorted_boxes (order.size ());
    for (std::size_t i = 0; i < keyed.size (); ++i) {
      sorted_order[i] = order[keyed[i].second];
      sorted_boxes[i] = boxes[keyed[i].second];
    }
    order.swap (sorted_order);
    return sorted_boxes;
  }

  const Points3& vertices_;
  const Triangles& triangles_;
  const MeshCheckOptions& options_;
  MeshReport& report_;
  const int threads_;
  std::vector<std::int8_t> axis_;
};

// ---------------------------------------------------------------------------
// Summary text.

std::string
counted (std::size_t n, const char* singular, const char* plural)
{
  return std::to_string (n) + " " + (n == 1 ? singular : plural);
}

/** Whether every corner of t indexes one of num_vertices vertices. */
bool
validTriangle (const Triangle& t, std::size_t num_vertices)
{
  for (const pcl::index_t v : t)
    if (v < 0 || static_cast<std::size_t> (v) >= num_vertices)
      return false;
  return true;
}

/** Vertex adjacency of the valid triangles as compressed rows; an edge shared by
  * two triangles is listed twice, which a search does not mind. */
void
vertexAdjacency (std::size_t num_vertices,
                 const Triangles& triangles,
                 std::vector<std::size_t>& offsets,
                 std::vector<pcl::index_t>& adjacent)
{
  offsets.assign (num_vertices + 1, 0);
  for (const Triangle& t : triangles)
    if (validTriangle (t, num_vertices))
      for (const pcl::index_t v : t)
        offsets[v + 1] += 2;
  std::partial_sum (offsets.begin (), offsets.end (), offsets.begin ());
  adjacent.resize (offsets.back ());
  std::vector<std::size_t> fill (offsets.begin (), offsets.end () - 1);
  for (const Triangle& t : triangles)
    if (validTriangle (t, num_vertices))
      for (int k = 0; k < 3; ++k) {
        adjacent[fill[t[k]]++] = t[(k + 1) % 3];
        adjacent[fill[t[k]]++] = t[(k + 2) % 3];
      }
}

} // namespace

bool
MeshReport::isManifold () const
{
  return num_triangles > 0 && num_faces == num_triangles && duplicate_triangles == 0 &&
         non_manifold_edges == 0 && non_manifold_vertices == 0;
}

bool
MeshReport::isOriented () const
{
  return inconsistent_edges == 0;
}

bool
MeshReport::isClosedManifold () const
{
  return isManifold () && isOriented () && boundary_edges == 0;
}

bool
MeshReport::isSphereLike () const
{
  return isClosedManifold () && components == 1 && euler_characteristic == 2;
}

bool
MeshReport::isDiscLike () const
{
  return isDiscWithHoles (0);
}

bool
MeshReport::isDiscWithHoles (std::size_t holes) const
{
  return isManifold () && isOriented () && components == 1 && boundary_loops == 1 + holes &&
         euler_characteristic == 1 - static_cast<long> (holes);
}

MeshReport
checkMesh (const Points3& vertices,
           const Triangles& triangles,
           const MeshCheckOptions& options)
{
  MeshReport report;
  report.num_vertices = vertices.size ();
  report.num_triangles = triangles.size ();
  // Vertex, half-edge and corner ids are 32-bit to halve the memory traffic (the
  // half-edge groups number half-edges with signed 32-bit ids).
  constexpr std::size_t id_limit = std::numeric_limits<std::int32_t>::max ();
  if (vertices.size () >= id_limit || triangles.size () >= id_limit / 3) {
    report.message = "mesh too large for 32-bit half-edge ids";
    return report;
  }
  try {
    // The topology is one serial pass, and the geometry builds its box tree
    // serially before its parallel search: on large meshes the two run side by
    // side, each into its own report.
    MeshReport geometry = report;
    std::thread topology;
    std::exception_ptr topology_failure;
    if (threadCount (options.num_threads) > 1 && triangles.size () >= concurrent_from) {
      try {
        topology = std::thread ([&] {
          try {
            Topology (triangles, vertices.size (), report).run ();
          } catch (...) {
            topology_failure = std::current_exception ();
          }
        });
      } catch (const std::system_error&) {
        // No thread to be had (a process at its limit): one after the other.
      }
    }
    if (topology.joinable ()) {
      try {
        Geometry (vertices, triangles, options, geometry).run ();
      } catch (...) {
        topology.join ();
        throw;
      }
      topology.join ();
      if (topology_failure)
        std::rethrow_exception (topology_failure);
    }
    else {
      Topology (triangles, vertices.size (), report).run ();
      Geometry (vertices, triangles, options, geometry).run ();
    }
    report.non_finite_vertices = geometry.non_finite_vertices;
    report.degenerate_triangles += geometry.degenerate_triangles;
    report.signed_volume = geometry.signed_volume;
    report.mean_min_angle_deg = geometry.mean_min_angle_deg;
    report.share_min_angle_below_10 = geometry.share_min_angle_below_10;
    report.self_intersections_checked = geometry.self_intersections_checked;
    report.self_intersecting_pairs = geometry.self_intersecting_pairs;
    report.intersecting_pairs = std::move (geometry.intersecting_pairs);
    report.success = true;
  } catch (const std::exception& e) {
    MeshReport failed;
    failed.num_vertices = vertices.size ();
    failed.num_triangles = triangles.size ();
    failed.message = std::string ("mesh check failed: ") + e.what ();
    return failed;
  }
  return report;
}

std::string
describe (const MeshReport& r)
{
  std::ostringstream out;
  if (!r.success) {
    out << "Mesh of " << counted (r.num_vertices, "vertex", "vertices") << " and "
        << counted (r.num_triangles, "triangle", "triangles")
        << " not checked: " << r.message << ".";
    return out.str ();
  }
  if (r.num_triangles == 0)
    out << "Empty mesh";
  else if (r.isSphereLike ())
    out << "Sphere-like mesh";
  else if (r.isDiscLike ())
    out << "Disc-like mesh";
  else if (r.isClosedManifold ())
    out << "Closed manifold mesh";
  else if (r.isManifold ())
    out << (r.isOriented () ? "Manifold mesh with boundary"
                            : "Inconsistently oriented manifold mesh");
  else
    out << "Non-manifold mesh";
  out << ": " << counted (r.num_vertices, "vertex", "vertices") << " ("
      << r.unused_vertices << " unused), "
      << counted (r.num_triangles, "triangle", "triangles") << ", "
      << counted (r.num_edges, "edge", "edges") << ", "
      << counted (r.components, "component", "components") << ", Euler characteristic "
      << r.euler_characteristic;
  if (r.genus >= 0)
    out << ", genus " << r.genus;
  out << ".";

  std::vector<std::string> defects;
  const auto note = [&defects] (std::size_t n, const char* singular,
                                const char* plural) {
    if (n > 0)
      defects.push_back (counted (n, singular, plural));
  };
  note (r.invalid_triangles, "triangle with an index out of range",
        "triangles with an index out of range");
  note (r.non_finite_vertices, "vertex with non-finite coordinates",
        "vertices with non-finite coordinates");
  if (r.boundary_edges > 0)
    defects.push_back (counted (r.boundary_edges, "boundary edge", "boundary edges") +
                       " in " + counted (r.boundary_loops, "loop", "loops"));
  note (r.non_manifold_edges, "non-manifold edge", "non-manifold edges");
  note (r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices");
  note (r.inconsistent_edges, "inconsistently oriented edge",
        "inconsistently oriented edges");
  note (r.degenerate_triangles, "degenerate triangle", "degenerate triangles");
  note (r.duplicate_triangles, "duplicate triangle", "duplicate triangles");
  if (r.self_intersecting_pairs > 0) {
    std::string text = counted (r.self_intersecting_pairs, "self-intersecting pair",
                                "self-intersecting pairs");
    if (!r.intersecting_pairs.empty ())
      text += " (e.g. triangles " + std::to_string (r.intersecting_pairs[0].first) +
              " and " + std::to_string (r.intersecting_pairs[0].second) + ")";
    defects.push_back (text);
  }
  if (!defects.empty ()) {
    out << " Defects: ";
    for (std::size_t i = 0; i < defects.size (); ++i)
      out << (i > 0 ? ", " : "") << defects[i];
    out << ".";
  }
  if (!r.self_intersections_checked)
    out << " Self-intersections not checked.";
  else if (r.self_intersecting_pairs == 0)
    out << " No self-intersections.";
  out << std::setprecision (4);
  if (r.isClosedManifold ())
    out << " Signed volume " << r.signed_volume << ".";
  out << " Smallest angle: mean " << std::fixed << std::setprecision (1)
      << r.mean_min_angle_deg << " deg, " << 100.0 * r.share_min_angle_below_10
      << "% below 10 deg.";
  return out.str ();
}

double
areaFacingAgainstNormals (const Points3& vertices,
                          const Triangles& triangles,
                          const std::vector<Eigen::Vector3f>& normals)
{
  double total = 0.0, against = 0.0;
  for (const auto& t : triangles) {
    const Eigen::Vector3d cross =
        (vertices[t[1]] - vertices[t[0]]).cross (vertices[t[2]] - vertices[t[0]]);
    const double area = cross.norm ();
    const Eigen::Vector3d normal_sum =
        (normals[t[0]] + normals[t[1]] + normals[t[2]]).cast<double> ();
    total += area;
    if (cross.dot (normal_sum) < 0.0)
      against += area;
  }
  return total > 0.0 ? against / total : 0.0;
}

std::size_t
distantIntersectingPairs (std::size_t num_vertices,
                          const Triangles& triangles,
                          const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                          std::size_t max_hops)
{
  std::vector<std::size_t> offsets;
  std::vector<pcl::index_t> adjacent;
  vertexAdjacency (num_vertices, triangles, offsets, adjacent);

  // Breadth-first search from the first triangle, ring by ring, until a vertex of
  // the second shows up; `seen` holds the number of the search that saw a vertex,
  // so it is never cleared.
  std::vector<std::size_t> seen (num_vertices, 0);
  std::vector<pcl::index_t> ring, next_ring;
  std::size_t search = 0, distant = 0;
  for (const auto& [first, second] : pairs) {
    if (first >= triangles.size () || second >= triangles.size () ||
        !validTriangle (triangles[first], num_vertices) ||
        !validTriangle (triangles[second], num_vertices))
      continue;
    ++search;
    const Triangle& target = triangles[second];
    const auto isTarget = [&] (pcl::index_t v) {
      return v == target[0] || v == target[1] || v == target[2];
    };
    ring.clear ();
    bool found = false;
    for (const pcl::index_t v : triangles[first]) {
      found = found || isTarget (v);
      seen[v] = search;
      ring.push_back (v);
    }
    for (std::size_t hop = 0; hop < max_hops && !found && !ring.empty (); ++hop) {
      next_ring.clear ();
      for (const pcl::index_t v : ring)
        for (std::size_t a = offsets[v]; a < offsets[v + 1] && !found; ++a) {
          const pcl::index_t w = adjacent[a];
          if (seen[w] == search)
            continue;
          seen[w] = search;
          found = isTarget (w);
          next_ring.push_back (w);
        }
      ring.swap (next_ring);
    }
    distant += found ? 0 : 1;
  }
  return distant;
}

std::size_t
neighboursSeparatedByTheMesh (const Points3& points,
                              const Triangles& triangles,
                              const CsrGraph& neighbours,
                              const std::vector<Eigen::Vector3f>& normals,
                              std::size_t max_hops,
                              int num_threads)
{
  const std::size_t n = points.size ();
  if (neighbours.offsets.size () != n + 1 || normals.size () != n ||
      neighbours.adjacency.size () != static_cast<std::size_t> (neighbours.offsets[n]))
    return 0;
  std::vector<std::size_t> offsets;
  std::vector<pcl::index_t> adjacent;
  vertexAdjacency (n, triangles, offsets, adjacent);
  // Neighbours whose normals differ by more than this lie across a thin part or
  // a crease, where the mesh rightly keeps them apart.
  const float min_cosine = 0.5f;
  // Wider neighbourhoods reach points a faithful mesh puts farther apart.
  const std::size_t nearest = 12;
  const auto agree = [&] (pcl::index_t u, pcl::index_t w) {
    const float lengths = normals[u].norm () * normals[w].norm ();
    return lengths > 0.0f && normals[u].dot (normals[w]) >= min_cosine * lengths;
  };
  const int threads = threadCount (num_threads);
  // Per thread: the number of the search that saw a vertex, never cleared.
  struct Search
  {
    std::vector<std::uint32_t> seen;
    std::uint32_t count = 0;
    std::vector<pcl::index_t> ring, next_ring, wanted;
    std::size_t separated = 0;
  };
  std::vector<Search> searches (static_cast<std::size_t> (threads));
  for (Search& search : searches)
    search.seen.assign (n, 0);
  parallelRanges (n, 1024, threads, [&] (std::size_t begin, std::size_t end, int thread) {
    Search& s = searches[static_cast<std::size_t> (thread)];
    for (std::size_t su = begin; su < end; ++su) {
      const auto u = static_cast<pcl::index_t> (su);
      s.wanted.clear ();
      for (const pcl::index_t* w = neighbours.begin (u); w != neighbours.end (u); ++w)
        if (*w >= 0 && static_cast<std::size_t> (*w) < n && *w != u && agree (u, *w))
          s.wanted.push_back (*w);
      if (s.wanted.size () > nearest) {
        const auto closer = [&] (pcl::index_t a, pcl::index_t b) {
          return (points[a] - points[u]).squaredNorm () < (points[b] - points[u]).squaredNorm ();
        };
        std::nth_element (s.wanted.begin (), s.wanted.begin () + (nearest - 1), s.wanted.end (),
                          closer);
        s.wanted.resize (nearest);
      }
      if (s.wanted.empty ())
        continue;
      // Rings of the mesh around u, one hop at a time, until every wanted
      // neighbour has been seen or max_hops is reached.
      if (++s.count == 0) { // wrapped: start the stamps afresh
        std::fill (s.seen.begin (), s.seen.end (), 0);
        s.count = 1;
      }
      s.seen[u] = s.count;
      s.ring.assign (1, u);
      std::size_t found = 0;
      for (std::size_t hop = 0; hop < max_hops && found < s.wanted.size () && !s.ring.empty ();
           ++hop) {
        s.next_ring.clear ();
        for (const pcl::index_t v : s.ring)
          for (std::size_t a = offsets[v]; a < offsets[v + 1]; ++a) {
            const pcl::index_t w = adjacent[a];
            if (s.seen[w] == s.count)
              continue;
            s.seen[w] = s.count;
            s.next_ring.push_back (w);
            found += std::count (s.wanted.begin (), s.wanted.end (), w);
          }
        s.ring.swap (s.next_ring);
      }
      for (const pcl::index_t w : s.wanted)
        s.separated += s.seen[w] == s.count ? 0 : 1;
    }
  });
  std::size_t separated = 0;
  for (const Search& search : searches)
    separated += search.separated;
  return separated;
}

} // namespace meshless
} // namespace pcl
