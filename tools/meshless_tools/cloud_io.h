// Reading clouds and meshes, writing meshes, converting them to the pipeline's
// types: shared by the command-line tools.
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

/** The cloud's points as the pipeline's doubles. */
pcl::meshless::Points3
toPoints (const pcl::PointCloud<pcl::PointXYZ>& cloud);

/** The mesh's triangles (polygons with other than three corners are skipped). */
pcl::meshless::Triangles
toTriangles (const pcl::PolygonMesh& mesh);

/** printf of one number into a string (table cells). */
std::string
format (const char* pattern, double value);

} // namespace meshless_tools
