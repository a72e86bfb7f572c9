/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief The point of triangle (a, b, c) closest to p (exact up to rounding; a
  * triangle of zero area is treated as its longest edge). */
Eigen::Vector3d
closestPointOnTriangle (const Eigen::Vector3d& p,
                        const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c);

/** \brief Where a mesh is closest to a query point. */
struct ClosestPoint
{
  /** \brief Euclidean distance; infinity if the mesh has no triangle. */
  double distance = std::numeric_limits<double>::infinity ();
  /** \brief Index of the triangle (into the mesh's triangle array) that holds point;
    * among triangles at the same distance the one with the smallest index. */
  std::size_t triangle = 0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero ();
};

/** \brief Nearest-triangle queries on a triangle mesh through a bounding-volume
  * hierarchy. A query descends into a node only while the distance to its box is
  * below the best distance found so far, so the answer is the exact nearest triangle
  * (not the one with the nearest centroid, which a large triangle next to small ones
  * would get wrong). Triangles with an index out of range or a non-finite vertex are
  * ignored. The index keeps references to both arrays: they must outlive it. At most
  * 2^32 - 1 triangles.
  */
class TriangleDistanceIndex
{
public:
  TriangleDistanceIndex (const Points3& vertices, const Triangles& triangles);

  /** \brief Number of triangles indexed. */
  std::size_t
  size () const
  {
    return faces_.size ();
  }

  ClosestPoint
  closest (const Eigen::Vector3d& p) const;

private:
  struct Node
  {
    Eigen::Vector3d lo, hi;
    std::uint32_t begin, end;
    /** Index of the right child (the left one follows its parent), 0 for a leaf. */
    std::uint32_t right;
  };

  std::uint32_t
  build (std::uint32_t begin, std::uint32_t end);

  const Points3& vertices_;
  const Triangles& triangles_;
  /** Indices of the indexed triangles, in tree order. */
  std::vector<std::uint32_t> faces_;
  std::vector<Node> nodes_;
};

struct MeshDistanceOptions
{
  /** \brief Default: 100000. Points sampled on each of the two meshes, uniformly by
    * area; the sampling error of the mean is about 1 / sqrt(samples) of the spread. */
  std::size_t samples = 100000;
  /** \brief Default: 0 (off). With L > 0, the maxima (DistanceStatistics::max)
    * also run over the points of a barycentric lattice of step 1/L on every
    * triangle of both meshes ((L+1)(L+2)/2 points each, its vertices among them),
    * so that no triangle is missed: a random sample misses small ones, and two runs
    * on meshes that differ in a few triangles sample different places. The mean and
    * the 99th percentile stay area-uniform. */
  int lattice_for_max = 0;
  /** \brief Seed of the sampling: same seed, same meshes, same report. */
  std::uint32_t seed = 1;
  /** \brief Default: 0, meaning OpenMP's default. The report does not depend on it. */
  int num_threads = 0;
};

/** \brief Distances from the points of one side to the other surface, as fractions of
  * MeshDistanceReport::diagonal. */
struct DistanceStatistics
{
  double mean = 0.0;
  /** \brief 99th percentile (nearest rank). */
  double p99 = 0.0;
  /** \brief Largest sampled distance: a lower bound of the one-sided Hausdorff
    * distance, tight up to the sample spacing. */
  double max = 0.0;
};

/** \brief How far a mesh is from a reference surface. */
struct MeshDistanceReport : StageStatus
{
  /** \brief Bounding-box diagonal of the reference mesh's used vertices, the unit of
    * every distance below. */
  double diagonal = 0.0;
  /** \brief Samples on the mesh, distances to the reference: large where the mesh
    * strays (folds, spurious triangles across a gap). */
  DistanceStatistics to_reference;
  /** \brief Samples on the reference, distances to the mesh: large where the mesh
    * misses part of the surface (holes). */
  DistanceStatistics from_reference;
  /** \brief Both sample sets pooled (same number from each side): the two-sided
    * distance. */
  DistanceStatistics two_sided;
  /** \brief Area-weighted mean, over the mesh's triangles, of the angle in degrees
    * between the triangle's plane and the plane of the reference triangle closest to
    * its centroid. Planes, not oriented normals: 0..90 degrees, so that a method
    * without a consistent orientation is judged on its geometry alone (checkMesh
    * reports the orientation). */
  double normal_deviation_deg = 0.0;
};

/** \brief Two-sided sampled distance and normal deviation between a mesh and a
  * reference mesh. Fails (with a message) if either has no triangle of positive area
  * or 2^32 triangles or more.
  * Deterministic; never throws.
  */
MeshDistanceReport
compareToReference (const Points3& vertices,
                    const Triangles& triangles,
                    const Points3& reference_vertices,
                    const Triangles& reference_triangles,
                    const MeshDistanceOptions& options = {});

/** \brief For each vertex, the reference vertex at exactly the same position.
  *
  * Coordinates are compared exactly (no tolerance): meant for a cloud made of a mesh's
  * vertices, in any order. Where several reference vertices share a position, the
  * one with the smallest index stands for all of them.
  * \param[in] vertices the points to look up
  * \param[in] reference_vertices the vertices to look them up in
  * \return #vertices indices into reference_vertices, -1 where no reference vertex
  *         has the same coordinates (or the point is not finite)
  */
std::vector<pcl::index_t>
matchVerticesByPosition (const Points3& vertices, const Points3& reference_vertices);

struct EdgeComparisonOptions
{
  /** \brief Default: 30. A reference edge is sharp when the normals of its two
    * triangles turn by more than this angle (degrees): the feature lines of machined
    * parts turn by 45 to 90 degrees, their smooth parts by a few. */
  double sharp_angle_deg = 30.0;
};

/** \brief Which edges of a mesh are edges of a reference mesh, for a mesh whose
  * vertices are (some of) the reference's vertices. */
struct EdgeComparison : StageStatus
{
  /** \brief Distinct undirected edges of the mesh. */
  std::size_t edges = 0;
  /** \brief Vertices used by the mesh with no reference vertex at their position;
    * their edges count as not found. */
  std::size_t unmatched_vertices = 0;
  /** \brief Edges of the mesh that are edges of the reference. */
  std::size_t reference_edges = 0;
  /** \brief reference_edges / edges (0 without edges). 1 means the mesh has the
    * reference's connectivity wherever they share vertices. */
  double reference_edge_fraction = 0.0;
  /** \brief Interior reference edges whose two triangles turn by more than
    * EdgeComparisonOptions::sharp_angle_deg (the model's feature lines). */
  std::size_t sharp_edges = 0;
  /** \brief Of those, the ones that are edges of the mesh. */
  std::size_t sharp_edges_found = 0;
  /** \brief sharp_edges_found / sharp_edges (0 without sharp edges). */
  double sharp_edge_fraction = 0.0;
  /** \brief The sharp edges the mesh lacks, as pairs of reference vertex indices
    * (for pictures and diagnostics), sorted. */
  std::vector<std::array<pcl::index_t, 2>> missing_sharp_edges;
};

/** \brief Counts the mesh's edges that are reference edges, and the reference's sharp
  * edges that the mesh has, matching vertices by exact position
  * (matchVerticesByPosition), so the two vertex arrays need not share an order.
  * Triangles with an index out of range are ignored; an edge is counted once however
  * many triangles use it. Deterministic; never throws (fails with a message when out
  * of memory).
  * \param[in] vertices, triangles the mesh
  * \param[in] reference_vertices, reference_triangles the reference mesh
  * \param[in] options what makes a reference edge sharp
  */
EdgeComparison
compareEdges (const Points3& vertices,
              const Triangles& triangles,
              const Points3& reference_vertices,
              const Triangles& reference_triangles,
              const EdgeComparisonOptions& options = {});

} // namespace meshless
} // namespace pcl
