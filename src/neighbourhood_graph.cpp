/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>

#include "common/threads.h"

#include <algorithm>
#include <cmath>

namespace pcl {
namespace meshless {

CsrGraph
symmetricGraph (const CsrGraph& neighbourhoods, int num_threads)
{
  const std::size_t n = neighbourhoods.size ();
  CsrGraph graph;
  if (n == 0)
    return graph;

  // Count each directed entry once in each direction, then fill both rows; sorting
  // and de-duplicating every row afterwards merges [v,w] given by both N(v) and N(w).
  std::vector<pcl::index_t> count (n + 1, 0);
  for (std::size_t v = 0; v < n; ++v)
    for (const pcl::index_t* w = neighbourhoods.begin (v); w != neighbourhoods.end (v); ++w)
      if (static_cast<std::size_t> (*w) != v) {
        ++count[v + 1];
        ++count[*w + 1];
      }
  for (std::size_t v = 0; v < n; ++v)
    count[v + 1] += count[v];

  std::vector<pcl::index_t> filled (count.begin (), count.end () - 1);
  std::vector<pcl::index_t> entries (count[n]);
  for (std::size_t v = 0; v < n; ++v)
    for (const pcl::index_t* w = neighbourhoods.begin (v); w != neighbourhoods.end (v); ++w)
      if (static_cast<std::size_t> (*w) != v) {
        entries[filled[v]++] = *w;
        entries[filled[*w]++] = static_cast<pcl::index_t> (v);
      }

  // Rows sorted and de-duplicated in place in parallel (they are independent, and
  // serial sorts are most of this function's time on large clouds), then packed.
  graph.offsets.assign (n + 1, 0);
  const auto rows = static_cast<std::ptrdiff_t> (n);
  const int threads = threadCount (num_threads);
#pragma omp parallel for schedule(static, 4096) num_threads(threads) if (rows >= 50000)
  for (std::ptrdiff_t v = 0; v < rows; ++v) {
    const auto first = entries.begin () + count[v];
    const auto last = entries.begin () + count[v + 1];
    std::sort (first, last);
    graph.offsets[v + 1] = static_cast<pcl::index_t> (std::unique (first, last) - first);
  }
  for (std::size_t v = 0; v < n; ++v)
    graph.offsets[v + 1] += graph.offsets[v];
  graph.adjacency.resize (static_cast<std::size_t> (graph.offsets[n]));
#pragma omp parallel for schedule(static, 4096) num_threads(threads) if (rows >= 50000)
  for (std::ptrdiff_t v = 0; v < rows; ++v)
    std::copy_n (entries.begin () + count[v], graph.offsets[v + 1] - graph.offsets[v],
                 graph.adjacency.begin () + graph.offsets[v]);
  return graph;
}

CsrGraph
transposeGraph (const CsrGraph& graph)
{
  return transposeGraph (graph.size (), graph.offsets.data (), graph.adjacency.data ());
}

CsrGraph
transposeGraph (std::size_t n, const pcl::index_t* offsets, const pcl::index_t* adjacency)
{
  CsrGraph transposed;
  transposed.offsets.assign (n + 1, 0);
  if (n == 0)
    return transposed;
  for (auto k = offsets[0]; k < offsets[n]; ++k)
    ++transposed.offsets[adjacency[k] + 1];
  for (std::size_t v = 0; v < n; ++v)
    transposed.offsets[v + 1] += transposed.offsets[v];
  transposed.adjacency.resize (static_cast<std::size_t> (offsets[n] - offsets[0]));
  std::vector<pcl::index_t> filled (transposed.offsets.begin (), transposed.offsets.end () - 1);
  for (std::size_t v = 0; v < n; ++v)
    for (auto k = offsets[v]; k < offsets[v + 1]; ++k)
      transposed.adjacency[filled[adjacency[k]]++] = static_cast<pcl::index_t> (v);
  return transposed;
}

std::size_t
connectedComponents (const CsrGraph& graph, std::vector<pcl::index_t>& labels)
{
  const std::size_t n = graph.size ();
  labels.assign (n, -1);
  std::vector<pcl::index_t> stack;
  pcl::index_t next_label = 0;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (labels[seed] >= 0)
      continue;
    labels[seed] = next_label;
    stack.push_back (static_cast<pcl::index_t> (seed));
    while (!stack.empty ()) {
      const pcl::index_t v = stack.back ();
      stack.pop_back ();
      for (const pcl::index_t* w = graph.begin (v); w != graph.end (v); ++w)
        if (labels[*w] < 0) {
          labels[*w] = next_label;
          stack.push_back (*w);
        }
    }
    ++next_label;
  }
  return static_cast<std::size_t> (next_label);
}

double
joinsAlongTheSurface (const Points3& points,
                      const CsrGraph& rows,
                      const std::vector<pcl::index_t>& labels,
                      const CsrGraph& wider)
{
  const std::size_t n = points.size ();
  if (rows.size () != n || labels.size () != n || wider.size () != n)
    return 0.0;
  // Each end's plane is fitted once, on the first join that reaches it.
  std::vector<Eigen::Vector3d> normal (n);
  std::vector<char> fitted (n, 0);
  const double sin_45 = std::sqrt (0.5);
  const auto along = [&] (pcl::index_t v, const Eigen::Vector3d& step) {
    if (!fitted[v]) {
      normal[v] = leastSquaresNormal (points, v, rows.begin (v), rows.end (v), true);
      fitted[v] = 1;
    }
    return !normal[v].isZero () && std::abs (normal[v].dot (step)) <= sin_45;
  };
  std::size_t joins = 0, joins_along = 0;
  for (pcl::index_t v = 0; v < static_cast<pcl::index_t> (n); ++v)
    for (const pcl::index_t* w = wider.begin (v); w != wider.end (v); ++w) {
      if (labels[*w] == labels[v])
        continue;
      ++joins;
      const Eigen::Vector3d step = (points[*w] - points[v]).normalized ();
      joins_along += along (v, step) && along (*w, step);
    }
  return joins == 0 ? 1.0 : static_cast<double> (joins_along) / static_cast<double> (joins);
}

} // namespace meshless
} // namespace pcl
