/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/neighbourhood_search.h>

#include "common/threads.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pcl {
namespace meshless {
namespace detail {

NeighbourRows::NeighbourRows (std::size_t cloud_size, const pcl::Indices& cloud_indices,
                              const NeighbourhoodOptions& options)
: options_ (options), n_ (cloud_indices.size ())
{
  const bool use_radius = options.radius > 0.0;
  if (!use_radius && options.k < 1) {
    problem_ = "the number of neighbours k must be at least 1";
    return;
  }
  if (!(options.radius >= 0.0) || !std::isfinite (options.radius)) {
    problem_ = "the search radius must be finite and not negative";
    return;
  }
  local_of_.assign (cloud_size, -1);
  for (std::size_t i = 0; i < n_; ++i) {
    const auto c = cloud_indices[i];
    if (c < 0 || static_cast<std::size_t> (c) >= cloud_size) {
      problem_ = "a point index lies outside the input cloud";
      return;
    }
    local_of_[c] = static_cast<pcl::index_t> (i);
  }
  // Counted in a wider type (k = INT_MAX would overflow an int) and bounded by the
  // cloud, more than which no search returns.
  const auto plus_self = [&] (int count) {
    return static_cast<int> (std::min<std::int64_t> ({std::int64_t{count} + 1,
                                                      static_cast<std::int64_t> (cloud_size),
                                                      std::numeric_limits<int>::max ()}));
  };
  query_count_ = plus_self (options.k);
  radius_cap_ = options.max_neighbours > 0
                    ? static_cast<unsigned int> (plus_self (options.max_neighbours))
                    : 0u;
  // A row holds at most min(k, query count) entries.
  stride_ = use_radius ? 0
                       : std::min (static_cast<std::size_t> (options.k),
                                   static_cast<std::size_t> (query_count_));
  if (stride_ > 256)
    stride_ = 0;
  if (stride_ > 0) {
    flat_rows_.resize (n_ * stride_);
    flat_size_.resize (n_);
  }
  else
    rows_.resize (n_);
}

int
NeighbourRows::threadCount (int requested)
{
  return meshless::threadCount (requested);
}

bool
NeighbourRows::filterRow (std::size_t i, const pcl::Indices& found,
                          const std::vector<float>& sqr_distances)
{
  // PCL returns the results sorted by distance (sorted_results_ is true for the
  // searches PCL builds); the query itself and exact duplicates come first.
  const bool use_radius = usesRadius ();
  const std::size_t limit =
      use_radius ? (options_.max_neighbours > 0 ? static_cast<std::size_t> (options_.max_neighbours)
                                                : found.size ())
                 : static_cast<std::size_t> (options_.k);
  std::size_t size = 0;
  for (std::size_t j = 0; j < found.size () && size < limit; ++j) {
    const auto w = local_of_[found[j]];
    if (w < 0 || static_cast<std::size_t> (w) == i)
      continue;
    if (use_radius && !(sqr_distances[j] < options_.radius * options_.radius))
      continue;
    if (stride_ > 0)
      flat_rows_[i * stride_ + size] = w;
    else
      rows_[i].push_back (w);
    ++size;
  }
  if (stride_ > 0)
    flat_size_[i] = static_cast<pcl::index_t> (size);
  return size > 0;
}

Neighbourhoods
NeighbourRows::pack (std::size_t num_empty)
{
  Neighbourhoods result;
  result.num_empty = num_empty;
  const bool flat = stride_ > 0;
  CsrGraph& g = result.neighbours;
  g.offsets.assign (n_ + 1, 0);
  for (std::size_t i = 0; i < n_; ++i)
    g.offsets[i + 1] =
        g.offsets[i] + (flat ? flat_size_[i] : static_cast<pcl::index_t> (rows_[i].size ()));
  if (flat) {
    // In place, front to back: row i moves to offsets[i] <= i * stride.
    g.adjacency = std::move (flat_rows_);
    for (std::size_t i = 0; i < n_; ++i) {
      const auto from = g.adjacency.begin () + static_cast<std::ptrdiff_t> (i * stride_);
      const auto to = g.adjacency.begin () + g.offsets[i];
      if (to != from)
        std::copy (from, from + flat_size_[i], to);
    }
    g.adjacency.resize (static_cast<std::size_t> (g.offsets[n_]));
  }
  else {
    g.adjacency.resize (static_cast<std::size_t> (g.offsets[n_]));
    for (std::size_t i = 0; i < n_; ++i) {
      std::copy (rows_[i].begin (), rows_[i].end (), g.adjacency.begin () + g.offsets[i]);
      pcl::Indices ().swap (rows_[i]);
    }
  }
  std::vector<pcl::index_t> ().swap (flat_size_);
  std::vector<pcl::index_t> ().swap (local_of_);
  result.success = true;
  return result;
}

} // namespace detail
} // namespace meshless
} // namespace pcl
