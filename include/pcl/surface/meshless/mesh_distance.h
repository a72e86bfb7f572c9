/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/types.h>

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

} // namespace meshless
} // namespace pcl
