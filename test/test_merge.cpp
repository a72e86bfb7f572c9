// Merging patch triangulations into one closed triangulation.
#include <pcl/surface/meshless/merge.h>

#include <gtest/gtest.h>

#include <algorithm>

using namespace pcl::meshless;

namespace {

pcl::index_t
smallest (const Triangle& t)
{
  return std::min ({t[0], t[1], t[2]});
}

} // namespace

TEST (Merge, TwoDiscsOfATetrahedronCloseUpInTheOrderOfTheirSmallestVertex)
{
  // A tetrahedron cut along the loop 0-1-2-3 into two discs of two triangles; the
  // first patch holds the triangle whose smallest vertex is the largest.
  const std::vector<Triangles> patches = {{{1, 2, 3}, {0, 2, 1}}, {{0, 1, 3}, {0, 3, 2}}};
  const MergedTriangulation merged = mergePatches (patches, 4);
  ASSERT_TRUE (merged.success) << merged.message;
  EXPECT_EQ (merged.num_repair_flips, 0u);
  ASSERT_EQ (merged.triangles.size (), 4u);
  for (std::size_t t = 1; t < merged.triangles.size (); ++t)
    EXPECT_LE (smallest (merged.triangles[t - 1]), smallest (merged.triangles[t]));
  // Nothing lost or changed: the same triangles, in the patches' order among equals.
  const Triangles expected = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_EQ (merged.triangles, expected);
}
