// The base mesh grown from the cloud: the genus it finds across generated families
// of closed shapes, and the validity of the polygonal D it returns.
#include <pcl/surface/meshless/grown_base_mesh.h>
#include <pcl/surface/meshless/surface_graphs.h>
#include <meshless_tools/synthetic_clouds.h>

#include "handles.h"
#include "test_support.h"

#include <set>

using namespace pcl::meshless;

namespace {

SurfaceGraphs
graphsOf (const Points3& points)
{
  SurfaceGraphs graphs = buildSurfaceGraphs (points, meshless_test::bruteForceKnn (points, 12), {});
  EXPECT_TRUE (graphs.success) << graphs.message;
  return graphs;
}

/** D is a closed, oriented polygonal mesh over distinct cloud points whose faces are
  * the regions, every point in one of them. */
void
expectValidRegions (const GrownBaseMesh& grown, const Points3& points)
{
  const std::size_t n = points.size ();
  // Turned outward: the faces, fanned from their first corner, enclose a positive
  // volume.
  double volume = 0.0;
  for (const auto& face : grown.mesh.faces)
    for (std::size_t k = 1; k + 1 < face.size (); ++k)
      volume += points[grown.mesh.vertices[face[0]]].dot (
          points[grown.mesh.vertices[face[k]]].cross (points[grown.mesh.vertices[face[k + 1]]]));
  EXPECT_GT (volume, 0.0) << "D turns outward";
  std::string problem;
  EXPECT_EQ (closedBaseMeshGenus (grown.mesh, n, problem), grown.genus) << problem;
  ASSERT_EQ (grown.seeds.size (), grown.mesh.faces.size ());
  ASSERT_EQ (grown.region_of.size (), n);
  std::vector<std::size_t> region_size (grown.mesh.faces.size (), 0);
  for (const int r : grown.region_of) {
    ASSERT_GE (r, 0) << "every point lies in a region";
    ASSERT_LT (r, static_cast<int> (region_size.size ()));
    ++region_size[r];
  }
  for (std::size_t f = 0; f < region_size.size (); ++f) {
    EXPECT_GE (grown.mesh.faces[f].size (), 3u) << "a region with fewer than three corners";
    EXPECT_EQ (grown.region_of[grown.seeds[f]], static_cast<int> (f)) << "its seed lies in it";
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

TEST (GrownBaseMesh, ClosedBaseMeshGenusReadsPolygonalMeshes)
{
  // A torus as a 3 x 3 grid of quadrilaterals: V = 9, E = 18, F = 9, genus 1.
  BaseMesh torus;
  for (int i = 0; i < 9; ++i)
    torus.vertices.push_back (i);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const auto at = [] (int a, int b) { return (a % 3) * 3 + (b % 3); };
      torus.faces.push_back ({at (i, j), at (i + 1, j), at (i + 1, j + 1), at (i, j + 1)});
    }
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
