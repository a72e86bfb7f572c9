// Reconstructs a Fibonacci sphere through the installed class and checks that the
// mesh is the closed one the class promises: 2n - 4 triangles over n points.
#include <pcl/point_types.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <cmath>
#include <iostream>

int
main ()
{
  // Points spread evenly over the unit sphere along a golden-angle spiral.
  constexpr int n = 400;
  const double golden_angle = M_PI * (3.0 - std::sqrt (5.0));
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt (1.0 - z * z);
    cloud->push_back (pcl::PointXYZ (static_cast<float> (r * std::cos (golden_angle * i)),
                                     static_cast<float> (r * std::sin (golden_angle * i)),
                                     static_cast<float> (z)));
  }

  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setNumberOfThreads (1);
  pcl::PolygonMesh mesh;
  reconstruction.reconstruct (mesh);

  const auto& report = reconstruction.getReport ();
  std::cout << "meshless_colcon_consumer: " << n << " points, " << mesh.polygons.size ()
            << " triangles" << (report.success ? "" : ", failed: " + report.message) << "\n";
  return report.success && mesh.polygons.size () == 2 * n - 4 ? 0 : 1;
}
