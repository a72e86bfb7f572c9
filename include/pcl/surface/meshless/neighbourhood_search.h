/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/search/search.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>

#include <vector>

namespace pcl {
namespace meshless {

namespace detail {

/** \brief The rows of the directed neighbourhoods N(v) as a search fills them, in
  * pipeline numbering; PointT-free, so that only the queries are a template. Not
  * part of the API: searchNeighbourhoods' machinery.
  *
  * Each thread fills its own rows (`filterRow`), then `pack` lays them out in order:
  * the result does not depend on the number of threads.
  */
class NeighbourRows
{
public:
  /** \param[in] cloud_size points in the search's input cloud
    * \param[in] cloud_indices point i of the pipeline is cloud_indices[i]
    * \param[in] options k or radius */
  NeighbourRows (std::size_t cloud_size, const pcl::Indices& cloud_indices,
                 const NeighbourhoodOptions& options);

  /** \brief Empty when the options and the indices are usable; else why not. */
  const std::string&
  problem () const
  {
    return problem_;
  }

  /** \brief How many results to ask for: one more than k or the cap, since the
    * query point is among them. */
  int
  queryCount () const
  {
    return query_count_;
  }
  /** \brief The radius search's cap on results (0 = all). */
  unsigned int
  radiusCap () const
  {
    return radius_cap_;
  }
  bool
  usesRadius () const
  {
    return options_.radius > 0.0;
  }

  /** \brief Row i from a search's results (cloud indices sorted by distance):
    * drops the query itself, points not reconstructed and those beyond the radius.
    * \return false if the row came out empty. Rows may be filled concurrently. */
  bool
  filterRow (std::size_t i, const pcl::Indices& found, const std::vector<float>& sqr_distances);

  /** \brief Threads for `requested` (0 = all cores); the library's OpenMP, so that
    * this header needs none. */
  static int
  threadCount (int requested);

  /** \brief The rows as one graph (consumes them). */
  Neighbourhoods
  pack (std::size_t num_empty);

private:
  NeighbourhoodOptions options_;
  std::vector<pcl::index_t> local_of_; // cloud index -> pipeline index, or -1
  std::size_t n_ = 0;
  int query_count_ = 0;
  unsigned int radius_cap_ = 0;
  // k nearest: rows share one array of this stride (a vector per point cost two
  // million allocations on a million points); ball neighbourhoods and a very large
  // k keep a vector per row.
  std::size_t stride_ = 0;
  std::vector<pcl::index_t> flat_rows_;
  std::vector<pcl::index_t> flat_size_;
  std::vector<pcl::Indices> rows_;
  std::string problem_;
};

} // namespace detail

/** \brief Query N(v) for every point through PCL's search interface.
  *
  * \param[in] search a search object whose input cloud is the cloud that
  *            `cloud_indices` index (as `MeshConstruction::tree_` after
  *            `reconstruct` has set it up)
  * \param[in] cloud_indices the points to reconstruct, as indices into the search's
  *            input cloud; point i of the pipeline is `cloud_indices[i]`
  * \param[in] options k or radius, and the threads for the queries
  * \return neighbourhoods in pipeline numbering (0 .. cloud_indices.size()-1);
  *         results that are not among cloud_indices are dropped.
  * \pre the search's input cloud is set and contains every index in cloud_indices
  */
template <typename PointT>
Neighbourhoods
searchNeighbourhoods (const pcl::search::Search<PointT>& search,
                      const pcl::Indices& cloud_indices,
                      const NeighbourhoodOptions& options)
{
  const auto cloud = search.getInputCloud ();
  if (!cloud) {
    Neighbourhoods result;
    result.message = "the search object has no input cloud";
    return result;
  }
  detail::NeighbourRows rows (cloud->size (), cloud_indices, options);
  if (!rows.problem ().empty ()) {
    Neighbourhoods result;
    result.message = rows.problem ();
    return result;
  }
  // Queries in parallel, as in pcl::NormalEstimationOMP: a built search structure
  // answers concurrent const queries.
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t> (cloud_indices.size ());
  const int threads = detail::NeighbourRows::threadCount (options.num_threads);
  std::size_t num_empty = 0;
#pragma omp parallel num_threads(threads) reduction(+ : num_empty)
  {
    pcl::Indices found;
    std::vector<float> sqr_distances;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const auto& query = (*cloud)[cloud_indices[i]];
      if (rows.usesRadius ())
        search.radiusSearch (query, options.radius, found, sqr_distances, rows.radiusCap ());
      else
        search.nearestKSearch (query, rows.queryCount (), found, sqr_distances);
      if (!rows.filterRow (static_cast<std::size_t> (i), found, sqr_distances))
        ++num_empty;
    }
  }
  return rows.pack (num_empty);
}

} // namespace meshless
} // namespace pcl
