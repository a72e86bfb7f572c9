// Uses the installed headers and library: generate a cloud, build its graph.
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/synthetic_clouds.h>

#include <iostream>

int
main ()
{
  using namespace pcl::meshless;
  const Points3 points = sampleShape (SyntheticShape::Sphere, {200, 1, 0.0});
  CsrGraph directed;
  directed.offsets.push_back (0);
  for (std::size_t v = 0; v < points.size (); ++v) {
    directed.adjacency.push_back (static_cast<pcl::index_t> ((v + 1) % points.size ()));
    directed.offsets.push_back (static_cast<pcl::index_t> (directed.adjacency.size ()));
  }
  const CsrGraph graph = symmetricGraph (directed);
  std::vector<pcl::index_t> labels;
  const std::size_t components = connectedComponents (graph, labels);
  std::cout << "consumer: " << graph.size () << " vertices, " << components
            << " component(s)\n";
  return components == 1 && graph.numEntries () == 2 * points.size () ? 0 : 1;
}
