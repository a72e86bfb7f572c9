// Helpers shared by the tests: data location, brute-force references.
#pragma once

#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/types.h>

#include <gtest/gtest.h>

#include <algorithm>
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

} // namespace meshless_test
