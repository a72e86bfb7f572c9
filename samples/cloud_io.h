// Reading clouds and meshes, writing meshes: shared by the command-line tools.
#pragma once

#include <pcl/PolygonMesh.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/meshless/types.h>

#include <string>

namespace meshless_tools {

bool
endsWith (const std::string& s, const std::string& suffix);

/** Loads a .pcd, .ply (float or double coordinates) or .xyz (x y z per line) cloud.
  * \return an empty string, or the reason it failed */
std::string
loadCloud (const std::string& path, pcl::PointCloud<pcl::PointXYZ>& cloud);

/** Loads a PLY mesh (float or double coordinates); polygons with more than three
  * corners are split into fans. \return an empty string, or the reason it failed */
std::string
loadMesh (const std::string& path,
          pcl::meshless::Points3& vertices,
          pcl::meshless::Triangles& triangles);

/** Saves by extension: .ply (binary), .vtk or .obj.
  * \return an empty string, or the reason it failed */
std::string
saveMesh (const std::string& path, const pcl::PolygonMesh& mesh);

} // namespace meshless_tools
