/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/search/search.h>
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

/** \brief Query N(v) for every point through PCL's search interface.
  *
  * \param[in] search a search object whose input cloud is the cloud that
  *            `cloud_indices` index (as `MeshConstruction::tree_` after
  *            `reconstruct` has set it up)
  * \param[in] cloud_indices the points to reconstruct, as indices into the search's
  *            input cloud; point i of the pipeline is `cloud_indices[i]`
  * \param[in] options k or radius
  * \return neighbourhoods in pipeline numbering (0 .. cloud_indices.size()-1);
  *         results that are not among cloud_indices are dropped.
  * \pre the search's input cloud is set and contains every index in cloud_indices
  */
template <typename PointT>
Neighbourhoods
searchNeighbourhoods (const pcl::search::Search<PointT>& search,
                      const pcl::Indices& cloud_indices,
                      const NeighbourhoodOptions& options);

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

// ---------------------------------------------------------------------------

template <typename PointT>
Neighbourhoods
searchNeighbourhoods (const pcl::search::Search<PointT>& search,
                      const pcl::Indices& cloud_indices,
                      const NeighbourhoodOptions& options)
{
  Neighbourhoods result;
  const auto cloud = search.getInputCloud ();
  if (!cloud) {
    result.message = "the search object has no input cloud";
    return result;
  }
  const bool use_radius = options.radius > 0.0;
  if (!use_radius && options.k < 1) {
    result.message = "the number of neighbours k must be at least 1";
    return result;
  }
  if (!(options.radius >= 0.0) || !std::isfinite (options.radius)) {
    result.message = "the search radius must be finite and not negative";
    return result;
  }

  // Search results are cloud indices; the pipeline numbers its points 0..n-1.
  std::vector<pcl::index_t> local_of (cloud->size (), -1);
  for (std::size_t i = 0; i < cloud_indices.size (); ++i) {
    const auto c = cloud_indices[i];
    if (c < 0 || static_cast<std::size_t> (c) >= cloud->size ()) {
      result.message = "a point index lies outside the input cloud";
      return result;
    }
    local_of[c] = static_cast<pcl::index_t> (i);
  }

  // Queries run in parallel, as in pcl::NormalEstimationOMP (a built search
  // structure answers concurrent const queries); each point's row is filtered
  // into its own slot, then the rows are packed in order, so the result does not
  // depend on the number of threads.
  const std::size_t n = cloud_indices.size ();
  // Ask for one more than k or the cap: the query point itself is among the results.
  // Counted in a wider type (k = INT_MAX overflowed an int) and bounded by the
  // cloud, more than which no search returns.
  const auto plus_self = [&] (int count) {
    return static_cast<int> (std::min<std::int64_t> (
        {std::int64_t{count} + 1, static_cast<std::int64_t> (cloud->size ()),
         std::numeric_limits<int>::max ()}));
  };
  const int knn = plus_self (options.k);
  const unsigned int cap =
      options.max_neighbours > 0 ? static_cast<unsigned int> (plus_self (options.max_neighbours))
                                 : 0u;
  // k nearest: a row holds at most min(k, knn) entries, so the rows share one array
  // with that stride and are packed in place afterwards (a vector per point cost
  // two million allocations and 80 MB on a million points). Ball neighbourhoods
  // and very large k keep a vector per row.
  const std::size_t stride =
      use_radius ? 0 : std::min (static_cast<std::size_t> (options.k), static_cast<std::size_t> (knn));
  const bool flat = stride > 0 && stride <= 256;
  std::vector<pcl::index_t> flat_rows (flat ? n * stride : 0);
  std::vector<pcl::index_t> flat_size (flat ? n : 0);
  std::vector<pcl::Indices> rows (flat ? 0 : n);
  std::size_t num_empty = 0;
#pragma omp parallel reduction(+ : num_empty)
  {
    pcl::Indices found;
    std::vector<float> sqr_distances;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t si = 0; si < static_cast<std::ptrdiff_t> (n); ++si) {
      const auto i = static_cast<std::size_t> (si);
      const auto query = cloud_indices[i];
      if (use_radius)
        search.radiusSearch ((*cloud)[query], options.radius, found, sqr_distances, cap);
      else
        search.nearestKSearch ((*cloud)[query], knn, found, sqr_distances);
      // PCL returns the results sorted by distance (sorted_results_ is true for the
      // searches PCL builds). The query itself and exact duplicates come first.
      const std::size_t limit =
          use_radius ? (options.max_neighbours > 0 ? static_cast<std::size_t> (options.max_neighbours)
                                                   : found.size ())
                     : static_cast<std::size_t> (options.k);
      std::size_t size = 0;
      for (std::size_t j = 0; j < found.size () && size < limit; ++j) {
        const auto w = local_of[found[j]];
        if (w < 0 || static_cast<std::size_t> (w) == i)
          continue;
        if (use_radius && !(sqr_distances[j] < options.radius * options.radius))
          continue;
        if (flat)
          flat_rows[i * stride + size] = w;
        else
          rows[i].push_back (w);
        ++size;
      }
      if (flat)
        flat_size[i] = static_cast<pcl::index_t> (size);
      if (size == 0)
        ++num_empty;
    }
  }
  result.num_empty = num_empty;

  CsrGraph& g = result.neighbours;
  g.offsets.assign (n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    g.offsets[i + 1] =
        g.offsets[i] + (flat ? flat_size[i] : static_cast<pcl::index_t> (rows[i].size ()));
  if (flat) {
    // In place, front to back: row i moves to offsets[i] <= i * stride.
    g.adjacency = std::move (flat_rows);
    for (std::size_t i = 0; i < n; ++i) {
      const auto from = g.adjacency.begin () + static_cast<std::ptrdiff_t> (i * stride);
      const auto to = g.adjacency.begin () + g.offsets[i];
      if (to != from)
        std::copy (from, from + flat_size[i], to);
    }
    g.adjacency.resize (static_cast<std::size_t> (g.offsets[n]));
  }
  else {
    g.adjacency.resize (static_cast<std::size_t> (g.offsets[n]));
    for (std::size_t i = 0; i < n; ++i) {
      std::copy (rows[i].begin (), rows[i].end (), g.adjacency.begin () + g.offsets[i]);
      pcl::Indices ().swap (rows[i]);
    }
  }
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
