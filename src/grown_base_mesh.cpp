/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "common/fans.h"
#include "common/union_find.h"
#include "handles.h"
#include "region_merging.h"

#include <pcl/surface/meshless/grown_base_mesh.h>

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <random>
#include <set>
#include <unordered_map>

namespace pcl {
namespace meshless {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity ();

/** Seeds the growth starts from for n points. */
std::size_t
initialSeedCount (std::size_t n)
{
  return std::clamp<std::size_t> (n / 1000, 12, 64);
}

/** Ring triangles of one triple of regions, as the rings read them. */
struct TripleSupport
{
  std::vector<std::array<pcl::index_t, 3>> triangles;
};

/** The state the rounds of growth share: seeds, the distance of every point to its
  * nearest seed along the graph, and the region (seed) it belongs to. */
class BaseMeshGrower
{
public:
  BaseMeshGrower (const Points3& points,
                  const CsrGraph& graph,
                  const CsrGraph& rings,
                  const std::vector<char>& eligible,
                  const GrownBaseMeshOptions& options,
                  bool in_local_spacings)
  : points_ (points)
  , graph_ (graph)
  , rings_ (rings)
  , eligible_ (eligible)
  , n_ (points.size ())
  , initial_seeds_ (options.initial_seeds ? options.initial_seeds : initialSeedCount (n_))
  , start_ (options.start)
  , in_local_spacings_ (in_local_spacings)
  , max_rounds_ (options.max_rounds)
  , max_seeds_ (std::max (initial_seeds_,
                          options.max_seeds ? options.max_seeds
                                            : std::min<std::size_t> (n_ / 20, 4096)))
  {}

  BaseMeshGrower (const BaseMeshGrower&) = delete; // face_support_ points into triples_
  BaseMeshGrower&
  operator= (const BaseMeshGrower&) = delete;

  GrownBaseMesh
  run ()
  {
    if (n_ < 4 || graph_.size () != n_ || rings_.size () != n_) {
      result_.message = "too few points, or graphs of another size, to grow a base mesh";
      return std::move (result_);
    }
    distance_.assign (n_, infinity);
    region_.assign (n_, -1);
    if (in_local_spacings_)
      measureSpacing ();
    plantSeed (firstSeed ());
    while (seeds_.size () < initial_seeds_) {
      const pcl::index_t next = farthestPoint ();
      if (next < 0 || distance_[next] == 0.0)
        break;
      plantSeed (next);
    }
    for (;;) {
      std::set<int> bad = readDual ();
      if (bad.empty ())
        buildRegionPolygons (bad);
      if (bad.empty ()) {
        std::string problem;
        result_.genus = closedBaseMeshGenus (result_.mesh, n_, problem);
        if (result_.genus >= 0) {
          result_.mesh.point_faces = region_;
          result_.region_of = std::move (region_);
          result_.seeds = seeds_;
          result_.success = true;
          return std::move (result_);
        }
        for (int r = 0; r < static_cast<int> (seeds_.size ()); ++r)
          bad.insert (r);
      }
      ++result_.rounds;
      if ((max_rounds_ > 0 && result_.rounds > max_rounds_) || !addSeeds (bad)) {
        result_.message = "no base mesh whose regions are discs was found within " +
                          std::to_string (max_seeds_) + " seeds" +
                          (max_rounds_ > 0 ? " and " + std::to_string (max_rounds_) + " rounds"
                                           : std::string ()) +
                          ": the topology is ambiguous at this sampling (a handle or "
                          "a gap about as thin as the point spacing, heavy noise, or more "
                          "than one object)";
        result_.mesh = {};
        return std::move (result_);
      }
    }
  }

private:
  /** The eligible point farthest from the centroid, or for another start an
    * eligible point picked by it: a deterministic start. */
  pcl::index_t
  firstSeed () const
  {
    if (start_ != 0) {
      std::mt19937 random (start_);
      std::uniform_int_distribution<std::size_t> any (0, n_ - 1);
      for (int tries = 0; tries < 1000; ++tries) {
        const std::size_t v = any (random);
        if (isEligible (v))
          return static_cast<pcl::index_t> (v);
      }
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
    for (const auto& p : points_)
      centroid += p;
    centroid /= static_cast<double> (n_);
    pcl::index_t best = 0;
    double best_distance = -1.0;
    for (std::size_t v = 0; v < n_; ++v)
      if (isEligible (v) && (points_[v] - centroid).squaredNorm () > best_distance) {
        best_distance = (points_[v] - centroid).squaredNorm ();
        best = static_cast<pcl::index_t> (v);
      }
    return best;
  }

  bool
  isEligible (std::size_t v) const
  {
    return eligible_.empty () || eligible_[v];
  }

  /** A new seed claims every point closer to it along the graph than to the seeds
    * before: the multi-source Dijkstra, grown one source at a time. */
  void
  plantSeed (pcl::index_t seed)
  {
    const int label = static_cast<int> (seeds_.size ());
    seeds_.push_back (seed);
    using Entry = std::pair<double, pcl::index_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    distance_[seed] = 0.0;
    region_[seed] = label;
    heap.push ({0.0, seed});
    while (!heap.empty ()) {
      const auto [d, v] = heap.top ();
      heap.pop ();
      if (d > distance_[v] || region_[v] != label)
        continue;
      for (const pcl::index_t* w = graph_.begin (v); w != graph_.end (v); ++w) {
        const double through = d + edgeLength (v, *w);
        if (through < distance_[*w]) {
          distance_[*w] = through;
          region_[*w] = label;
          heap.push ({through, *w});
        }
      }
    }
  }

  /** An edge's length along which regions grow: in the cloud's units, or in local
    * point spacings (spacing_ set). */
  double
  edgeLength (pcl::index_t v, pcl::index_t w) const
  {
    const double length = (points_[w] - points_[v]).norm ();
    return spacing_.empty () ? length : length / (0.5 * (spacing_[v] + spacing_[w]));
  }

  /** Each point's mean distance to its graph neighbours, over their mean over the
    * cloud: lengths divided by it count spacings, so regions hold about as many
    * points where the sampling is sparse as where it is dense. */
  void
  measureSpacing ()
  {
    spacing_.assign (n_, 0.0);
    double total = 0.0;
    std::size_t measured = 0;
    for (std::size_t v = 0; v < n_; ++v) {
      double sum = 0.0;
      for (const pcl::index_t* w = graph_.begin (v); w != graph_.end (v); ++w)
        sum += (points_[*w] - points_[v]).norm ();
      const auto degree = static_cast<double> (graph_.degree (static_cast<pcl::index_t> (v)));
      if (degree > 0.0 && sum > 0.0) {
        spacing_[v] = sum / degree;
        total += spacing_[v];
        ++measured;
      }
    }
    const double mean = measured > 0 ? total / static_cast<double> (measured) : 1.0;
    for (double& h : spacing_)
      h = h > 0.0 ? h / mean : 1.0;
  }

  /** The farthest point from the seeds among those offered, eligible ones first. */
  struct Farthest
  {
    pcl::index_t eligible = -1, other = -1;
  };

  void
  offer (std::size_t v, Farthest& farthest) const
  {
    pcl::index_t& slot = isEligible (v) ? farthest.eligible : farthest.other;
    if (slot < 0 || distance_[v] > distance_[slot])
      slot = static_cast<pcl::index_t> (v);
  }

  /** The reached point farthest from the seeds, eligible ones first; -1 if no
    * point is reached. */
  pcl::index_t
  farthestPoint () const
  {
    Farthest farthest;
    for (std::size_t v = 0; v < n_; ++v)
      if (distance_[v] != infinity) // else another component: not grown into
        offer (v, farthest);
    return farthest.eligible >= 0 && distance_[farthest.eligible] > 0.0 ? farthest.eligible
                                                                        : farthest.other;
  }

  /** A further seed in every region of `bad`, at its point farthest from its seed
    * (eligible points first). \return false if the seeds allowed are used up or no
    * region can take one. */
  bool
  addSeeds (const std::set<int>& bad)
  {
    std::vector<Farthest> farthest (seeds_.size ());
    for (std::size_t v = 0; v < n_; ++v) {
      const int r = region_[v];
      if (r >= 0 && distance_[v] > 0.0 && bad.count (r))
        offer (v, farthest[r]);
    }
    const auto pick = [&] (int r) {
      return farthest[r].eligible >= 0 ? farthest[r].eligible : farthest[r].other;
    };
    // One seed per group of touching bad regions, in the widest first: a problem
    // usually spans a few regions, and a seed in each would shrink all regions
    // faster than the problems need (small regions leave the paths no room).
    std::vector<std::pair<double, int>> widest;
    for (int r : bad)
      if (pick (r) >= 0)
        widest.emplace_back (distance_[pick (r)], r);
    std::sort (widest.rbegin (), widest.rend ());
    const std::vector<std::set<int>> touching = touchingRegions (bad);
    std::set<int> covered;
    std::vector<pcl::index_t> added;
    for (const auto& [width, r] : widest) {
      if (covered.count (r))
        continue;
      added.push_back (pick (r));
      covered.insert (r);
      covered.insert (touching[r].begin (), touching[r].end ());
    }
    if (seeds_.size () + added.size () > max_seeds_)
      return false;
    const std::size_t before = seeds_.size ();
    for (auto s : added)
      if (distance_[s] > 0.0) // an earlier seed of this round may have claimed it
        plantSeed (s);
    return seeds_.size () > before;
  }

  /** For each region of `among`, the regions of `among` it touches. */
  std::vector<std::set<int>>
  touchingRegions (const std::set<int>& among) const
  {
    std::vector<std::set<int>> touching (seeds_.size ());
    for (const auto& [pair, count] : touches_)
      if (among.count (pair[0]) && among.count (pair[1])) {
        touching[pair[0]].insert (pair[1]);
        touching[pair[1]].insert (pair[0]);
      }
    return touching;
  }

  /** D from the regions: faces where the rings see three regions meet. \return the
    * regions where a condition fails (empty when D is a closed manifold). */
  std::set<int>
  readDual ()
  {
    collectTriples ();
    countTouches ();
    std::set<int> bad;
    dual_faces_.clear ();
    face_support_.clear ();
    // Where four regions meet near one point the rings read both diagonals: the
    // faces best seen are taken first, and a face is left out if one of its edges
    // is already used in its direction. Faces seen by one ring only fill holes.
    std::vector<const std::pair<const std::array<int, 3>, TripleSupport>*> by_support;
    for (const auto& entry : triples_)
      by_support.push_back (&entry);
    std::stable_sort (by_support.begin (), by_support.end (), [] (auto a, auto b) {
      return a->second.triangles.size () > b->second.triangles.size ();
    });
    std::set<std::array<int, 2>> used;
    const auto directedEdges = [] (const std::array<int, 3>& t) {
      return std::array<std::array<int, 2>, 3> {
          {{t[0], t[1]}, {t[1], t[2]}, {t[2], t[0]}}};
    };
    for (const bool filling : {false, true})
      for (const auto* entry : by_support) {
        const auto& [key, support] = *entry;
        if ((support.triangles.size () >= 2) == filling)
          continue;
        const auto edges = directedEdges (key);
        bool fits = true;
        for (const auto& e : edges)
          fits = fits && !used.count (e) && (!filling || used.count ({e[1], e[0]}));
        if (!fits)
          continue;
        used.insert (edges.begin (), edges.end ());
        if (meetingPlaces (support) > 1)
          bad.insert (key.begin (), key.end ());
        dual_faces_.push_back (key);
        face_support_.push_back (&support);
      }
    fillSmallHoles (used);
    findManifoldProblems (bad);
    findTouchesWithoutEdge (bad);
    return bad;
  }

  /** The polygonal D of §5 from the dual triangulation: a corner per place where
    * three regions meet (a point of the ring triangles seen there), a face per
    * region, its corners in the order of the dual's faces around the seed. Corners
    * have three paths each, which their rings have room for; the dual's vertices,
    * six on average on a torus, would not. Adds to `bad` the regions where two
    * meeting places offer no distinct point. */
  void
  buildRegionPolygons (std::set<int>& bad)
  {
    result_.mesh = {};
    std::vector<char> taken (n_, 0);
    for (std::size_t f = 0; f < dual_faces_.size (); ++f) {
      const pcl::index_t corner = face_support_[f]->triangles.empty ()
                                      ? meetingPoint (dual_faces_[f], taken)
                                      : cornerPoint (*face_support_[f], taken);
      if (corner < 0) {
        bad.insert (dual_faces_[f].begin (), dual_faces_[f].end ());
        continue;
      }
      taken[corner] = 1;
      result_.mesh.vertices.push_back (corner);
    }
    if (!bad.empty ())
      return;
    // Around region a, the face (a, b, c) is followed by the face (a, c, d).
    std::vector<std::map<int, int>> face_after (seeds_.size ()); // region -> (b -> face)
    for (std::size_t f = 0; f < dual_faces_.size (); ++f)
      for (int k = 0; k < 3; ++k)
        face_after[dual_faces_[f][k]][dual_faces_[f][(k + 1) % 3]] = static_cast<int> (f);
    for (int a = 0; a < static_cast<int> (seeds_.size ()); ++a) {
      std::vector<int> polygon;
      int face = face_after[a].begin ()->second;
      do {
        polygon.push_back (face);
        const auto& t = dual_faces_[face];
        const int k = static_cast<int> (std::find (t.begin (), t.end (), a) - t.begin ());
        face = face_after[a].at (t[(k + 2) % 3]);
      } while (face != polygon.front () && polygon.size () <= face_after[a].size ());
      if (polygon.size () < 3)
        bad.insert (a); // a region with two neighbours: a face of two sides
      result_.mesh.faces.push_back (std::move (polygon));
    }
  }

  /** For a face filled into a hole: the free point of its three regions next to
    * most of the other two; -1 if none touches both. */
  pcl::index_t
  meetingPoint (const std::array<int, 3>& face, const std::vector<char>& taken) const
  {
    pcl::index_t best = -1;
    for (std::size_t v = 0; v < n_; ++v) {
      const int own = region_[v];
      if (taken[v] || (own != face[0] && own != face[1] && own != face[2]))
        continue;
      std::set<int> others;
      for (const pcl::index_t* w = graph_.begin (v); w != graph_.end (v); ++w)
        if (region_[*w] != own &&
            (region_[*w] == face[0] || region_[*w] == face[1] || region_[*w] == face[2]))
          others.insert (region_[*w]);
      if (others.size () == 2 &&
          (best < 0 || rings_.degree (static_cast<pcl::index_t> (v)) > rings_.degree (best)))
        best = static_cast<pcl::index_t> (v);
    }
    return best;
  }

  /** The point of a meeting place that best takes three paths: not taken by another
    * corner, eligible, with the largest ring; -1 if every point is taken. */
  pcl::index_t
  cornerPoint (const TripleSupport& support, const std::vector<char>& taken) const
  {
    pcl::index_t best = -1;
    const auto better = [&] (pcl::index_t p, pcl::index_t q) {
      if (isEligible (p) != isEligible (q))
        return isEligible (p);
      if (rings_.degree (p) != rings_.degree (q))
        return rings_.degree (p) > rings_.degree (q);
      return p < q;
    };
    for (const auto& triangle : support.triangles)
      for (auto p : triangle)
        if (!taken[p] && (best < 0 || better (p, best)))
          best = p;
    return best;
  }

  /** Three or four regions around a point where no face was read (the rings there
    * disagree): the hole they leave in the dual is closed with one face, or two
    * split along the pair of regions that touch more. Larger holes are left: they
    * may go around a handle. */
  void
  fillSmallHoles (std::set<std::array<int, 2>>& used)
  {
    std::map<int, int> hole_next; // along the missing faces' edges
    std::set<int> visited;        // and vertices on two holes: not simple ones to fill
    for (const auto& e : used)
      if (!used.count ({e[1], e[0]}) && !hole_next.emplace (e[1], e[0]).second)
        visited.insert (e[1]);
    for (const auto& [start, unused] : hole_next) {
      if (visited.count (start))
        continue;
      std::vector<int> loop;
      int v = start;
      while (loop.size () <= 4 && !visited.count (v) && hole_next.count (v)) {
        visited.insert (v);
        loop.push_back (v);
        v = hole_next[v];
      }
      if (v != start || loop.size () < 3 || loop.size () > 4)
        continue;
      std::vector<std::array<int, 3>> faces;
      if (loop.size () == 3)
        faces.push_back ({loop[0], loop[1], loop[2]});
      else if (touchCount (loop[0], loop[2]) >= touchCount (loop[1], loop[3]))
        faces = {{loop[0], loop[1], loop[2]}, {loop[0], loop[2], loop[3]}};
      else
        faces = {{loop[1], loop[2], loop[3]}, {loop[1], loop[3], loop[0]}};
      for (auto face : faces) {
        for (int k = 0; k < 3; ++k)
          used.insert ({face[k], face[(k + 1) % 3]});
        std::rotate (face.begin (), std::min_element (face.begin (), face.end ()), face.end ());
        dual_faces_.push_back (face);
        face_support_.push_back (&no_support_);
      }
    }
  }

  /** Graph edges between every two regions that touch, counted once per round:
    * the hole filling, the touch check and the seeding all read them. */
  void
  countTouches ()
  {
    touches_.clear ();
    for (std::size_t v = 0; v < n_; ++v)
      for (const pcl::index_t* w = graph_.begin (v); w != graph_.end (v); ++w) {
        const int a = region_[v], b = region_[*w];
        if (a >= 0 && b >= 0 && a < b)
          ++touches_[{a, b}];
      }
  }

  /** Graph edges between regions a and b (the graph is symmetric). */
  int
  touchCount (int a, int b) const
  {
    const auto it = touches_.find ({std::min (a, b), std::max (a, b)});
    return it == touches_.end () ? 0 : it->second;
  }

  /** Every ring triangle (v, a, b) whose points lie in three regions, under the
    * regions' triple turned to start at its smallest label. */
  void
  collectTriples ()
  {
    triples_.clear ();
    for (std::size_t v = 0; v < n_; ++v) {
      const int rv = region_[v];
      const long d = rings_.degree (static_cast<pcl::index_t> (v));
      if (rv < 0 || d < 3)
        continue;
      const pcl::index_t* ring = rings_.begin (static_cast<pcl::index_t> (v));
      for (long i = 0; i < d; ++i) {
        const pcl::index_t a = ring[i], b = ring[(i + 1) % d];
        const int ra = region_[a], rb = region_[b];
        if (ra < 0 || rb < 0 || ra == rv || rb == rv || ra == rb)
          continue;
        std::array<int, 3> key = {rv, ra, rb};
        std::rotate (key.begin (), std::min_element (key.begin (), key.end ()), key.end ());
        triples_[key].triangles.push_back ({static_cast<pcl::index_t> (v), a, b});
      }
    }
  }

  /** Groups of a triple's ring triangles that share no point: separate places
    * where the same three regions meet, counting only groups seen twice. */
  static std::size_t
  meetingPlaces (const TripleSupport& support)
  {
    const std::size_t t = support.triangles.size ();
    DisjointSets<std::size_t> groups (t);
    std::unordered_map<pcl::index_t, std::size_t> first_triangle;
    for (std::size_t i = 0; i < t; ++i)
      for (auto p : support.triangles[i]) {
        const auto inserted = first_triangle.emplace (p, i);
        if (!inserted.second)
          groups.join (i, inserted.first->second);
      }
    std::map<std::size_t, std::size_t> group_size;
    for (std::size_t i = 0; i < t; ++i)
      ++group_size[groups.find (i)];
    std::size_t places = 0;
    for (const auto& [root, size] : group_size)
      places += size >= 2;
    return places;
  }

  /** Edges of D not in exactly two faces of opposite turn, vertices whose faces do
    * not form one fan, seeds in no face. */
  void
  findManifoldProblems (std::set<int>& bad)
  {
    const auto& faces = dual_faces_;
    std::map<std::array<int, 2>, int> directed;
    std::vector<std::vector<std::array<int, 2>>> fan (seeds_.size ());
    for (const auto& f : faces)
      for (int k = 0; k < 3; ++k) {
        ++directed[{f[k], f[(k + 1) % 3]}];
        fan[f[k]].push_back ({f[(k + 1) % 3], f[(k + 2) % 3]});
      }
    for (const auto& [edge, count] : directed) {
      const auto back = directed.find ({edge[1], edge[0]});
      if (count != 1 || back == directed.end () || back->second != 1) {
        bad.insert (edge[0]);
        bad.insert (edge[1]);
      }
    }
    for (int v = 0; v < static_cast<int> (seeds_.size ()); ++v)
      if (!isOneFan (fan[v]))
        bad.insert (v);
  }

  /** Two regions that touch along more than a point must be an edge of D: a region
    * enclosed by another, or touching it where no third one meets them, makes no
    * face. */
  void
  findTouchesWithoutEdge (std::set<int>& bad) const
  {
    std::set<std::array<int, 2>> edges;
    for (const auto& f : dual_faces_)
      for (int k = 0; k < 3; ++k)
        edges.insert ({std::min (f[k], f[(k + 1) % 3]), std::max (f[k], f[(k + 1) % 3])});
    for (const auto& [pair, count] : touches_)
      if (count > 2 && !edges.count (pair)) {
        bad.insert (pair[0]);
        bad.insert (pair[1]);
      }
  }

  const Points3& points_;
  const CsrGraph& graph_;
  const CsrGraph& rings_;
  const std::vector<char>& eligible_;
  const std::size_t n_;
  const std::size_t initial_seeds_;
  const std::uint32_t start_;
  const bool in_local_spacings_;
  const std::size_t max_rounds_;
  const std::size_t max_seeds_;
  std::vector<pcl::index_t> seeds_;
  /** The dual triangulation of the regions (seed labels), and the ring triangles
    * each of its faces was read from. */
  std::map<std::array<int, 3>, TripleSupport> triples_;
  /** Graph edges between two touching regions (smaller label first), this round. */
  std::map<std::array<int, 2>, int> touches_;
  std::vector<std::array<int, 3>> dual_faces_;
  std::vector<const TripleSupport*> face_support_;
  /** The support of a face filled into a hole: no ring triangle. */
  const TripleSupport no_support_;
  std::vector<double> distance_;
  std::vector<int> region_;
  /** Per point, the local spacing over the cloud's mean; empty: lengths in the
    * cloud's units. */
  std::vector<double> spacing_;
  GrownBaseMesh result_;
};

} // namespace

std::string
handlesRefusal (int genus)
{
  return "the cloud has " + std::to_string (genus) + " handle" + (genus > 1 ? "s" : "") +
         " (genus " + std::to_string (genus) +
         "): a sphere-like mesh would span them; use setTopology (Topology::Closed), which "
         "keeps the genus";
}

int
clearHandles (const Points3& points,
              const CsrGraph& graph,
              const CsrGraph& rings,
              const std::vector<char>& eligible)
{
  GrownBaseMeshOptions bounded;
  bounded.max_seeds = std::min<std::size_t> (points.size () / 20, max_seeds_for_handles);
  bounded.max_rounds = max_rounds_for_handles;
  bounded.merge_regions_below = 1; // only the genus is wanted
  int genus = -1, agreeing = 0, failed = 0;
  for (bounded.start = 0; bounded.start < 3 && agreeing < 2 && failed < 2; ++bounded.start) {
    const GrownBaseMesh grown = growBaseMesh (points, graph, rings, eligible, bounded);
    if (!grown.success) {
      ++failed;
      continue;
    }
    if (grown.genus == 0 || (genus >= 0 && grown.genus != genus))
      return 0;
    genus = grown.genus;
    ++agreeing;
  }
  return agreeing == 2 ? genus : 0;
}

GrownBaseMesh
growBaseMesh (const Points3& points,
              const CsrGraph& graph,
              const CsrGraph& rings,
              const std::vector<char>& eligible,
              const GrownBaseMeshOptions& options)
{
  GrownBaseMesh grown = BaseMeshGrower (points, graph, rings, eligible, options, false).run ();
  if (!grown.success && options.retry_in_local_spacings) {
    GrownBaseMesh adapted = BaseMeshGrower (points, graph, rings, eligible, options, true).run ();
    if (adapted.success)
      grown = std::move (adapted);
  }
  // A quarter of the initial regions' size: merged further, the patches of a tube's
  // long strips turn back over themselves where the sampling is uneven.
  const std::size_t initial =
      options.initial_seeds ? options.initial_seeds : initialSeedCount (points.size ());
  const std::size_t min_points = options.merge_regions_below
                                     ? options.merge_regions_below
                                     : points.size () / (4 * initial);
  mergeSmallRegions (grown, min_points);
  return grown;
}

} // namespace meshless
} // namespace pcl
