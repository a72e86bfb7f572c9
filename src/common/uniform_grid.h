/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

/** \file
  * The pieces every uniform grid over triangle boxes needs: where the cells lie, the
  * range of cells a box meets, and per-query visit stamps. The edge swaps' grid
  * (hashed buckets over the whole mesh, entries moved as swaps change boxes) and
  * the fold repair's (tables for the blocks near the folds only, entries never
  * removed) store their cells differently because they answer different queries.
  */

namespace pcl {
namespace meshless {

/** \brief A cell of a uniform grid in space: integer coordinates per axis. */
using GridCell = std::array<std::int64_t, 3>;

/** \brief The cells from `lo` to `hi` inclusive, on every axis. */
struct CellRange
{
  GridCell lo, hi;

  /** \brief Number of cells, as a double: a range clamped to 2^21 cells per axis
    * holds more than an int64 counts. */
  double
  count () const
  {
    double n = 1.0;
    for (int k = 0; k < 3; ++k)
      n *= static_cast<double> (hi[k] - lo[k] + 1);
    return n;
  }

  bool
  contains (const GridCell& c) const
  {
    for (int k = 0; k < 3; ++k)
      if (c[k] < lo[k] || hi[k] < c[k])
        return false;
    return true;
  }

  bool
  operator== (const CellRange& other) const
  {
    return lo == other.lo && hi == other.hi;
  }
};

/** \brief Calls visit (cell) for every cell of the range, z fastest. */
template <typename Visit>
void
forEachCell (const CellRange& range, Visit&& visit)
{
  for (std::int64_t x = range.lo[0]; x <= range.hi[0]; ++x)
    for (std::int64_t y = range.lo[1]; y <= range.hi[1]; ++y)
      for (std::int64_t z = range.lo[2]; z <= range.hi[2]; ++z)
        visit (GridCell{x, y, z});
}

/** \brief Where the cells of a uniform grid of cubes lie: cell c covers
  * [origin + c cell, origin + (c + 1) cell) on each axis.
  *
  * Coordinates are clamped to [first, last], so that the conversion to integers is
  * defined and cell counts stay finite; the mapping stays monotone, so boxes that
  * overlap still share a cell. The triangle grids of the edge swaps and of the fold
  * repair both index their triangles' bounding boxes through it.
  */
class GridFrame
{
public:
  GridFrame (const Eigen::Vector3d& origin, double cell, std::int64_t first, std::int64_t last)
    : origin_ (origin), inverse_cell_ (1.0 / cell), first_ (static_cast<double> (first)),
      last_ (static_cast<double> (last))
  {}

  /** \brief The cells the box [lo, hi] meets. */
  CellRange
  cellsOf (const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const
  {
    CellRange range;
    for (int k = 0; k < 3; ++k) {
      range.lo[k] = toCell (lo[k] - origin_[k]);
      range.hi[k] = toCell (hi[k] - origin_[k]);
    }
    return range;
  }

private:
  std::int64_t
  toCell (double offset) const
  {
    return static_cast<std::int64_t> (std::clamp (std::floor (offset * inverse_cell_), first_, last_));
  }

  Eigen::Vector3d origin_;
  double inverse_cell_;
  double first_, last_;
};

/** \brief Which triangle slots a grid query has reported already: a stamp per slot,
  * so that starting a query costs nothing (sorting or clearing a list of candidates
  * would). One per thread that queries. */
class VisitStamps
{
public:
  explicit VisitStamps (std::size_t slots) : stamp_of_ (slots, 0) {}

  /** \brief Starts a new query: every slot counts as not visited. */
  void
  startQuery ()
  {
    if (++stamp_ == 0) {
      std::fill (stamp_of_.begin (), stamp_of_.end (), 0);
      stamp_ = 1;
    }
  }

  /** \brief True the first time slot t is asked about in this query. */
  bool
  firstVisit (std::int32_t t)
  {
    if (stamp_of_[t] == stamp_)
      return false;
    stamp_of_[t] = stamp_;
    return true;
  }

private:
  std::vector<std::uint32_t> stamp_of_;
  std::uint32_t stamp_ = 0;
};

} // namespace meshless
} // namespace pcl
