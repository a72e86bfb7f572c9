/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/normal_orientation.h>
#include <pcl/surface/meshless/surface_graphs.h>

namespace pcl {
namespace meshless {

namespace {

/** Whether the oriented normals of v and w point away from each other: the edge
  * crosses a part thinner than the point spacing. */
bool
acrossThinPart (const SurfaceGraphs& surface, std::size_t v, pcl::index_t w)
{
  return surface.ordered.normals[v].dot (surface.ordered.normals[w]) < 0.0f;
}

/** The graph without the edges across thin parts, and how many (undirected) it
  * lost; an empty graph if it lost none or would fall apart. */
CsrGraph
graphWithoutThinPartEdges (const SurfaceGraphs& surface, std::vector<pcl::index_t>& component, std::size_t& dropped)
{
  dropped = 0;
  for (std::size_t v = 0; v < surface.graph.size (); ++v)
    for (const pcl::index_t* w = surface.graph.begin (v); w != surface.graph.end (v); ++w)
      dropped += acrossThinPart (surface, v, *w) ? 1 : 0;
  dropped /= 2;
  if (dropped == 0)
    return {};
  CsrGraph kept;
  kept.offsets.assign (surface.graph.size () + 1, 0);
  for (std::size_t v = 0; v < surface.graph.size (); ++v) {
    for (const pcl::index_t* w = surface.graph.begin (v); w != surface.graph.end (v); ++w)
      if (!acrossThinPart (surface, v, *w))
        kept.adjacency.push_back (*w);
    kept.offsets[v + 1] = static_cast<pcl::index_t> (kept.adjacency.size ());
  }
  if (connectedComponents (kept, component) != 1) {
    dropped = 0;
    return {};
  }
  return kept;
}

/** Drops the edges whose oriented normals point away from each other and orders
  * the rings again on the rest (see buildSurfaceGraphs); leaves everything as it
  * is if that would disconnect the graph. */
void
separateThinSheets (const Points3& points,
                    std::vector<pcl::index_t>& component,
                    const OrderingOptions& ordering,
                    SurfaceGraphs& surface)
{
  std::size_t dropped = 0;
  CsrGraph kept = graphWithoutThinPartEdges (surface, component, dropped);
  if (dropped == 0)
    return;
  surface.sheet_edges_dropped = dropped;
  surface.graph = std::move (kept);
  surface.ordered = orderNeighbourhoods (points, surface.graph, ordering);
  if (!surface.ordered.success)
    return;
  surface.mutual = mutualRingGraph (surface.ordered.rings);
  orientNormals (points, surface.graph, surface.mutual, surface.ordered);
}

} // namespace

SurfaceGraphs
buildSurfaceGraphs (const Points3& points,
                    const CsrGraph& neighbourhoods,
                    const SurfaceGraphOptions& options,
                    const SurfaceStageDone& done)
{
  SurfaceGraphs result;
  auto report = [&] (const std::string& stage, const std::string& detail) {
    if (!done || done (stage, detail))
      return true;
    result.message = "cancelled by the progress callback";
    return false;
  };

  OrderingOptions ordering;
  ordering.num_threads = options.num_threads;
  ordering.max_neighbour_elevation_deg = options.max_neighbour_elevation_deg;
  ordering.plane_weight_width = options.plane_weight_width;
  ordering.normal_fit = options.normal_fit;
  WeightOptions weighting;
  weighting.type = options.weights;
  weighting.num_threads = options.num_threads;

  result.graph = symmetricGraph (neighbourhoods, options.num_threads);
  std::vector<pcl::index_t> component;
  result.pieces = connectedComponents (result.graph, component);
  if (result.pieces != 1) {
    result.message = "the neighbourhood graph is disconnected (several objects, outliers, "
                     "or too few neighbours: increase k or the radius)";
    return result;
  }
  if (!report ("graph", std::to_string (result.graph.numEntries () / 2) + " edges"))
    return result;

  result.ordered = orderNeighbourhoods (points, result.graph, ordering);
  if (!result.ordered.success) {
    result.message = result.ordered.message;
    return result;
  }
  result.mutual = mutualRingGraph (result.ordered.rings);
  const NormalOrientation orientation =
      orientNormals (points, result.graph, result.mutual, result.ordered);
  if (!orientation.success) {
    result.message = orientation.message;
    return result;
  }
  result.normals_flipped = orientation.num_flipped;
  const bool separate_thin_sheets = options.separate_thin_sheets;
  if (separate_thin_sheets)
    separateThinSheets (points, component, ordering, result);
  else
    graphWithoutThinPartEdges (result, component, result.sheet_edges_droppable);
  if (!result.ordered.success) {
    result.message = result.ordered.message;
    return result;
  }
  if (!report ("rings", std::to_string (orientation.num_flipped) + " normals flipped" +
                            (separate_thin_sheets ? ", " + std::to_string (result.sheet_edges_dropped) +
                                                        " edges across thin parts dropped"
                                                  : std::string ())))
    return result;

  result.weights = computeWeights (points, result.ordered.rings, result.graph,
                                   result.ordered.normals, weighting);
  if (!result.weights.success) {
    result.message = result.weights.message;
    return result;
  }
  if (!report ("weights", std::to_string (result.weights.num_fallbacks) + " fallbacks"))
    return result;
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
