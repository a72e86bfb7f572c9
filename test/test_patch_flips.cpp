/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/delaunay_2d.h>
#include <pcl/surface/meshless/edge_swap.h>
#include <pcl/surface/meshless/patch_flips.h>
#include <pcl/surface/meshless/triangle_intersection.h>

#include "common/swap_predicates.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>

using namespace pcl::meshless;

namespace {

using meshless_test::boundaryEdges;
using meshless_test::Edge;
using meshless_test::edgeUse;

/** A (size + 1)^2 lattice in the plane, each cell cut along the diagonal from
  * (i, j) to (i + 1, j + 1); the 3D points are the lattice sheared by `shear` along
  * x (and lifted by `lift` * x * y), so that the other diagonal is the shorter one
  * in space wherever shear > 0. */
struct Lattice
{
  Points2 uv;
  Points3 points;
  std::vector<pcl::index_t> global_of;
  Triangles triangles;
};

Lattice
shearedLattice (int size, double shear)
{
  Lattice lattice;
  const auto id = [size] (int i, int j) { return static_cast<pcl::index_t> (j * (size + 1) + i); };
  for (int j = 0; j <= size; ++j)
    for (int i = 0; i <= size; ++i) {
      lattice.uv.emplace_back (i, j);
      lattice.points.emplace_back (i + shear * j, j, 0.0);
      lattice.global_of.push_back (id (i, j));
    }
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      lattice.triangles.push_back ({id (i, j), id (i + 1, j), id (i + 1, j + 1)});
      lattice.triangles.push_back ({id (i, j), id (i + 1, j + 1), id (i, j + 1)});
    }
  return lattice;
}

} // namespace

TEST (PatchFlips, ShearedFlatLatticeEndsLocallyDelaunayInSpace)
{
  Lattice lattice = shearedLattice (12, 0.6);
  const Triangles before = lattice.triangles;
  const std::size_t flips =
      flipFlatEdgesInPatch (lattice.points, lattice.global_of, lattice.uv, lattice.triangles);
  // Each of the 144 cells has its long diagonal in space: every one is flipped.
  EXPECT_EQ (flips, 144u);
  ASSERT_EQ (lattice.triangles.size (), before.size ());
  EXPECT_EQ (boundaryEdges (lattice.triangles), boundaryEdges (before)) << "the loop changed";
  for (const auto& [edge, count] : edgeUse (lattice.triangles))
    EXPECT_LE (count, 2) << "not a manifold disc";
  // Still an embedding of the parameter points, and Delaunay in space.
  for (const Triangle& t : lattice.triangles)
    EXPECT_GT (orient2d (lattice.uv[t[0]], lattice.uv[t[1]], lattice.uv[t[2]]), 0) << "folded in the plane";
  std::map<Edge, std::vector<pcl::index_t>> opposite;
  for (const Triangle& t : lattice.triangles)
    for (int k = 0; k < 3; ++k)
      opposite[{t[k], t[(k + 1) % 3]}].push_back (t[(k + 2) % 3]);
  for (const auto& [edge, across] : opposite) {
    const auto twin = opposite.find ({edge.second, edge.first});
    if (twin == opposite.end ())
      continue;
    EXPECT_FALSE (oppositeAnglesExceedPi (lattice.points[edge.first], lattice.points[edge.second],
                                          lattice.points[across[0]], lattice.points[twin->second[0]]))
        << "edge " << edge.first << "-" << edge.second << " is not locally Delaunay";
  }
}

TEST (PatchFlips, NothingToDoOnADelaunayLatticeOrAcrossACrease)
{
  Lattice delaunay = shearedLattice (8, -0.6); // the cut diagonals are the short ones
  const Triangles kept = delaunay.triangles;
  EXPECT_EQ (flipFlatEdgesInPatch (delaunay.points, delaunay.global_of, delaunay.uv, delaunay.triangles), 0u);
  EXPECT_EQ (delaunay.triangles, kept);

  // A quad whose diagonal a-b is long (angles near 150 degrees at c and d), bent
  // along it by about 44 degrees: a crease the angle pass must not cut at 15
  // degrees, and may at 60.
  const Points3 points = {{0.0, 0.0, 0.0}, {4.0, 0.0, 0.0}, {2.0, 0.5, 0.2}, {2.0, -0.5, 0.2}};
  const Points2 uv = {{0.0, 0.0}, {1.0, 0.0}, {0.5, 1.0}, {0.5, -1.0}};
  const std::vector<pcl::index_t> global_of = {0, 1, 2, 3};
  const Triangles quad = {{0, 1, 2}, {1, 0, 3}};
  PatchFlipOptions options;
  Triangles creased = quad;
  options.max_dihedral_deg = 15.0;
  EXPECT_EQ (flipFlatEdgesInPatch (points, global_of, uv, creased, options), 0u);
  EXPECT_EQ (creased, quad);
  options.max_dihedral_deg = 60.0;
  EXPECT_EQ (flipFlatEdgesInPatch (points, global_of, uv, creased, options), 1u);
}

TEST (PatchFlips, AQuadNotConvexInThePlaneKeepsItsDiagonal)
{
  // In space the diagonal a-b is long and c-d short (angles at c and d near 150
  // degrees each): the angle pass would swap it.
  const Points3 points = {{0.0, 0.0, 0.0}, {4.0, 0.0, 0.0}, {2.0, 0.5, 0.0}, {2.0, -0.5, 0.0}};
  const std::vector<pcl::index_t> global_of = {0, 1, 2, 3};
  const Triangles quad = {{0, 1, 2}, {1, 0, 3}};
  // Convex in the plane: flipped.
  {
    const Points2 uv = {{0.0, 0.0}, {1.0, 0.0}, {0.5, 1.0}, {0.5, -1.0}};
    Triangles triangles = quad;
    EXPECT_EQ (flipFlatEdgesInPatch (points, global_of, uv, triangles), 1u);
    EXPECT_EQ (edgeUse (triangles).count ({2, 3}), 1u) << "the new diagonal is c-d";
  }
  // d beyond b in the plane: the new triangle (d, b, c) would turn the other way.
  {
    const Points2 uv = {{0.0, 0.0}, {1.0, 0.0}, {0.5, 1.0}, {1.5, -0.1}};
    Triangles triangles = quad;
    EXPECT_EQ (flipFlatEdgesInPatch (points, global_of, uv, triangles), 0u);
    EXPECT_EQ (triangles, quad);
  }
}

TEST (PatchFlips, FlipsADelaunayTriangulationOfDistortedParameters)
{
  // Random parameter points in the unit square, triangulated by delaunay2D; in
  // space the square is stretched 1:4, so that the plane's Delaunay triangles are
  // slivers there. After the flips: same vertices, same boundary, same count, no
  // edge flippable any more.
  Points2 uv;
  Points3 points;
  std::vector<pcl::index_t> global_of;
  std::uint32_t state = 12345u;
  const auto random = [&state] () {
    state = state * 1664525u + 1013904223u;
    return static_cast<double> (state >> 8) / static_cast<double> (1u << 24);
  };
  for (int k = 0; k < 600; ++k) {
    uv.emplace_back (random (), random ());
    points.emplace_back (4.0 * uv.back ().x (), uv.back ().y (), 0.0);
    global_of.push_back (k);
  }
  Delaunay2DResult delaunay = delaunay2D (uv);
  ASSERT_TRUE (delaunay.success);
  Triangles triangles = delaunay.triangles;
  const std::size_t flips = flipFlatEdgesInPatch (points, global_of, uv, triangles);
  EXPECT_GT (flips, 100u);
  EXPECT_EQ (triangles.size (), delaunay.triangles.size ());
  EXPECT_EQ (boundaryEdges (triangles), boundaryEdges (delaunay.triangles));
  std::set<pcl::index_t> used;
  for (const Triangle& t : triangles) {
    used.insert (t.begin (), t.end ());
    EXPECT_GT (orient2d (uv[t[0]], uv[t[1]], uv[t[2]]), 0);
  }
  EXPECT_EQ (used.size (), uv.size ());
  // The stretch is affine: what is Delaunay in space is a triangulation of the same
  // points, so a second run finds nothing.
  EXPECT_EQ (flipFlatEdgesInPatch (points, global_of, uv, triangles), 0u);
}
