/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <cstdint>

namespace pcl {
namespace meshless {

/** \brief Shapes the project samples itself: the default input of the demo, test
  * fixtures and benchmark clouds of any size. */
enum class SyntheticShape
{
  Sphere,      ///< unit sphere (genus 0)
  Ellipsoid,   ///< semi-axes 1 : 1 : 6 (genus 0, elongated)
  BumpySphere, ///< sphere with smooth bumps, radius 0.75 .. 1.25 (genus 0)
  Torus,       ///< radii 1 and 0.35 (genus 1: not sphere-like)
  Disc,        ///< flat unit disc in the z = 0 plane (open, one boundary loop)
  HeightField  ///< graph of a smooth bump over the unit disc (open, one loop)
};

struct SyntheticCloudOptions
{
  /** \brief Number of points. Default 10000. */
  std::size_t num_points = 10000;
  /** \brief Seed of the pseudo-random generator: same seed, same cloud. */
  std::uint32_t seed = 1;
  /** \brief Gaussian noise added to every coordinate, as a fraction of the shape's
    * bounding-box diagonal. Default 0. */
  double noise = 0.0;
};

/** \brief Points sampled on a shape, close to uniformly per area (a jittered
  * Fibonacci lattice on closed shapes, a jittered sunflower on discs), so that the
  * spacing is even without being a regular grid. */
Points3
sampleShape (SyntheticShape shape, const SyntheticCloudOptions& options = {});

/** \brief Parse "sphere", "ellipsoid", "bumpy_sphere", "torus", "disc",
  * "height_field". \return false if the name is unknown. */
bool
parseSyntheticShape (const std::string& name, SyntheticShape& shape);

} // namespace meshless
} // namespace pcl
