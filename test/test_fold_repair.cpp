#include <pcl/surface/meshless/fold_repair.h>
#include <pcl/surface/meshless/mesh_checks.h>

#include <gtest/gtest.h>

#include "test_support.h"

#include <algorithm>

using namespace pcl::meshless;
using meshless_test::geodesicSphere;
using meshless_test::Mesh;

namespace {

MeshReport
checkAll (const Mesh& m)
{
  MeshCheckOptions options;
  options.max_listed_intersections = 65536;
  return checkMesh (m.vertices, m.triangles, options);
}

/** Every vertex of a sphere mesh still used, the topology unchanged. */
void
expectSameSphere (const Mesh& before, const Mesh& after, const MeshReport& report)
{
  EXPECT_TRUE (report.isSphereLike ());
  EXPECT_EQ (after.triangles.size (), before.triangles.size ());
  EXPECT_EQ (report.used_vertices, before.vertices.size ());
  EXPECT_EQ (report.unused_vertices, 0u);
  EXPECT_GT (report.signed_volume, 0.0);
}

/** The first neighbour (in triangle order) of vertex v. */
pcl::index_t
someNeighbour (const Mesh& m, pcl::index_t v)
{
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] == v)
        return t[(k + 1) % 3];
  return -1;
}

} // namespace

TEST (FoldRepair, AVertexPushedPastItsNeighbourIsPutBack)
{
  const Mesh sphere = geodesicSphere (8);
  ASSERT_EQ (checkAll (sphere).self_intersecting_pairs, 0u);
  for (const pcl::index_t v : {100, 333, 500}) {
    Mesh folded = sphere;
    const pcl::index_t w = someNeighbour (sphere, v);
    ASSERT_GE (w, 0);
    // On the sphere, beyond its neighbour: its fan folds over the neighbour's.
    folded.vertices[v] =
        (sphere.vertices[w] + 0.6 * (sphere.vertices[w] - sphere.vertices[v])).normalized ();
    const MeshReport fold = checkAll (folded);
    ASSERT_GT (fold.self_intersecting_pairs, 0u) << "vertex " << v;

    Mesh repaired = folded;
    const FoldRepairResult result =
        repairFoldsByReinsertion (repaired.vertices, repaired.triangles, fold.intersecting_pairs);
    ASSERT_TRUE (result.success) << result.message;
    const MeshReport after = checkAll (repaired);
    EXPECT_EQ (result.pairs_before, fold.self_intersecting_pairs);
    EXPECT_EQ (result.pairs_after, after.self_intersecting_pairs);
    EXPECT_EQ (after.self_intersecting_pairs, 0u) << "vertex " << v;
    EXPECT_GT (result.regions_remeshed, 0u);
    expectSameSphere (folded, repaired, after);
  }
}

TEST (FoldRepair, ACrossingItCannotOpenIsLeftAsItWas)
{
  // A vertex pushed through the far side of the sphere: its fan cuts the surface
  // there, which no disc around it can change. The count never rises, and what
  // the repair reports is what the check counts.
  Mesh pierced = geodesicSphere (8);
  pierced.vertices[100] *= -1.2;
  const MeshReport before = checkAll (pierced);
  ASSERT_GT (before.self_intersecting_pairs, 0u);
  Mesh repaired = pierced;
  const FoldRepairResult result =
      repairFoldsByReinsertion (repaired.vertices, repaired.triangles, before.intersecting_pairs);
  ASSERT_TRUE (result.success) << result.message;
  const MeshReport after = checkAll (repaired);
  EXPECT_LE (after.self_intersecting_pairs, before.self_intersecting_pairs);
  EXPECT_GT (after.self_intersecting_pairs, 0u);
  EXPECT_EQ (result.pairs_after, after.self_intersecting_pairs);
  EXPECT_TRUE (after.isSphereLike ());
  EXPECT_EQ (after.used_vertices, pierced.vertices.size ());
}

TEST (FoldRepair, NothingToDoOrBadInputChangesNothing)
{
  Mesh sphere = geodesicSphere (4);
  const Triangles original = sphere.triangles;
  FoldRepairResult result = repairFoldsByReinsertion (sphere.vertices, sphere.triangles, {});
  EXPECT_TRUE (result.success);
  EXPECT_EQ (result.regions_remeshed, 0u);
  EXPECT_EQ (sphere.triangles, original);

  result = repairFoldsByReinsertion (sphere.vertices, sphere.triangles,
                                     {{0, sphere.triangles.size ()}});
  EXPECT_FALSE (result.success);
  EXPECT_NE (result.message.find ("out of range"), std::string::npos) << result.message;
  EXPECT_EQ (sphere.triangles, original);

  Triangles broken = original;
  broken[0][0] = static_cast<pcl::index_t> (sphere.vertices.size ());
  result = repairFoldsByReinsertion (sphere.vertices, broken, {{0, 1}});
  EXPECT_FALSE (result.success);
}

TEST (FoldRepair, ManyFoldsAtOnceOnALargerSphere)
{
  // Folds scattered over the sphere, all repaired in one call; the mesh stays the
  // same closed sphere through every vertex.
  const Mesh sphere = geodesicSphere (24);
  Mesh folded = sphere;
  for (pcl::index_t v = 50; v < static_cast<pcl::index_t> (sphere.vertices.size ()); v += 397) {
    const pcl::index_t w = someNeighbour (sphere, v);
    folded.vertices[v] =
        (sphere.vertices[w] + 0.5 * (sphere.vertices[w] - sphere.vertices[v])).normalized ();
  }
  const MeshReport fold = checkAll (folded);
  ASSERT_GT (fold.self_intersecting_pairs, 10u);
  Mesh repaired = folded;
  const FoldRepairResult result =
      repairFoldsByReinsertion (repaired.vertices, repaired.triangles, fold.intersecting_pairs);
  ASSERT_TRUE (result.success) << result.message;
  const MeshReport after = checkAll (repaired);
  EXPECT_EQ (after.self_intersecting_pairs, 0u);
  EXPECT_EQ (result.pairs_after, 0u);
  expectSameSphere (folded, repaired, after);
}

TEST (FoldRepair, WhereNoPlaneWillDoTheNeighbourhoodMapDoes)
{
  // On a coarse sphere the discs around a fold are too curved to project simply
  // onto any plane; with the cloud's neighbourhoods and normals the repair maps
  // them instead and opens the fold.
  const Mesh sphere = geodesicSphere (2);
  Mesh folded = sphere;
  const pcl::index_t v = 30, w = someNeighbour (sphere, v);
  folded.vertices[v] =
      (sphere.vertices[w] + 0.3 * (sphere.vertices[w] - sphere.vertices[v])).normalized ();
  const MeshReport fold = checkAll (folded);
  ASSERT_GT (fold.self_intersecting_pairs, 0u);

  Mesh planar_only = folded;
  const FoldRepairResult planar = repairFoldsByReinsertion (
      planar_only.vertices, planar_only.triangles, fold.intersecting_pairs);
  ASSERT_TRUE (planar.success) << planar.message;
  EXPECT_GT (checkAll (planar_only).self_intersecting_pairs, 0u);

  const CsrGraph neighbours = meshless_test::bruteForceKnn (folded.vertices, 8);
  std::vector<Eigen::Vector3f> normals;
  for (const auto& p : folded.vertices)
    normals.push_back (p.normalized ().cast<float> ()); // outward on the unit sphere
  FoldRepairOptions options;
  options.neighbours = &neighbours;
  options.normals = &normals;
  Mesh mapped = folded;
  const FoldRepairResult result =
      repairFoldsByReinsertion (mapped.vertices, mapped.triangles, fold.intersecting_pairs, options);
  ASSERT_TRUE (result.success) << result.message;
  const MeshReport after = checkAll (mapped);
  EXPECT_EQ (after.self_intersecting_pairs, 0u);
  EXPECT_EQ (result.pairs_after, 0u);
  expectSameSphere (folded, mapped, after);
}
