// Uses the installed headers and library as a PCL user does: a sampled sphere in,
// a closed mesh out.
#include <pcl/point_types.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <cmath>
#include <iostream>

int
main ()
{
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  const int n = 300;
  const double golden = M_PI * (3.0 - std::sqrt (5.0));
  for (int i = 0; i < n; ++i) { // a Fibonacci lattice on the unit sphere
    const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt (1.0 - z * z);
    cloud->push_back (pcl::PointXYZ (static_cast<float> (r * std::cos (golden * i)),
                                     static_cast<float> (r * std::sin (golden * i)),
                                     static_cast<float> (z)));
  }
  pcl::SphericalMeshlessReconstruction<pcl::PointXYZ> reconstruction;
  reconstruction.setInputCloud (cloud);
  reconstruction.setNumberOfThreads (1);
  pcl::PolygonMesh mesh;
  reconstruction.reconstruct (mesh);
  std::cout << "consumer: " << mesh.polygons.size () << " triangles through " << n
            << " points\n";
  return reconstruction.getReport ().success && mesh.polygons.size () == 2u * n - 4 ? 0 : 1;
}
