// PCL's GreedyProjectionTriangulation as its tutorial sets it up, with the radius
// scaled to the cloud: the baseline of pcl_surface_compare and the benchmark.
#pragma once

#include <pcl/PolygonMesh.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <string>

namespace meshless_tools {

struct GreedyParameters
{
  /** Mean distance from each point to its nearest other point. */
  double spacing = 0.0;
  /** Maximum edge length: radius_in_spacings * spacing. */
  double radius = 0.0;
  /** PCL's tutorial: radius 0.025 on its bunny (bun0.pcd, the shared bunny_pcl.pcd),
    * whose mean spacing is 0.00583, so 4.3 spacings. */
  static constexpr double radius_in_spacings = 4.3;
  static constexpr double mu = 2.5;
  static constexpr int max_neighbours = 100;
  static constexpr int normal_neighbours = 20;
  static constexpr double max_surface_angle_deg = 45.0;
  static constexpr double min_angle_deg = 10.0;
  static constexpr double max_angle_deg = 120.0;

  /** One line with every value, so that anyone can rerun them. */
  std::string
  describe () const;
};

/** Parameters for a cloud, from its mean spacing; tree searches the cloud. */
GreedyParameters
greedyParameters (const pcl::search::KdTree<pcl::PointXYZ>& tree,
                  const pcl::PointCloud<pcl::PointXYZ>& cloud);

/** Normals from pcl::NormalEstimation (k nearest through tree), then greedy projection.
  * The mesh's cloud holds the points with their normals. */
void
greedyProjection (const pcl::PointCloud<pcl::PointXYZ>::ConstPtr& cloud,
                  const pcl::search::KdTree<pcl::PointXYZ>::Ptr& tree,
                  const GreedyParameters& parameters,
                  pcl::PolygonMesh& mesh);

} // namespace meshless_tools
