/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "common/union_find.h"

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
/** Cost factor of a step onto a point of a grown D's region that is neither of the
  * edge's two faces: a path that strays across a third region takes room the paths of
  * that region's own edges need. */
constexpr double off_border_cost = 3.0;

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

/** Routes the paths of one base mesh D in turn (see computeCutPaths) and keeps,
  * per point, the region the paths routed so far cut the surface into. */
class CutPathRouter
{
public:
  CutPathRouter (const Points3& points,
                 const CsrGraph& graph,
                 const CsrGraph& rings,
                 const BaseMesh& base)
  : points_ (points)
  , graph_ (graph)
  , rings_ (rings)
  , base_ (base)
  , n_ (points.size ())
  , corners_ (static_cast<int> (base.vertices.size ()))
  , num_faces_ (static_cast<int> (base.faces.size ()))
  {}

  CutPaths
  route ()
  {
    result_.edges = baseMeshEdges (base_);
    result_.paths.resize (result_.edges.size ());
    findEdgeSides ();
    if (!startRegions ()) {
      result_.message = "the base mesh vertices lie in different components of the ring graph "
                        "(a thin part whose rings do not agree with the rest)";
      return std::move (result_);
    }
    orderEdges ();
    orderAroundCorners ();
    guardCornerRings ();
    startScratch ();
    for (std::size_t e : order_)
      if (!routeEdge (e))
        return std::move (result_);
    if (!checkCyclicOrders ())
      return std::move (result_);
    result_.face_of = std::move (region_);
    result_.success = true;
    return std::move (result_);
  }

private:
  /** The edge of D being routed: its corners (positions into BaseMesh::vertices),
    * their cloud points, and the region it runs in. */
  struct Route
  {
    int ca, cb;
    pcl::index_t a, b;
    int own_region;
  };

  /** Region label of the points a split is relabelling. */
  static constexpr int pending = -2;

  /** The faces of D left and right of each edge (edges[e][0] -> edges[e][1]). */
  void
  findEdgeSides ()
  {
    sides_.assign (result_.edges.size (), {-1, -1});
    for (int f = 0; f < num_faces_; ++f)
      for (std::size_t k = 0, m = base_.faces[f].size (); k < m; ++k) {
        const int from = base_.faces[f][k], to = base_.faces[f][(k + 1) % m];
        const std::array<int, 2> key = {std::min (from, to), std::max (from, to)};
        const auto e = std::lower_bound (result_.edges.begin (), result_.edges.end (), key) -
                       result_.edges.begin ();
        sides_[e][from == key[0] ? 0 : 1] = f;
      }
  }

  /** One region at first: the component of the ring graph that holds the corners,
    * minus the corners themselves. \return false if the corners lie in different
    * components. */
  bool
  startRegions ()
  {
    std::vector<pcl::index_t> component;
    connectedComponents (graph_, component);
    const pcl::index_t main_component = component[base_.vertices[0]];
    for (auto c : base_.vertices)
      if (component[c] != main_component)
        return false;
    region_.assign (n_, -1);
    for (std::size_t v = 0; v < n_; ++v)
      if (component[v] == main_component)
        region_[v] = 0;
    blocked_.assign (n_, 0);
    for (auto v : base_.vertices) {
      blocked_[v] = 1;
      region_[v] = -1;
    }
    return true;
  }

  /** First a spanning tree of D (shortest edges first), which cannot enclose
    * anything, then the remaining edges by length; each of them closes a loop and
    * splits the region it runs in. */
  void
  orderEdges ()
  {
    const std::size_t num_edges = result_.edges.size ();
    std::vector<std::size_t> by_length (num_edges);
    std::iota (by_length.begin (), by_length.end (), 0);
    auto edgeLength = [&] (std::size_t e) {
      return (points_[base_.vertices[result_.edges[e][0]]] -
              points_[base_.vertices[result_.edges[e][1]]])
          .norm ();
    };
    std::stable_sort (by_length.begin (), by_length.end (), [&] (std::size_t a, std::size_t b) {
      return edgeLength (a) < edgeLength (b);
    });
    in_tree_.assign (num_edges, 0);
    DisjointSets<int> tree (corners_);
    for (std::size_t e : by_length)
      if (tree.join (result_.edges[e][0], result_.edges[e][1])) {
        in_tree_[e] = 1;
        order_.push_back (e);
      }
    for (std::size_t e : by_length)
      if (!in_tree_[e])
        order_.push_back (e);
  }

  /** D's cyclic order around each of its vertices: a face (.., b, c, a, ..),
    * counter-clockwise from outside, puts b directly after a around c. */
  void
  orderAroundCorners ()
  {
    next_around_.resize (corners_);
    for (const auto& f : base_.faces)
      for (std::size_t k = 0, m = f.size (); k < m; ++k)
        next_around_[f[k]].push_back ({f[(k + 1) % m], f[(k + m - 1) % m]});
  }

  /** The corner of D that follows corner a around corner c, or -1. */
  int
  after (int c, int a) const
  {
    for (const auto& [from, to] : next_around_[c])
      if (from == a)
        return to;
    return -1;
  }

  /** The corner of D that precedes corner b around corner c, or -1. */
  int
  before (int c, int b) const
  {
    for (const auto& [from, to] : next_around_[c])
      if (to == b)
        return from;
    return -1;
  }

  /** The ring of a corner is the room its paths leave through: no other path may
    * take it, and its own paths only for their first or last step. guard[w]: the
    * corner whose ring holds w, -2 if several rings do. */
  void
  guardCornerRings ()
  {
    guard_.assign (n_, -1);
    guarding_.assign (n_, 0);
    paths_to_route_.assign (corners_, 0);
    for (const auto& edge : result_.edges) {
      ++paths_to_route_[edge[0]];
      ++paths_to_route_[edge[1]];
    }
    for (int c = 0; c < corners_; ++c) {
      const pcl::index_t corner = base_.vertices[c];
      for (const pcl::index_t* w = rings_.begin (corner); w != rings_.end (corner); ++w)
      {
        guard_[*w] = guard_[*w] == -1 ? c : -2;
        ++guarding_[*w];
      }
    }
  }

  bool
  inRingOf (pcl::index_t w, int c) const
  {
    return guard_[w] == c || (guard_[w] == -2 && ringPosition (rings_, base_.vertices[c], w) >= 0);
  }

  /** The per-point and per-corner arrays the routing fills in as it goes. */
  void
  startScratch ()
  {
    // first_step[c][other]: the ring neighbour of corner c that the path to `other`
    // leaves through, once that path exists; is_step marks all of them.
    first_step_.assign (corners_, std::vector<pcl::index_t> (corners_, -1));
    is_step_.assign (n_, 0);
    face_region_.assign (num_faces_, 0);
    beside_path_.assign (n_, 0);
    piece_.assign (n_, -1);
    path_prev_.assign (n_, -1);
    path_next_.assign (n_, -1);
    routed_.assign (result_.edges.size (), 0);
    distance_.assign (n_, infinity);
    previous_.assign (n_, -1);
    seed_.assign (n_, 0);
  }

  /** The ring graph is only nearly planar: an edge may jump across a path between
    * two points that lie on different sides of it in the ring of a path point, or
    * in different wedges between the paths of a corner. Neither paths nor regions
    * may take such a step. */
  bool
  crossesPath (pcl::index_t x, pcl::index_t y) const
  {
    return (beside_path_[x] && beside_path_[y] && jumpsAcrossPathPoint (x, y)) ||
           (guard_[x] != -1 && guard_[y] != -1 && jumpsBetweenWedges (x, y));
  }

  /** Whether x and y lie on different sides of the path in the ring of a path
    * point next to both. */
  bool
  jumpsAcrossPathPoint (pcl::index_t x, pcl::index_t y) const
  {
    for (const pcl::index_t* p = graph_.begin (x); p != graph_.end (x); ++p) {
      if (path_prev_[*p] < 0 || x == path_prev_[*p] || x == path_next_[*p] ||
          y == path_prev_[*p] || y == path_next_[*p])
        continue;
      const long px = ringPosition (rings_, *p, x), py = ringPosition (rings_, *p, y);
      const long ps = ringPosition (rings_, *p, path_next_[*p]);
      const long pp = ringPosition (rings_, *p, path_prev_[*p]);
      if (px < 0 || py < 0 || ps < 0 || pp < 0)
        continue;
      const long d = rings_.degree (*p);
      const long left_end = (pp - ps + d) % d;
      if (((px - ps + d) % d < left_end) != ((py - ps + d) % d < left_end))
        return true;
    }
    return false;
  }

  /** Whether x and y lie in different wedges between the paths of a corner whose
    * ring holds both. */
  bool
  jumpsBetweenWedges (pcl::index_t x, pcl::index_t y) const
  {
    for (int c = 0; c < corners_; ++c) {
      if ((guard_[x] != c && guard_[x] != -2) || (guard_[y] != c && guard_[y] != -2))
        continue;
      const pcl::index_t corner = base_.vertices[c];
      const long px = ringPosition (rings_, corner, x), py = ringPosition (rings_, corner, y);
      if (px < 0 || py < 0)
        continue;
      // Same wedge: one of the two arcs between x and y holds no path.
      const long d = rings_.degree (corner);
      bool arc_xy = false, arc_yx = false;
      for (int other = 0; other < corners_; ++other) {
        const long ps = ringPosition (rings_, corner, first_step_[c][other]);
        if (ps < 0)
          continue;
        const long from_x = (ps - px + d) % d, until_y = (py - px + d) % d;
        (from_x < until_y ? arc_xy : arc_yx) = true;
      }
      if (arc_xy && arc_yx)
        return true;
    }
    return false;
  }

  /** A new path from corner c towards `other` must leave c strictly between the
    * existing paths that D puts directly before and after it around c, and leave
    * one ring member free for each path D puts between them and it that is still to
    * come: block the ring neighbours of c outside that window for this search. */
  void
  blockOutsideWedge (int c, int other)
  {
    const pcl::index_t corner = base_.vertices[c];
    int lo = before (c, other), hi = after (c, other);
    long reserve_lo = 0, reserve_hi = 0;
    while (lo >= 0 && lo != other && first_step_[c][lo] < 0) {
      lo = before (c, lo);
      ++reserve_lo;
    }
    while (hi >= 0 && hi != other && first_step_[c][hi] < 0) {
      hi = after (c, hi);
      ++reserve_hi;
    }
    if (lo < 0 || hi < 0 || lo == other)
      return; // no path at c yet: any direction
    const pcl::index_t* begin = rings_.begin (corner);
    const long d = rings_.degree (corner);
    const long plo = ringPosition (rings_, corner, first_step_[c][lo]);
    const long phi = ringPosition (rings_, corner, first_step_[c][hi]);
    if (plo < 0 || phi < 0)
      return;
    // Allowed: positions after plo by more than reserve_lo and before phi by more
    // than reserve_hi (cyclically; a single existing path has plo == phi).
    const long gap = plo == phi ? d : (phi - plo + d) % d;
    for (long pos = 0; pos < d; ++pos) {
      const long from_lo = (pos - plo + d) % d;
      const bool inside = from_lo > reserve_lo && from_lo < gap - reserve_hi;
      if (!inside && !blocked_[begin[pos]]) {
        blocked_[begin[pos]] = 1;
        wedge_blocked_.push_back (begin[pos]);
      }
    }
  }

  void
  unblockWedges ()
  {
    for (auto v : wedge_blocked_)
      blocked_[v] = 0;
    wedge_blocked_.clear ();
  }

  /** Whether the path of `route` may step from v to w. */
  bool
  mayStep (const Route& route, pcl::index_t v, pcl::index_t w) const
  {
    if (w == route.b)
      return !crossesPath (v, w);
    if (blocked_[w] || region_[w] != route.own_region || (v != route.a && inRingOf (v, route.cb)) ||
        crossesPath (v, w))
      return false;
    // Into the rings of the end corners only as the first or the last step.
    return guarding_[w] == 0 || (v == route.a && inRingOf (w, route.ca)) || inRingOf (w, route.cb);
  }

  /** Routes edge e of D inside its region and splits the region if the path closes
    * a loop. \return false (the message set) if no path fits. */
  bool
  routeEdge (std::size_t e)
  {
    const int ca = result_.edges[e][0], cb = result_.edges[e][1];
    const Route route = {ca, cb, base_.vertices[ca], base_.vertices[cb],
                         face_region_[sides_[e][0]]};
    blockOutsideWedge (ca, cb);
    blockOutsideWedge (cb, ca);
    std::vector<pcl::index_t> path = shortestPath (
        points_, graph_, route.a, route.b,
        [&] (pcl::index_t v, pcl::index_t w) { return mayStep (route, v, w); },
        [&] (pcl::index_t w) {
          return (beside_path_[w] ? crowding_cost : 1.0) *
                 (offBorder (e, w) ? off_border_cost : 1.0);
        },
        distance_,
        previous_, touched_);
    unblockWedges ();
    if (path.size () < 2) {
      result_.message = std::string ("no path between two base mesh vertices runs inside their "
                                     "region") +
                        (in_tree_[e] ? "" : " after the paths around it closed") +
                        " (a corner in a thin part, or the cloud is too sparse there)";
      return false;
    }
    markPath (path);
    first_step_[ca][cb] = path[1];
    first_step_[cb][ca] = path[path.size () - 2];
    is_step_[path[1]] = is_step_[path[path.size () - 2]] = 1;
    routed_[e] = 1;
    releaseFinishedCorner (ca);
    releaseFinishedCorner (cb);
    updateRegions (e, path, route.own_region);
    result_.paths[e] = std::move (path);
    return true;
  }

  /** Whether point w lies in a grown region other than edge e's two faces. */
  bool
  offBorder (std::size_t e, pcl::index_t w) const
  {
    if (base_.point_faces.size () != n_)
      return false; // no hint, or not one per point
    const int f = base_.point_faces[w];
    return f >= 0 && f != sides_[e][0] && f != sides_[e][1];
  }

  /** A corner whose paths all exist needs its ring no longer: later paths may pass
    * through it (where corners lie close, their rings would otherwise wall the
    * paths in). */
  void
  releaseFinishedCorner (int c)
  {
    if (--paths_to_route_[c] > 0)
      return;
    const pcl::index_t corner = base_.vertices[c];
    for (const pcl::index_t* w = rings_.begin (corner); w != rings_.end (corner); ++w)
      --guarding_[*w];
  }

  /** The path's inner points leave every region and block later paths. */
  void
  markPath (const std::vector<pcl::index_t>& path)
  {
    for (std::size_t k = 1; k + 1 < path.size (); ++k) {
      blocked_[path[k]] = 1;
      region_[path[k]] = -1;
      path_prev_[path[k]] = path[k - 1];
      path_next_[path[k]] = path[k + 1];
      for (const pcl::index_t* w = graph_.begin (path[k]); w != graph_.end (path[k]); ++w)
        beside_path_[*w] = 1;
    }
  }

  /** The regions after edge e was routed: one per face of the subgraph H of D
    * routed so far, i.e. faces of D joined across the edges not routed yet. */
  void
  updateRegions (std::size_t e, const std::vector<pcl::index_t>& path, int old_region)
  {
    DisjointSets<int> joined (num_faces_);
    for (std::size_t other = 0; other < result_.edges.size (); ++other)
      if (!routed_[other])
        joined.join (sides_[other][0], sides_[other][1]);
    const int left = joined.find (sides_[e][0]), right = joined.find (sides_[e][1]);
    if (left != right)
      splitRegion (path, old_region, left, right);
    for (int f = 0; f < num_faces_; ++f)
      face_region_[f] = joined.find (f);
  }

  void
  addSeed (pcl::index_t w, int side, int old_region)
  {
    if (region_[w] != old_region)
      return;
    if (!seed_[w])
      seeded_.push_back (w);
    seed_[w] |= static_cast<char> (side);
  }

  /** Walk v's ring from position `start` in direction `step` (+1 counter-clockwise)
    * up to the first member that `stop` accepts, seeding `side`. */
  template <typename Stop>
  void
  seedWalk (pcl::index_t v, long start, long step, const Stop& stop, int side, int old_region)
  {
    const long d = rings_.degree (v);
    for (long k = 1; k < d; ++k) {
      const pcl::index_t w = rings_.begin (v)[((start + step * k) % d + d) % d];
      if (stop (w))
        break;
      addSeed (w, side, old_region);
    }
  }

  /** Seeds of the two sides of a new path: at an inner point v with predecessor p
    * and successor s, the ring members counter-clockwise after s and before p lie
    * left of p -> v -> s, the others right. At the end corners, the ring members
    * between the path and the neighbouring paths there. seed[v]: 1 left, 2 right,
    * 3 both (a conflict: left to the flood). */
  void
  seedSides (const std::vector<pcl::index_t>& path, int old_region)
  {
    for (std::size_t j = 1; j + 1 < path.size (); ++j) {
      const pcl::index_t v = path[j];
      const long ps = ringPosition (rings_, v, path[j + 1]);
      const long pp = ringPosition (rings_, v, path[j - 1]);
      if (ps < 0 || pp < 0)
        continue;
      auto neighbourOnPath = [&] (pcl::index_t w) { return w == path[j - 1] || w == path[j + 1]; };
      seedWalk (v, ps, 1, neighbourOnPath, 1, old_region);
      seedWalk (v, ps, -1, neighbourOnPath, 2, old_region);
    }
    auto otherStep = [&] (pcl::index_t w) { return is_step_[w] != 0; };
    const long pa = ringPosition (rings_, path.front (), path[1]);
    const long pb = ringPosition (rings_, path.back (), path[path.size () - 2]);
    if (pa >= 0) {
      seedWalk (path.front (), pa, 1, otherStep, 1, old_region);
      seedWalk (path.front (), pa, -1, otherStep, 2, old_region);
    }
    if (pb >= 0) {
      seedWalk (path.back (), pb, -1, otherStep, 1, old_region);
      seedWalk (path.back (), pb, 1, otherStep, 2, old_region);
    }
  }

  /** Relabel the points of old_region after `path` split it into left_region and
    * right_region: a multi-source flood from both sides' seeds through the ring
    * graph, inside the old region. Points it does not reach leave every region. */
  void
  splitRegion (const std::vector<pcl::index_t>& path,
               int old_region,
               int left_region,
               int right_region)
  {
    seedSides (path, old_region);
    std::vector<pcl::index_t> members;
    for (std::size_t v = 0; v < n_; ++v)
      if (region_[v] == old_region) {
        members.push_back (static_cast<pcl::index_t> (v));
        region_[v] = pending;
      }
    std::vector<pcl::index_t> queue;
    labelSeeds (left_region, right_region, queue);
    flood (queue);
    if (keepLargestPieces (members, left_region, queue) > 0)
      handOverPending (members, queue);
    for (auto v : members) {
      piece_[v] = -1;
      if (region_[v] == pending)
        region_[v] = -1;
    }
  }

  /** The seeds claimed by one side take its region and go into the queue; those
    * both sides claimed are counted as conflicts. */
  void
  labelSeeds (int left_region, int right_region, std::vector<pcl::index_t>& queue)
  {
    for (auto w : seeded_) {
      if (seed_[w] == 3)
        ++result_.num_side_conflicts;
      else {
        region_[w] = seed_[w] == 1 ? left_region : right_region;
        queue.push_back (w);
      }
      seed_[w] = 0;
    }
    seeded_.clear ();
  }

  /** Breadth-first from all labelled points in the queue at once: each pending
    * point takes the label that reaches it first. */
  void
  flood (std::vector<pcl::index_t>& queue)
  {
    for (std::size_t head = 0; head < queue.size (); ++head) {
      const pcl::index_t v = queue[head];
      for (const pcl::index_t* w = graph_.begin (v); w != graph_.end (v); ++w)
        if (region_[*w] == pending && !blocked_[*w] && !crossesPath (v, *w)) {
          region_[*w] = region_[v];
          queue.push_back (*w);
        }
    }
    queue.clear ();
  }

  /** A side whose seeds were wrong (a stretch of flipped rings) or a pocket the
    * paths pinched off leaves a region in several pieces, and a later path could
    * not run through it: keep each new region's largest piece and set the other
    * pieces pending. \return the number of pending members. */
  std::size_t
  keepLargestPieces (const std::vector<pcl::index_t>& members,
                     int left_region,
                     std::vector<pcl::index_t>& queue)
  {
    std::vector<std::size_t> piece_size;
    std::vector<int> piece_region;
    for (auto s : members) {
      if (region_[s] < 0 || piece_[s] >= 0)
        continue;
      const int id = static_cast<int> (piece_size.size ());
      piece_[s] = id;
      queue.push_back (s);
      for (std::size_t head = 0; head < queue.size (); ++head) {
        const pcl::index_t v = queue[head];
        for (const pcl::index_t* w = graph_.begin (v); w != graph_.end (v); ++w)
          if (piece_[*w] < 0 && region_[*w] == region_[s] && !crossesPath (v, *w)) {
            piece_[*w] = id;
            queue.push_back (*w);
          }
      }
      piece_size.push_back (queue.size ());
      piece_region.push_back (region_[s]);
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
      if (region_[v] >= 0 && piece_[v] != largest[0] && piece_[v] != largest[1])
        region_[v] = pending;
      left_pending += region_[v] == pending;
    }
    return left_pending;
  }

  /** The pieces given up and the points the flood did not reach go to the regions
    * around them. Mostly there are none, and this scan of every member's
    * neighbours is skipped. */
  void
  handOverPending (const std::vector<pcl::index_t>& members, std::vector<pcl::index_t>& queue)
  {
    for (auto v : members)
      if (region_[v] >= 0)
        for (const pcl::index_t* w = graph_.begin (v); w != graph_.end (v); ++w)
          if (region_[*w] == pending) {
            queue.push_back (v);
            break;
          }
    flood (queue);
  }

  /** Cyclic order at each vertex c of D: a face (.., b, c, a, ..), counter-clockwise
    * from outside, puts a's path directly before b's path around c. \return false (the
    * message set) if the paths leave some corner in another order. */
  bool
  checkCyclicOrders ()
  {
    for (int c = 0; c < corners_; ++c)
      for (const auto& f : base_.faces) {
        const std::size_t m = f.size ();
        const auto k = static_cast<std::size_t> (std::find (f.begin (), f.end (), c) - f.begin ());
        if (k == m)
          continue;
        const char* problem = cyclicOrderProblem (c, f[(k + 1) % m], f[(k + m - 1) % m]);
        if (problem) {
          result_.message = problem;
          return false;
        }
      }
    return true;
  }

  /** Why the path of c towards fb does not directly follow its path towards fa,
    * counter-clockwise around c; nullptr if it does. */
  const char*
  cyclicOrderProblem (int c, int fa, int fb) const
  {
    const pcl::index_t corner = base_.vertices[c];
    const long ring_size = rings_.degree (corner);
    const long pa = ringPosition (rings_, corner, first_step_[c][fa]);
    const long pb = ringPosition (rings_, corner, first_step_[c][fb]);
    if (pa < 0 || pb < 0)
      return "a path leaves a base mesh vertex outside its ring";
    // b must follow a counter-clockwise before any other path of c does.
    for (int other = 0; other < corners_; ++other) {
      if (other == fa || other == fb || first_step_[c][other] < 0)
        continue;
      const long po = ringPosition (rings_, corner, first_step_[c][other]);
      const long between = (po - pa + ring_size) % ring_size;
      const long until_b = (pb - pa + ring_size) % ring_size;
      if (po < 0 || (between > 0 && between < until_b))
        return "the paths leave a base mesh vertex in another cyclic order than the base "
               "mesh prescribes (they would cross)";
    }
    if ((pb - pa + ring_size) % ring_size == 0)
      return "two paths leave a base mesh vertex through the same neighbour";
    return nullptr;
  }

  const Points3& points_;
  const CsrGraph& graph_;
  const CsrGraph& rings_;
  const BaseMesh& base_;
  const std::size_t n_;
  const int corners_;
  const int num_faces_;
  CutPaths result_;

  // Per edge of D.
  std::vector<std::array<int, 2>> sides_;
  std::vector<std::size_t> order_;
  std::vector<char> in_tree_, routed_;
  // Per corner of D.
  std::vector<std::vector<std::pair<int, int>>> next_around_;
  std::vector<std::vector<pcl::index_t>> first_step_;
  // Per face of D: the region that holds it.
  std::vector<int> face_region_;
  // Per point. The surface minus the paths so far falls into regions, one per face
  // of the subgraph H of D routed so far; region[v] names the region of point v by
  // the smallest face of D inside it (-1: on a path, or not reached through the
  // ring graph). A path may only run through the region its edge of D lies in, so
  // that it can neither cross an earlier path nor shut a corner out of its region.
  std::vector<int> region_;
  std::vector<char> blocked_, is_step_, beside_path_;
  std::vector<int> guard_, piece_;
  // Per point: how many corners with paths still to route hold it in their ring;
  // per corner: its paths still to route.
  std::vector<int> guarding_, paths_to_route_;
  std::vector<pcl::index_t> path_prev_, path_next_;
  // Scratch of the path search and the region splits.
  std::vector<double> distance_;
  std::vector<pcl::index_t> previous_, touched_, wedge_blocked_;
  std::vector<char> seed_;
  std::vector<pcl::index_t> seeded_;
};

} // namespace

CutPaths
computeCutPaths (const Points3& points,
                 const CsrGraph& graph,
                 const CsrGraph& rings,
                 const BaseMesh& base)
{
  return CutPathRouter (points, graph, rings, base).route ();
}

} // namespace meshless
} // namespace pcl
