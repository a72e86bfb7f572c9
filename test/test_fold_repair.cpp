#include <pcl/surface/meshless/fold_repair.h>
#include <pcl/surface/meshless/mesh_checks.h>

#include <gtest/gtest.h>

#include "test_support.h"

#include <algorithm>
#include <map>
#include <set>

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

/** The sphere with vertex v moved past its first neighbour (in triangle order) by
  * `beyond` times their distance, back onto the unit sphere: v's fan folds over
  * the neighbour's. */
Mesh
foldPastNeighbour (const Mesh& sphere, pcl::index_t v, double beyond)
{
  pcl::index_t w = -1;
  for (const auto& t : sphere.triangles)
    for (int k = 0; k < 3 && w < 0; ++k)
      if (t[k] == v)
        w = t[(k + 1) % 3];
  EXPECT_GE (w, 0);
  Mesh folded = sphere;
  if (w >= 0)
    folded.vertices[v] =
        (sphere.vertices[w] + beyond * (sphere.vertices[w] - sphere.vertices[v])).normalized ();
  return folded;
}

/** The mesh after repairFoldsByReinsertion of the pairs `found` lists. */
Mesh
repaired (const Mesh& mesh,
          const MeshReport& found,
          FoldRepairResult& result,
          const FoldRepairOptions& options = {})
{
  Mesh out = mesh;
  result = repairFoldsByReinsertion (out.vertices, out.triangles, found.intersecting_pairs, options);
  EXPECT_TRUE (result.success) << result.message;
  return out;
}

} // namespace

TEST (FoldRepair, AVertexPushedPastItsNeighbourIsPutBack)
{
  const Mesh sphere = geodesicSphere (8);
  ASSERT_EQ (checkAll (sphere).self_intersecting_pairs, 0u);
  for (const pcl::index_t v : {100, 333, 500}) {
    const Mesh folded = foldPastNeighbour (sphere, v, 0.6);
    const MeshReport fold = checkAll (folded);
    ASSERT_GT (fold.self_intersecting_pairs, 0u) << "vertex " << v;

    FoldRepairResult result;
    const Mesh mesh = repaired (folded, fold, result);
    const MeshReport after = checkAll (mesh);
    EXPECT_EQ (result.pairs_before, fold.self_intersecting_pairs);
    EXPECT_EQ (result.pairs_after, after.self_intersecting_pairs);
    EXPECT_EQ (after.self_intersecting_pairs, 0u) << "vertex " << v;
    EXPECT_GT (result.regions_remeshed, 0u);
    expectSameSphere (folded, mesh, after);
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
  FoldRepairResult result;
  const MeshReport after = checkAll (repaired (pierced, before, result));
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
  for (pcl::index_t v = 50; v < static_cast<pcl::index_t> (sphere.vertices.size ()); v += 397)
    folded.vertices[v] = foldPastNeighbour (sphere, v, 0.5).vertices[v];
  const MeshReport fold = checkAll (folded);
  ASSERT_GT (fold.self_intersecting_pairs, 10u);
  FoldRepairResult result;
  std::vector<char> rewritten (folded.triangles.size (), 0);
  FoldRepairOptions options;
  options.rewritten = &rewritten;
  const Mesh mesh = repaired (folded, fold, result, options);
  const MeshReport after = checkAll (mesh);
  EXPECT_EQ (after.self_intersecting_pairs, 0u);
  EXPECT_EQ (result.pairs_after, 0u);
  expectSameSphere (folded, mesh, after);
  // Every slot whose triangle changed is marked (a later check relies on it), and
  // only slots the re-meshed discs took.
  std::size_t changed = 0, marked = 0;
  for (std::size_t t = 0; t < mesh.triangles.size (); ++t) {
    changed += mesh.triangles[t] != folded.triangles[t];
    marked += rewritten[t] != 0;
    if (mesh.triangles[t] != folded.triangles[t])
      EXPECT_TRUE (rewritten[t]) << "slot " << t << " changed unmarked";
  }
  EXPECT_GT (changed, 0u);
  EXPECT_LT (marked, mesh.triangles.size () / 4);
}

TEST (FoldRepair, WhereNoPlaneWillDoTheNeighbourhoodMapDoes)
{
  // On a coarse sphere the discs around a fold are too curved to project simply
  // onto any plane; with the cloud's neighbourhoods and normals the repair maps
  // them instead and opens the fold.
  const Mesh sphere = geodesicSphere (2);
  const Mesh folded = foldPastNeighbour (sphere, 30, 0.3);
  const MeshReport fold = checkAll (folded);
  ASSERT_GT (fold.self_intersecting_pairs, 0u);

  FoldRepairOptions planar_only;
  planar_only.swaps = false;
  planar_only.max_passes = 1;
  FoldRepairResult planar;
  EXPECT_GT (checkAll (repaired (folded, fold, planar, planar_only)).self_intersecting_pairs, 0u);

  const CsrGraph neighbours = meshless_test::bruteForceKnn (folded.vertices, 8);
  std::vector<Eigen::Vector3f> normals;
  for (const auto& p : folded.vertices)
    normals.push_back (p.normalized ().cast<float> ()); // outward on the unit sphere
  FoldRepairOptions options;
  options.neighbours = &neighbours;
  options.normals = &normals;
  FoldRepairResult result;
  const Mesh mapped = repaired (folded, fold, result, options);
  const MeshReport after = checkAll (mapped);
  EXPECT_EQ (after.self_intersecting_pairs, 0u);
  EXPECT_EQ (result.pairs_after, 0u);
  expectSameSphere (folded, mapped, after);
}

TEST (FoldRepair, SwapsLowerWhatNoDiscCanReach)
{
  // Discs switched off (none is small enough to be tried): edge swaps alone must
  // lower the pair count of folded fans, report it exactly, and keep the same
  // closed sphere; with swaps switched off too, nothing changes.
  const Mesh sphere = geodesicSphere (12);
  Mesh folded = sphere;
  for (const pcl::index_t v : {60, 400, 900})
    folded.vertices[v] = foldPastNeighbour (sphere, v, 0.4).vertices[v];
  const MeshReport fold = checkAll (folded);
  ASSERT_GT (fold.self_intersecting_pairs, 0u);

  FoldRepairOptions no_discs;
  no_discs.max_region_triangles = 3;
  no_discs.swaps = false;
  FoldRepairResult idle;
  const Mesh untouched = repaired (folded, fold, idle, no_discs);
  EXPECT_EQ (untouched.triangles, folded.triangles);
  EXPECT_EQ (idle.pairs_after, fold.self_intersecting_pairs);

  no_discs.swaps = true;
  FoldRepairResult result;
  const Mesh swapped = repaired (folded, fold, result, no_discs);
  const MeshReport after = checkAll (swapped);
  EXPECT_GT (result.swaps, 0u);
  EXPECT_EQ (result.regions_remeshed, 0u);
  EXPECT_LT (after.self_intersecting_pairs, fold.self_intersecting_pairs);
  EXPECT_EQ (result.pairs_after, after.self_intersecting_pairs);
  expectSameSphere (folded, swapped, after);
}

namespace {

/** A flat triangular lattice of size x size vertices (row-major, vertex (i, j) at
  * i + j / 2, j * sqrt(3) / 2), every inner vertex of degree 6, counter-clockwise. */
Triangles
triangularLattice (int size)
{
  Triangles triangles;
  const auto at = [size] (int i, int j) { return static_cast<pcl::index_t> (j * size + i); };
  for (int j = 0; j + 1 < size; ++j)
    for (int i = 0; i + 1 < size; ++i) {
      triangles.push_back ({at (i, j), at (i + 1, j), at (i, j + 1)});
      triangles.push_back ({at (i + 1, j), at (i + 1, j + 1), at (i, j + 1)});
    }
  return triangles;
}

/** closedDiscRegion on `triangles` with stars found by scanning. */
std::vector<std::int32_t>
closedDisc (const Triangles& triangles, std::vector<pcl::index_t>& inner, std::size_t max_triangles)
{
  const auto star = [&] (pcl::index_t v) {
    std::vector<std::int32_t> around;
    for (std::size_t t = 0; t < triangles.size (); ++t)
      if (std::find (triangles[t].begin (), triangles[t].end (), v) != triangles[t].end ())
        around.push_back (static_cast<std::int32_t> (t));
    return around;
  };
  return closedDiscRegion (triangles, star, inner, max_triangles);
}

/** Boundary loops of the triangles in `slots` (directed edges without their
  * reverse), and whether some vertex starts two boundary edges. */
std::size_t
boundaryLoops (const Triangles& triangles, const std::vector<std::int32_t>& slots, bool& pinched)
{
  std::set<std::pair<pcl::index_t, pcl::index_t>> directed;
  for (const std::int32_t t : slots)
    for (int k = 0; k < 3; ++k)
      directed.insert ({triangles[t][k], triangles[t][(k + 1) % 3]});
  std::map<pcl::index_t, pcl::index_t> next;
  pinched = false;
  for (const auto& [a, b] : directed)
    if (!directed.count ({b, a}))
      pinched |= !next.emplace (a, b).second;
  std::set<pcl::index_t> seen;
  std::size_t loops = 0;
  for (const auto& [start, after] : next) {
    if (seen.count (start))
      continue;
    ++loops;
    for (pcl::index_t x = start; seen.insert (x).second && next.count (x);)
      x = next[x];
  }
  return loops;
}

} // namespace

TEST (FoldRepair, DiscRegionTakesInAVertexItsStarsReachFromTwoSides)
{
  // Two vertices two steps apart on a row of the lattice: their stars meet only in
  // the vertex between them, which the boundary passes twice. The region takes
  // that vertex in and becomes the disc of the three stars.
  const int size = 9;
  const Triangles lattice = triangularLattice (size);
  const pcl::index_t middle = 4 * size + 4;
  std::vector<pcl::index_t> inner{middle - 1, middle + 1};
  bool pinched = false;
  std::vector<std::int32_t> stars;
  for (std::size_t t = 0; t < lattice.size (); ++t)
    for (const pcl::index_t v : inner)
      if (std::find (lattice[t].begin (), lattice[t].end (), v) != lattice[t].end ())
        stars.push_back (static_cast<std::int32_t> (t));
  std::sort (stars.begin (), stars.end ());
  stars.erase (std::unique (stars.begin (), stars.end ()), stars.end ());
  ASSERT_EQ (stars.size (), 12u);
  boundaryLoops (lattice, stars, pinched);
  ASSERT_TRUE (pinched); // the two stars alone are no disc

  const std::vector<std::int32_t> region = closedDisc (lattice, inner, 300);
  EXPECT_TRUE (std::binary_search (inner.begin (), inner.end (), middle));
  EXPECT_EQ (region.size (), 14u); // three stars of 6, the middle one sharing 2 with each
  EXPECT_EQ (boundaryLoops (lattice, region, pinched), 1u);
  EXPECT_FALSE (pinched);
  // A limit that the two stars meet but the closed disc does not gives no region.
  std::vector<pcl::index_t> again{middle - 1, middle + 1};
  EXPECT_TRUE (closedDisc (lattice, again, 13).empty ());
}

TEST (FoldRepair, DiscRegionFillsTheHoleItSurrounds)
{
  // The stars of the ring two steps around a vertex form an annulus around the
  // vertex's own star: the inner loop is a hole, and the region grows over it.
  const int size = 11;
  const Triangles lattice = triangularLattice (size);
  const pcl::index_t centre = 5 * size + 5;
  std::set<pcl::index_t> ring1, ring2;
  for (const auto& t : lattice)
    if (std::find (t.begin (), t.end (), centre) != t.end ())
      for (const pcl::index_t x : t)
        if (x != centre)
          ring1.insert (x);
  for (const auto& t : lattice)
    for (const pcl::index_t x : t)
      if (ring1.count (x))
        for (const pcl::index_t y : t)
          if (y != centre && !ring1.count (y))
            ring2.insert (y);
  ASSERT_EQ (ring1.size (), 6u);
  ASSERT_EQ (ring2.size (), 12u);
  std::vector<pcl::index_t> inner (ring2.begin (), ring2.end ());
  const std::vector<std::int32_t> region = closedDisc (lattice, inner, 300);
  bool pinched = true;
  EXPECT_EQ (boundaryLoops (lattice, region, pinched), 1u);
  EXPECT_FALSE (pinched);
  for (const pcl::index_t x : ring1)
    EXPECT_TRUE (std::binary_search (inner.begin (), inner.end (), x)) << x;
  // Every triangle within three steps of the centre: 6 * 3^2 = 54.
  EXPECT_EQ (region.size (), 54u);
  // The annulus alone (48 triangles) fits a limit of 50, the filled disc does not.
  std::vector<pcl::index_t> again (ring2.begin (), ring2.end ());
  EXPECT_TRUE (closedDisc (lattice, again, 50).empty ());
}

TEST (FoldRepair, DiscRegionOfAWholeClosedMeshIsNone)
{
  // Every vertex of a closed sphere: no boundary at all, so no disc to re-mesh.
  const Mesh sphere = geodesicSphere (2);
  std::vector<pcl::index_t> inner (sphere.vertices.size ());
  for (std::size_t v = 0; v < inner.size (); ++v)
    inner[v] = static_cast<pcl::index_t> (v);
  EXPECT_TRUE (closedDisc (sphere.triangles, inner, sphere.triangles.size ()).empty ());
  // One vertex's star is a disc as it is.
  std::vector<pcl::index_t> one{0};
  const std::vector<std::int32_t> star = closedDisc (sphere.triangles, one, 300);
  bool pinched = true;
  EXPECT_EQ (boundaryLoops (sphere.triangles, star, pinched), 1u);
  EXPECT_FALSE (pinched);
  EXPECT_EQ (one, std::vector<pcl::index_t>{0});
}

namespace {

/** Discs off (none is small enough), swaps in runs of at most two, then up to
  * `when_few` where at most `few` pairs are left. */
FoldRepairOptions
swapsOnly (int when_few, std::size_t few = FoldRepairOptions ().max_pairs_for_longer_runs)
{
  FoldRepairOptions options;
  options.max_region_triangles = 3;
  options.max_swaps_in_a_row_when_few = when_few;
  options.max_pairs_for_longer_runs = few;
  return options;
}

} // namespace

TEST (FoldRepair, LongerRunsOfSwapsWhereFewPairsAreLeft)
{
  // One vertex pushed past a neighbour, discs off: runs of two swaps leave a few
  // pairs; runs of three and four, tried because so few are left, must never leave
  // more, leave fewer on most members, count exactly and keep the sphere.
  const Mesh sphere = geodesicSphere (12);
  std::size_t members = 0, fewer = 0;
  for (const double beyond : {0.4, 1.2})
    for (const pcl::index_t v : {400, 900, 1200}) {
      SCOPED_TRACE ("beyond " + std::to_string (beyond) + " vertex " + std::to_string (v));
      const Mesh folded = foldPastNeighbour (sphere, v, beyond);
      const MeshReport fold = checkAll (folded);
      ASSERT_GT (fold.self_intersecting_pairs, 0u);
      FoldRepairResult by_two, by_four;
      repaired (folded, fold, by_two, swapsOnly (2));
      ASSERT_GT (by_two.pairs_after, 0u);
      ASSERT_LE (by_two.pairs_after, FoldRepairOptions ().max_pairs_for_longer_runs);
      const Mesh longer = repaired (folded, fold, by_four, swapsOnly (4));
      const MeshReport after = checkAll (longer);
      EXPECT_LE (by_four.pairs_after, by_two.pairs_after);
      EXPECT_EQ (by_four.pairs_after, after.self_intersecting_pairs);
      expectSameSphere (folded, longer, after);
      ++members;
      if (by_four.pairs_after < by_two.pairs_after)
        ++fewer;
    }
  EXPECT_GT (2 * fewer, members);

  // Four such folds at once leave more pairs than the longer runs are tried for;
  // with a higher limit the same runs do lower them.
  Mesh many = sphere;
  for (const pcl::index_t v : {400, 900, 1200, 60})
    many.vertices[v] = foldPastNeighbour (sphere, v, 1.2).vertices[v];
  const MeshReport fold = checkAll (many);
  FoldRepairResult by_two, by_four, by_four_any;
  const Mesh with_two = repaired (many, fold, by_two, swapsOnly (2));
  EXPECT_GT (by_two.pairs_after, FoldRepairOptions ().max_pairs_for_longer_runs);
  EXPECT_EQ (repaired (many, fold, by_four, swapsOnly (4)).triangles, with_two.triangles);
  repaired (many, fold, by_four_any, swapsOnly (4, fold.self_intersecting_pairs));
  EXPECT_LT (by_four_any.pairs_after, by_two.pairs_after);
}

TEST (FoldRepair, LongerRunsStopAtTheirSwapLimit)
{
  // The longer runs branch at every step: their search must stop at the limit,
  // say so, and leave a mesh no worse than the short runs did.
  const Mesh sphere = geodesicSphere (12);
  const Mesh folded = foldPastNeighbour (sphere, 900, 1.2);
  const MeshReport fold = checkAll (folded);
  FoldRepairResult by_two, default_limit, limited, none;
  const Mesh with_two = repaired (folded, fold, by_two, swapsOnly (2));
  ASSERT_GT (by_two.pairs_after, 0u);
  EXPECT_EQ (by_two.longer_run_swaps_tried, 0u);

  repaired (folded, fold, default_limit, swapsOnly (4));
  ASSERT_GT (default_limit.longer_run_swaps_tried, 20u);
  EXPECT_LE (default_limit.longer_run_swaps_tried, FoldRepairOptions ().max_swaps_tried_in_longer_runs);
  EXPECT_FALSE (default_limit.longer_runs_cut_short);

  FoldRepairOptions few_swaps = swapsOnly (4);
  few_swaps.max_swaps_tried_in_longer_runs = 20;
  const Mesh cut = repaired (folded, fold, limited, few_swaps);
  EXPECT_EQ (limited.longer_run_swaps_tried, 20u);
  EXPECT_TRUE (limited.longer_runs_cut_short);
  const MeshReport after = checkAll (cut);
  EXPECT_LE (limited.pairs_after, by_two.pairs_after);
  EXPECT_EQ (limited.pairs_after, after.self_intersecting_pairs);
  expectSameSphere (folded, cut, after);

  few_swaps.max_swaps_tried_in_longer_runs = 0;
  EXPECT_EQ (repaired (folded, fold, none, few_swaps).triangles, with_two.triangles);
  EXPECT_EQ (none.longer_run_swaps_tried, 0u);
  EXPECT_FALSE (none.longer_runs_cut_short);
}

TEST (FoldRepair, TanglesAreLeftAlone)
{
  // Where the pairs outnumber the limit per triangle the repair tries nothing and
  // says so; just under it, the same mesh is repaired as before.
  const Mesh sphere = geodesicSphere (12);
  const Mesh folded = foldPastNeighbour (sphere, 900, 1.2);
  const MeshReport fold = checkAll (folded);
  ASSERT_GT (fold.self_intersecting_pairs, 0u);
  const double density =
      static_cast<double> (fold.self_intersecting_pairs) / static_cast<double> (folded.triangles.size ());

  FoldRepairOptions below;
  below.max_pairs_per_triangle = 0.99 * density;
  FoldRepairResult tangle;
  EXPECT_EQ (repaired (folded, fold, tangle, below).triangles, folded.triangles);
  EXPECT_TRUE (tangle.success);
  EXPECT_TRUE (tangle.tangle);
  EXPECT_EQ (tangle.pairs_before, fold.self_intersecting_pairs);
  EXPECT_EQ (tangle.pairs_after, fold.self_intersecting_pairs);
  EXPECT_EQ (tangle.regions_remeshed + tangle.swaps, 0u);

  FoldRepairOptions above;
  above.max_pairs_per_triangle = 1.01 * density;
  FoldRepairResult folds, by_default;
  const Mesh with_limit = repaired (folded, fold, folds, above);
  EXPECT_FALSE (folds.tangle);
  EXPECT_LT (folds.pairs_after, folds.pairs_before);
  EXPECT_EQ (with_limit.triangles, repaired (folded, fold, by_default, FoldRepairOptions ()).triangles);
}
