/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/cut_paths.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <queue>

namespace pcl {
namespace meshless {

namespace {

/** Dijkstra from `source` to `target` avoiding blocked points; empty if none. */
std::vector<pcl::index_t>
shortestPath (const Points3& points,
              const CsrGraph& graph,
              pcl::index_t source,
              pcl::index_t target,
              const std::vector<char>& blocked,
              std::vector<double>& distance,
              std::vector<pcl::index_t>& previous,
              std::vector<pcl::index_t>& touched)
{
  // distance/previous are shared scratch arrays reset through `touched`, so a
  // short path costs what it visits, not the size of the cloud.
  for (auto v : touched) {
    distance[v] = std::numeric_limits<double>::infinity ();
    previous[v] = -1;
  }
  touched.clear ();
  using Entry = std::pair<double, pcl::index_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  distance[source] = 0.0;
  touched.push_back (source);
  heap.push ({0.0, source});
  while (!heap.empty ()) {
    const auto [d, v] = heap.top ();
    heap.pop ();
    if (d > distance[v])
      continue;
    if (v == target)
      break;
    for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w) {
      if (blocked[*w] && *w != target)
        continue;
      const double nd = d + (points[*w] - points[v]).norm ();
      if (nd < distance[*w]) {
        if (distance[*w] == std::numeric_limits<double>::infinity ())
          touched.push_back (*w);
        distance[*w] = nd;
        previous[*w] = v;
        heap.push ({nd, *w});
      }
    }
  }
  std::vector<pcl::index_t> path;
  if (previous[target] < 0 && target != source)
    return path;
  for (pcl::index_t v = target; v != -1; v = previous[v])
    path.push_back (v);
  std::reverse (path.begin (), path.end ());
  return path;
}

} // namespace

CutPaths
computeCutPaths (const Points3& points,
                 const CsrGraph& graph,
                 const CsrGraph& rings,
                 const BaseMesh& base)
{
  CutPaths result;
  const std::size_t n = points.size ();
  result.edges = baseMeshEdges (base);
  result.paths.resize (result.edges.size ());

  std::vector<std::size_t> order (result.edges.size ());
  std::iota (order.begin (), order.end (), 0);
  auto edgeLength = [&] (std::size_t e) {
    return (points[base.vertices[result.edges[e][0]]] - points[base.vertices[result.edges[e][1]]])
        .norm ();
  };
  std::stable_sort (order.begin (), order.end (),
                    [&] (std::size_t a, std::size_t b) { return edgeLength (a) < edgeLength (b); });

  // D's cyclic order around each of its vertices: faces (c, a, b), counter-clockwise
  // from outside, put b directly after a around c.
  const int corners = static_cast<int> (base.vertices.size ());
  std::vector<std::vector<std::pair<int, int>>> next_around (corners);
  for (const auto& f : base.faces)
    for (int k = 0; k < 3; ++k)
      next_around[f[k]].push_back ({f[(k + 1) % 3], f[(k + 2) % 3]});
  auto after = [&] (int c, int a) {
    for (const auto& [from, to] : next_around[c])
      if (from == a)
        return to;
    return -1;
  };
  auto before = [&] (int c, int b) {
    for (const auto& [from, to] : next_around[c])
      if (to == b)
        return from;
    return -1;
  };
  // first_step[c][other]: the ring neighbour of corner c that the path to `other`
  // leaves through, once that path exists.
  std::vector<std::vector<pcl::index_t>> first_step (corners, std::vector<pcl::index_t> (corners, -1));

  std::vector<char> blocked (n, 0);
  for (auto v : base.vertices)
    blocked[v] = 1;
  std::vector<double> distance (n, std::numeric_limits<double>::infinity ());
  std::vector<pcl::index_t> previous (n, -1), touched;
  std::vector<pcl::index_t> wedge_blocked;

  // A new path from corner c towards `other` must leave c strictly between the
  // existing paths that D puts directly before and after it around c: block the
  // ring neighbours of c outside that wedge for this search.
  auto blockOutsideWedge = [&] (int c, int other) {
    const pcl::index_t corner = base.vertices[c];
    int lo = before (c, other), hi = after (c, other);
    while (lo >= 0 && lo != other && first_step[c][lo] < 0)
      lo = before (c, lo);
    while (hi >= 0 && hi != other && first_step[c][hi] < 0)
      hi = after (c, hi);
    if (lo < 0 || hi < 0 || lo == other)
      return; // no path at c yet: any direction
    const pcl::index_t* begin = rings.begin (corner);
    const long d = rings.degree (corner);
    const long plo = std::find (begin, begin + d, first_step[c][lo]) - begin;
    const long phi = std::find (begin, begin + d, first_step[c][hi]) - begin;
    if (plo == d || phi == d)
      return;
    // Allowed: positions strictly after plo and strictly before phi (cyclically);
    // with a single existing path (plo == phi) every position but that one.
    const long gap = (phi - plo + d) % d;
    for (long pos = 0; pos < d; ++pos) {
      const long from_lo = (pos - plo + d) % d;
      const bool inside = gap == 0 ? pos != plo : (from_lo > 0 && from_lo < gap);
      if (!inside && !blocked[begin[pos]]) {
        blocked[begin[pos]] = 1;
        wedge_blocked.push_back (begin[pos]);
      }
    }
  };

  for (std::size_t e : order) {
    const int ca = result.edges[e][0], cb = result.edges[e][1];
    const pcl::index_t a = base.vertices[ca];
    const pcl::index_t b = base.vertices[cb];
    blockOutsideWedge (ca, cb);
    blockOutsideWedge (cb, ca);
    std::vector<pcl::index_t> path =
        shortestPath (points, graph, a, b, blocked, distance, previous, touched);
    for (auto v : wedge_blocked)
      blocked[v] = 0;
    wedge_blocked.clear ();
    if (path.size () < 2) {
      result.message = "no path between two base mesh vertices avoids the earlier paths "
                       "(the cloud is disconnected or too sparse there)";
      return result;
    }
    for (std::size_t k = 1; k + 1 < path.size (); ++k)
      blocked[path[k]] = 1;
    first_step[ca][cb] = path[1];
    first_step[cb][ca] = path[path.size () - 2];
    result.paths[e] = std::move (path);
  }

  // Cyclic order at each vertex c of D: faces (c, a, b), counter-clockwise from
  // outside, put a's path directly before b's path around c.
  for (int c = 0; c < static_cast<int> (base.vertices.size ()); ++c) {
    const pcl::index_t corner = base.vertices[c];
    auto firstStepTowards = [&] (int other) -> pcl::index_t {
      for (std::size_t e = 0; e < result.edges.size (); ++e) {
        const auto& path = result.paths[e];
        if (result.edges[e][0] == c && result.edges[e][1] == other)
          return path[1];
        if (result.edges[e][1] == c && result.edges[e][0] == other)
          return path[path.size () - 2];
      }
      return -1;
    };
    auto ringPosition = [&] (pcl::index_t w) -> long {
      const pcl::index_t* it = std::find (rings.begin (corner), rings.end (corner), w);
      return it == rings.end (corner) ? -1 : it - rings.begin (corner);
    };
    const long ring_size = rings.degree (corner);
    for (const auto& f : base.faces) {
      const int k = static_cast<int> (std::find (f.begin (), f.end (), c) - f.begin ());
      if (k == 3)
        continue;
      const long pa = ringPosition (firstStepTowards (f[(k + 1) % 3]));
      const long pb = ringPosition (firstStepTowards (f[(k + 2) % 3]));
      if (pa < 0 || pb < 0) {
        result.message = "a path leaves a base mesh vertex outside its ring";
        return result;
      }
      // b must follow a counter-clockwise before any other path of c does.
      for (std::size_t e = 0; e < result.edges.size (); ++e) {
        int other = -1;
        if (result.edges[e][0] == c)
          other = result.edges[e][1];
        else if (result.edges[e][1] == c)
          other = result.edges[e][0];
        if (other < 0 || other == f[(k + 1) % 3] || other == f[(k + 2) % 3])
          continue;
        const long po = ringPosition (firstStepTowards (other));
        const long between = (po - pa + ring_size) % ring_size;
        const long until_b = (pb - pa + ring_size) % ring_size;
        if (po < 0 || (between > 0 && between < until_b)) {
          result.message = "the paths leave a base mesh vertex in another cyclic order than "
                           "the base mesh prescribes (they would cross)";
          return result;
        }
      }
      if ((pb - pa + ring_size) % ring_size == 0) {
        result.message = "two paths leave a base mesh vertex through the same neighbour";
        return result;
      }
    }
  }
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
