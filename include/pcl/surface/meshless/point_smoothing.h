/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

/** \file
  * Points moved onto a surface fitted to their neighbours (moving least squares,
  * PCL's MLSResult): for noise about as large as the point spacing, where the
  * neighbours' order around a point, and the cuts between the patches, are no
  * longer those of a surface.
  */
namespace pcl {
namespace meshless {

/** \brief How far a cloud lies off the surfaces fitted to it. */
struct PointNoise
{
  /** \brief The median over the points of the distance from a point to its
    * projection, over the median point spacing (mean distance to the six nearest).
    * Clean samples of smooth surfaces measure near 0; Gaussian noise of standard
    * deviation s about 0.67 s over the spacing. Measurements: doc/design.md. */
  double noise_ratio = 0.0;
  /** \brief Median and largest distance from a point to its projection. */
  double median_offset = 0.0;
  double max_offset = 0.0;
  double median_spacing = 0.0;
};

/** \brief Median offset from the fitted surfaces, over the point spacing, above
  * which PointSmoothing::IfNoisy moves a failed cloud's points: Gaussian noise of
  * about a fifth of the spacing. Coarse meshes' vertices and depth-camera scans can
  * measure above it too (doc/design.md); they are moved only where their own run
  * fails. */
constexpr double min_noise_ratio = 0.15;

/** \brief In disc mode, the noise ratio up to which PointSmoothing::IfNoisy moves a
  * failed cloud's points. Above it the sample's own gaps on the projections grow as
  * wide as holes and a hole's rim can be missed, so that the hole count would be
  * wrong; such a cloud is refused unless asked to smooth always. */
constexpr double max_disc_noise_ratio = 0.5;

/** \brief The points projected onto the quadratic surfaces fitted to their
  * neighbourhoods, and how far they moved. */
struct SmoothedPoints
{
  Points3 points;
  PointNoise noise;
};

/** \brief Projects every point onto the quadratic MLS surface fitted to it and its
  * neighbours (Gaussian weights over the farthest neighbour's distance). A point
  * keeps its position where fewer than six points fit, the fit fails, or its
  * projection would lie farther than its farthest neighbour.
  * \param[in] points the points
  * \param[in] neighbours each point's neighbours (wide enough to average the
  *            noise: a few dozen)
  * \param[in] num_threads threads (0 = all cores)
  */
SmoothedPoints
projectOntoFittedSurfaces (const Points3& points, const CsrGraph& neighbours,
                           int num_threads = 0);

} // namespace meshless
} // namespace pcl
