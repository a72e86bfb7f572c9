/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/normal_orientation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <queue>
#include <tuple>

namespace pcl {
namespace meshless {

namespace {

/** Above this confidence an edge joins two points into one region of settled
  * orientation (see settleRegionsByConsensus). */
constexpr double region_confidence = 0.3;
/** Every graph edge's least say in the consensus between two regions. */
constexpr double evidence_floor = 0.05;

/** How much the orientation of v says about w's: parallel normals, and an edge in
  * both tangent planes (1 at best; an edge along either normal crosses a thin part
  * and says little or the opposite). */
double
confidence (const Points3& points, const std::vector<Eigen::Vector3f>& normals, pcl::index_t v, pcl::index_t w)
{
  const Eigen::Vector3d nv = normals[v].cast<double> ();
  const Eigen::Vector3d nw = normals[w].cast<double> ();
  const Eigen::Vector3d e = (points[w] - points[v]).normalized ();
  return std::abs (nv.dot (nw)) - std::abs (nv.dot (e)) - std::abs (nw.dot (e));
}

/** Revises the signs `flip` that the spanning tree gave: one edge of the tree
  * decides a whole part, and on a limb a few points around (legs, horns) that edge
  * may cross the limb, turning everything beyond it inwards.
  * Points joined by confident edges whose signs agree form regions; between two
  * regions every graph edge votes, weighted by its confidence (at least
  * evidence_floor), for the same or the opposite sign; from each component's largest
  * region a spanning tree over the regions, strongest sums first, settles each
  * region's sign. Signs inside a region stay as they are. */
void
settleRegionsByConsensus (const Points3& points,
                          const CsrGraph& graph,
                          const CsrGraph& mutual,
                          const std::vector<Eigen::Vector3f>& normals,
                          std::vector<char>& flip)
{
  const std::size_t n = points.size ();
  // Whether the signs of v and w agree as their normals do.
  const auto agree = [&] (pcl::index_t v, pcl::index_t w) {
    return (normals[v].dot (normals[w]) > 0.0f) == (flip[v] == flip[w]);
  };
  // Regions: the components of the confident mutual edges whose signs agree.
  CsrGraph settled_edges;
  settled_edges.offsets.assign (n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) {
    for (const pcl::index_t* w = mutual.begin (v); w != mutual.end (v); ++w)
      if (agree (static_cast<pcl::index_t> (v), *w) &&
          confidence (points, normals, static_cast<pcl::index_t> (v), *w) > region_confidence)
        settled_edges.adjacency.push_back (*w);
    settled_edges.offsets[v + 1] = static_cast<pcl::index_t> (settled_edges.adjacency.size ());
  }
  std::vector<pcl::index_t> region;
  const std::size_t regions = connectedComponents (settled_edges, region);
  std::vector<std::size_t> region_size (regions, 0);
  for (const pcl::index_t r : region)
    ++region_size[r];

  // Sum of votes per pair of regions: > 0 keep their present relative sign.
  struct Vote
  {
    pcl::index_t a, b;
    double sum;
  };
  std::vector<Vote> votes;
  // A point without a normal (a degenerate neighbourhood) says nothing about signs.
  for (std::size_t v = 0; v < n; ++v)
    for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w)
      if (region[v] < region[*w] && !normals[v].isZero () && !normals[*w].isZero ()) {
        const double weight =
            std::max (0.0, confidence (points, normals, static_cast<pcl::index_t> (v), *w)) + evidence_floor;
        votes.push_back ({region[v], region[*w], agree (static_cast<pcl::index_t> (v), *w) ? weight : -weight});
      }
  std::sort (votes.begin (), votes.end (), [] (const Vote& x, const Vote& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  std::vector<Vote> sums;
  for (const Vote& vote : votes)
    if (!sums.empty () && sums.back ().a == vote.a && sums.back ().b == vote.b)
      sums.back ().sum += vote.sum;
    else
      sums.push_back (vote);
  std::vector<std::vector<std::size_t>> around (regions);
  for (std::size_t i = 0; i < sums.size (); ++i) {
    around[sums[i].a].push_back (i);
    around[sums[i].b].push_back (i);
  }

  std::vector<pcl::index_t> by_size (regions);
  for (std::size_t r = 0; r < regions; ++r)
    by_size[r] = static_cast<pcl::index_t> (r);
  std::stable_sort (by_size.begin (), by_size.end (), [&] (pcl::index_t x, pcl::index_t y) {
    return region_size[x] > region_size[y];
  });
  std::vector<char> turn (regions, 0), settled (regions, 0);
  using Entry = std::pair<double, std::pair<pcl::index_t, std::size_t>>; // (|sum|, (from, vote))
  std::priority_queue<Entry> heap;
  for (const pcl::index_t start : by_size) {
    if (settled[start])
      continue;
    settled[start] = 1;
    for (const std::size_t i : around[start])
      heap.push ({std::abs (sums[i].sum), {start, i}});
    while (!heap.empty ()) {
      const auto [from, i] = heap.top ().second;
      heap.pop ();
      const pcl::index_t to = sums[i].a == from ? sums[i].b : sums[i].a;
      if (settled[to])
        continue;
      settled[to] = 1;
      turn[to] = sums[i].sum >= 0.0 ? turn[from] : !turn[from];
      for (const std::size_t j : around[to])
        heap.push ({std::abs (sums[j].sum), {to, j}});
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (turn[region[v]])
      flip[v] = !flip[v];
}

/** The points next to the oriented ones, each keyed by its best edge so far
  * (confidence, then the oriented end): a binary max-heap indexed by point, whose
  * pop is the largest (confidence, from, to) over the points not yet oriented. A
  * heap of every edge offered, stale ones skipped when popped, makes the same
  * choices (per point it holds the same best edge) but grows to millions of edges
  * on a million points, where its sifts miss the cache (same flips, slower). */
class FrontierHeap
{
public:
  explicit FrontierHeap (std::size_t n) : position_ (n, never) {}

  bool
  empty () const
  {
    return heap_.empty ();
  }

  /** Offers edge (from, to) of the given confidence for point `to`, kept if its key
    * (confidence, from) is larger than the one `to` has. */
  void
  offer (pcl::index_t to, double confidence, pcl::index_t from)
  {
    const Entry entry{confidence, from, to};
    std::int64_t at = position_[to];
    if (at == taken)
      return;
    if (at == never) {
      at = static_cast<std::int64_t> (heap_.size ());
      heap_.push_back (entry);
    }
    else if (above (entry, heap_[at]))
      heap_[at] = entry;
    else
      return;
    up (at);
  }

  /** Takes out the point with the largest key; returns (from, to). */
  std::pair<pcl::index_t, pcl::index_t>
  pop ()
  {
    const Entry top = heap_.front ();
    position_[top.to] = taken;
    heap_.front () = heap_.back ();
    heap_.pop_back ();
    if (!heap_.empty ())
      down (0);
    return {top.from, top.to};
  }

private:
  struct Entry
  {
    double confidence;
    pcl::index_t from, to;
  };

  /** Whether a comes out before b: the larger (confidence, from, to). */
  static bool
  above (const Entry& a, const Entry& b)
  {
    return std::tie (b.confidence, b.from, b.to) < std::tie (a.confidence, a.from, a.to);
  }

  void
  place (std::int64_t at, const Entry& entry)
  {
    heap_[at] = entry;
    position_[entry.to] = static_cast<pcl::index_t> (at);
  }

  void
  up (std::int64_t at)
  {
    const Entry entry = heap_[at];
    while (at > 0) {
      const std::int64_t parent = (at - 1) / 2;
      if (!above (entry, heap_[parent]))
        break;
      place (at, heap_[parent]);
      at = parent;
    }
    place (at, entry);
  }

  void
  down (std::int64_t at)
  {
    const Entry entry = heap_[at];
    const auto size = static_cast<std::int64_t> (heap_.size ());
    for (;;) {
      std::int64_t child = 2 * at + 1;
      if (child >= size)
        break;
      if (child + 1 < size && above (heap_[child + 1], heap_[child]))
        ++child;
      if (!above (heap_[child], entry))
        break;
      place (at, heap_[child]);
      at = child;
    }
    place (at, entry);
  }

  static constexpr pcl::index_t never = -1; // not offered yet
  static constexpr pcl::index_t taken = -2; // popped: offers are ignored

  std::vector<Entry> heap_;
  std::vector<pcl::index_t> position_; // in heap_, or never or taken
};

} // namespace

NormalOrientation
orientNormals (const Points3& points,
               const CsrGraph& graph,
               const CsrGraph& mutual,
               OrderedNeighbourhoods& ordered)
{
  NormalOrientation result;
  const std::size_t n = points.size ();
  if (graph.size () != n || mutual.size () != n || ordered.normals.size () != n ||
      ordered.rings.size () != n) {
    result.message = "normals, rings and graphs must have one entry per point";
    return result;
  }
  std::vector<pcl::index_t> component;
  const std::size_t components = connectedComponents (graph, component);
  result.num_components = components;

  // Seed of each component: the point whose normal is the longest lever along its
  // offset from the component's centroid, |n . (v - c)|. Far out and facing
  // outwards or inwards with certainty; the farthest point alone may be a sharp
  // tip whose least-squares plane says nothing about the outside.
  std::vector<Eigen::Vector3d> centroid (components, Eigen::Vector3d::Zero ());
  std::vector<std::size_t> size (components, 0);
  for (std::size_t v = 0; v < n; ++v) {
    centroid[component[v]] += points[v];
    ++size[component[v]];
  }
  for (std::size_t c = 0; c < components; ++c)
    centroid[c] /= static_cast<double> (size[c]);
  std::vector<pcl::index_t> seed (components, -1);
  std::vector<double> farthest (components, -1.0);
  for (std::size_t v = 0; v < n; ++v) {
    const double d = std::abs (ordered.normals[v].cast<double> ().dot (points[v] - centroid[component[v]]));
    if (d > farthest[component[v]] && !ordered.normals[v].isZero ()) {
      farthest[component[v]] = d;
      seed[component[v]] = static_cast<pcl::index_t> (v);
    }
  }

  std::vector<char> flip (n, 0), done (n, 0);
  auto signedNormal = [&] (pcl::index_t v) -> Eigen::Vector3d {
    const Eigen::Vector3d normal = ordered.normals[v].cast<double> ();
    return flip[v] ? Eigen::Vector3d (-normal) : normal;
  };
  auto confidence = [&] (pcl::index_t v, pcl::index_t w) {
    return meshless::confidence (points, ordered.normals, v, w);
  };
  FrontierHeap heap (n);
  // Prim's algorithm from every oriented point over `edges`, best edges first.
  auto grow = [&] (const CsrGraph& edges) {
    for (std::size_t v = 0; v < n; ++v)
      if (done[v])
        for (const pcl::index_t* w = edges.begin (v); w != edges.end (v); ++w)
          if (!done[*w])
            heap.offer (*w, confidence (static_cast<pcl::index_t> (v), *w), static_cast<pcl::index_t> (v));
    while (!heap.empty ()) {
      const auto [from, to] = heap.pop ();
      done[to] = 1;
      flip[to] = signedNormal (from).dot (ordered.normals[to].cast<double> ()) < 0.0;
      for (const pcl::index_t* w = edges.begin (to); w != edges.end (to); ++w)
        if (!done[*w])
          heap.offer (*w, confidence (to, *w), to);
    }
  };
  for (std::size_t c = 0; c < components; ++c) {
    const pcl::index_t s = seed[c];
    if (s < 0)
      continue;
    flip[s] = ordered.normals[s].cast<double> ().dot (points[s] - centroid[c]) < 0.0;
    done[s] = 1;
  }
  grow (mutual);
  grow (graph);
  settleRegionsByConsensus (points, graph, mutual, ordered.normals, flip);

  // The seed decides each component's sign alone and may sit in a thin part whose
  // propagation went astray. On a closed surface the outward normal field gives
  // sum n_v . (v - c) A_v = 3 volume > 0 (divergence theorem): let every oriented
  // point vote, weighted by its squared distance to its nearest graph neighbour
  // (a share of the area), and turn the whole component if the vote is negative.
  std::vector<double> vote (components, 0.0);
  for (std::size_t v = 0; v < n; ++v) {
    if (ordered.normals[v].isZero ())
      continue;
    double spacing = std::numeric_limits<double>::infinity ();
    for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w)
      spacing = std::min (spacing, (points[*w] - points[v]).squaredNorm ());
    if (std::isfinite (spacing))
      vote[component[v]] += spacing * signedNormal (static_cast<pcl::index_t> (v))
                                          .dot (points[v] - centroid[component[v]]);
  }
  for (std::size_t v = 0; v < n; ++v)
    if (vote[component[v]] < 0.0)
      flip[v] = !flip[v];

  for (std::size_t v = 0; v < n; ++v)
    if (flip[v]) {
      ordered.normals[v] = -ordered.normals[v];
      std::reverse (ordered.rings.adjacency.begin () + ordered.rings.offsets[v],
                    ordered.rings.adjacency.begin () + ordered.rings.offsets[v + 1]);
      ++result.num_flipped;
    }
  result.success = true;
  return result;
}

CsrGraph
mutualRingGraph (const CsrGraph& rings)
{
  const std::size_t n = rings.size ();
  CsrGraph graph;
  graph.offsets.assign (n + 1, 0);
  std::vector<pcl::index_t> row;
  for (std::size_t v = 0; v < n; ++v) {
    row.clear ();
    for (const pcl::index_t* w = rings.begin (v); w != rings.end (v); ++w)
      if (std::find (rings.begin (*w), rings.end (*w), static_cast<pcl::index_t> (v)) !=
          rings.end (*w))
        row.push_back (*w);
    std::sort (row.begin (), row.end ());
    row.erase (std::unique (row.begin (), row.end ()), row.end ());
    graph.adjacency.insert (graph.adjacency.end (), row.begin (), row.end ());
    graph.offsets[v + 1] = static_cast<pcl::index_t> (graph.adjacency.size ());
  }
  return graph;
}

} // namespace meshless
} // namespace pcl
