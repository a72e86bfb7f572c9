// The cut paths on their own: the regions they leave, the cyclic order in which
// they leave the corners of D, and the failure a cloud in two parts gives.
#include <pcl/surface/meshless/cut_paths.h>
#include <pcl/surface/meshless/normal_orientation.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <meshless_tools/synthetic_clouds.h>

#include "test_support.h"

#include <set>

using namespace pcl::meshless;

namespace {

/** The graphs the paths are routed in: the 12 nearest neighbours' rings, oriented,
  * and the mutual ring graph. */
struct RoutingGraphs
{
  CsrGraph graph;
  OrderedNeighbourhoods ordered;
  CsrGraph mutual;
  bool oriented = false;
};

RoutingGraphs
routingGraphs (const Points3& points)
{
  RoutingGraphs g;
  g.graph = meshless_test::bruteForceKnnGraph (points, 12);
  g.ordered = orderNeighbourhoods (points, g.graph);
  g.mutual = mutualRingGraph (g.ordered.rings);
  g.oriented = orientNormals (points, g.graph, g.mutual, g.ordered).success;
  return g;
}

/** The ring neighbour of corner c (a position into BaseMesh::vertices) that the path
  * of edge e leaves c through. */
pcl::index_t
firstStep (const CutPaths& paths, std::size_t e, int c)
{
  const auto& path = paths.paths[e];
  return paths.edges[e][0] == c ? path[1] : path[path.size () - 2];
}

long
ringPosition (const CsrGraph& rings, pcl::index_t v, pcl::index_t w)
{
  const pcl::index_t* it = std::find (rings.begin (v), rings.end (v), w);
  return it == rings.end (v) ? -1 : it - rings.begin (v);
}

} // namespace

TEST (CutPaths, PathsLeaveEveryCornerInTheCyclicOrderOfD)
{
  // Faces (c, a, b) of D, counter-clockwise from outside, put the path towards b
  // directly after the path towards a, counter-clockwise in c's ring.
  const Points3 points = sampleShape (SyntheticShape::BumpySphere, {3000, 5, 0.0});
  const RoutingGraphs g = routingGraphs (points);
  ASSERT_TRUE (g.oriented);
  for (BasePolyhedron polyhedron :
       {BasePolyhedron::Tetrahedron, BasePolyhedron::Octahedron, BasePolyhedron::Icosahedron}) {
    const BaseMesh base = polyhedronBaseMesh (points, polyhedron);
    const CutPaths paths = computeCutPaths (points, g.mutual, g.ordered.rings, base);
    ASSERT_TRUE (paths.success) << paths.message;
    const int corners = static_cast<int> (base.vertices.size ());
    for (int c = 0; c < corners; ++c) {
      const pcl::index_t corner = base.vertices[c];
      const long d = g.ordered.rings.degree (corner);
      // Ring position of the path from c towards each other corner, -1 if none.
      std::vector<long> leaves (corners, -1);
      for (std::size_t e = 0; e < paths.edges.size (); ++e)
        if (paths.edges[e][0] == c || paths.edges[e][1] == c) {
          const int other = paths.edges[e][0] == c ? paths.edges[e][1] : paths.edges[e][0];
          leaves[other] = ringPosition (g.ordered.rings, corner, firstStep (paths, e, c));
          ASSERT_GE (leaves[other], 0) << "a path leaves its corner outside the ring";
        }
      for (const auto& f : base.faces) {
        const int k = static_cast<int> (std::find (f.begin (), f.end (), c) - f.begin ());
        if (k == 3)
          continue;
        const long pa = leaves[f[(k + 1) % 3]], pb = leaves[f[(k + 2) % 3]];
        const long until_b = (pb - pa + d) % d;
        EXPECT_GT (until_b, 0) << "two paths leave corner " << c << " through one neighbour";
        for (int other = 0; other < corners; ++other)
          if (leaves[other] >= 0 && other != f[(k + 1) % 3] && other != f[(k + 2) % 3]) {
            const long between = (leaves[other] - pa + d) % d;
            EXPECT_FALSE (between > 0 && between < until_b)
                << "another path leaves corner " << c << " between two of one face";
          }
      }
    }
  }
}

TEST (CutPaths, EveryFaceOfDKeepsARegionAndThePathsBelongToNone)
{
  const Points3 points = sampleShape (SyntheticShape::Ellipsoid, {3000, 3, 0.0});
  const RoutingGraphs g = routingGraphs (points);
  ASSERT_TRUE (g.oriented);
  const BaseMesh base = polyhedronBaseMesh (points, BasePolyhedron::Octahedron);
  const CutPaths paths = computeCutPaths (points, g.mutual, g.ordered.rings, base);
  ASSERT_TRUE (paths.success) << paths.message;
  ASSERT_EQ (paths.face_of.size (), points.size ());

  std::set<pcl::index_t> on_path;
  for (const auto& path : paths.paths)
    on_path.insert (path.begin (), path.end ());
  std::vector<std::size_t> region_size (base.faces.size (), 0);
  for (std::size_t v = 0; v < points.size (); ++v) {
    const int f = paths.face_of[v];
    if (on_path.count (static_cast<pcl::index_t> (v))) {
      EXPECT_EQ (f, -1) << "path point " << v << " lies in a region";
      continue;
    }
    ASSERT_GE (f, -1);
    ASSERT_LT (f, static_cast<int> (base.faces.size ()));
    if (f >= 0)
      ++region_size[f];
  }
  for (std::size_t f = 0; f < base.faces.size (); ++f)
    EXPECT_GT (region_size[f], 0u) << "face " << f << " of D has no region";
}

TEST (CutPaths, CornersInTwoPartsOfTheCloudAreAnError)
{
  // Two spheres far apart: the ring graph has two components, and no path joins a
  // corner on one to a corner on the other.
  Points3 points = sampleShape (SyntheticShape::Sphere, {800, 2, 0.0});
  const std::size_t first = points.size ();
  points.reserve (2 * first);
  for (std::size_t v = 0; v < first; ++v)
    points.push_back (points[v] + Eigen::Vector3d (10.0, 0.0, 0.0));
  const RoutingGraphs g = routingGraphs (points);
  BaseMesh base;
  base.vertices = {0, 1, 2, static_cast<pcl::index_t> (first)};
  base.faces = {{{0, 2, 1}}, {{0, 1, 3}}, {{1, 2, 3}}, {{0, 3, 2}}};
  const CutPaths paths = computeCutPaths (points, g.mutual, g.ordered.rings, base);
  EXPECT_FALSE (paths.success);
  EXPECT_NE (paths.message.find ("different components"), std::string::npos) << paths.message;
  EXPECT_TRUE (paths.face_of.empty ());
}
