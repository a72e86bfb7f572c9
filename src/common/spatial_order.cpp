/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "spatial_order.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace pcl {
namespace meshless {

namespace {

/** The 21 low bits of x spread to every third bit of a 63-bit word. */
std::uint64_t
spreadBits (std::uint64_t x)
{
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

} // namespace

std::uint64_t
mortonKey (std::uint64_t x, std::uint64_t y, std::uint64_t z)
{
  return spreadBits (x) | spreadBits (y) << 1 | spreadBits (z) << 2;
}

std::vector<pcl::index_t>
mortonOrder (const Points3& points)
{
  const std::size_t n = points.size ();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant (std::numeric_limits<double>::infinity ());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : points)
    if (p.allFinite ()) {
      lo = lo.cwiseMin (p);
      hi = hi.cwiseMax (p);
    }
  const double extent = (hi - lo).maxCoeff ();
  constexpr double cells = 2097151.0; // 2^21 - 1
  const double scale = extent > 0.0 && std::isfinite (extent) ? cells / extent : 0.0;
  const auto cell = [&] (double value, double low) -> std::uint64_t {
    const double c = (value - low) * scale;
    // Written so that NaN lands in cell 0 too.
    return c > 0.0 ? static_cast<std::uint64_t> (std::min (c, cells)) : 0u;
  };
  std::vector<std::pair<std::uint64_t, pcl::index_t>> keyed (n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = points[i];
    keyed[i] = {mortonKey (cell (p.x (), lo.x ()), cell (p.y (), lo.y ()), cell (p.z (), lo.z ())),
                static_cast<pcl::index_t> (i)};
  }
  std::sort (keyed.begin (), keyed.end ()); // ties by index: input order kept
  std::vector<pcl::index_t> order (n);
  for (std::size_t k = 0; k < n; ++k)
    order[k] = keyed[k].second;
  return order;
}

} // namespace meshless
} // namespace pcl
