/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <Eigen/Geometry>

namespace pcl {
namespace meshless {

/** \brief The coarse mesh D of §3 and §5 whose vertices are cloud points and whose
  * topology the result takes. */
struct BaseMesh
{
  /** \brief Cloud point of each vertex of D (distinct). */
  std::vector<pcl::index_t> vertices;
  /** \brief Faces of D as positions into `vertices`, counter-clockwise seen from
    * outside: triangles (the polyhedra), or polygons of three or more corners (§5:
    * each face becomes one disc patch). */
  std::vector<std::vector<int>> faces;
  /** \brief Optional: per cloud point, the face whose region holds it (a D grown from
    * the cloud), -1 for none. Paths then keep to the border of their edge's two faces
    * where they can. Empty (or not one entry per point): no preference. */
  std::vector<int> point_faces;
};

/** \brief Regular polyhedra whose directions pick the vertices of D. */
enum class BasePolyhedron
{
  Tetrahedron, ///< 4 faces: the paper's choice (§4)
  Octahedron,  ///< 8 faces
  Icosahedron, ///< 20 faces: shorter paths, smaller and less distorted patches
  /** The tetrahedron up to points_per_base_face_by_size * 4 points, the octahedron
    * above (see polyhedronForSize). */
  BySize
};

/** \brief Points per face above which BasePolyhedron::BySize takes more faces. */
constexpr std::size_t points_per_base_face_by_size = 125000;

/** \brief What BasePolyhedron::BySize means for n points; any other value is
  * returned as it is.
  *
  * The tetrahedron's four patches make four sparse systems whose LU factors grow
  * faster than the points (fill of a planar graph's elimination) and are solved
  * side by side: on large clouds the octahedron's eight smaller patches lower the peak
  * memory by a fifth or more and are no slower. Below 500,000 points the
  * tetrahedron, the paper's choice, stays: its fewer corners meet fewer thin parts.
  * Not the icosahedron: its twelve corners include limb tips on shapes with limbs,
  * where its paths find no room. */
BasePolyhedron
polyhedronForSize (BasePolyhedron polyhedron, std::size_t n);

/** \brief Which cloud point becomes the vertex of D for a direction w. */
enum class CornerPlacement
{
  /** The point farthest along w, maximising <v - s, w> (the paper's choice, §4). On
    * shapes with limbs it is the tip of a leg, ear or tail, where the three to five
    * paths of the corner find no room. */
  Farthest,
  /** The point seen from the centroid s closest to the direction w, maximising
    * <M (v - s), w> / |M (v - s)| with M = C^(-1/2), C the cloud's covariance:
    * where the ray along w leaves the shape in the frame in which the cloud is as
    * wide in every direction. Mostly on its bulk, since thin parts subtend small
    * solid angles, and spread along an elongated shape as around a round one. */
  AlongRays
};

/** \brief The base mesh of §4 generalised: for each vertex direction w_i of a
  * regular polyhedron (rotated by `rotation`), a cloud point chosen by `placement`
  * (by default the one maximising <v - s, w_i>, s the centroid); faces as in the
  * polyhedron.
  * Faces are then oriented by the signed volume of the chosen points, so that D
  * turns the same way as the cloud's outward orientation.
  * \param[in] eligible optional per-point mask: only points marked non-zero may
  *            become vertices (e.g. points whose ring surrounds them: a sharp tip
  *            makes a poor corner); empty means all points
  * \return an empty mesh if two directions pick the same point (the cloud is too
  *         small or too flat for this polyhedron)
  */
BaseMesh
polyhedronBaseMesh (const Points3& points,
                    BasePolyhedron polyhedron,
                    const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity (),
                    const std::vector<char>& eligible = {},
                    CornerPlacement placement = CornerPlacement::Farthest);

/** \brief Check that D is a valid sphere-topology base mesh over n points: at least
  * two faces of three or more corners, distinct in-range vertices, every edge in
  * exactly two faces used in opposite directions, every vertex's faces forming one
  * fan, connected, Euler characteristic 2. \return an empty string if valid, else
  * the reason (naming the genus of a closed D of higher genus). */
std::string
validateBaseMesh (const BaseMesh& mesh, std::size_t n);

/** \brief The genus of D if it is a valid closed base mesh over n points of any
  * genus (§5): the checks of validateBaseMesh without the Euler characteristic 2.
  * \return the genus, or -1 with `problem` set to the reason. */
int
closedBaseMeshGenus (const BaseMesh& mesh, std::size_t n, std::string& problem);

/** \brief The edges of D, each once as (smaller position, larger position) into
  * `vertices`, sorted. */
std::vector<std::array<int, 2>>
baseMeshEdges (const BaseMesh& mesh);

} // namespace meshless
} // namespace pcl
