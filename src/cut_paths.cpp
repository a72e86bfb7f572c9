/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/cut_paths.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <queue>

namespace pcl {
namespace meshless {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity ();
/** Cost factor of a step onto a point next to an earlier path: paths keep some
  * room between them, so that the regions between them do not pinch off. */
constexpr double crowding_cost = 3.0;

/** Union-find over a few elements (the corners or faces of D). */
struct DisjointSets
{
  explicit DisjointSets (std::size_t size) : parent (size) { std::iota (parent.begin (), parent.end (), 0); }

  int
  find (int x)
  {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  }

  /** \return false if a and b were already joined. */
  bool
  join (int a, int b)
  {
    a = find (a);
    b = find (b);
    if (a == b)
      return false;
    parent[std::max (a, b)] = std::min (a, b);
    return true;
  }

  std::vector<int> parent;
};

/** Position of w in v's ring, or -1. */
long
ringPosition (const CsrGraph& rings, pcl::index_t v, pcl::index_t w)
{
  const pcl::index_t* it = std::find (rings.begin (v), rings.end (v), w);
  return it == rings.end (v) ? -1 : it - rings.begin (v);
}

/** Shortest path from `source` to `target` over the steps (v, w) that `passable`
  * accepts, a step into w costing its length times factor(w) >= 1; empty if there
  * is none. A* search: the straight distance to the target is a lower bound of the
  * rest, so the search stays near the path instead of flooding the cloud.
  * distance/previous are scratch arrays (all infinity / -1 on entry and again on
  * exit, reset through `touched`), so that a short path costs what it visits, not
  * the size of the cloud. */
template <typename Passable, typename Factor>
std::vector<pcl::index_t>
shortestPath (const Points3& points,
              const CsrGraph& graph,
              pcl::index_t source,
              pcl::index_t target,
              const Passable& passable,
              const Factor& factor,
              std::vector<double>& distance,
              std::vector<pcl::index_t>& previous,
              std::vector<pcl::index_t>& touched)
{
  struct Entry
  {
    double estimate, distance;
    pcl::index_t v;
    bool operator> (const Entry& other) const { return estimate > other.estimate; }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  auto remaining = [&] (pcl::index_t v) { return (points[target] - points[v]).norm (); };
  distance[source] = 0.0;
  touched.push_back (source);
  heap.push ({remaining (source), 0.0, source});
  while (!heap.empty ()) {
    const Entry top = heap.top ();
    heap.pop ();
    const pcl::index_t v = top.v;
    if (top.distance > distance[v])
      continue;
    if (v == target)
      break;
    for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w) {
      if (!passable (v, *w))
        continue;
      const double nd = top.distance + factor (*w) * (points[*w] - points[v]).norm ();
      if (nd < distance[*w]) {
        if (distance[*w] == infinity)
          touched.push_back (*w);
        distance[*w] = nd;
        previous[*w] = v;
        heap.push ({nd + remaining (*w), nd, *w});
      }
    }
  }
  std::vector<pcl::index_t> path;
  if (distance[target] < infinity)
    for (pcl::index_t v = target; v != -1; v = previous[v])
      path.push_back (v);
  std::reverse (path.begin (), path.end ());
  for (auto v : touched) {
    distance[v] = infinity;
    previous[v] = -1;
  }
  touched.clear ();
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
  const int corners = static_cast<int> (base.vertices.size ());
  const int num_faces = static_cast<int> (base.faces.size ());
  result.edges = baseMeshEdges (base);
  const std::size_t num_edges = result.edges.size ();
  result.paths.resize (num_edges);

  // The faces of D left and right of each edge (edges[e][0] -> edges[e][1]).
  std::vector<std::array<int, 2>> sides (num_edges, {-1, -1});
  for (int f = 0; f < num_faces; ++f)
    for (int k = 0; k < 3; ++k) {
      const int from = base.faces[f][k], to = base.faces[f][(k + 1) % 3];
      const std::array<int, 2> key = {std::min (from, to), std::max (from, to)};
      const auto e = std::lower_bound (result.edges.begin (), result.edges.end (), key) -
                     result.edges.begin ();
      sides[e][from == key[0] ? 0 : 1] = f;
    }

  std::vector<pcl::index_t> component;
  connectedComponents (graph, component);
  for (auto c : base.vertices)
    if (component[c] != component[base.vertices[0]]) {
      result.message = "the base mesh vertices lie in different components of the ring graph "
                       "(a thin part whose rings do not agree with the rest)";
      return result;
    }

  // Order: first a spanning tree of D (shortest edges first), which cannot enclose
  // anything, then the remaining edges by length; each of them closes a loop and
  // splits the region it runs in.
  std::vector<std::size_t> by_length (num_edges);
  std::iota (by_length.begin (), by_length.end (), 0);
  auto edgeLength = [&] (std::size_t e) {
    return (points[base.vertices[result.edges[e][0]]] - points[base.vertices[result.edges[e][1]]])
        .norm ();
  };
  std::stable_sort (by_length.begin (), by_length.end (),
                    [&] (std::size_t a, std::size_t b) { return edgeLength (a) < edgeLength (b); });
  std::vector<std::size_t> order;
  std::vector<char> in_tree (num_edges, 0);
  DisjointSets tree (corners);
  for (std::size_t e : by_length)
    if (tree.join (result.edges[e][0], result.edges[e][1])) {
      in_tree[e] = 1;
      order.push_back (e);
    }
  for (std::size_t e : by_length)
    if (!in_tree[e])
      order.push_back (e);

  // D's cyclic order around each of its vertices: faces (c, a, b), counter-clockwise
  // from outside, put b directly after a around c.
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
  // leaves through, once that path exists; is_step marks all of them.
  std::vector<std::vector<pcl::index_t>> first_step (corners, std::vector<pcl::index_t> (corners, -1));
  std::vector<char> is_step (n, 0);

  // The surface minus the paths so far falls into regions, one per face of the
  // subgraph H of D routed so far; region[v] names the region of point v by the
  // smallest face of D inside it (-1: on a path, or not reached through the ring
  // graph). A path may only run through the region its edge of D lies in, so that
  // it can neither cross an earlier path nor shut a corner out of its region.
  std::vector<int> region (n, -1);
  for (std::size_t v = 0; v < n; ++v)
    if (component[v] == component[base.vertices[0]])
      region[v] = 0;
  std::vector<char> blocked (n, 0);
  for (auto v : base.vertices) {
    blocked[v] = 1;
    region[v] = -1;
  }
  // The ring of a corner is the room its paths leave through: no other path may
  // take it, and its own paths only for their first or last step. guard[w]: the
  // corner whose ring holds w, -2 if several rings do.
  std::vector<int> guard (n, -1);
  for (int c = 0; c < corners; ++c)
    for (const pcl::index_t* w = rings.begin (base.vertices[c]); w != rings.end (base.vertices[c]); ++w)
      guard[*w] = guard[*w] == -1 ? c : -2;
  auto inRingOf = [&] (pcl::index_t w, int c) {
    return guard[w] == c || (guard[w] == -2 && ringPosition (rings, base.vertices[c], w) >= 0);
  };
  std::vector<int> face_region (num_faces, 0);
  std::vector<char> beside_path (n, 0);
  std::vector<int> piece (n, -1);
  // The ring graph is only nearly planar: an edge may jump across a path between
  // two points that lie on different sides of it in the ring of a path point, or
  // in different wedges between the paths of a corner. Neither paths nor regions
  // may take such a step.
  std::vector<pcl::index_t> path_prev (n, -1), path_next (n, -1);
  auto crossesPath = [&] (pcl::index_t x, pcl::index_t y) {
    if (beside_path[x] && beside_path[y])
      for (const pcl::index_t* p = graph.begin (x); p != graph.end (x); ++p) {
        if (path_prev[*p] < 0 || x == path_prev[*p] || x == path_next[*p] ||
            y == path_prev[*p] || y == path_next[*p])
          continue;
        const long px = ringPosition (rings, *p, x), py = ringPosition (rings, *p, y);
        const long ps = ringPosition (rings, *p, path_next[*p]);
        const long pp = ringPosition (rings, *p, path_prev[*p]);
        if (px < 0 || py < 0 || ps < 0 || pp < 0)
          continue;
        const long d = rings.degree (*p);
        const long left_end = (pp - ps + d) % d;
        if (((px - ps + d) % d < left_end) != ((py - ps + d) % d < left_end))
          return true;
      }
    if (guard[x] != -1 && guard[y] != -1)
      for (int c = 0; c < corners; ++c) {
        if ((guard[x] != c && guard[x] != -2) || (guard[y] != c && guard[y] != -2))
          continue;
        const pcl::index_t corner = base.vertices[c];
        const long px = ringPosition (rings, corner, x), py = ringPosition (rings, corner, y);
        if (px < 0 || py < 0)
          continue;
        // Same wedge: one of the two arcs between x and y holds no path.
        const long d = rings.degree (corner);
        bool arc_xy = false, arc_yx = false;
        for (int other = 0; other < corners; ++other) {
          const long ps = ringPosition (rings, corner, first_step[c][other]);
          if (ps < 0)
            continue;
          const long from_x = (ps - px + d) % d, until_y = (py - px + d) % d;
          (from_x < until_y ? arc_xy : arc_yx) = true;
        }
        if (arc_xy && arc_yx)
          return true;
      }
    return false;
  };
  std::vector<char> routed (num_edges, 0);

  std::vector<double> distance (n, infinity);
  std::vector<pcl::index_t> previous (n, -1), touched;
  std::vector<pcl::index_t> wedge_blocked;

  // A new path from corner c towards `other` must leave c strictly between the
  // existing paths that D puts directly before and after it around c, and leave
  // one ring member free for each path D puts between them and it that is still to
  // come: block the ring neighbours of c outside that window for this search.
  auto blockOutsideWedge = [&] (int c, int other) {
    const pcl::index_t corner = base.vertices[c];
    int lo = before (c, other), hi = after (c, other);
    long reserve_lo = 0, reserve_hi = 0;
    while (lo >= 0 && lo != other && first_step[c][lo] < 0) {
      lo = before (c, lo);
      ++reserve_lo;
    }
    while (hi >= 0 && hi != other && first_step[c][hi] < 0) {
      hi = after (c, hi);
      ++reserve_hi;
    }
    if (lo < 0 || hi < 0 || lo == other)
      return; // no path at c yet: any direction
    const pcl::index_t* begin = rings.begin (corner);
    const long d = rings.degree (corner);
    const long plo = ringPosition (rings, corner, first_step[c][lo]);
    const long phi = ringPosition (rings, corner, first_step[c][hi]);
    if (plo < 0 || phi < 0)
      return;
    // Allowed: positions after plo by more than reserve_lo and before phi by more
    // than reserve_hi (cyclically; a single existing path has plo == phi).
    const long gap = plo == phi ? d : (phi - plo + d) % d;
    for (long pos = 0; pos < d; ++pos) {
      const long from_lo = (pos - plo + d) % d;
      const bool inside = from_lo > reserve_lo && from_lo < gap - reserve_hi;
      if (!inside && !blocked[begin[pos]]) {
        blocked[begin[pos]] = 1;
        wedge_blocked.push_back (begin[pos]);
      }
    }
  };

  // Seeds of the two sides of a new path: at an inner point v with predecessor p
  // and successor s, the ring members counter-clockwise after s and before p lie
  // left of p -> v -> s, the others right. At the end corners, the ring members
  // between the path and the neighbouring paths there. seed[v]: 1 left, 2 right,
  // 3 both (a conflict: left to the flood).
  std::vector<char> seed (n, 0);
  std::vector<pcl::index_t> seeded;
  auto addSeed = [&] (pcl::index_t w, int side, int old_region) {
    if (region[w] != old_region)
      return;
    if (!seed[w])
      seeded.push_back (w);
    seed[w] |= static_cast<char> (side);
  };
  // Walk v's ring from position `start` in direction `step` (+1 counter-clockwise)
  // up to the first member that `stop` accepts, seeding `side`.
  auto seedWalk = [&] (pcl::index_t v, long start, long step, const auto& stop, int side,
                       int old_region) {
    const long d = rings.degree (v);
    for (long k = 1; k < d; ++k) {
      const pcl::index_t w = rings.begin (v)[((start + step * k) % d + d) % d];
      if (stop (w))
        break;
      addSeed (w, side, old_region);
    }
  };

  // Relabel the points of old_region after `path` split it into left_region and
  // right_region: a multi-source Dijkstra from both sides' seeds through the ring
  // graph, inside the old region. Points it does not reach leave every region.
  auto splitRegion = [&] (const std::vector<pcl::index_t>& path, int old_region, int left_region,
                          int right_region) {
    for (std::size_t j = 1; j + 1 < path.size (); ++j) {
      const pcl::index_t v = path[j];
      const long ps = ringPosition (rings, v, path[j + 1]);
      const long pp = ringPosition (rings, v, path[j - 1]);
      if (ps < 0 || pp < 0)
        continue;
      auto neighbourOnPath = [&] (pcl::index_t w) { return w == path[j - 1] || w == path[j + 1]; };
      seedWalk (v, ps, 1, neighbourOnPath, 1, old_region);
      seedWalk (v, ps, -1, neighbourOnPath, 2, old_region);
    }
    auto otherStep = [&] (pcl::index_t w) { return is_step[w] != 0; };
    const long pa = ringPosition (rings, path.front (), path[1]);
    const long pb = ringPosition (rings, path.back (), path[path.size () - 2]);
    if (pa >= 0) {
      seedWalk (path.front (), pa, 1, otherStep, 1, old_region);
      seedWalk (path.front (), pa, -1, otherStep, 2, old_region);
    }
    if (pb >= 0) {
      seedWalk (path.back (), pb, -1, otherStep, 1, old_region);
      seedWalk (path.back (), pb, 1, otherStep, 2, old_region);
    }

    constexpr int pending = -2;
    std::vector<pcl::index_t> members;
    for (std::size_t v = 0; v < n; ++v)
      if (region[v] == old_region) {
        members.push_back (static_cast<pcl::index_t> (v));
        region[v] = pending;
      }
    std::vector<pcl::index_t> queue;
    for (auto w : seeded) {
      if (seed[w] == 3)
        ++result.num_side_conflicts;
      else {
        region[w] = seed[w] == 1 ? left_region : right_region;
        queue.push_back (w);
      }
      seed[w] = 0;
    }
    seeded.clear ();
    // Breadth-first from all labelled points in the queue at once: each pending
    // point takes the label that reaches it first.
    auto flood = [&] () {
      for (std::size_t head = 0; head < queue.size (); ++head) {
        const pcl::index_t v = queue[head];
        for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w)
          if (region[*w] == pending && !blocked[*w] && !crossesPath (v, *w)) {
            region[*w] = region[v];
            queue.push_back (*w);
          }
      }
      queue.clear ();
    };
    flood ();

    // A side whose seeds were wrong (a stretch of flipped rings) or a pocket the
    // paths pinched off leaves a region in several pieces, and a later path could
    // not run through it: keep each new region's largest piece and hand the other
    // pieces to the regions around them.
    std::vector<std::size_t> piece_size;
    std::vector<int> piece_region;
    for (auto s : members) {
      if (region[s] < 0 || piece[s] >= 0)
        continue;
      const int id = static_cast<int> (piece_size.size ());
      piece[s] = id;
      queue.push_back (s);
      for (std::size_t head = 0; head < queue.size (); ++head) {
        const pcl::index_t v = queue[head];
        for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w)
          if (piece[*w] < 0 && region[*w] == region[s] && !crossesPath (v, *w)) {
            piece[*w] = id;
            queue.push_back (*w);
          }
      }
      piece_size.push_back (queue.size ());
      piece_region.push_back (region[s]);
      queue.clear ();
    }
    std::array<int, 2> largest = {-1, -1};
    for (int id = 0; id < static_cast<int> (piece_size.size ()); ++id) {
      int& best = largest[piece_region[id] == left_region ? 0 : 1];
      if (best < 0 || piece_size[id] > piece_size[best])
        best = id;
    }
    std::size_t left_pending = 0;
    for (auto v : members) {
      if (region[v] >= 0 && piece[v] != largest[0] && piece[v] != largest[1])
        region[v] = pending;
      left_pending += region[v] == pending;
    }
    // The pieces given up and the points the flood did not reach go to the regions
    // around them; mostly there are none, and this scan of every member's
    // neighbours is skipped (a third of the split's time on a million points).
    if (left_pending > 0) {
      for (auto v : members)
        if (region[v] >= 0)
          for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w)
            if (region[*w] == pending) {
              queue.push_back (v);
              break;
            }
      flood ();
    }
    for (auto v : members) {
      piece[v] = -1;
      if (region[v] == pending)
        region[v] = -1;
    }
  };

  for (std::size_t e : order) {
    const int ca = result.edges[e][0], cb = result.edges[e][1];
    const pcl::index_t a = base.vertices[ca];
    const pcl::index_t b = base.vertices[cb];
    const int own_region = face_region[sides[e][0]];
    blockOutsideWedge (ca, cb);
    blockOutsideWedge (cb, ca);
    std::vector<pcl::index_t> path = shortestPath (
        points, graph, a, b,
        [&] (pcl::index_t v, pcl::index_t w) {
          if (w == b)
            return !crossesPath (v, w);
          if (blocked[w] || region[w] != own_region || (v != a && inRingOf (v, cb)) ||
              crossesPath (v, w))
            return false;
          // Into the rings of the end corners only as the first or the last step.
          return guard[w] == -1 || (v == a && inRingOf (w, ca)) || inRingOf (w, cb);
        },
        [&] (pcl::index_t w) { return beside_path[w] ? crowding_cost : 1.0; }, distance, previous,
        touched);
    for (auto v : wedge_blocked)
      blocked[v] = 0;
    wedge_blocked.clear ();
    if (path.size () < 2) {
      result.message = std::string ("no path between two base mesh vertices runs inside their "
                                    "region") +
                       (in_tree[e] ? "" : " after the paths around it closed") +
                       " (a corner in a thin part, or the cloud is too sparse there)";
      return result;
    }
    for (std::size_t k = 1; k + 1 < path.size (); ++k) {
      blocked[path[k]] = 1;
      region[path[k]] = -1;
      path_prev[path[k]] = path[k - 1];
      path_next[path[k]] = path[k + 1];
      for (const pcl::index_t* w = graph.begin (path[k]); w != graph.end (path[k]); ++w)
        beside_path[*w] = 1;
    }
    first_step[ca][cb] = path[1];
    first_step[cb][ca] = path[path.size () - 2];
    is_step[path[1]] = is_step[path[path.size () - 2]] = 1;
    routed[e] = 1;

    // Faces of H: faces of D joined across the edges not routed yet.
    DisjointSets joined (num_faces);
    for (std::size_t other = 0; other < num_edges; ++other)
      if (!routed[other])
        joined.join (sides[other][0], sides[other][1]);
    const int left = joined.find (sides[e][0]), right = joined.find (sides[e][1]);
    if (left != right)
      splitRegion (path, own_region, left, right);
    for (int f = 0; f < num_faces; ++f)
      face_region[f] = joined.find (f);
    result.paths[e] = std::move (path);
  }

  // Cyclic order at each vertex c of D: faces (c, a, b), counter-clockwise from
  // outside, put a's path directly before b's path around c.
  for (int c = 0; c < corners; ++c) {
    const pcl::index_t corner = base.vertices[c];
    const long ring_size = rings.degree (corner);
    for (const auto& f : base.faces) {
      const int k = static_cast<int> (std::find (f.begin (), f.end (), c) - f.begin ());
      if (k == 3)
        continue;
      const int fa = f[(k + 1) % 3], fb = f[(k + 2) % 3];
      const long pa = ringPosition (rings, corner, first_step[c][fa]);
      const long pb = ringPosition (rings, corner, first_step[c][fb]);
      if (pa < 0 || pb < 0) {
        result.message = "a path leaves a base mesh vertex outside its ring";
        return result;
      }
      // b must follow a counter-clockwise before any other path of c does.
      for (int other = 0; other < corners; ++other) {
        if (other == fa || other == fb || first_step[c][other] < 0)
          continue;
        const long po = ringPosition (rings, corner, first_step[c][other]);
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
  result.face_of = std::move (region);
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
