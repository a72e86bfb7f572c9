/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

namespace pcl {
namespace meshless {

/** \brief pi rounded to the nearest double (std::numbers::pi is C++20). */
constexpr double pi = 3.14159265358979323846;
/** \brief 2 pi; doubling is exact, so this is also 2 pi rounded to the nearest double. */
constexpr double two_pi = 2.0 * pi;

} // namespace meshless
} // namespace pcl
