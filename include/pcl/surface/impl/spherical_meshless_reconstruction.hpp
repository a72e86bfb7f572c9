/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/common/point_tests.h> // pcl::isFinite

#include <pcl/conversions.h>
#include <pcl/surface/meshless/neighbourhood_search.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <algorithm>
#include <limits>

namespace pcl {

template <typename PointInT>
bool
SphericalMeshlessReconstruction<PointInT>::inputIsUsable ()
{
  report_ = SphericalMeshlessReport ();
  vertex_cloud_.reset ();
  // PCL's own indices of all points (fake_indices_) may still be those of an earlier,
  // larger cloud: initCompute renews them; only the user's are checked.
  const bool user_indices = indices_ && !this->fake_indices_;
  if (!input_)
    report_.message = "no input cloud (setInputCloud)";
  else if (user_indices)
    for (const auto i : *indices_)
      if (i < 0 || static_cast<std::size_t> (i) >= input_->size ()) {
        report_.message = "an index lies outside the input cloud (setIndices)";
        break;
      }
  // PCL's kd-tree (FLANN, built by MeshConstruction before computeReconstruction)
  // measures squared distances in float: finite points more than about 1.8e19
  // apart overflow them, and FLANN's tree building asserts.
  if (report_.message.empty ()) {
    Eigen::Array3d lo = Eigen::Array3d::Constant (std::numeric_limits<double>::max ());
    Eigen::Array3d hi = -lo;
    const auto extend = [&] (const PointInT& p) {
      if (pcl::isFinite (p)) {
        lo = lo.min (p.getVector3fMap ().template cast<double> ().array ());
        hi = hi.max (p.getVector3fMap ().template cast<double> ().array ());
      }
    };
    if (user_indices)
      for (const auto i : *indices_)
        extend ((*input_)[i]);
    else
      for (const auto& p : *input_)
        extend (p);
    if ((hi >= lo).all () && !((hi - lo).maxCoeff () <= 1e18))
      report_.message = "the points span more than 1e18 units, beyond what the float kd-tree "
                        "can measure (scale the cloud)";
  }
  if (report_.message.empty ())
    return true;
  PCL_ERROR ("[pcl::%s::reconstruct] %s\n", getClassName ().c_str (), report_.message.c_str ());
  return false;
}

template <typename PointInT>
void
SphericalMeshlessReconstruction<PointInT>::reconstruct (pcl::PolygonMesh& output)
{
  if (!inputIsUsable ()) {
    output.polygons.clear ();
    output.cloud = pcl::PCLPointCloud2 ();
    return;
  }
  MeshConstruction<PointInT>::reconstruct (output);
}

template <typename PointInT>
void
SphericalMeshlessReconstruction<PointInT>::reconstruct (std::vector<pcl::Vertices>& polygons)
{
  polygons.clear ();
  if (inputIsUsable ())
    MeshConstruction<PointInT>::reconstruct (polygons);
}

template <typename PointInT>
void
SphericalMeshlessReconstruction<PointInT>::performReconstruction (pcl::PolygonMesh& output)
{
  if (!triangulate (output.polygons)) {
    output.cloud.width = output.cloud.height = 0;
    output.cloud.data.clear ();
  }
  else if (report_.smoothed)
    pcl::toPCLPointCloud2 (*vertex_cloud_, output.cloud);
}

template <typename PointInT>
void
SphericalMeshlessReconstruction<PointInT>::performReconstruction (
    std::vector<pcl::Vertices>& polygons)
{
  triangulate (polygons);
}

template <typename PointInT>
bool
SphericalMeshlessReconstruction<PointInT>::triangulate (std::vector<pcl::Vertices>& polygons)
{
  // Input hygiene and the search adapter here; the rest is PointT-free
  // (meshless::reconstruct), compiled once.
  report_ = SphericalMeshlessReport ();
  polygons.clear ();
  vertex_cloud_ = input_;
  report_.message = meshless::checkOptions (options_);
  if (!report_.message.empty ()) {
    PCL_ERROR ("[pcl::%s::reconstruct] %s\n", getClassName ().c_str (), report_.message.c_str ());
    return false;
  }
  // Finite points through indices_ (checked by inputIsUsable); a repeated index is
  // the same point.
  pcl::Indices finite;
  finite.reserve (indices_->size ());
  std::size_t num_non_finite = 0;
  for (const auto i : *indices_) {
    if (pcl::isFinite ((*input_)[i]))
      finite.push_back (i);
    else
      ++num_non_finite;
  }
  std::sort (finite.begin (), finite.end ());
  finite.erase (std::unique (finite.begin (), finite.end ()), finite.end ());
  meshless::PreparedPoints prepared;
  {
    std::vector<Eigen::Vector3f> xyz (finite.size ());
    for (std::size_t k = 0; k < finite.size (); ++k)
      xyz[k] = (*input_)[finite[k]].getVector3fMap ();
    prepared = meshless::preparePoints (xyz, finite);
  }
  pcl::Indices ().swap (finite);

  const auto search = [&] (int k) {
    meshless::NeighbourhoodOptions neighbourhood;
    neighbourhood.k = k;
    neighbourhood.radius = options_.radius;
    neighbourhood.num_threads = static_cast<int> (options_.num_threads);
    return meshless::searchNeighbourhoods (*tree_, prepared.cloud_indices, neighbourhood);
  };
  meshless::Reconstruction result = meshless::reconstruct (prepared, search, options_);
  report_ = std::move (result.report);
  report_.num_non_finite = num_non_finite;
  if (!report_.success) {
    PCL_ERROR ("[pcl::%s::reconstruct] %s\n", getClassName ().c_str (), report_.message.c_str ());
    return false;
  }
  if (report_.mesh.self_intersecting_pairs > 0)
    PCL_WARN ("[pcl::%s::reconstruct] %zu pair(s) of triangles intersect in local folds "
              "(noisy or thin input); the mesh is %s and oriented all the same\n",
              getClassName ().c_str (), report_.mesh.self_intersecting_pairs,
              options_.topology != Topology::Disc ? "closed" : "manifold");
  if (report_.smoothed) {
    auto moved = pcl::make_shared<pcl::PointCloud<PointInT>> (*input_);
    for (std::size_t i = 0; i < result.smoothed_points.size (); ++i)
      (*moved)[prepared.cloud_indices[i]].getVector3fMap () =
          (result.smoothed_points[i] + prepared.centroid).template cast<float> ();
    // An exact duplicate goes where the point it repeats went.
    for (const auto& [duplicate, repeated] : prepared.duplicates)
      (*moved)[duplicate].getVector3fMap () =
          (*moved)[prepared.cloud_indices[repeated]].getVector3fMap ();
    vertex_cloud_ = moved;
    PCL_WARN ("[pcl::%s::reconstruct] the points lie %.2f of their spacing off the surfaces "
              "fitted to them (median): the mesh runs through their projections onto those "
              "surfaces, moved by up to %g (getVertexCloud; setPointSmoothing (Off) to mesh "
              "the points as given or refuse)\n",
              getClassName ().c_str (), report_.noise.noise_ratio, report_.noise.max_offset);
  }
  // Output triangles refer to the input's indices.
  polygons.resize (result.triangles.size ());
  for (std::size_t t = 0; t < result.triangles.size (); ++t) {
    auto& vertices = polygons[t].vertices;
    vertices.resize (3);
    for (int k = 0; k < 3; ++k)
      vertices[k] = prepared.cloud_indices[result.triangles[t][k]];
  }
  return true;
}

} // namespace pcl

#define PCL_INSTANTIATE_SphericalMeshlessReconstruction(T)                            \
  template class PCL_EXPORTS pcl::SphericalMeshlessReconstruction<T>;
