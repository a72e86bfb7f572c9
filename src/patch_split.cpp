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

} // namespace

PatchSplit
splitIntoPatches (const Points3& points,
                  const CsrGraph& graph,
                  const CsrGraph& fallback_graph,
                  const CsrGraph& dependencies,
                  const BaseMesh& base,
                  const CutPaths& paths)
{
  PatchSplit result;
  const std::size_t n = points.size ();
  const std::size_t faces = base.faces.size ();
  if (!paths.success || paths.paths.size () != paths.edges.size ()) {
    result.message = "the cut paths are missing";
    return result;
  }

  std::vector<char> on_path (n, 0);
  for (const auto& path : paths.paths)
    for (auto v : path)
      on_path[v] = 1;

  // Loops; every point keeps the region the paths cut it into.
  if (paths.face_of.size () != n) {
    result.message = "the cut paths carry no regions";
    return result;
  }
  result.patches.resize (faces);
  std::vector<int>& label = result.face_of;
  label = paths.face_of;
  result.num_side_conflicts = paths.num_side_conflicts;
  for (std::size_t f = 0; f < faces; ++f) {
    std::vector<pcl::index_t>& loop = result.patches[f].loop;
    for (int k = 0; k < 3; ++k) {
      const std::vector<pcl::index_t> side =
          directedPath (paths, base.faces[f][k], base.faces[f][(k + 1) % 3]);
      if (side.size () < 2) {
        result.message = "a face of the base mesh has an edge without a path";
        return result;
      }
      loop.insert (loop.end (), side.begin (), side.end () - 1);
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (on_path[v])
      label[v] = -1;

  growLabels (points, graph, on_path, label);
  growLabels (points, fallback_graph, on_path, label);
  for (std::size_t v = 0; v < n; ++v)
    if (!on_path[v] && label[v] < 0) {
      result.message = "some points are not connected to the rest of the cloud (the "
                       "neighbourhood graph is disconnected; increase k or the radius, "
                       "or remove outliers)";
      return result;
    }

  // Every interior point must reach its face's loop through its dependencies (the
  // neighbours its weights use) inside the face, or the face's system is singular.
  // Search backwards from each loop over reversed dependencies; move points that
  // are not reached to a face that one of their dependencies reaches or bounds,
  // and repeat until nothing moves.
  std::vector<std::vector<int>> loops_of (n); // faces whose loop holds a path point
  for (std::size_t f = 0; f < faces; ++f)
    for (auto b : result.patches[f].loop)
      loops_of[b].push_back (static_cast<int> (f));
  const CsrGraph depended_on = transposeGraph (dependencies);
  bool settled = false;
  for (int pass = 0; pass < 64 && !settled; ++pass) {
    std::vector<char> reached (n, 0);
    std::vector<pcl::index_t> stack;
    auto visitDependents = [&] (pcl::index_t j, int face) {
      for (const pcl::index_t* i = depended_on.begin (j); i != depended_on.end (j); ++i)
        if (!on_path[*i] && !reached[*i] && label[*i] == face) {
          reached[*i] = 1;
          stack.push_back (*i);
        }
    };
    for (std::size_t f = 0; f < faces; ++f) {
      for (auto b : result.patches[f].loop)
        visitDependents (b, static_cast<int> (f));
      while (!stack.empty ()) {
        const pcl::index_t j = stack.back ();
        stack.pop_back ();
        visitDependents (j, static_cast<int> (f));
      }
    }
    std::size_t moved = 0, stranded = 0;
    for (std::size_t v = 0; v < n; ++v) {
      if (on_path[v] || reached[v])
        continue;
      int to = -1;
      for (const pcl::index_t* w = dependencies.begin (v); w != dependencies.end (v) && to < 0; ++w)
        if (on_path[*w] && !loops_of[*w].empty ())
          to = loops_of[*w].front ();
        else if (!on_path[*w] && reached[*w])
          to = label[*w];
      if (to >= 0 && to != label[v]) {
        label[v] = to;
        ++moved;
      }
      else
        ++stranded;
    }
    result.num_reassigned += moved;
    settled = moved == 0 && stranded == 0;
    if (moved == 0 && stranded > 0) {
      result.message = std::to_string (stranded) +
                       " point(s) are cut off from every patch boundary by the paths";
      return result;
    }
  }
  if (!settled) {
    result.message = "the patch regions did not settle into connected discs";
    return result;
  }

  for (std::size_t f = 0; f < faces; ++f)
    result.patches[f].points = result.patches[f].loop;
  for (std::size_t v = 0; v < n; ++v)
    if (!on_path[v])
      result.patches[label[v]].points.push_back (static_cast<pcl::index_t> (v));
  result.success = true;
  return result;
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
