/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/patch_split.h>

#include <algorithm>
#include <limits>
#include <queue>

namespace pcl {
namespace meshless {

namespace {

/** The path of D's directed edge (a, b) (positions into BaseMesh::vertices), from
  * a to b; empty if (a, b) is not an edge. */
std::vector<pcl::index_t>
directedPath (const CutPaths& paths, int a, int b)
{
  for (std::size_t e = 0; e < paths.edges.size (); ++e) {
    if (paths.edges[e][0] == a && paths.edges[e][1] == b)
      return paths.paths[e];
    if (paths.edges[e][0] == b && paths.edges[e][1] == a)
      return {paths.paths[e].rbegin (), paths.paths[e].rend ()};
  }
  return {};
}

/** Multi-source Dijkstra: every unlabelled, non-path point reachable in `graph`
  * gets the label of its nearest labelled point. */
void
growLabels (const Points3& points,
            const CsrGraph& graph,
            const std::vector<char>& on_path,
            std::vector<int>& label)
{
  const std::size_t n = points.size ();
  std::vector<double> distance (n, std::numeric_limits<double>::infinity ());
  using Entry = std::pair<double, pcl::index_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  for (std::size_t v = 0; v < n; ++v)
    if (label[v] >= 0 && !on_path[v]) {
      distance[v] = 0.0;
      for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w)
        if (label[*w] < 0 && !on_path[*w]) {
          heap.push ({0.0, static_cast<pcl::index_t> (v)});
          break;
        }
    }
  while (!heap.empty ()) {
    const auto [d, v] = heap.top ();
    heap.pop ();
    if (d > distance[v])
      continue;
    for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w) {
      if (on_path[*w])
        continue;
      const double nd = d + (points[*w] - points[v]).norm ();
      if (nd < distance[*w]) {
        distance[*w] = nd;
        label[*w] = label[v];
        heap.push ({nd, *w});
      }
    }
  }
}

/** Splits the points among the faces of D (see splitIntoPatches): the loops, the
  * regions grown over the points the paths' regions missed, then the moves that
  * connect every interior point to its face's loop. */
class PatchSplitter
{
public:
  PatchSplitter (const Points3& points,
                 const CsrGraph& graph,
                 const CsrGraph& fallback_graph,
                 const CsrGraph& dependencies,
                 const BaseMesh& base,
                 const CutPaths& paths)
  : points_ (points)
  , graph_ (graph)
  , fallback_graph_ (fallback_graph)
  , dependencies_ (dependencies)
  , base_ (base)
  , paths_ (paths)
  , n_ (points.size ())
  , faces_ (base.faces.size ())
  , label_ (result_.face_of)
  {}

  PatchSplit
  split ()
  {
    if (!paths_.success || paths_.paths.size () != paths_.edges.size ()) {
      result_.message = "the cut paths are missing";
      return std::move (result_);
    }
    markPathPoints ();
    if (paths_.face_of.size () != n_) {
      result_.message = "the cut paths carry no regions";
      return std::move (result_);
    }
    if (!buildLoops () || !growRegions () || !settleDependencies ())
      return std::move (result_);
    collectPatchPoints ();
    result_.success = true;
    return std::move (result_);
  }

private:
  void
  markPathPoints ()
  {
    on_path_.assign (n_, 0);
    for (const auto& path : paths_.paths)
      for (auto v : path)
        on_path_[v] = 1;
  }

  /** Each face's loop from its paths; every point keeps the region the paths
    * cut it into. \return false (the message set) if an edge of D has no path. */
  bool
  buildLoops ()
  {
    result_.patches.resize (faces_);
    label_ = paths_.face_of;
    result_.num_side_conflicts = paths_.num_side_conflicts;
    for (std::size_t f = 0; f < faces_; ++f) {
      std::vector<pcl::index_t>& loop = result_.patches[f].loop;
      const std::vector<int>& face = base_.faces[f];
      for (std::size_t k = 0; k < face.size (); ++k) {
        const std::vector<pcl::index_t> side =
            directedPath (paths_, face[k], face[(k + 1) % face.size ()]);
        if (side.size () < 2) {
          result_.message = "a face of the base mesh has an edge without a path";
          return false;
        }
        loop.insert (loop.end (), side.begin (), side.end () - 1);
      }
    }
    for (std::size_t v = 0; v < n_; ++v)
      if (on_path_[v])
        label_[v] = -1;
    return true;
  }

  /** The points the paths' regions did not reach join the nearest region, first
    * in the graph, then in the fallback graph. \return false (the message set) if
    * some point is still unlabelled. */
  bool
  growRegions ()
  {
    growLabels (points_, graph_, on_path_, label_);
    growLabels (points_, fallback_graph_, on_path_, label_);
    for (std::size_t v = 0; v < n_; ++v)
      if (!on_path_[v] && label_[v] < 0) {
        result_.message = "some points are not connected to the rest of the cloud (the "
                          "neighbourhood graph is disconnected; increase k or the radius, "
                          "or remove outliers)";
        return false;
      }
    return true;
  }

  /** Every interior point must reach its face's loop through its dependencies (the
    * neighbours its weights use) inside the face, or the face's system is singular.
    * Points that do not are moved, pass by pass, until nothing moves.
    * \return false (the message set) if some points cannot be moved anywhere or
    * the passes do not settle. */
  bool
  settleDependencies ()
  {
    loops_of_.resize (n_);
    for (std::size_t f = 0; f < faces_; ++f)
      for (auto b : result_.patches[f].loop)
        loops_of_[b].push_back (static_cast<int> (f));
    depended_on_ = transposeGraph (dependencies_);
    for (int pass = 0; pass < 64; ++pass) {
      findReached ();
      std::size_t stranded = 0;
      const std::size_t moved = moveUnreached (stranded);
      result_.num_reassigned += moved;
      if (moved == 0 && stranded == 0)
        return true;
      if (moved == 0) {
        result_.message = std::to_string (stranded) +
                          " point(s) are cut off from every patch boundary by the paths";
        return false;
      }
    }
    result_.message = "the patch regions did not settle into connected discs";
    return false;
  }

  /** reached_[v]: whether v reaches its face's loop; searched backwards from each
    * loop over reversed dependencies. */
  void
  findReached ()
  {
    reached_.assign (n_, 0);
    std::vector<pcl::index_t> stack;
    auto visitDependents = [&] (pcl::index_t j, int face) {
      for (const pcl::index_t* i = depended_on_.begin (j); i != depended_on_.end (j); ++i)
        if (!on_path_[*i] && !reached_[*i] && label_[*i] == face) {
          reached_[*i] = 1;
          stack.push_back (*i);
        }
    };
    for (std::size_t f = 0; f < faces_; ++f) {
      for (auto b : result_.patches[f].loop)
        visitDependents (b, static_cast<int> (f));
      while (!stack.empty ()) {
        const pcl::index_t j = stack.back ();
        stack.pop_back ();
        visitDependents (j, static_cast<int> (f));
      }
    }
  }

  /** Moves each point not reached to a face that one of its dependencies reaches
    * or bounds. \return the number moved; `stranded` counts those that stay. */
  std::size_t
  moveUnreached (std::size_t& stranded)
  {
    std::size_t moved = 0;
    for (std::size_t v = 0; v < n_; ++v) {
      if (on_path_[v] || reached_[v])
        continue;
      int to = -1;
      for (const pcl::index_t* w = dependencies_.begin (v); w != dependencies_.end (v) && to < 0;
           ++w)
        if (on_path_[*w] && !loops_of_[*w].empty ())
          to = loops_of_[*w].front ();
        else if (!on_path_[*w] && reached_[*w])
          to = label_[*w];
      if (to >= 0 && to != label_[v]) {
        label_[v] = to;
        ++moved;
      }
      else
        ++stranded;
    }
    return moved;
  }

  /** Each patch's points: its loop, then its interior points. */
  void
  collectPatchPoints ()
  {
    for (std::size_t f = 0; f < faces_; ++f)
      result_.patches[f].points = result_.patches[f].loop;
    for (std::size_t v = 0; v < n_; ++v)
      if (!on_path_[v])
        result_.patches[label_[v]].points.push_back (static_cast<pcl::index_t> (v));
  }

  const Points3& points_;
  const CsrGraph& graph_;
  const CsrGraph& fallback_graph_;
  const CsrGraph& dependencies_;
  const BaseMesh& base_;
  const CutPaths& paths_;
  const std::size_t n_;
  const std::size_t faces_;
  PatchSplit result_;
  /** Per point: its face (result_.face_of), or -1 on a path. */
  std::vector<int>& label_;
  std::vector<char> on_path_, reached_;
  /** Per point: the faces whose loop holds it (path points only). */
  std::vector<std::vector<int>> loops_of_;
  CsrGraph depended_on_;
};

} // namespace

PatchSplit
splitIntoPatches (const Points3& points,
                  const CsrGraph& graph,
                  const CsrGraph& fallback_graph,
                  const CsrGraph& dependencies,
                  const BaseMesh& base,
                  const CutPaths& paths)
{
  return PatchSplitter (points, graph, fallback_graph, dependencies, base, paths).split ();
}

CsrGraph
candidatesNearCuts (const CsrGraph& candidates,
                    const CsrGraph& dependencies,
                    const PatchSplit& split)
{
  const std::size_t n = candidates.size ();
  // The patch each point is an interior point of; -1 on a loop (in several).
  std::vector<int> interior_of (n, -1);
  for (std::size_t f = 0; f < split.patches.size (); ++f) {
    const Patch& patch = split.patches[f];
    for (std::size_t k = patch.loop.size (); k < patch.points.size (); ++k)
      interior_of[patch.points[k]] = static_cast<int> (f);
  }
  std::vector<char> kept (n, 0);
  for (std::size_t v = 0; v < n && v < dependencies.size (); ++v)
    if (interior_of[v] >= 0)
      for (const pcl::index_t* w = dependencies.begin (static_cast<pcl::index_t> (v));
           w != dependencies.end (static_cast<pcl::index_t> (v)); ++w)
        if (interior_of[*w] != interior_of[v]) {
          kept[v] = 1;
          break;
        }
  CsrGraph near;
  near.offsets.assign (n + 1, 0);
  for (std::size_t v = 0; v < n; ++v)
    near.offsets[v + 1] =
        near.offsets[v] +
        (kept[v] ? static_cast<pcl::index_t> (candidates.degree (static_cast<pcl::index_t> (v))) : 0);
  near.adjacency.reserve (static_cast<std::size_t> (near.offsets[n]));
  for (std::size_t v = 0; v < n; ++v)
    if (kept[v])
      near.adjacency.insert (near.adjacency.end (), candidates.begin (static_cast<pcl::index_t> (v)),
                             candidates.end (static_cast<pcl::index_t> (v)));
  return near;
}

} // namespace meshless
} // namespace pcl
