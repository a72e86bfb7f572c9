// Helpers shared by the tests: data location, brute-force references.
#pragma once

#include <pcl/surface/meshless/types.h>

#include <gtest/gtest.h>

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

} // namespace meshless_test
