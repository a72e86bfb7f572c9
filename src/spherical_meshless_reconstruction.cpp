/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/impl/instantiate.hpp>
#include <pcl/point_types.h>
#include <pcl/surface/impl/spherical_meshless_reconstruction.hpp>
#include <pcl/surface/spherical_meshless_reconstruction.h>

// Point types with x, y, z; others through PCL_NO_PRECOMPILE.
PCL_INSTANTIATE (SphericalMeshlessReconstruction,
                 (pcl::PointXYZ)(pcl::PointXYZI)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)(
                     pcl::PointNormal)(pcl::PointXYZRGBNormal)(pcl::PointXYZINormal))
