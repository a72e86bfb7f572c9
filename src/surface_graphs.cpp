/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/normal_orientation.h>
#include <pcl/surface/meshless/surface_graphs.h>

namespace pcl {
namespace meshless {

SurfaceGraphs
buildSurfaceGraphs (const Points3& points,
                    const CsrGraph& neighbourhoods,
                    WeightType weights,
                    const SurfaceStageDone& done)
{
  SurfaceGraphs result;
  auto report = [&] (const std::string& stage, const std::string& detail) {
    if (!done || done (stage, detail))
      return true;
    result.message = "cancelled by the progress callback";
    return false;
  };

  result.graph = symmetricGraph (neighbourhoods);
  std::vector<pcl::index_t> component;
  if (connectedComponents (result.graph, component) != 1) {
    result.message = "the neighbourhood graph is disconnected (several objects, outliers, "
                     "or too few neighbours: increase k or the radius)";
    return result;
  }
  if (!report ("graph", std::to_string (result.graph.numEntries () / 2) + " edges"))
    return result;

  result.ordered = orderNeighbourhoods (points, result.graph);
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
  if (!report ("rings", std::to_string (orientation.num_flipped) + " normals flipped"))
    return result;

  result.weights = computeWeights (points, result.ordered.rings, result.graph,
                                   result.ordered.normals, {weights});
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
