/*
 * Software License Agreement (BSD License)
 *
 *  pcl_spherical_meshless: meshless triangulation of point clouds with spherical
 *  topology (Hormann and Reimers 2003) for the Point Cloud Library.
 */
#pragma once

#include <pcl/types.h> // pcl::index_t

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

/** \brief PointT-free stages of the meshless reconstruction pipeline.
  *
  * Every stage is a function of plain arrays: 3D points as Eigen vectors in double
  * precision (the conductor centres the cloud first, so float clouds far from the
  * origin keep their precision), graphs in compressed sparse row form, triangles as
  * index triples. Stages neither print nor throw; they return a result struct whose
  * `success` and `message` say what happened.
  */
namespace pcl {
namespace meshless {

/** \brief 3D points, one per input point, in the conductor's centred frame. */
using Points3 = std::vector<Eigen::Vector3d>;
/** \brief 2D points (local projections, parameter points). */
using Points2 = std::vector<Eigen::Vector2d>;
/** \brief A triangle as three vertex indices, counter-clockwise seen from outside. */
using Triangle = std::array<pcl::index_t, 3>;
using Triangles = std::vector<Triangle>;

/** \brief Adjacency lists of n vertices in compressed sparse row form.
  *
  * The neighbours of vertex v are `adjacency[offsets[v]] .. adjacency[offsets[v+1]-1]`;
  * `offsets` has n + 1 entries (or none for an empty graph).
  */
struct CsrGraph
{
  std::vector<pcl::index_t> offsets;
  std::vector<pcl::index_t> adjacency;

  /** \brief Number of vertices. */
  std::size_t
  size () const
  {
    return offsets.empty () ? 0 : offsets.size () - 1;
  }

  /** \brief Number of stored (directed) entries. */
  std::size_t
  numEntries () const
  {
    return adjacency.size ();
  }

  pcl::index_t
  degree (pcl::index_t v) const
  {
    return offsets[v + 1] - offsets[v];
  }

  const pcl::index_t*
  begin (pcl::index_t v) const
  {
    return adjacency.data () + offsets[v];
  }

  const pcl::index_t*
  end (pcl::index_t v) const
  {
    return adjacency.data () + offsets[v + 1];
  }
};

/** \brief What every stage result carries: did it work, and if not, why. */
struct StageStatus
{
  bool success = false;
  /** \brief Empty on success; otherwise one sentence naming the cause. */
  std::string message;
};

} // namespace meshless
} // namespace pcl
