// Merging patch triangulations into one closed triangulation.
#include <pcl/surface/meshless/merge.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>

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

TEST (Merge, AChordBothPatchesHoldIsFlippedInsideOnePatch)
{
  // A double pyramid cut along the equator 0-1-2-3: the top disc (apex 4) and the
  // bottom disc (apex 5) both triangulate the quad 0-1-2 with the chord 0-2, which
  // four triangles then use. One flip inside a patch leaves a closed triangulation.
  const std::vector<Triangles> patches = {{{0, 1, 2}, {0, 2, 4}, {2, 3, 4}, {3, 0, 4}},
                                          {{2, 1, 0}, {2, 0, 5}, {3, 2, 5}, {0, 3, 5}}};
  const MergedTriangulation merged = mergePatches (patches, 6);
  ASSERT_TRUE (merged.success) << merged.message;
  EXPECT_EQ (merged.num_repair_flips, 1u);
  ASSERT_EQ (merged.triangles.size (), 2u * 6u - 4u);
  // Closed and consistently oriented: every directed edge once, with its reverse.
  std::vector<std::pair<pcl::index_t, pcl::index_t>> directed;
  for (const Triangle& t : merged.triangles)
    for (int k = 0; k < 3; ++k)
      directed.emplace_back (t[k], t[(k + 1) % 3]);
  std::sort (directed.begin (), directed.end ());
  EXPECT_EQ (std::adjacent_find (directed.begin (), directed.end ()), directed.end ());
  for (const auto& [a, b] : directed)
    EXPECT_TRUE (std::binary_search (directed.begin (), directed.end (), std::make_pair (b, a)))
        << a << "-" << b;
  for (std::size_t t = 1; t < merged.triangles.size (); ++t)
    EXPECT_LE (smallest (merged.triangles[t - 1]), smallest (merged.triangles[t]));
}

TEST (Merge, RefusesATriangleNamingAPointOutOfRange)
{
  const std::vector<Triangles> patches = {{{0, 1, 2}, {0, 2, 4}}};
  const MergedTriangulation merged = mergePatches (patches, 4);
  EXPECT_FALSE (merged.success);
  EXPECT_NE (merged.message.find ("out of range"), std::string::npos) << merged.message;
  EXPECT_TRUE (merged.triangles.empty ());
}
