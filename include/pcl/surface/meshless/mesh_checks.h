/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief What checkMesh examines besides the always computed topology and metrics. */
struct MeshCheckOptions
{
  /** \brief Default: true. Look for pairs of triangles that meet other than in
    * what they share (see MeshReport::self_intersecting_pairs). This is the only
    * expensive part: O(F log F) plus one exact test per pair of triangles whose
    * bounding boxes touch. */
  bool check_self_intersections = true;
  /** \brief Default: 8. How many intersecting pairs to list in
    * MeshReport::intersecting_pairs (the smallest ones, so the list does not depend
    * on the number of threads); 0 lists none, at most 65536 are listed. */
  std::size_t max_listed_intersections = 8;
  /** \brief Default: 0, meaning OpenMP's default. Threads for the per-triangle
    * work; the report is the same for every thread count. */
  int num_threads = 0;
  /** \brief Default: none. Optional, one entry per triangle: triangles marked
    * non-zero are known to meet no other marked triangle (for instance unchanged
    * since an earlier check of the same vertices that listed all its pairs, and in
    * none of them), so pairs of two marked triangles are not tested. The caller
    * vouches for that; the count of intersecting pairs is then exact if it holds.
    * Ignored (everything tested) if its size differs from the number of triangles.
    * Topology, angles and volume are always computed in full. */
  const std::vector<char>* known_apart = nullptr;
};

/** \brief Topology, validity and quality of a triangle mesh.
  *
  * Terms used below:
  * - a *face* is a triangle whose three indices are in range and pairwise distinct;
  *   only faces take part in the topology (edges, Euler characteristic, components)
  *   and the geometry. Triangles with an index out of range are counted in
  *   invalid_triangles, those with a repeated index in degenerate_triangles.
  * - a vertex is *used* if some face references it.
  * - geometry (degeneracy by area, self-intersections, volume, angles) looks only at
  *   faces whose three vertices have finite coordinates.
  *
  * `success` (from StageStatus) says whether the check ran to completion (it fails
  * only when memory runs out or the mesh has 2^32 vertices or 2^32 / 3 triangles or
  * more), not whether the mesh is good: that is what the counts and the predicates
  * tell.
  */
struct MeshReport : StageStatus
{
  /** \brief Size of the vertex array. */
  std::size_t num_vertices = 0;
  /** \brief Size of the triangle array (faces and non-faces). */
  std::size_t num_triangles = 0;
  /** \brief Faces: triangles with three distinct in-range indices (F in the Euler
    * characteristic). */
  std::size_t num_faces = 0;
  /** \brief Triangles with a negative index or one not below num_vertices. */
  std::size_t invalid_triangles = 0;
  std::size_t used_vertices = 0, unused_vertices = 0;
  /** \brief Used vertices with a non-finite coordinate. */
  std::size_t non_finite_vertices = 0;
  /** \brief Undirected edges of the faces. */
  std::size_t num_edges = 0;
  /** \brief Edges used by exactly one face. */
  std::size_t boundary_edges = 0;
  /** \brief Connected components of the graph formed by the boundary edges. On a
    * manifold mesh these are disjoint simple loops; two loops touching at a
    * (non-manifold) vertex count as one. */
  std::size_t boundary_loops = 0;
  /** \brief Edges used by more than two faces. */
  std::size_t non_manifold_edges = 0;
  /** \brief Used vertices whose incident edges are all manifold (one or two faces)
    * but whose faces form more than one fan, a fan being a maximal set of faces
    * connected through edges at the vertex (a bowtie has two). Vertices on a
    * non-manifold edge are not counted here: non_manifold_edges reports them. */
  std::size_t non_manifold_vertices = 0;
  /** \brief Edges used by exactly two faces that traverse them in the same
    * direction (the faces disagree on orientation). */
  std::size_t inconsistent_edges = 0;
  /** \brief Connected components of the faces, two faces being connected when they
    * share a vertex (so a bowtie is one component). */
  std::size_t components = 0;
  /** \brief used_vertices - num_edges + num_faces. */
  long euler_characteristic = 0;
  /** \brief Total genus (sum over the components) of a manifold, consistently
    * oriented mesh: (2 * components - euler_characteristic - boundary_loops) / 2;
    * 0 for a sphere or a disc, 1 for a torus. -1 where isManifold () or
    * isOriented () is false. */
  long genus = -1;
  /** \brief Triangles with a repeated (in-range) index, plus faces with finite
    * coordinates whose vertices are exactly collinear (zero area in exact
    * arithmetic, coincident vertices included). No tolerance: near-degenerate
    * slivers show in the smallest-angle statistics instead. */
  std::size_t degenerate_triangles = 0;
  /** \brief Faces with the same vertex set as an earlier face (k copies count k-1),
    * whatever their orientation. */
  std::size_t duplicate_triangles = 0;
  /** \brief Unordered pairs of faces whose closed point sets intersect in more than
    * what their shared indices entitle them to: nothing for faces without a common
    * vertex index, the vertex for one common index, the edge for two common indices;
    * faces with all three indices in common always count. Coincidence is exact:
    * "touching" means having a common point in exact arithmetic on the given double
    * coordinates, so a vertex lying exactly on another face, distinct vertices at
    * the same position, or coplanar faces folded onto each other across their
    * shared edge all count, while a gap of one unit in the last place does not.
    * The orientation predicates behind this are exact: a floating-point evaluation
    * trusted only under a conservative error bound, big-integer arithmetic otherwise.
    * Exactly degenerate faces are not tested (degenerate_triangles reports them).
    * Zero if not checked. */
  std::size_t self_intersecting_pairs = 0;
  /** \brief Whether self_intersecting_pairs was computed. */
  bool self_intersections_checked = false;
  /** \brief The first intersecting pairs (i < j, sorted), at most
    * MeshCheckOptions::max_listed_intersections of them. */
  std::vector<std::pair<std::size_t, std::size_t>> intersecting_pairs;
  /** \brief Sum of the signed volumes of the tetrahedra from the centroid of the
    * used vertices (those with finite coordinates) to each face. Meaningful for closed
    * meshes, where it is the enclosed volume, positive if the faces are
    * counter-clockwise seen from outside.
    */
  double signed_volume = 0.0;
  /** \brief Mean over the faces of the smallest interior angle, in degrees. */
  double mean_min_angle_deg = 0.0;
  /** \brief Share (0..1) of the faces whose smallest angle is below 10 degrees. */
  double share_min_angle_below_10 = 0.0;

  /** \brief Every triangle is a face, there is at least one, no two have the same
    * vertex set, and every edge and every vertex is manifold. */
  bool
  isManifold () const;

  /** \brief No edge used twice in the same direction. Combined with isManifold (),
    * the faces are consistently oriented. */
  bool
  isOriented () const;

  /** \brief Manifold, consistently oriented, without boundary. */
  bool
  isClosedManifold () const;

  /** \brief Closed manifold, one component, Euler characteristic 2. */
  bool
  isSphereLike () const;

  /** \brief Manifold, consistently oriented, one component, one boundary loop,
    * Euler characteristic 1. */
  bool
  isDiscLike () const;

  /** \brief A disc with `holes` holes: manifold, consistently oriented, one
    * component, 1 + holes boundary loops, Euler characteristic 1 - holes. */
  bool
  isDiscWithHoles (std::size_t holes) const;
};

/** \brief Checks a triangle mesh: topology, degeneracies, self-intersections, volume
  * and angle statistics. Never throws; the report is deterministic.
  * \param[in] vertices the vertex positions
  * \param[in] triangles index triples into vertices, counter-clockwise seen from
  *            outside
  * \param[in] options what to check
  */
MeshReport
checkMesh (const Points3& vertices,
           const Triangles& triangles,
           const MeshCheckOptions& options = {});

/** \brief Share of the mesh's area whose triangles face against the normals of
  * their vertices (the triangle's normal against the sum of its three vertex
  * normals), 0 .. 1.
  *
  * A faithful surface through a cloud faces the way the cloud's oriented normals
  * do almost everywhere. A closed genus-0 surface forced through a cloud of higher
  * genus or an open sheet must turn back over itself somewhere, and there large
  * parts of it face against the normals: tens of percent of the area, where
  * genus-0 scans stay at a few percent at most.
  * \param[in] normals one per vertex, oriented (need not be unit length)
  * 
eturn 0 for an empty mesh or one of zero area */
double
areaFacingAgainstNormals (const Points3& vertices,
                          const Triangles& triangles,
                          const std::vector<Eigen::Vector3f>& normals);

/** \brief How many of the given intersecting pairs join triangles that lie far
  * apart on the mesh: no vertex of the second is within `max_hops` edges of a
  * vertex of the first.
  *
  * Telling local folds from crossings. A triangulation that wrinkles where its
  * points crowd (a fold, a flap) intersects itself between triangles one or two
  * edges apart. A closed genus-0 surface forced through a cloud with a handle has
  * to pass through itself somewhere else: a membrane across the hole or a cut
  * through the tube meets the surface tens of edges away, where the folds of
  * genus-0 clouds stay within a few edges (a dozen on layered raw scans).
  * \param[in] num_vertices size of the vertex array the triangles index
  * \param[in] triangles the mesh; triangles with an index out of range are ignored
  * \param[in] pairs indices into triangles, e.g. MeshReport::intersecting_pairs;
  *   pairs naming a triangle out of range are ignored
  * \param[in] max_hops the largest edge distance still counted as local
  * \return the number of pairs farther apart than max_hops */
std::size_t
distantIntersectingPairs (std::size_t num_vertices,
                          const Triangles& triangles,
                          const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                          std::size_t max_hops);

/** \brief How many of the given neighbour pairs (u, w) whose normals agree
  * (within 60 degrees) lie more than `max_hops` edges apart on the mesh; each
  * directed entry counts once, and of each row only the twelve nearest such
  * neighbours are looked at (wider neighbourhoods reach points that any mesh puts
  * farther apart).
  *
  * Telling a handle the mesh cut through. A closed genus-0 mesh through a cloud
  * with a handle that does not intersect itself has cut the handle's tube and
  * capped both ends: points next to each other on one side of the surface, which
  * any faithful mesh joins within a few edges, then lie a whole loop apart.
  * Across a thin part or a sharp crease the normals differ and the pair is not
  * counted.
  * \param[in] neighbours the points' neighbourhoods (e.g. their k nearest)
  * \param[in] normals one per point, oriented (need not be unit length; zero:
  *   the point is skipped)
  * \return the count; 0 also if the neighbourhoods' or the normals' sizes do not
  *   match the points (nothing was looked at) */
std::size_t
neighboursSeparatedByTheMesh (const Points3& points,
                              const Triangles& triangles,
                              const CsrGraph& neighbours,
                              const std::vector<Eigen::Vector3f>& normals,
                              std::size_t max_hops,
                              int num_threads = 0);

/** \brief A compact one-paragraph human summary of a report: the kind of surface,
  * the sizes, every defect found, and the quality figures. */
std::string
describe (const MeshReport& report);

} // namespace meshless
} // namespace pcl
