// The closed topology over generated families of closed shapes of genus 0 to 2:
// sizes, seeds, light noise, uneven density and points in rows. Per member:
// whether the class closed the cloud with the generator's genus (all invariants
// checked by the class itself), and whether the sphere topology refused the shapes
// with handles naming their genus. Run by hand (build/bench/closed_families
// [points ...]); the counts go to doc/benchmarks.md.
#include <meshless_tools/synthetic_clouds.h>

#include <pcl/console/print.h>
#include <pcl/console/time.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Reconstruction = pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>;
using pcl::meshless::SyntheticShape;

Cloud::Ptr
generate (SyntheticShape shape, const pcl::meshless::SyntheticCloudOptions& options)
{
  auto cloud = pcl::make_shared<Cloud> ();
  for (const auto& p : pcl::meshless::sampleShape (shape, options))
    cloud->push_back (pcl::PointXYZ (static_cast<float> (p.x ()), static_cast<float> (p.y ()),
                                     static_cast<float> (p.z ())));
  return cloud;
}

struct Outcome
{
  bool closed = false;         // closed mode: success with the generator's genus
  bool wrong = false;          // closed mode: success with another genus
  bool refused = false;        // sphere mode: refused naming the genus (genus > 0)
  bool spanned = false;        // sphere mode: a genus-0 mesh over the handles (genus > 0)
  double seconds = 0.0;        // closed mode
  std::string message;         // closed mode's failure
};

Outcome
run (SyntheticShape shape, const pcl::meshless::SyntheticCloudOptions& options)
{
  const int genus = pcl::meshless::syntheticGenus (shape);
  const Cloud::Ptr cloud = generate (shape, options);
  Outcome outcome;
  std::vector<pcl::Vertices> polygons;
  Reconstruction closed;
  closed.setTopology (Reconstruction::Topology::Closed);
  closed.setInputCloud (cloud);
  pcl::console::TicToc timer;
  timer.tic ();
  closed.reconstruct (polygons);
  outcome.seconds = timer.toc () / 1000.0;
  outcome.closed = closed.getReport ().success && closed.getReport ().stats.genus == genus;
  outcome.wrong = closed.getReport ().success && closed.getReport ().stats.genus != genus;
  outcome.message = closed.getReport ().message;
  if (genus > 0) {
    Reconstruction sphere;
    sphere.setInputCloud (cloud);
    sphere.reconstruct (polygons);
    outcome.spanned = sphere.getReport ().success;
    outcome.refused = !sphere.getReport ().success &&
                      sphere.getReport ().message.find ("genus " + std::to_string (genus)) !=
                          std::string::npos;
  }
  return outcome;
}

} // namespace

int
main (int argc, char** argv)
{
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  std::vector<std::size_t> sizes;
  for (int i = 1; i < argc; ++i)
    sizes.push_back (static_cast<std::size_t> (std::strtoul (argv[i], nullptr, 10)));
  if (sizes.empty ())
    sizes = {5000, 20000};
  const std::pair<const char*, SyntheticShape> shapes[] = {
      {"sphere", SyntheticShape::Sphere},           {"bumpy_sphere", SyntheticShape::BumpySphere},
      {"torus", SyntheticShape::Torus},             {"thin_torus", SyntheticShape::ThinTorus},
      {"fat_torus", SyntheticShape::FatTorus},      {"double_torus", SyntheticShape::DoubleTorus},
      {"knotted_tube", SyntheticShape::KnottedTube},   {"thin_limbs", SyntheticShape::ThinLimbs}};
  struct Variant
  {
    const char* name;
    double noise, uneven, stretch;
  };
  const Variant variants[] = {{"uniform", 0.0, 0.0, 0.0},
                              {"noise 0.1%", 0.001, 0.0, 0.0},
                              {"noise 0.2%", 0.002, 0.0, 0.0},
                              {"uneven 4:1", 0.0, 4.0, 0.0},
                              {"rows 3:1", 0.0, 0.0, 3.0}};
  std::printf ("| shape | genus | variant | closed with its genus | closed with another genus | sphere refused naming it | "
               "sphere gave genus 0 | seconds (closed, mean) |\n|---|---|---|---|---|---|---|---|\n");
  std::size_t all = 0, all_closed = 0, all_wrong = 0;
  for (const auto& [name, shape] : shapes)
    for (const Variant& variant : variants) {
      std::size_t members = 0, closed = 0, wrong = 0, refused = 0, spanned = 0;
      double seconds = 0.0;
      std::string last_failure;
      for (const std::size_t n : sizes)
        for (std::uint32_t seed = 1; seed <= 3; ++seed) {
          pcl::meshless::SyntheticCloudOptions options;
          options.num_points = n;
          options.seed = seed;
          options.noise = variant.noise;
          options.uneven = variant.uneven;
          options.stretch = variant.stretch;
          const Outcome outcome = run (shape, options);
          ++members;
          closed += outcome.closed;
          wrong += outcome.wrong;
          refused += outcome.refused;
          spanned += outcome.spanned;
          seconds += outcome.seconds;
          if (!outcome.closed)
            last_failure = outcome.message.substr (0, 120);
        }
      all += members;
      all_closed += closed;
      all_wrong += wrong;
      const int genus = pcl::meshless::syntheticGenus (shape);
      const auto ofMembers = [&] (std::size_t count) {
        return genus > 0 ? std::to_string (count) + " / " + std::to_string (members)
                         : std::string ("-");
      };
      std::printf ("| %s | %d | %s | %zu / %zu | %zu | %s | %s | %.2f |%s\n", name, genus,
                   variant.name, closed, members, wrong, ofMembers (refused).c_str (),
                   ofMembers (spanned).c_str (), seconds / static_cast<double> (members),
                   last_failure.empty () ? "" : (" " + last_failure).c_str ());
      std::fflush (stdout);
    }
  std::printf ("\nclosed with the right genus: %zu of %zu members; with another genus: %zu\n",
               all_closed, all, all_wrong);
  return 0;
}
