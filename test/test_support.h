// Helpers shared by the tests: data location, brute-force references.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/types.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <map>
#include <set>
#include <utility>
#include <vector>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace meshless_test {

/** Directory of the shared clouds and meshes (../shared/data beside the checkout,
  * or $MESHLESS_DATA_DIR). */
inline std::string
sharedDataDir ()
{
  if (const char* env = std::getenv ("MESHLESS_DATA_DIR"))
    return env;
  return MESHLESS_SHARED_DATA_DIR;
}

/** Path of a shared file, or "" if it is missing. Under CI a missing file fails the
  * calling test instead of skipping it: CI must prove the data tests. */
inline std::string
sharedFile (const std::string& relative)
{
  const std::string path = sharedDataDir () + "/" + relative;
  if (std::filesystem::exists (path))
    return path;
  if (std::getenv ("CI"))
    ADD_FAILURE () << "shared data missing under CI: " << path;
  return "";
}

#define MESHLESS_REQUIRE_SHARED_FILE(var, relative)                                   \
  const std::string var = meshless_test::sharedFile (relative);                       \
  if (var.empty ())                                                                    \
  GTEST_SKIP () << "shared data not found: " << relative

/** The points as a PCL cloud (float coordinates). */
inline pcl::PointCloud<pcl::PointXYZ>::Ptr
toCloud (const pcl::meshless::Points3& points)
{
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (const auto& p : points)
    cloud->push_back (pcl::PointXYZ (static_cast<float> (p.x ()), static_cast<float> (p.y ()),
                                     static_cast<float> (p.z ())));
  return cloud;
}

/** Directed k nearest neighbourhoods by brute force, nearest first: what the
  * conductor gets from PCL's search, for stage tests that must not depend on it. */
inline pcl::meshless::CsrGraph
bruteForceKnn (const pcl::meshless::Points3& points, int k)
{
  pcl::meshless::CsrGraph directed;
  directed.offsets.push_back (0);
  std::vector<std::pair<double, pcl::index_t>> d;
  for (std::size_t v = 0; v < points.size (); ++v) {
    d.clear ();
    for (std::size_t w = 0; w < points.size (); ++w)
      if (w != v)
        d.emplace_back ((points[w] - points[v]).squaredNorm (), static_cast<pcl::index_t> (w));
    const std::size_t kk = std::min<std::size_t> (k, d.size ());
    std::partial_sort (d.begin (), d.begin () + kk, d.end ());
    for (std::size_t j = 0; j < kk; ++j)
      directed.adjacency.push_back (d[j].second);
    directed.offsets.push_back (static_cast<pcl::index_t> (directed.adjacency.size ()));
  }
  return directed;
}

/** The symmetric k-nearest-neighbour graph G by brute force. */
inline pcl::meshless::CsrGraph
bruteForceKnnGraph (const pcl::meshless::Points3& points, int k)
{
  return pcl::meshless::symmetricGraph (bruteForceKnn (points, k));
}

/** A triangle mesh for hand-built test cases. */
struct Mesh
{
  pcl::meshless::Points3 vertices;
  pcl::meshless::Triangles triangles;
};

/** Geodesic sphere: every icosahedron face cut into k^2 triangles, vertices pushed to
  * the unit sphere. 20 k^2 triangles, 10 k^2 + 2 vertices. Star-shaped around the
  * origin, hence free of self-intersections. */
inline Mesh
geodesicSphere (int k)
{
  const double g = (1.0 + std::sqrt (5.0)) / 2.0;
  Mesh m;
  m.vertices = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& v : m.vertices)
    v.normalize ();
  const std::vector<pcl::meshless::Triangle> faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10},
                                       {0, 10, 11}, {1, 5, 9},  {5, 11, 4}, {11, 10, 2},
                                       {10, 7, 6},  {7, 1, 8},  {3, 9, 4},  {3, 4, 2},
                                       {3, 2, 6},   {3, 6, 8},  {3, 8, 9},  {4, 9, 5},
                                       {2, 4, 11},  {6, 2, 10}, {8, 6, 7},  {9, 8, 1}};
  std::map<std::pair<int, int>, int> edge_start; // first id of an edge's inner points
  const auto edgePoint = [&] (int from, int to, int step) {
    const auto key = std::minmax (from, to);
    auto it = edge_start.find (key);
    if (it == edge_start.end ()) {
      it = edge_start.emplace (key, static_cast<int> (m.vertices.size ())).first;
      const Eigen::Vector3d a = m.vertices[key.first], b = m.vertices[key.second];
      for (int s = 1; s < k; ++s)
        m.vertices.push_back ((a + (b - a) * s / k).normalized ());
    }
    return it->second + (from < to ? step : k - step) - 1;
  };
  for (const pcl::meshless::Triangle& f : faces) {
    const Eigen::Vector3d a = m.vertices[f[0]], b = m.vertices[f[1]],
                          c = m.vertices[f[2]];
    EXPECT_GT (a.dot ((b - a).cross (c - a)), 0.0) << "icosahedron face not outward";
    std::vector<int> grid ((k + 1) * (k + 1));
    const auto at = [&grid, k] (int i, int j) -> int& { return grid[i * (k + 1) + j]; };
    for (int i = 0; i <= k; ++i)
      for (int j = 0; i + j <= k; ++j) {
        if (i == 0 && j == 0)
          at (i, j) = f[0];
        else if (i == k)
          at (i, j) = f[1];
        else if (j == k)
          at (i, j) = f[2];
        else if (j == 0)
          at (i, j) = edgePoint (f[0], f[1], i);
        else if (i == 0)
          at (i, j) = edgePoint (f[0], f[2], j);
        else if (i + j == k)
          at (i, j) = edgePoint (f[1], f[2], j);
        else {
          at (i, j) = static_cast<int> (m.vertices.size ());
          m.vertices.push_back ((a + (b - a) * i / k + (c - a) * j / k).normalized ());
        }
      }
    for (int i = 0; i < k; ++i)
      for (int j = 0; i + j < k; ++j) {
        m.triangles.push_back ({at (i, j), at (i + 1, j), at (i, j + 1)});
        if (i + j < k - 1)
          m.triangles.push_back ({at (i + 1, j), at (i + 1, j + 1), at (i, j + 1)});
      }
  }
  return m;
}

/** An undirected edge as (smaller, larger) vertex. */
using Edge = std::pair<pcl::index_t, pcl::index_t>;

/** Undirected edge -> number of triangles using it. */
inline std::map<Edge, int>
edgeUse (const pcl::meshless::Triangles& triangles)
{
  std::map<Edge, int> use;
  for (const auto& t : triangles)
    for (int i = 0; i < 3; ++i)
      ++use[std::minmax (t[i], t[(i + 1) % 3])];
  return use;
}

/** The edges in one triangle only. */
inline std::set<Edge>
boundaryEdges (const pcl::meshless::Triangles& triangles)
{
  std::set<Edge> boundary;
  for (const auto& [edge, count] : edgeUse (triangles))
    if (count == 1)
      boundary.insert (edge);
  return boundary;
}

} // namespace meshless_test
