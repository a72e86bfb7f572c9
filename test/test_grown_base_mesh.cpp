// The base mesh grown from the cloud: the genus it finds across generated families
// of closed shapes, and the validity of the polygonal D it returns.
#include <pcl/surface/meshless/cut_paths.h>
#include <pcl/surface/meshless/grown_base_mesh.h>
#include <pcl/surface/meshless/surface_graphs.h>
#include <meshless_tools/synthetic_clouds.h>

#include "handles.h"
#include "region_merging.h"
#include "test_support.h"

#include <iostream>
#include <set>

using namespace pcl::meshless;

namespace {

SurfaceGraphs
graphsOf (const Points3& points, int k = 12)
{
  SurfaceGraphs graphs = buildSurfaceGraphs (points, meshless_test::bruteForceKnn (points, k), {});
  EXPECT_TRUE (graphs.success) << graphs.message;
  return graphs;
}

/** D is a closed, oriented polygonal mesh over distinct cloud points whose faces are
  * the regions, every point in one of them (or, unless `every_point_reached`, in none
  * where the graph does not reach it: expectConnectedRegions checks that). The volume
  * test of the orientation needs regions small against the curvature: a merged
  * region, a long strip of a tube, fans through the tube's inside. */
void
expectValidRegions (const GrownBaseMesh& grown,
                    const Points3& points,
                    bool small_regions = true,
                    bool every_point_reached = true)
{
  const std::size_t n = points.size ();
  // Turned outward: the faces, fanned from their seeds (a region's corners alone can
  // lie far apart on a curved strip), enclose a positive volume.
  ASSERT_EQ (grown.seeds.size (), grown.mesh.faces.size ());
  double volume = 0.0;
  for (std::size_t f = 0; f < grown.mesh.faces.size (); ++f) {
    const auto& face = grown.mesh.faces[f];
    for (std::size_t k = 0; k < face.size (); ++k)
      volume += points[grown.seeds[f]].dot (
          points[grown.mesh.vertices[face[k]]].cross (
              points[grown.mesh.vertices[face[(k + 1) % face.size ()]]]));
  }
  if (small_regions)
    EXPECT_GT (volume, 0.0) << "D turns outward";
  std::string problem;
  EXPECT_EQ (closedBaseMeshGenus (grown.mesh, n, problem), grown.genus) << problem;
  ASSERT_EQ (grown.seeds.size (), grown.mesh.faces.size ());
  ASSERT_EQ (grown.region_of.size (), n);
  std::vector<std::size_t> region_size (grown.mesh.faces.size (), 0);
  for (const int r : grown.region_of) {
    if (r < 0 && !every_point_reached)
      continue;
    ASSERT_GE (r, 0) << "every point lies in a region";
    ASSERT_LT (r, static_cast<int> (region_size.size ()));
    ++region_size[r];
  }
  for (std::size_t f = 0; f < region_size.size (); ++f) {
    EXPECT_GE (grown.mesh.faces[f].size (), 3u) << "a region with fewer than three corners";
    EXPECT_EQ (grown.region_of[grown.seeds[f]], static_cast<int> (f)) << "its seed lies in it";
  }
  EXPECT_EQ (grown.mesh.point_faces, grown.region_of) << "the router's hint is the regions";
}

/** A torus as an m x m grid of quadrilaterals over vertices 0 .. m^2 - 1. */
BaseMesh
quadTorus (int m)
{
  BaseMesh torus;
  for (int i = 0; i < m * m; ++i)
    torus.vertices.push_back (i);
  const auto at = [m] (int a, int b) { return (a % m) * m + (b % m); };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      torus.faces.push_back ({at (i, j), at (i + 1, j), at (i + 1, j + 1), at (i, j + 1)});
  return torus;
}

/** Every region is one piece of the graph; a point in no region is one the graph
  * does not lead to from any seed. */
void
expectConnectedRegions (const GrownBaseMesh& grown, const CsrGraph& graph)
{
  std::vector<char> reached (grown.region_of.size (), 0);
  std::vector<pcl::index_t> all (grown.seeds.begin (), grown.seeds.end ());
  for (const pcl::index_t s : all)
    reached[s] = 1;
  for (std::size_t head = 0; head < all.size (); ++head)
    for (const pcl::index_t* w = graph.begin (all[head]); w != graph.end (all[head]); ++w)
      if (!reached[*w]) {
        reached[*w] = 1;
        all.push_back (*w);
      }
  std::vector<char> seen (grown.region_of.size (), 0);
  for (std::size_t f = 0; f < grown.seeds.size (); ++f) {
    std::vector<pcl::index_t> queue = {grown.seeds[f]};
    seen[grown.seeds[f]] = 1;
    for (std::size_t head = 0; head < queue.size (); ++head)
      for (const pcl::index_t* w = graph.begin (queue[head]); w != graph.end (queue[head]); ++w)
        if (!seen[*w] && grown.region_of[*w] == static_cast<int> (f)) {
          seen[*w] = 1;
          queue.push_back (*w);
        }
  }
  for (std::size_t v = 0; v < seen.size (); ++v) {
    ASSERT_EQ (grown.region_of[v] >= 0, static_cast<bool> (reached[v])) << "point " << v;
    if (reached[v])
      ASSERT_TRUE (seen[v]) << "point " << v << " is cut off from its region's seed";
  }
}

struct FamilyMember
{
  SyntheticShape shape;
  std::size_t points;
  std::uint32_t seed;
  double noise;
  double uneven;
};

std::string
describeMember (const FamilyMember& m)
{
  return std::to_string (static_cast<int> (m.shape)) + " n=" + std::to_string (m.points) +
         " seed=" + std::to_string (m.seed) + " noise=" + std::to_string (m.noise) +
         " uneven=" + std::to_string (m.uneven);
}

} // namespace

TEST (GrownBaseMesh, FindsTheGenusOfEveryGeneratedClosedShape)
{
  std::vector<FamilyMember> family;
  for (const SyntheticShape shape :
       {SyntheticShape::Sphere, SyntheticShape::BumpySphere, SyntheticShape::Torus,
        SyntheticShape::ThinTorus, SyntheticShape::FatTorus, SyntheticShape::DoubleTorus,
        SyntheticShape::KnottedTube})
    for (const std::uint32_t seed : {1u, 2u})
      family.push_back ({shape, 6000, seed, 0.0, 0.0});
  for (const SyntheticShape shape : {SyntheticShape::Torus, SyntheticShape::DoubleTorus}) {
    family.push_back ({shape, 8000, 3, 0.0, 4.0});   // density 4:1 along the shape
    family.push_back ({shape, 8000, 4, 0.001, 0.0}); // light noise, 0.1% of the diagonal
  }
  for (const FamilyMember& m : family) {
    SCOPED_TRACE (describeMember (m));
    SyntheticCloudOptions options;
    options.num_points = m.points;
    options.seed = m.seed;
    options.noise = m.noise;
    options.uneven = m.uneven;
    const Points3 points = sampleShape (m.shape, options);
    const SurfaceGraphs graphs = graphsOf (points);
    const GrownBaseMesh grown = growBaseMesh (points, graphs.mutual, graphs.ordered.rings);
    ASSERT_TRUE (grown.success) << grown.message;
    EXPECT_EQ (grown.genus, syntheticGenus (m.shape));
    expectValidRegions (grown, points);
    // The sphere topology's check: no handle on a genus-0 shape; on the others
    // either the genus or no verdict, never another genus.
    const int handles = clearHandles (points, graphs.mutual, graphs.ordered.rings);
    if (syntheticGenus (m.shape) == 0)
      EXPECT_EQ (handles, 0);
    else
      EXPECT_TRUE (handles == 0 || handles == syntheticGenus (m.shape)) << handles;
    if (m.noise == 0.0 && m.uneven == 0.0 && syntheticGenus (m.shape) > 0 &&
        m.shape != SyntheticShape::KnottedTube)
      EXPECT_EQ (handles, syntheticGenus (m.shape)) << "a clear handle is named";
  }
}

TEST (GrownBaseMesh, UnevenDensityGrowsInLocalSpacings)
{
  // Density 4:1 along tubes a few dozen points around: regions of equal extent hold
  // a quarter of the points in the sparse parts, whose rings read no clean dual.
  // Counted in local spacings the regions even out. Every member must grow with its
  // genus from 12 neighbours or else 24 (as the class tries), and the retry must be
  // what grows at least one of them.
  std::size_t needed_the_retry = 0;
  for (const SyntheticShape shape : {SyntheticShape::DoubleTorus, SyntheticShape::KnottedTube})
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
      const FamilyMember m {shape, 5000, seed, 0.0, 4.0};
      SCOPED_TRACE (describeMember (m));
      const Points3 points = sampleShape (shape, {m.points, seed, 0.0, m.uneven});
      bool grew = false;
      for (const int k : {12, 24}) {
        const SurfaceGraphs graphs = graphsOf (points, k);
        const GrownBaseMesh grown = growBaseMesh (points, graphs.mutual, graphs.ordered.rings);
        GrownBaseMeshOptions in_units_only;
        in_units_only.retry_in_local_spacings = false;
        const GrownBaseMesh plain =
            growBaseMesh (points, graphs.mutual, graphs.ordered.rings, {}, in_units_only);
        if (plain.success)
          EXPECT_EQ (plain.genus, syntheticGenus (shape)) << "never another genus";
        if (!grown.success)
          continue;
        EXPECT_EQ (grown.genus, syntheticGenus (shape));
        expectValidRegions (grown, points, false, false);
        expectConnectedRegions (grown, graphs.mutual);
        needed_the_retry += !plain.success;
        grew = true;
        break;
      }
      EXPECT_TRUE (grew) << "no D from 12 nor 24 neighbours";
    }
  EXPECT_GE (needed_the_retry, 1u);
}

TEST (GrownBaseMesh, MergedRegionsKeepDValid)
{
  for (const SyntheticShape shape :
       {SyntheticShape::Torus, SyntheticShape::DoubleTorus, SyntheticShape::KnottedTube})
    for (const std::uint32_t seed : {1u, 2u}) {
      SCOPED_TRACE ("shape " + std::to_string (static_cast<int> (shape)) + " seed " +
                    std::to_string (seed));
      const Points3 points = sampleShape (shape, {5000, seed, 0.0, 0.0});
      const SurfaceGraphs graphs = graphsOf (points);
      GrownBaseMeshOptions keep_all;
      keep_all.merge_regions_below = 1;
      const GrownBaseMesh fine =
          growBaseMesh (points, graphs.mutual, graphs.ordered.rings, {}, keep_all);
      const GrownBaseMesh merged = growBaseMesh (points, graphs.mutual, graphs.ordered.rings);
      ASSERT_TRUE (fine.success) << fine.message;
      ASSERT_TRUE (merged.success) << merged.message;
      EXPECT_EQ (merged.genus, syntheticGenus (shape));
      EXPECT_LE (merged.mesh.faces.size (), fine.mesh.faces.size ());
      if (shape == SyntheticShape::KnottedTube)
        EXPECT_LT (merged.mesh.faces.size (), fine.mesh.faces.size ()) << "its small regions merge";
      expectValidRegions (fine, points);
      expectValidRegions (merged, points, false);
      expectConnectedRegions (merged, graphs.mutual);
    }
}

TEST (GrownBaseMesh, MergedRegionsLeaveThePathsRoomOnATube)
{
  // A knotted tube about 25 points around shows its genus only with regions of a
  // few dozen points; routed as they are, the corners' rings leave the paths no room.
  std::size_t routed_fine = 0, routed_merged = 0;
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE ("seed " + std::to_string (seed));
    const Points3 points = sampleShape (SyntheticShape::KnottedTube, {5000, seed, 0.0, 0.0});
    const SurfaceGraphs graphs = graphsOf (points);
    std::size_t routed_here = 0;
    for (std::uint32_t start = 0; start < 4; ++start) {
      GrownBaseMeshOptions options;
      options.start = start;
      const GrownBaseMesh merged =
          growBaseMesh (points, graphs.mutual, graphs.ordered.rings, {}, options);
      options.merge_regions_below = 1;
      const GrownBaseMesh fine =
          growBaseMesh (points, graphs.mutual, graphs.ordered.rings, {}, options);
      ASSERT_TRUE (fine.success && merged.success);
      EXPECT_LT (2 * merged.mesh.faces.size (), fine.mesh.faces.size ());
      routed_fine +=
          computeCutPaths (points, graphs.mutual, graphs.ordered.rings, fine.mesh).success;
      routed_here +=
          computeCutPaths (points, graphs.mutual, graphs.ordered.rings, merged.mesh).success;
    }
    EXPECT_GE (routed_here, 1u) << "one of four starts routes, as the pipeline's attempts need";
    routed_merged += routed_here;
  }
  std::cout << "routed: " << routed_fine << " of 12 fine D, " << routed_merged << " merged\n";
  EXPECT_GE (routed_merged, routed_fine + 4);
}

TEST (GrownBaseMesh, MergingKeepsTheGenusOfAPolygonalTorus)
{
  // A torus as a 4 x 4 grid of quadrilaterals, one region of 10 points per face:
  // merges must stop before a face wraps around the torus (it would share two arcs).
  GrownBaseMesh grown;
  for (int f = 0; f < 16; ++f) {
    grown.seeds.push_back (f * 10);
    for (int k = 0; k < 10; ++k)
      grown.region_of.push_back (f);
  }
  grown.mesh = quadTorus (4);
  grown.genus = 1;
  grown.success = true;
  EXPECT_GT (mergeSmallRegions (grown, 1000), 0u);
  EXPECT_LT (grown.mesh.faces.size (), 16u);
  std::string problem;
  EXPECT_EQ (closedBaseMeshGenus (grown.mesh, grown.region_of.size (), problem), 1) << problem;
  for (std::size_t f = 0; f < grown.seeds.size (); ++f)
    EXPECT_EQ (grown.region_of[grown.seeds[f]], static_cast<int> (f));
  EXPECT_EQ (grown.mesh.point_faces, grown.region_of);
}

TEST (GrownBaseMesh, ClosedBaseMeshGenusReadsPolygonalMeshes)
{
  // A torus as a 3 x 3 grid of quadrilaterals: V = 9, E = 18, F = 9, genus 1.
  const BaseMesh torus = quadTorus (3);
  std::string problem;
  EXPECT_EQ (closedBaseMeshGenus (torus, 9, problem), 1) << problem;
  EXPECT_NE (validateBaseMesh (torus, 9).find ("genus 1"), std::string::npos)
      << "the sphere check names the genus";
  BaseMesh open = torus;
  open.faces.pop_back ();
  EXPECT_EQ (closedBaseMeshGenus (open, 9, problem), -1);
  EXPECT_NE (problem.find ("boundary"), std::string::npos) << problem;
  BaseMesh two = torus;
  for (const auto& f : torus.faces) {
    std::vector<int> shifted;
    for (const int v : f)
      shifted.push_back (v + 9);
    two.faces.push_back (shifted);
  }
  for (int i = 9; i < 18; ++i)
    two.vertices.push_back (i);
  EXPECT_EQ (closedBaseMeshGenus (two, 18, problem), -1);
  EXPECT_NE (problem.find ("not connected"), std::string::npos) << problem;
}
