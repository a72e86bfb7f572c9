/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief How the unordered neighbourhood N(v) of a point is chosen (paper §2). */
struct NeighbourhoodOptions
{
  /** \brief Number of nearest neighbours k (the paper: about 10-12). Used when
    * radius is 0. Default 12. */
  int k = 12;
  /** \brief Ball radius r: N(v) = { w : 0 < |v - w| < r }. 0 (default) selects the
    * k-nearest-neighbour variant. Same units as the cloud. */
  double radius = 0.0;
  /** \brief With a radius: keep at most this many neighbours, the nearest ones
    * (0 = all). Default 0. */
  int max_neighbours = 0;
  /** \brief Threads for the queries (0 = all cores). Default 0. */
  int num_threads = 0;
};

/** \brief Directed neighbourhoods N(v): row v lists the neighbours of v, nearest
  * first, never v itself. */
struct Neighbourhoods : StageStatus
{
  CsrGraph neighbours;
  /** \brief Points whose neighbourhood came out empty (isolated points). */
  std::size_t num_empty = 0;
};

/** \brief The connectivity graph G of the paper: E = { [v,w] : w in N(v) or v in
  * N(w) }, stored symmetrically (each edge in both rows), rows sorted ascending,
  * without self loops or repeated entries.
  * \param[in] neighbourhoods directed neighbourhoods of n vertices (entries must be
  *            in [0, n); self entries are dropped)
  * \param[in] num_threads threads for the row sorts (0 = all cores)
  */
CsrGraph
symmetricGraph (const CsrGraph& neighbourhoods, int num_threads = 0);

/** \brief The transposed (reversed) graph: w lists v for every entry w in row v.
  * Rows come out sorted ascending. */
CsrGraph
transposeGraph (const CsrGraph& graph);

/** \brief The same for a graph stored elsewhere in CSR form (a sparse matrix's
  * pattern, say): n rows, offsets[0..n], adjacency[offsets[0]..offsets[n]). */
CsrGraph
transposeGraph (std::size_t n, const pcl::index_t* offsets, const pcl::index_t* adjacency);

/** \brief Number of connected components of a symmetric graph, and each vertex's
  * component label (0-based, in order of the smallest vertex of each component). */
std::size_t
connectedComponents (const CsrGraph& graph, std::vector<pcl::index_t>& labels);

/** \brief How the edges of a wider neighbourhood graph join the pieces of a narrower
  * one: the fraction of its edges between two pieces that run along the surface,
  * within 45 degrees of the planes the narrower rows span at both ends (1 if no edge
  * joins pieces). Pieces of one surface sampled in dense groups join along it; two
  * objects that nearly touch join across their surfaces.
  * \param[in] rows the narrower (directed) neighbourhoods
  * \param[in] labels their symmetric graph's component of every point
  * \param[in] wider the wider (directed) neighbourhoods
  * \return 0 if the sizes of the graphs and labels differ from the points' */
double
joinsAlongTheSurface (const Points3& points,
                      const CsrGraph& rows,
                      const std::vector<pcl::index_t>& labels,
                      const CsrGraph& wider);

} // namespace meshless
} // namespace pcl
