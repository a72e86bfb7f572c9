/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/types.h>
#include <pcl/surface/meshless/weights.h>

#include <functional>

namespace pcl {
namespace meshless {

/** \brief What every pipeline builds from the neighbourhoods before it cuts: the
  * graph G, rings oriented counter-clockwise around consistent outward normals,
  * the mutual ring graph and the weights (paper §2). */
struct SurfaceGraphs : StageStatus
{
  /** \brief The symmetric connectivity graph G. */
  CsrGraph graph;
  /** \brief Connected components of G (more than one: the build failed). */
  std::size_t pieces = 0;
  /** \brief Rings and normals, oriented (orientNormals). */
  OrderedNeighbourhoods ordered;
  /** \brief Edges both end points' rings agree on (mutualRingGraph). */
  CsrGraph mutual;
  std::size_t normals_flipped = 0;
  /** \brief Edges dropped as crossing a thin part (separate_thin_sheets). */
  std::size_t sheet_edges_dropped = 0;
  /** \brief Without separate_thin_sheets: the edges a run with it would drop (0 if
    * dropping them would disconnect the graph), so that a caller knows whether
    * such a run can differ at all. */
  std::size_t sheet_edges_droppable = 0;
  Weights weights;
};

/** \brief Options of buildSurfaceGraphs(). */
struct SurfaceGraphOptions
{
  /** \brief The weights of the parameterization. Default: WeightType::MeanValue. */
  WeightType weights = WeightType::MeanValue;
  /** \brief Drop the edges across parts thinner than the point spacing (see
    * buildSurfaceGraphs). Default false. */
  bool separate_thin_sheets = false;
  /** \brief OrderingOptions::max_neighbour_elevation_deg of the rings. Default 90:
    * every neighbour kept. */
  double max_neighbour_elevation_deg = 90.0;
  /** \brief OrderingOptions::plane_weight_width of the rings. Default 0: the
    * unweighted plane. */
  double plane_weight_width = 0.0;
  /** \brief OrderingOptions::normal_fit of the rings. Default NormalFit::Plane. */
  NormalFit normal_fit = NormalFit::Plane;
  /** \brief Threads for the graph, the rings and the weights (0 = all cores). The
    * result does not depend on it. Default 0. */
  int num_threads = 0;
};

/** \brief Called after "graph", "rings" and "weights" with a short detail line;
  * return false to cancel. */
using SurfaceStageDone = std::function<bool (const std::string& stage, const std::string& detail)>;

/** \brief Symmetric graph, Delaunay rings, orientation, mutual graph, weights.
  *
  * With `separate_thin_sheets`, edges of G whose oriented normals point away from
  * each other (more than 90 degrees apart) are dropped after the orientation and
  * the rings are ordered again (unless dropping them disconnects the graph). Where
  * the surface is thinner than the point spacing, kNN edges join its two sides,
  * and rings that mix the sides fold the patches there. The test cannot tell a
  * sheet from a convex crease sharper than 90 degrees, so it is an option, which
  * the class uses as a second attempt: it removes most folds on thin parts and
  * adds some on sharp creases.
  * \param[in] neighbourhoods directed neighbourhoods N(v) of the points
  * \return fails if the graph is disconnected (several objects, outliers, too few
  *         neighbours), a stage fails, or `done` cancels (message "cancelled by
  *         the progress callback")
  */
SurfaceGraphs
buildSurfaceGraphs (const Points3& points,
                    const CsrGraph& neighbourhoods,
                    const SurfaceGraphOptions& options,
                    const SurfaceStageDone& done = {});

} // namespace meshless
} // namespace pcl
