/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief The half-edges of a triangle mesh grouped by the smaller vertex of their
  * edge: the one structure every stage that pairs half-edges builds on.
  *
  * Half-edge 3 t + j runs from corner j of triangle t to corner j + 1. Group v holds
  * (larger vertex, half-edge) for every half-edge whose edge's smaller vertex is v,
  * sorted, so that the half-edges of one edge are adjacent (by id) and the edges
  * come in the order of (smaller, larger) vertex.
  */
struct HalfEdgeGroups
{
  using Entry = std::pair<pcl::index_t, std::int32_t>;
  /** \brief Group v is ends[start[v]] .. ends[start[v + 1]] (n + 1 entries). */
  std::vector<std::uint32_t> start;
  std::vector<Entry> ends;
};

/** \brief Groups the half-edges of the triangles t with is_face (t) by the smaller
  * vertex of their edge, with a counting pass (linear, and a quarter of the memory
  * of sorting 64-bit edge keys with their half-edges).
  * \param[in] triangles vertex indices in [0, n) wherever is_face holds, fewer than
  *            2^31 / 3 triangles
  * \param[in] n number of vertices
  * \param[in] is_face is_face (t) for a triangle index t: whether its half-edges
  *            take part (the others may hold anything)
  */
template <typename IsFace>
HalfEdgeGroups
groupHalfEdges (const Triangles& triangles, std::size_t n, IsFace&& is_face)
{
  HalfEdgeGroups groups;
  groups.start.assign (n + 1, 0);
  for (std::size_t t = 0; t < triangles.size (); ++t)
    if (is_face (t))
      for (int j = 0; j < 3; ++j)
        ++groups.start[std::min (triangles[t][j], triangles[t][(j + 1) % 3]) + 1];
  for (std::size_t v = 0; v < n; ++v)
    groups.start[v + 1] += groups.start[v];
  groups.ends.resize (groups.start[n]);
  {
    std::vector<std::uint32_t> fill (groups.start.begin (), groups.start.end () - 1);
    for (std::size_t t = 0; t < triangles.size (); ++t)
      if (is_face (t))
        for (int j = 0; j < 3; ++j) {
          const pcl::index_t a = triangles[t][j], b = triangles[t][(j + 1) % 3];
          groups.ends[fill[std::min (a, b)]++] = {std::max (a, b),
                                                  static_cast<std::int32_t> (3 * t + j)};
        }
  }
  for (std::size_t v = 0; v < n; ++v)
    std::sort (groups.ends.begin () + groups.start[v], groups.ends.begin () + groups.start[v + 1]);
  return groups;
}

/** \brief The same for all triangles. */
HalfEdgeGroups
groupHalfEdges (const Triangles& triangles, std::size_t n);

/** \brief Calls edge (smaller, first, last) once per undirected edge, in the order of
  * (smaller, larger) vertex: [first, last) are the edge's entries, at least one. */
template <typename Edge>
void
forEachEdge (const HalfEdgeGroups& groups, Edge&& edge)
{
  const HalfEdgeGroups::Entry* const ends = groups.ends.data ();
  for (std::size_t v = 0; v + 1 < groups.start.size (); ++v) {
    const HalfEdgeGroups::Entry* const last = ends + groups.start[v + 1];
    for (const HalfEdgeGroups::Entry* i = ends + groups.start[v]; i != last;) {
      const HalfEdgeGroups::Entry* j = i + 1;
      while (j != last && j->first == i->first)
        ++j;
      edge (v, i, j);
      i = j;
    }
  }
}

/** \brief The twin of every half-edge: twin[h] is the lowest-numbered half-edge that
  * runs along h's edge the other way, -1 if there is none (a boundary edge). On a
  * manifold, consistently oriented mesh that is the edge's other half-edge.
  *
  * Four bytes per half-edge besides the result, where HalfEdgeGroups takes eight:
  * stages that run beside another's peak (the patch flips) use this one.
  * \param[in] triangles vertex indices in [0, n), fewer than 2^31 / 3 triangles
  * \param[in] n number of vertices
  */
std::vector<std::int32_t>
halfEdgeTwins (const Triangles& triangles, std::size_t n);

} // namespace meshless
} // namespace pcl
