// The base mesh D: polyhedra placed on the cloud, validation of user meshes.
#include <pcl/surface/meshless/base_mesh.h>
#include <meshless_tools/synthetic_clouds.h>

#include "test_support.h"

using namespace pcl::meshless;

namespace {

double
signedVolume (const Points3& points, const BaseMesh& mesh)
{
  double volume = 0.0;
  for (const auto& f : mesh.faces)
    volume += points[mesh.vertices[f[0]]].dot (
        points[mesh.vertices[f[1]]].cross (points[mesh.vertices[f[2]]]));
  return volume / 6.0;
}

} // namespace

TEST (BaseMesh, PolyhedraOnASphereAreValidOutwardSpheres)
{
  const Points3 points = sampleShape (SyntheticShape::Sphere, {2000, 1, 0.0});
  const std::pair<BasePolyhedron, std::size_t> kinds[] = {
      {BasePolyhedron::Tetrahedron, 4}, {BasePolyhedron::Octahedron, 8}, {BasePolyhedron::Icosahedron, 20}};
  for (const auto& [kind, faces] : kinds) {
    const BaseMesh mesh = polyhedronBaseMesh (points, kind);
    ASSERT_EQ (mesh.faces.size (), faces);
    EXPECT_EQ (validateBaseMesh (mesh, points.size ()), "");
    EXPECT_GT (signedVolume (points, mesh), 0.0) << "faces must turn outward";
    EXPECT_EQ (baseMeshEdges (mesh).size (), faces * 3 / 2);
  }
}

TEST (BaseMesh, BySizeIsTheTetrahedronUpToItsLimitAndTheOctahedronAbove)
{
  const std::size_t limit = 4 * points_per_base_face_by_size;
  EXPECT_EQ (polyhedronForSize (BasePolyhedron::BySize, 4), BasePolyhedron::Tetrahedron);
  EXPECT_EQ (polyhedronForSize (BasePolyhedron::BySize, limit), BasePolyhedron::Tetrahedron);
  EXPECT_EQ (polyhedronForSize (BasePolyhedron::BySize, limit + 1), BasePolyhedron::Octahedron);
  // A polyhedron the user chose stays whatever the size.
  for (BasePolyhedron kind :
       {BasePolyhedron::Tetrahedron, BasePolyhedron::Octahedron, BasePolyhedron::Icosahedron}) {
    EXPECT_EQ (polyhedronForSize (kind, 10), kind);
    EXPECT_EQ (polyhedronForSize (kind, 10 * limit), kind);
  }
  const Points3 points = sampleShape (SyntheticShape::Sphere, {2000, 1, 0.0});
  const BaseMesh mesh = polyhedronBaseMesh (points, BasePolyhedron::BySize);
  EXPECT_EQ (mesh.faces.size (), 4u);
  EXPECT_EQ (validateBaseMesh (mesh, points.size ()), "");
}

TEST (BaseMesh, TetrahedronCornersMaximiseTheirDirections)
{
  const Points3 points = sampleShape (SyntheticShape::Ellipsoid, {3000, 2, 0.0});
  const BaseMesh mesh = polyhedronBaseMesh (points, BasePolyhedron::Tetrahedron);
  ASSERT_EQ (mesh.vertices.size (), 4u);
  const Eigen::Vector3d directions[] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
  for (const auto& p : points)
    centroid += p;
  centroid /= static_cast<double> (points.size ());
  for (int i = 0; i < 4; ++i)
    for (const auto& p : points)
      EXPECT_LE ((p - centroid).dot (directions[i]),
                 (points[mesh.vertices[i]] - centroid).dot (directions[i]) + 1e-12);
}

TEST (BaseMesh, IneligibleCornersAreAvoided)
{
  const Points3 points = sampleShape (SyntheticShape::Sphere, {500, 3, 0.0});
  const BaseMesh free = polyhedronBaseMesh (points, BasePolyhedron::Tetrahedron);
  std::vector<char> eligible (points.size (), 1);
  for (auto v : free.vertices)
    eligible[v] = 0;
  const BaseMesh constrained =
      polyhedronBaseMesh (points, BasePolyhedron::Tetrahedron, Eigen::Matrix3d::Identity (), eligible);
  ASSERT_EQ (constrained.vertices.size (), 4u);
  for (auto v : constrained.vertices)
    EXPECT_TRUE (eligible[v]);
  EXPECT_TRUE (polyhedronBaseMesh (points, BasePolyhedron::Tetrahedron, Eigen::Matrix3d::Identity (),
                                   std::vector<char> (points.size (), 0))
                   .faces.empty ());
}

TEST (BaseMesh, InvalidUserMeshesAreNamed)
{
  BaseMesh tetra;
  tetra.vertices = {0, 1, 2, 3};
  tetra.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_EQ (validateBaseMesh (tetra, 10), "");

  BaseMesh open = tetra;
  open.faces.pop_back ();
  EXPECT_NE (validateBaseMesh (open, 10), "");

  BaseMesh flipped = tetra;
  std::swap (flipped.faces[0][1], flipped.faces[0][2]);
  EXPECT_NE (validateBaseMesh (flipped, 10).find ("same direction"), std::string::npos);

  BaseMesh repeated = tetra;
  repeated.vertices[3] = 0;
  EXPECT_NE (validateBaseMesh (repeated, 10).find ("twice"), std::string::npos);

  EXPECT_NE (validateBaseMesh (tetra, 3).find ("not a point"), std::string::npos);

  BaseMesh two = tetra; // two disjoint tetrahedra: closed, but in two pieces
  two.vertices = {0, 1, 2, 3, 4, 5, 6, 7};
  for (const auto& f : tetra.faces)
    two.faces.push_back ({f[0] + 4, f[1] + 4, f[2] + 4});
  EXPECT_NE (validateBaseMesh (two, 10).find ("not connected"), std::string::npos);
}
