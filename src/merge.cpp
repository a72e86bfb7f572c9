/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/merge.h>

#include "common/half_edges.h"

#include <algorithm>
#include <cstdint>

namespace pcl {
namespace meshless {

namespace {

std::uint64_t
edgeKey (pcl::index_t a, pcl::index_t b)
{
  const auto lo = static_cast<std::uint64_t> (std::min (a, b));
  const auto hi = static_cast<std::uint64_t> (std::max (a, b));
  return (lo << 32) | hi;
}

/** Triangles in the order of their smallest vertex (stable: ties keep the patches'
  * order). The points come in Z-order, so every later pass over the mesh (checks,
  * the swaps' intersection grid, the repair) then walks memory mostly in order. */
void
orderBySmallestVertex (Triangles& triangles, std::size_t n)
{
  // A counting sort: stable, and linear where std::stable_sort is not.
  const auto smallest = [] (const Triangle& t) { return std::min ({t[0], t[1], t[2]}); };
  std::vector<std::size_t> start (n + 1, 0);
  for (const Triangle& t : triangles)
    ++start[smallest (t) + 1];
  for (std::size_t v = 0; v < n; ++v)
    start[v + 1] += start[v];
  Triangles ordered (triangles.size ());
  for (const Triangle& t : triangles)
    ordered[start[smallest (t)]++] = t;
  triangles.swap (ordered);
}

/** The edges used by more than two triangles, as edgeKey sorted. */
std::vector<std::uint64_t>
overusedEdges (const Triangles& triangles, std::size_t n)
{
  // Grouped by smaller vertex: linear, where sorting every edge key is not.
  const HalfEdgeGroups groups = groupHalfEdges (triangles, n);
  std::vector<std::uint64_t> overused;
  forEachEdge (groups, [&] (std::size_t v, const HalfEdgeGroups::Entry* first,
                            const HalfEdgeGroups::Entry* last) {
    if (last - first > 2)
      overused.push_back (edgeKey (static_cast<pcl::index_t> (v), first->first));
  });
  return overused;
}

} // namespace

MergedTriangulation
mergePatches (const std::vector<Triangles>& patches, std::size_t n)
{
  MergedTriangulation result;
  std::vector<int> patch_of;
  for (std::size_t p = 0; p < patches.size (); ++p) {
    result.triangles.insert (result.triangles.end (), patches[p].begin (), patches[p].end ());
    patch_of.insert (patch_of.end (), patches[p].size (), static_cast<int> (p));
  }
  Triangles& tris = result.triangles;
  for (const Triangle& t : tris)
    for (const pcl::index_t v : t)
      if (v < 0 || static_cast<std::size_t> (v) >= n) {
        result.message = "a patch triangle names a point out of range";
        result.triangles.clear ();
        return result;
      }

  // Edges used by more than two triangles.
  const std::vector<std::uint64_t> overused = overusedEdges (tris, n);
  if (overused.empty ()) {
    orderBySmallestVertex (tris, n);
    result.success = true;
    return result;
  }

  // Triangles around each vertex, kept up to date through the flips.
  std::vector<std::vector<std::size_t>> around (n);
  for (std::size_t t = 0; t < tris.size (); ++t)
    for (int k = 0; k < 3; ++k)
      around[tris[t][k]].push_back (t);
  auto edgeExists = [&] (pcl::index_t a, pcl::index_t b) {
    for (std::size_t t : around[a])
      if (std::find (tris[t].begin (), tris[t].end (), b) != tris[t].end ())
        return true;
    return false;
  };
  auto replace = [&] (std::size_t t, const Triangle& next) {
    for (auto v : tris[t]) {
      auto& list = around[v];
      list.erase (std::find (list.begin (), list.end (), t));
    }
    tris[t] = next;
    for (auto v : next)
      around[v].push_back (t);
  };

  for (std::uint64_t key : overused) {
    const auto a = static_cast<pcl::index_t> (key >> 32);
    const auto b = static_cast<pcl::index_t> (key & 0xffffffffu);
    // Flip the chord in patches that hold it as an interior edge until at most
    // two triangles remain on it.
    bool progress = true;
    while (progress) {
      std::vector<std::size_t> on_edge;
      for (std::size_t t : around[a])
        if (std::find (tris[t].begin (), tris[t].end (), b) != tris[t].end ())
          on_edge.push_back (t);
      if (on_edge.size () <= 2)
        break;
      progress = false;
      for (std::size_t i = 0; i < on_edge.size () && !progress; ++i)
        for (std::size_t j = i + 1; j < on_edge.size () && !progress; ++j) {
          const std::size_t t1 = on_edge[i], t2 = on_edge[j];
          if (patch_of[t1] != patch_of[t2])
            continue;
          // Rotate so that t1 = (p, q, c) and t2 = (q, p, d) around the chord.
          Triangle x = tris[t1], y = tris[t2];
          while (!((x[0] == a && x[1] == b) || (x[0] == b && x[1] == a)))
            std::rotate (x.begin (), x.begin () + 1, x.end ());
          while (!(y[0] == x[1] && y[1] == x[0]))
            std::rotate (y.begin (), y.begin () + 1, y.end ());
          const pcl::index_t p = x[0], q = x[1], c = x[2], d = y[2];
          if (c == d || edgeExists (c, d))
            continue;
          // Flip the chord p-q of the quad p, d, q, c to c-d:
          //     c            c
          //    / \          /|\   .
          //   p---q   ->   p | q   (p, q, c), (q, p, d) -> (p, d, c), (d, q, c)
          //    \ /          \|/   .
          //     d            d
          replace (t1, {p, d, c});
          replace (t2, {d, q, c});
          ++result.num_repair_flips;
          progress = true;
        }
    }
  }
  for (std::uint64_t key : overused) {
    const auto a = static_cast<pcl::index_t> (key >> 32);
    const auto b = static_cast<pcl::index_t> (key & 0xffffffffu);
    std::size_t count = 0;
    for (std::size_t t : around[a])
      count += std::find (tris[t].begin (), tris[t].end (), b) != tris[t].end ();
    if (count > 2) {
      result.message = "two patches share a chord that no flip could remove";
      return result;
    }
  }
  orderBySmallestVertex (tris, n);
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
