// Off-screen pictures of meshes (VTK): shared by pcl_surface_compare and
// pcl_optimization_report. Needs an X display (xvfb-run on a headless machine).
#pragma once

#include <pcl/PolygonMesh.h>

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace meshless_tools {

/** Segments drawn over the mesh in one colour (feature lines, defects). */
struct LineSet
{
  std::vector<std::array<Eigen::Vector3d, 2>> segments;
  std::array<double, 3> colour{1.0, 0.0, 0.0};
  double width = 3.0;
};

struct RenderOptions
{
  /** Picture width and height in pixels. */
  int size = 600;
  /** Draw every triangle edge (thin, dark) over the shading. */
  bool draw_edges = false;
  /** Extra segments on top of the mesh. */
  std::vector<LineSet> lines;
  /** Camera direction from the focal point (front, a little from the right and
    * above, y up), fitted to `bounds`. */
  std::array<double, 3> view{0.5, 0.4, 1.0};
};

/** Renders the mesh (both sides shaded alike) off screen into a PNG, with the camera
  * fitted to bounds = {xmin, xmax, ymin, ymax, zmin, zmax}, so that pictures of
  * different meshes of one cloud share it.
  * \return an empty string, or the reason it failed */
std::string
renderPng (const pcl::PolygonMesh& mesh,
           const std::array<double, 6>& bounds,
           const std::string& path,
           const RenderOptions& options = {});

} // namespace meshless_tools
