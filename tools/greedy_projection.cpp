#include <meshless_tools/greedy_projection.h>

#include "common/constants.h"

#include <pcl/common/io.h>
#include <pcl/features/normal_3d.h>
#include <pcl/surface/gp3.h>

#include <cmath>
#include <cstdio>

namespace meshless_tools {

namespace {


} // namespace

std::string
GreedyParameters::describe () const
{
  char line[512];
  std::snprintf (
      line, sizeof (line),
      "normals pcl::NormalEstimation k = %d; search radius %.4g (%.1f x mean "
      "spacing %.4g), mu %.1f, max %d neighbours, max surface angle %.0f deg, "
      "min angle %.0f deg, max angle %.0f deg, normal consistency off",
      normal_neighbours, radius, radius_in_spacings, spacing, mu, max_neighbours,
      max_surface_angle_deg, min_angle_deg, max_angle_deg);
  return line;
}

GreedyParameters
greedyParameters (const pcl::search::KdTree<pcl::PointXYZ>& tree,
                  const pcl::PointCloud<pcl::PointXYZ>& cloud)
{
  GreedyParameters parameters;
  pcl::Indices indices (2);
  std::vector<float> squared (2);
  double sum = 0.0;
  for (const auto& p : cloud) {
    // The first neighbour is the point itself.
    tree.nearestKSearch (p, 2, indices, squared);
    sum += std::sqrt (static_cast<double> (squared.back ()));
  }
  parameters.spacing = cloud.empty () ? 0.0 : sum / static_cast<double> (cloud.size ());
  parameters.radius = GreedyParameters::radius_in_spacings * parameters.spacing;
  return parameters;
}

void
greedyProjection (const pcl::PointCloud<pcl::PointXYZ>::ConstPtr& cloud,
                  const pcl::search::KdTree<pcl::PointXYZ>::Ptr& tree,
                  const GreedyParameters& parameters, pcl::PolygonMesh& mesh)
{
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  auto normals = pcl::make_shared<pcl::PointCloud<pcl::Normal>> ();
  estimation.setInputCloud (cloud);
  estimation.setSearchMethod (tree);
  estimation.setKSearch (GreedyParameters::normal_neighbours);
  estimation.compute (*normals);
  auto with_normals = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>> ();
  pcl::concatenateFields (*cloud, *normals, *with_normals);
  // Greedy projection searches PointNormal clouds: a tree over the same points.
  auto normal_tree = pcl::make_shared<pcl::search::KdTree<pcl::PointNormal>> ();
  normal_tree->setInputCloud (with_normals);
  pcl::GreedyProjectionTriangulation<pcl::PointNormal> gp3;
  gp3.setSearchRadius (parameters.radius);
  gp3.setMu (GreedyParameters::mu);
  gp3.setMaximumNearestNeighbors (GreedyParameters::max_neighbours);
  gp3.setMaximumSurfaceAngle (GreedyParameters::max_surface_angle_deg * pcl::meshless::pi / 180.0);
  gp3.setMinimumAngle (GreedyParameters::min_angle_deg * pcl::meshless::pi / 180.0);
  gp3.setMaximumAngle (GreedyParameters::max_angle_deg * pcl::meshless::pi / 180.0);
  gp3.setNormalConsistency (false);
  gp3.setInputCloud (with_normals);
  gp3.setSearchMethod (normal_tree);
  gp3.reconstruct (mesh);
}

} // namespace meshless_tools
