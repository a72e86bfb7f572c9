/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "common/fans.h"
#include "common/union_find.h"

#include <pcl/surface/meshless/base_mesh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <Eigen/Eigenvalues>

namespace pcl {
namespace meshless {

namespace {

struct Polyhedron
{
  std::vector<Eigen::Vector3d> directions;
  std::vector<std::array<int, 3>> faces;
};

/** Orient every face counter-clockwise seen from outside (the directions are
  * centred at the origin, so outward means positive volume with the origin). */
void
orientOutward (Polyhedron& p)
{
  for (auto& f : p.faces) {
    const Eigen::Vector3d& a = p.directions[f[0]];
    const Eigen::Vector3d& b = p.directions[f[1]];
    const Eigen::Vector3d& c = p.directions[f[2]];
    if ((b - a).cross (c - a).dot (a + b + c) < 0.0)
      std::swap (f[1], f[2]);
  }
}

Polyhedron
regularPolyhedron (BasePolyhedron kind)
{
  Polyhedron p;
  switch (kind) {
  case BasePolyhedron::BySize: // resolved by polyhedronBaseMesh before
  case BasePolyhedron::Tetrahedron:
    p.directions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    p.faces = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
    break;
  case BasePolyhedron::Octahedron:
    p.directions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int x : {0, 1})
      for (int y : {2, 3})
        for (int z : {4, 5})
          p.faces.push_back ({x, y, z});
    break;
  case BasePolyhedron::Icosahedron: {
    const double g = (1.0 + std::sqrt (5.0)) / 2.0;
    p.directions = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                    {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
    // Faces: the triples of mutually nearest directions (edge length 2).
    const int m = 12;
    for (int a = 0; a < m; ++a)
      for (int b = a + 1; b < m; ++b)
        for (int c = b + 1; c < m; ++c)
          if (std::abs ((p.directions[a] - p.directions[b]).norm () - 2.0) < 1e-9 &&
              std::abs ((p.directions[b] - p.directions[c]).norm () - 2.0) < 1e-9 &&
              std::abs ((p.directions[a] - p.directions[c]).norm () - 2.0) < 1e-9)
            p.faces.push_back ({a, b, c});
    break;
  }
  }
  for (auto& d : p.directions)
    d.normalize ();
  orientOutward (p);
  return p;
}

} // namespace

BasePolyhedron
polyhedronForSize (BasePolyhedron polyhedron, std::size_t n)
{
  if (polyhedron != BasePolyhedron::BySize)
    return polyhedron;
  return n > 4 * points_per_base_face_by_size ? BasePolyhedron::Octahedron
                                              : BasePolyhedron::Tetrahedron;
}

BaseMesh
polyhedronBaseMesh (const Points3& points,
                    BasePolyhedron polyhedron,
                    const Eigen::Matrix3d& rotation,
                    const std::vector<char>& eligible,
                    CornerPlacement placement)
{
  BaseMesh mesh;
  if (points.empty ())
    return mesh;
  const Polyhedron p = regularPolyhedron (polyhedronForSize (polyhedron, points.size ()));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
  for (const auto& v : points)
    centroid += v;
  centroid /= static_cast<double> (points.size ());
  // Rays are cast in the frame where the cloud's covariance is the identity, so
  // that an elongated shape gets its corners spread along its length as a round
  // one does around it.
  Eigen::Matrix3d whiten = Eigen::Matrix3d::Identity ();
  if (placement == CornerPlacement::AlongRays) {
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero ();
    for (const auto& v : points)
      covariance += (v - centroid) * (v - centroid).transpose ();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen (covariance);
    const Eigen::Vector3d values = eigen.eigenvalues ();
    if (values.minCoeff () > 1e-12 * values.maxCoeff ())
      whiten = eigen.eigenvectors () * values.cwiseSqrt ().cwiseInverse ().asDiagonal () *
               eigen.eigenvectors ().transpose ();
  }
  for (const auto& direction : p.directions) {
    const Eigen::Vector3d w = rotation * direction;
    pcl::index_t best = 0;
    double best_value = -std::numeric_limits<double>::infinity ();
    for (std::size_t v = 0; v < points.size (); ++v) {
      if (!eligible.empty () && !eligible[v])
        continue;
      double value = (points[v] - centroid).dot (w);
      if (placement == CornerPlacement::AlongRays) {
        const Eigen::Vector3d offset = whiten * (points[v] - centroid);
        const double length = offset.norm ();
        value = length > 0.0 ? offset.dot (w) / length : -1.0;
      }
      if (value > best_value) {
        best_value = value;
        best = static_cast<pcl::index_t> (v);
      }
    }
    if (best_value == -std::numeric_limits<double>::infinity () ||
        std::find (mesh.vertices.begin (), mesh.vertices.end (), best) != mesh.vertices.end ())
      return {};
    mesh.vertices.push_back (best);
  }
  for (const auto& f : p.faces)
    mesh.faces.push_back ({f[0], f[1], f[2]});
  // Signed volume of D's faces as placed on the cloud (relative to the centroid):
  // negative means the chosen points turn the other way than the directions.
  double volume = 0.0;
  for (const auto& f : mesh.faces)
    volume += (points[mesh.vertices[f[0]]] - centroid)
                  .dot ((points[mesh.vertices[f[1]]] - centroid)
                            .cross (points[mesh.vertices[f[2]]] - centroid));
  if (volume < 0.0)
    for (auto& f : mesh.faces)
      std::swap (f[1], f[2]);
  return mesh;
}

std::vector<std::array<int, 2>>
baseMeshEdges (const BaseMesh& mesh)
{
  std::set<std::array<int, 2>> edges;
  for (const auto& f : mesh.faces)
    for (std::size_t k = 0, m = f.size (); k < m; ++k)
      edges.insert ({std::min (f[k], f[(k + 1) % m]), std::max (f[k], f[(k + 1) % m])});
  return {edges.begin (), edges.end ()};
}

namespace {

/** Empty if D is a closed, consistently oriented manifold over n points, else why. */
std::string
closedManifoldProblem (const BaseMesh& mesh, std::size_t n)
{
  const int nv = static_cast<int> (mesh.vertices.size ());
  if (mesh.faces.size () < 2)
    return "the base mesh needs at least two faces";
  std::set<pcl::index_t> distinct (mesh.vertices.begin (), mesh.vertices.end ());
  if (static_cast<int> (distinct.size ()) != nv)
    return "the base mesh uses a cloud point twice";
  for (auto v : mesh.vertices)
    if (v < 0 || static_cast<std::size_t> (v) >= n)
      return "a base mesh vertex is not a point of the cloud";
  std::map<std::array<int, 2>, int> directed;
  std::vector<std::vector<std::array<int, 2>>> fan (nv); // per vertex: (next, prev) pairs
  for (const auto& f : mesh.faces) {
    const std::size_t m = f.size ();
    if (m < 3)
      return "a base mesh face has fewer than three corners";
    if (std::set<int> (f.begin (), f.end ()).size () != m)
      return "a base mesh face repeats a vertex";
    for (std::size_t k = 0; k < m; ++k) {
      if (f[k] < 0 || f[k] >= nv)
        return "a base mesh face refers to a missing vertex";
      if (++directed[{f[k], f[(k + 1) % m]}] > 1)
        return "a base mesh edge is used twice in the same direction (faces not "
               "consistently oriented, or more than two faces on an edge)";
      fan[f[k]].push_back ({f[(k + 1) % m], f[(k + m - 1) % m]});
    }
  }
  for (const auto& [edge, count] : directed)
    if (!directed.count ({edge[1], edge[0]}))
      return "the base mesh has a boundary edge (it must be closed)";
  for (int v = 0; v < nv; ++v) {
    if (fan[v].empty ())
      return "a base mesh vertex is in no face";
    if (!isOneFan (fan[v]))
      return "the faces around a base mesh vertex do not form one fan";
  }
  DisjointSets<int> pieces (nv);
  int components = nv;
  for (const auto& f : mesh.faces)
    for (std::size_t k = 0; k < f.size (); ++k)
      components -= pieces.join (f[k], f[(k + 1) % f.size ()]) ? 1 : 0;
  if (components != 1)
    return "the base mesh is not connected";
  return "";
}

} // namespace

int
closedBaseMeshGenus (const BaseMesh& mesh, std::size_t n, std::string& problem)
{
  problem = closedManifoldProblem (mesh, n);
  if (!problem.empty ())
    return -1;
  const long euler = static_cast<long> (mesh.vertices.size ()) -
                     static_cast<long> (baseMeshEdges (mesh).size ()) +
                     static_cast<long> (mesh.faces.size ());
  if (euler > 2 || euler % 2 != 0) {
    problem = "the base mesh's Euler characteristic " + std::to_string (euler) +
              " is not that of a closed orientable surface";
    return -1;
  }
  return static_cast<int> ((2 - euler) / 2);
}

std::string
validateBaseMesh (const BaseMesh& mesh, std::size_t n)
{
  std::string problem;
  const int genus = closedBaseMeshGenus (mesh, n, problem);
  if (genus > 0)
    return "the base mesh is not a sphere (genus " + std::to_string (genus) + ")";
  return problem;
}

} // namespace meshless
} // namespace pcl
