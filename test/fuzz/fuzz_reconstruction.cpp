/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
// libFuzzer target: raw bytes -> a small cloud and options ->
// pcl::SphericalMeshlessReconstruction -> the contract of the README checked from
// the outside. The process aborts when the class reports success on a mesh that
// breaks a promise, or fails without saying why; crashes, hangs, leaks, undefined
// behaviour and escaping exceptions are caught by libFuzzer and the sanitizers.
//
// Input layout (kHeader option bytes, then float triples; see make_corpus.py):
//   byte 0   k = byte % 16 (0..2 are invalid on purpose: the failure path); bit 7
//            setAllowSelfIntersections (true)
//   byte 1   bits 0-1 weight type, bit 2 disc topology, bit 3 optimization off,
//            bits 4-5 base polyhedron (0: tetrahedron, 3: by size), bit 6 no self-intersection
//            check, bit 7 ball neighbourhoods (radius from byte 2)
//   byte 2   radius = (byte + 1) / 256 of the bounding-box diagonal of the finite
//            points (with bit 7 of byte 1); otherwise bit 0 the closed topology
//            (any genus) unless bit 2 of byte 1 asks for the disc
//   byte 3   bit 0 setIndices (every point backwards, the first bits 2-7 indices
//            again), bit 1 a user base mesh on the first four points, bit 2 the
//            std::vector<pcl::Vertices> overload instead of pcl::PolygonMesh
//   then     x y z as little-endian IEEE floats, 12 bytes per point, at most
//            kMaxPoints points; a trailing partial triple is ignored.
// NaN, infinities and duplicates come from the bytes as they are.
#include <pcl/common/point_tests.h>
#include <pcl/console/print.h>
#include <pcl/point_types.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Reconstruction = pcl::SphericalMeshlessReconstruction<pcl::PointXYZ>;

constexpr std::size_t kHeader = 4;
/** Enough for every stage to do real work (patches, paths, swaps), few enough for
  * hundreds of executions per second under the sanitizers. */
constexpr std::size_t kMaxPoints = 400;

/** A broken promise: say which and stop, so that libFuzzer saves the input. */
[[noreturn]] void
broken (const char* what, const Reconstruction& reconstruction)
{
  const auto& report = reconstruction.getReport ();
  std::fprintf (stderr, "fuzz_reconstruction: %s\n  success=%d message='%s'\n  %s\n",
                what, report.success ? 1 : 0, report.message.c_str (),
                pcl::meshless::describe (report.mesh).c_str ());
  std::fflush (stderr);
  std::abort ();
}

float
readFloat (const std::uint8_t* bytes)
{
  std::uint32_t bits = static_cast<std::uint32_t> (bytes[0]) |
                       static_cast<std::uint32_t> (bytes[1]) << 8 |
                       static_cast<std::uint32_t> (bytes[2]) << 16 |
                       static_cast<std::uint32_t> (bytes[3]) << 24;
  float value;
  std::memcpy (&value, &bits, sizeof value);
  return value;
}

/** The distinct finite points the class must use, found independently of it:
  * through `indices` (all points if empty), the smallest index at each position. */
std::set<pcl::index_t>
expectedVertices (const Cloud& cloud, const pcl::Indices& indices)
{
  std::map<std::tuple<float, float, float>, pcl::index_t> first;
  auto visit = [&] (pcl::index_t i) {
    const auto& p = cloud[i];
    if (!pcl::isFinite (p))
      return;
    // Compared by value, as the class does: +0 and -0 are the same position.
    auto [it, inserted] = first.emplace (std::make_tuple (p.x, p.y, p.z), i);
    if (!inserted)
      it->second = std::min (it->second, i);
  };
  if (indices.empty ())
    for (std::size_t i = 0; i < cloud.size (); ++i)
      visit (static_cast<pcl::index_t> (i));
  else
    for (const auto i : indices)
      visit (i);
  std::set<pcl::index_t> vertices;
  for (const auto& entry : first)
    vertices.insert (entry.second);
  return vertices;
}

/** What the header bytes ask for. */
struct FuzzCase
{
  int k = 0;
  pcl::meshless::WeightType weights{};
  bool disc = false, closed = false, optimize = true, check_intersections = true, use_radius = false;
  int polyhedron = 0;
  bool use_indices = false, user_base_mesh = false, polygons_overload = false;
  bool allow_intersections = false;
  std::size_t repeats = 0;
  double radius_fraction = 0.0; // of the diagonal
};

FuzzCase
decodeHeader (const std::uint8_t* data)
{
  FuzzCase c;
  c.k = data[0] % 16;
  const std::uint8_t flags = data[1];
  c.weights = static_cast<pcl::meshless::WeightType> (flags & 3);
  c.disc = flags & 4;
  c.optimize = !(flags & 8);
  c.polyhedron = (flags >> 4) & 3;
  c.check_intersections = !(flags & 64);
  c.use_radius = flags & 128;
  c.use_indices = data[3] & 1;
  c.user_base_mesh = data[3] & 2;
  c.polygons_overload = data[3] & 4;
  c.allow_intersections = data[0] & 128;
  c.repeats = data[3] >> 3;
  c.radius_fraction = (data[2] + 1) / 256.0;
  c.closed = !c.disc && !c.use_radius && (data[2] & 1);
  return c;
}

Cloud::Ptr
decodeCloud (const std::uint8_t* data, std::size_t size)
{
  auto cloud = pcl::make_shared<Cloud> ();
  const std::size_t n = std::min ((size - kHeader) / 12, kMaxPoints);
  bool dense = true;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = data + kHeader + 12 * i;
    cloud->push_back (
        pcl::PointXYZ (readFloat (p), readFloat (p + 4), readFloat (p + 8)));
    dense = dense && pcl::isFinite (cloud->back ());
  }
  cloud->is_dense = dense; // honest: PCL's searches trust it
  return cloud;
}

/** Sets the class up as the case asks; returns the indices it was given (or none). */
pcl::Indices
configure (const FuzzCase& c, const Cloud::Ptr& cloud, Reconstruction& reconstruction)
{
  const std::size_t n = cloud->size ();
  reconstruction.setInputCloud (cloud);
  reconstruction.setNumberOfNeighbours (c.k);
  reconstruction.setWeightType (c.weights);
  if (c.disc)
    reconstruction.setTopology (Reconstruction::Topology::Disc);
  if (c.closed)
    reconstruction.setTopology (Reconstruction::Topology::Closed);
  reconstruction.setOptimize (c.optimize);
  reconstruction.setBasePolyhedron (
      c.polyhedron == 1   ? pcl::meshless::BasePolyhedron::Octahedron
      : c.polyhedron == 2 ? pcl::meshless::BasePolyhedron::Icosahedron
      : c.polyhedron == 3 ? pcl::meshless::BasePolyhedron::BySize
                          : pcl::meshless::BasePolyhedron::Tetrahedron);
  reconstruction.setCheckSelfIntersections (c.check_intersections);
  reconstruction.setAllowSelfIntersections (c.allow_intersections);
  if (c.use_radius) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant (INFINITY), hi = -lo;
    for (const auto& p : *cloud)
      if (pcl::isFinite (p)) {
        lo = lo.cwiseMin (p.getVector3fMap ().cast<double> ());
        hi = hi.cwiseMax (p.getVector3fMap ().cast<double> ());
      }
    const double diagonal = (hi - lo).norm ();
    if (std::isfinite (diagonal))
      reconstruction.setSearchRadius (diagonal * c.radius_fraction);
  }
  pcl::Indices indices;
  if (c.use_indices) {
    for (std::size_t i = n; i-- > 0;)
      indices.push_back (static_cast<pcl::index_t> (i));
    for (std::size_t r = 0; r < std::min (c.repeats, n); ++r)
      indices.push_back (static_cast<pcl::index_t> (r));
    reconstruction.setIndices (pcl::make_shared<pcl::Indices> (indices));
  }
  if (c.user_base_mesh && n >= 4) {
    std::vector<pcl::Vertices> faces (4);
    // Counter-clockwise seen from outside when point 0 is above the other three
    // and they turn counter-clockwise seen from above; inverted otherwise.
    const int corners[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    for (int f = 0; f < 4; ++f)
      faces[f].vertices.assign (corners[f], corners[f] + 3);
    reconstruction.setBaseMesh ({0, 1, 2, 3}, faces);
  }
  return indices;
}

/** A failure must say why and leave nothing behind. */
void
checkFailure (const FuzzCase& c, const pcl::PolygonMesh& mesh,
              const Reconstruction& reconstruction)
{
  const auto& report = reconstruction.getReport ();
  if (report.message.empty ())
    broken ("failure without a message", reconstruction);
  // The class checks its result before it reports success; when that check
  // fails, the class itself calls it a bug.
  if (report.message.find ("failed its own check") != std::string::npos)
    broken ("the class rejected its own result", reconstruction);
  if (!mesh.polygons.empty ())
    broken ("failure with polygons", reconstruction);
  if (!c.polygons_overload && !mesh.cloud.data.empty ())
    broken ("failure with a non-empty output cloud", reconstruction);
}

/** The polygons as triangles over the cloud, every vertex index checked. */
pcl::meshless::Triangles
trianglesOf (const pcl::PolygonMesh& mesh, const Cloud& cloud, std::set<pcl::index_t>& used,
             const Reconstruction& reconstruction)
{
  pcl::meshless::Triangles triangles;
  for (const auto& polygon : mesh.polygons) {
    if (polygon.vertices.size () != 3)
      broken ("a polygon that is not a triangle", reconstruction);
    pcl::meshless::Triangle t;
    for (int j = 0; j < 3; ++j) {
      const auto v = static_cast<pcl::index_t> (polygon.vertices[j]);
      if (v < 0 || static_cast<std::size_t> (v) >= cloud.size ())
        broken ("a vertex index outside the cloud", reconstruction);
      t[j] = v;
      used.insert (v);
    }
    triangles.push_back (t);
  }
  return triangles;
}

/** Sphere mode: closed genus 0 with 2n - 4 triangles, outward; closed mode: the
  * same with the reported genus g, 2n - 4 + 4g triangles; disc mode: one oriented
  * manifold disc with the reported holes. */
void
checkTopology (const FuzzCase& c, const pcl::meshless::MeshReport& check,
               const pcl::meshless::Triangles& triangles, const pcl::meshless::Points3& vertices,
               const std::set<pcl::index_t>& expected, const Reconstruction& reconstruction)
{
  const auto& report = reconstruction.getReport ();
  if (!c.disc) {
    const long genus = c.closed ? report.stats.genus : 0;
    if (genus < 0 || !check.isClosedManifold () || !check.isOriented () ||
        check.components != 1 || check.euler_characteristic != 2 - 2 * genus)
      broken ("closed mode: not one closed, oriented component of Euler characteristic "
              "2 - 2g",
              reconstruction);
    if (static_cast<long> (triangles.size ()) !=
        2 * static_cast<long> (expected.size ()) - 4 + 4 * genus)
      broken ("closed mode: not 2n - 4 + 4g triangles", reconstruction);
    // Outward. The class computes the volume from other roundings of the same
    // points; allow for that, far below the volume of any cloud that is not flat.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant (INFINITY), hi = -lo;
    for (const auto v : expected) {
      lo = lo.cwiseMin (vertices[v]);
      hi = hi.cwiseMax (vertices[v]);
    }
    const double extent = (hi - lo).norm ();
    if (check.signed_volume < -1e-9 * extent * extent * extent)
      broken ("sphere mode: inward orientation (negative volume)", reconstruction);
  }
  else {
    const long holes = static_cast<long> (report.holes);
    if (!check.isManifold () || !check.isOriented () || check.components != 1 ||
        static_cast<long> (check.boundary_loops) != 1 + holes ||
        check.euler_characteristic != 1 - holes)
      broken ("disc mode: not one oriented manifold disc with the reported holes",
              reconstruction);
  }
}

/** A success checked as a user would, on the input cloud's own indices. */
void
checkSuccess (const FuzzCase& c, const Cloud::Ptr& cloud, const pcl::Indices& indices,
              const pcl::PolygonMesh& mesh, const Reconstruction& reconstruction)
{
  const auto& report = reconstruction.getReport ();
  if (!report.message.empty ())
    broken ("success with a message", reconstruction);
  if (!c.polygons_overload && mesh.cloud.width * mesh.cloud.height != cloud->size ())
    broken ("the output cloud is not the input cloud", reconstruction);
  const std::set<pcl::index_t> expected = expectedVertices (*cloud, indices);
  if (report.num_points != expected.size ())
    broken ("num_points is not the number of distinct finite points", reconstruction);
  // The positions the triangles run through: the input's, or their projections
  // where a noisy cloud was smoothed.
  const auto positions = reconstruction.getVertexCloud ();
  if (!positions || positions->size () != cloud->size () ||
      (!report.smoothed && positions != cloud))
    broken ("the vertex cloud is not the input cloud or a moved copy of it", reconstruction);
  pcl::meshless::Points3 vertices (cloud->size ());
  for (std::size_t i = 0; i < cloud->size (); ++i)
    vertices[i] = (*positions)[i].getVector3fMap ().cast<double> ();
  std::set<pcl::index_t> used;
  const pcl::meshless::Triangles triangles = trianglesOf (mesh, *cloud, used, reconstruction);
  if (used != expected)
    broken ("the vertices are not exactly the distinct finite points", reconstruction);
  pcl::meshless::MeshCheckOptions options;
  // The class counts pairs on its own (centred) copy of the points, where a
  // touching pair may round differently than here: its own count is the contract.
  options.check_self_intersections = false;
  options.num_threads = 1;
  const pcl::meshless::MeshReport check =
      pcl::meshless::checkMesh (vertices, triangles, options);
  if (!check.success)
    broken ("checkMesh did not run", reconstruction);
  if (c.check_intersections && !c.allow_intersections && report.mesh.self_intersecting_pairs > 0)
    broken ("success with self-intersecting pairs, which were not allowed", reconstruction);
  checkTopology (c, check, triangles, vertices, expected, reconstruction);
}

} // namespace


extern "C" int
LLVMFuzzerInitialize (int* /*argc*/, char*** /*argv*/)
{
  // Failures are expected on many inputs; PCL_ERROR / PCL_WARN would flood the log.
  // MESHLESS_FUZZ_VERBOSE=1 keeps them, to see what the class says on one input.
  const char* verbose = std::getenv ("MESHLESS_FUZZ_VERBOSE");
  if (!verbose || std::string (verbose) != "1")
    pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t* data, std::size_t size)
{
  if (size < kHeader)
    return 0;
  const FuzzCase c = decodeHeader (data);
  const Cloud::Ptr cloud = decodeCloud (data, size);
  Reconstruction reconstruction;
  const pcl::Indices indices = configure (c, cloud, reconstruction);
  pcl::PolygonMesh mesh;
  if (c.polygons_overload)
    reconstruction.reconstruct (mesh.polygons);
  else
    reconstruction.reconstruct (mesh);
  if (reconstruction.getReport ().success)
    checkSuccess (c, cloud, indices, mesh, reconstruction);
  else
    checkFailure (c, mesh, reconstruction);
  return 0;
}
