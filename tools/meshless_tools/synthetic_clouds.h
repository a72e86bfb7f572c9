/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <cstdint>
#include <string>

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
  HeightField, ///< graph of a smooth bump over the unit disc (open, one loop)
  ThinTorus,   ///< radii 1 and 0.15 (genus 1, a thin handle)
  FatTorus,    ///< radii 1 and 0.6 (genus 1, a small hole)
  /** Genus 2: the zero set of g(x, y)^2 + z^2 - 0.1^2 with
    * g = (x^2 + y^2)^2 - x^2 + y^2, a tube around the lemniscate whose two lobes leave
    * two holes; about 2.1 x 0.7 x 0.2. */
  DoubleTorus,
  /** Genus 1: a tube of radius 0.3 around the (2, 3) torus knot (a trefoil)
    * c(t) = ((2 + cos 3t) cos 2t, (2 + cos 3t) sin 2t, sin 3t), t in [0, 2 pi). */
  KnottedTube,
  /** Genus 0 with thin parts, like an animal's legs: a ball of radius 0.5 and three
    * rods of radius 0.05 through it along the axes, ends at +-1.5, their joins
    * rounded (a smooth union of their distance functions). */
  ThinLimbs
};

/** \brief Genus of a closed shape (0 for the sphere-like ones), -1 for the open
  * ones (Disc, HeightField). */
int
syntheticGenus (SyntheticShape shape);

struct SyntheticCloudOptions
{
  /** \brief Number of points. Default 10000. */
  std::size_t num_points = 10000;
  /** \brief Seed of the pseudo-random generator: same seed, same cloud. */
  std::uint32_t seed = 1;
  /** \brief Gaussian noise added to every coordinate, as a fraction of the shape's
    * bounding-box diagonal. Default 0. */
  double noise = 0.0;
  /** \brief Ratio of the densest to the sparsest part of the cloud: the density grows
    * smoothly along the shape's longest bounding-box axis (the first
    * of those within 1% of the longest), as
    * 1 + (uneven - 1) (1 - cos (pi s)) / 2 for s from 0 to 1 along it. 0 or 1:
    * uniform. */
  double uneven = 0.0;
  /** \brief Points per cluster: the cloud comes in small dense clusters around an
    * even sample of the shape, the gaps between them wider than a cluster (like the
    * vertices of a mesh whose long thin triangles join small dense groups), so that
    * a point's nearest neighbours, fewer than a cluster, mostly stay in it. The
    * count is rounded down to whole clusters. Quadratic in the points: for clouds
    * of some thousands. 0: no clusters. Ignored with `uneven`. */
  std::size_t cluster_size = 0;
  /** \brief The open shapes (Disc, HeightField) on a regular square grid, turned
    * and shifted by the seed, its spacing giving about num_points inside the unit
    * disc: ties in every neighbour order, and a staircase outline of collinear
    * points (like a depth image's or a pixel mask's). Ignored for the closed shapes
    * and with `uneven` or `cluster_size`. Default false. */
  bool lattice = false;
  /** \brief Round holes cut out of the open shapes (Disc, HeightField), up to 5:
    * radius 0.15 of the unit disc, centres placed by the seed inside radius 0.65
    * and at least three radii apart; the points inside are dropped, so fewer than
    * num_points remain. Ignored for the closed shapes. Default 0. */
  std::size_t holes = 0;
  /** \brief Points in rows across the shape's longest bounding-box axis (the first
    * of those within 1% of the longest), this many times the spacing along a row
    * apart: like the vertices of a mesh whose triangles are long one way (rings
    * around a limb spaced apart along it); where the surface turns across the axis
    * the gaps between the rows are filled. Ignored with `uneven` or
    * `cluster_size`, and on the open shapes with `lattice`; at most 1, or not
    * finite: even spacing. */
  double stretch = 0.0;
};

/** \brief Points sampled on a shape, close to uniformly per area (a jittered
  * Fibonacci lattice on the sphere-like shapes and the torus, a jittered sunflower on
  * discs; on the other shapes five times as many random points, uniform per area, of
  * which the most crowded are removed one at a time), so that the spacing is even
  * without being a regular grid. With options.uneven > 1, a random subset of a larger
  * uniform cloud, kept with probability proportional to the density asked for; with
  * options.stretch > 1, in rows. */
Points3
sampleShape (SyntheticShape shape, const SyntheticCloudOptions& options = {});

/** \brief Parse "sphere", "ellipsoid", "bumpy_sphere", "torus", "disc",
  * "height_field", "thin_torus", "fat_torus", "double_torus", "knotted_tube", "thin_limbs".
  * \return false if the name is unknown. */
bool
parseSyntheticShape (const std::string& name, SyntheticShape& shape);

} // namespace meshless
} // namespace pcl
