/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/common/point_tests.h> // pcl::isFinite

#include <limits>
#include <pcl/conversions.h>
#include <pcl/surface/meshless/freed_memory.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/spherical_meshless_reconstruction.h>

#include <Eigen/Eigenvalues> // SelfAdjointEigenSolver

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace pcl {

template <typename PointInT>
bool
SphericalMeshlessReconstruction<PointInT>::inputIsUsable ()
{
  report_ = SphericalMeshlessReport ();
  if (!input_)
    report_.message = "no input cloud (setInputCloud)";
  else if (indices_)
    for (const auto i : *indices_)
      if (i < 0 || static_cast<std::size_t> (i) >= input_->size ()) {
        report_.message = "an index lies outside the input cloud (setIndices)";
        break;
      }
  // PCL's kd-tree (FLANN, built by MeshConstruction before computeReconstruction)
  // measures squared distances in float: finite points more than about 1.8e19
  // apart overflow them, and FLANN's tree building asserts (a fuzzer finding).
  if (report_.message.empty ()) {
    Eigen::Array3d lo = Eigen::Array3d::Constant (std::numeric_limits<double>::max ());
    Eigen::Array3d hi = -lo;
    const auto extend = [&] (const PointInT& p) {
      if (pcl::isFinite (p)) {
        lo = lo.min (p.getVector3fMap ().template cast<double> ().array ());
        hi = hi.max (p.getVector3fMap ().template cast<double> ().array ());
      }
    };
    if (indices_)
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
  // The conductor: input -> plain arrays -> neighbourhoods through tree_ -> the
  // PointT-free pipeline -> the check of the result -> polygons over cloud indices.
  report_ = SphericalMeshlessReport ();
  polygons.clear ();
  std::string precision_hint; // appended to failures once the points are known
  auto fail = [&] (const std::string& reason) {
    const std::string why = reason + precision_hint;
    report_.message = why;
    PCL_ERROR ("[pcl::%s::reconstruct] %s\n", getClassName ().c_str (), why.c_str ());
    polygons.clear ();
    return false;
  };

  if (!(radius_ >= 0.0) || !std::isfinite (radius_))
    return fail ("the search radius must be finite and not negative (setSearchRadius)");
  if (radius_ == 0.0 && k_ < 3)
    return fail ("the number of neighbours must be at least 3 (setNumberOfNeighbours)");
  if (base_retries_ < 0)
    return fail ("the number of base mesh retries must not be negative (setBaseRetries)");
  // Finite points through indices_ (a repeated index is the same point), then
  // exact duplicates merged into the first.
  pcl::Indices finite;
  finite.reserve (indices_->size ());
  // The input and the index range were checked by inputIsUsable ().
  for (const auto i : *indices_) {
    if (pcl::isFinite ((*input_)[i]))
      finite.push_back (i);
    else
      ++report_.num_non_finite;
  }
  std::sort (finite.begin (), finite.end ());
  finite.erase (std::unique (finite.begin (), finite.end ()), finite.end ());
  // Sorted by position (then by index, so the first of equal points is kept) as
  // one contiguous array: sorting indices that load their points from the cloud
  // took 0.48 s of random access on a million points, this 0.1 s.
  struct Keyed
  {
    float x, y, z;
    std::uint32_t k;
  };
  std::vector<Keyed> sorted (finite.size ());
  for (std::size_t k = 0; k < finite.size (); ++k) {
    const auto& p = (*input_)[finite[k]];
    sorted[k] = {p.x, p.y, p.z, static_cast<std::uint32_t> (k)};
  }
  std::sort (sorted.begin (), sorted.end (), [] (const Keyed& a, const Keyed& b) {
    if (a.x != b.x)
      return a.x < b.x;
    if (a.y != b.y)
      return a.y < b.y;
    if (a.z != b.z)
      return a.z < b.z;
    return a.k < b.k;
  });
  std::vector<char> keep (finite.size (), 1);
  for (std::size_t j = 1; j < sorted.size (); ++j)
    if (sorted[j].x == sorted[j - 1].x && sorted[j].y == sorted[j - 1].y &&
        sorted[j].z == sorted[j - 1].z) {
      keep[sorted[j].k] = 0;
      ++report_.num_duplicates;
    }
  pcl::Indices cloud_indices; // pipeline point i is input point cloud_indices[i]
  cloud_indices.reserve (finite.size ());
  for (std::size_t k = 0; k < finite.size (); ++k)
    if (keep[k])
      cloud_indices.push_back (finite[k]);
  // 21 MB on a million points that would otherwise live through every stage.
  pcl::Indices ().swap (finite);
  std::vector<Keyed> ().swap (sorted);
  std::vector<char> ().swap (keep);
  const std::size_t n = cloud_indices.size ();
  report_.num_points = n;
  const bool sphere = topology_ == Topology::Sphere;
  if (n < (sphere ? 4u : 3u))
    return fail (std::string ("a ") + (sphere ? "closed surface needs at least four" : "disc needs at least three") +
                 " distinct finite points; the input has " + std::to_string (n));

  // Centre in double precision so that clouds far from the origin keep their
  // accuracy in the geometric stages.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
  for (const auto i : cloud_indices)
    centroid += (*input_)[i].getVector3fMap ().template cast<double> ();
  centroid /= static_cast<double> (n);
  meshless::Points3 points (n);
  for (std::size_t i = 0; i < n; ++i)
    points[i] = (*input_)[cloud_indices[i]].getVector3fMap ().template cast<double> () - centroid;
  // The pipeline numbers the points along a Z-order curve, so that neighbours in
  // space are mostly neighbours in memory (every stage walks neighbourhoods; see
  // spatial_order.h for what it saves on a million points). Output triangles refer
  // to the input's indices all the same.
  {
    const std::vector<pcl::index_t> order = meshless::mortonOrder (points);
    pcl::Indices ordered_indices (n);
    meshless::Points3 ordered_points (n);
    for (std::size_t k = 0; k < n; ++k) {
      ordered_indices[k] = cloud_indices[order[k]];
      ordered_points[k] = points[order[k]];
    }
    cloud_indices.swap (ordered_indices);
    points.swap (ordered_points);
  }

  // Float coordinates far from the origin against the cloud's size (a small object
  // in UTM coordinates) are quantized before the class sees them: at 5e6 floats
  // are 0.5 apart, and a unit sphere collapses onto a few positions. Failures then
  // say so, since the stage that fails cannot know why.
  {
    double largest = 0.0;
    Eigen::Vector3d lo = points[0], hi = points[0];
    for (const auto& p : points) {
      largest = std::max (largest, (p + centroid).cwiseAbs ().maxCoeff ());
      lo = lo.cwiseMin (p);
      hi = hi.cwiseMax (p);
    }
    const double float_step = largest * static_cast<double> (std::numeric_limits<float>::epsilon ());
    const double size = (hi - lo).norm ();
    if (float_step > size / 200.0) {
      char text[256];
      std::snprintf (text, sizeof text,
                     " (the coordinates reach %.3g against a cloud %.3g across: in float they "
                     "are only %.3g apart there; subtract an offset such as the centroid "
                     "before filling the cloud)",
                     largest, size, float_step);
      precision_hint = text;
    }
  }

  // Issue 7: a cloud with no extent in some direction (all points on one plane or
  // one line) encloses no volume. Without this check the pipeline either failed in
  // the base mesh ("two base mesh directions picked the same point") or built a flat,
  // self-intersecting closed mesh that only the final check rejected as "a bug".
  // The bound is relative (1e-12 of the largest variance, i.e. 1e-6 of the extent),
  // far below any real object's thickness and above float rounding of a tilted plane.
  if (sphere) {
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero ();
    for (const auto& p : points)
      covariance += p * p.transpose ();
    const Eigen::Vector3d variances =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> (covariance, Eigen::EigenvaluesOnly)
            .eigenvalues (); // ascending
    if (!(variances[0] > 1e-12 * variances[2]))
      return fail (std::string ("all points lie ") +
                   (variances[1] > 1e-12 * variances[2] ? "in one plane" : "on one line") +
                   ": there is no closed surface through them (for a flat open surface use "
                   "setTopology (Topology::Disc))");
  }

  ProgressCallback record = [this] (const meshless::ProgressReport& stage) {
    report_.stage_seconds.emplace_back (stage.stage, stage.seconds);
    return progress_ ? progress_ (stage) : true;
  };
  const auto search_start = std::chrono::steady_clock::now ();
  meshless::NeighbourhoodOptions neighbourhood;
  neighbourhood.k = k_;
  neighbourhood.radius = radius_;
  const meshless::Neighbourhoods nb =
      meshless::searchNeighbourhoods (*tree_, cloud_indices, neighbourhood);
  if (!nb.success)
    return fail (nb.message);
  if (nb.num_empty > 0)
    return fail (std::to_string (nb.num_empty) + " point(s) have no neighbour" +
                 (radius_ > 0.0 ? " within the search radius (increase setSearchRadius)"
                                : " (check setNumberOfNeighbours)"));
  if (!record ({"neighbourhoods",
                0.02,
                std::chrono::duration<double> (std::chrono::steady_clock::now () - search_start)
                    .count (),
                std::to_string (n) + " points"}))
    return fail ("cancelled by the progress callback");

  // The neighbourhoods the current run works with (a denser set may follow, see
  // the retries below).
  const meshless::CsrGraph* neighbours = &nb.neighbours;
  meshless::Neighbourhoods denser;
  report_.neighbours_k = radius_ > 0.0 ? 0 : k_;

  meshless::Triangles triangles;
  std::vector<Eigen::Vector3f> normals; // sphere mode: the oriented point normals
  meshless::SpherePipelineOptions sphere_options; // kept for a second attempt
  meshless::SpherePipelineOptions first_options;  // the first run's, for a denser one
  if (sphere) {
    meshless::SpherePipelineOptions options;
    options.weights = weights_;
    options.polyhedron = polyhedron_;
    options.progress = record;
    // The swaps' angle pass starts inside the patches, where they are triangulated
    // in parallel (flipFlatEdgesInPatch); the swaps find most of it done.
    options.patch_flips.enabled = optimize_ && swap_options_.improve_angles;
    options.patch_flips.max_dihedral_deg = swap_options_.angle_pass_max_dihedral_deg;
    options.patch_flips.max_fold_angle_deg = swap_options_.max_fold_angle_deg;
    if (!base_faces_.empty ()) {
      // The user's base mesh refers to cloud indices; the pipeline to its points.
      std::vector<std::pair<pcl::index_t, pcl::index_t>> pipeline_of; // (cloud, pipeline)
      pipeline_of.reserve (n);
      for (std::size_t i = 0; i < n; ++i)
        pipeline_of.emplace_back (cloud_indices[i], static_cast<pcl::index_t> (i));
      std::sort (pipeline_of.begin (), pipeline_of.end ());
      for (const auto v : base_vertices_) {
        const auto it = std::lower_bound (pipeline_of.begin (), pipeline_of.end (),
                                          std::make_pair (static_cast<pcl::index_t> (v),
                                                          pcl::index_t {-1}));
        if (it == pipeline_of.end () || it->first != v)
          return fail ("a base mesh vertex is not a finite, distinct input point (setBaseMesh)");
        options.user_base_mesh.vertices.push_back (it->second);
      }
      for (const auto& face : base_faces_) {
        if (face.vertices.size () != 3)
          return fail ("base mesh faces must be triangles (setBaseMesh)");
        options.user_base_mesh.faces.push_back ({static_cast<int> (face.vertices[0]),
                                                 static_cast<int> (face.vertices[1]),
                                                 static_cast<int> (face.vertices[2])});
      }
    }
    first_options = options;
    meshless::SphereTriangulation result =
        meshless::triangulateSphere (points, nb.neighbours, options);
    meshless::releaseFreedMemory (); // the pipeline's graphs and factors (freed_memory.h)
    report_.stats = result.stats;
    if (result.success) {
      triangles = std::move (result.triangles);
      normals = std::move (result.normals);
      sphere_options = options;
    }
    else {
      // A few dozen points leave the pipeline too little to work with; if they all
      // lie on their convex hull, that is the closed surface through them.
      triangles = base_faces_.empty () ? meshless::convexHullThroughAll (points, max_hull_points)
                                       : meshless::Triangles ();
      // Neighbourhoods spanning much of the cloud are not local: name the setter.
      const bool wide = 4 * nb.neighbours.numEntries () >= n * n;
      if (triangles.empty ())
        return fail ("the spherical reconstruction failed: " + result.message +
                     (wide ? std::string (" (the neighbourhoods span a quarter of the cloud or "
                                          "more on average: lower ") +
                                 (radius_ > 0.0 ? "setSearchRadius)" : "setNumberOfNeighbours)")
                           : std::string ()));
      report_.convex_hull = true;
      record ({"hull", 0.9, 0.0, std::to_string (triangles.size ()) + " triangles"});
    }
  }
  else {
    meshless::DiscPipelineOptions options;
    options.weights = weights_;
    options.progress = record;
    meshless::DiscTriangulation result = meshless::triangulateDisc (points, nb.neighbours, options);
    if (!result.success)
      return fail ("the disc reconstruction failed: " + result.message);
    report_.holes = result.holes;
    triangles = std::move (result.triangles);
  }

  // Sphere topology: the share of the mesh's area facing against the cloud's
  // oriented normals (meshless::areaFacingAgainstNormals). A mesh turned as a whole
  // (see the check below) faces against its normals everywhere: it is measured
  // against the normals turned too. 0 in disc mode.
  auto areaAgainstNormals = [&] (const meshless::Triangles& mesh_triangles,
                                 const std::vector<Eigen::Vector3f>& mesh_normals) {
    if (!sphere || mesh_normals.size () != points.size ())
      return 0.0;
    const double against = meshless::areaFacingAgainstNormals (points, mesh_triangles, mesh_normals);
    return std::min (against, 1.0 - against);
  };

  // Local folds re-meshed away (meshless::repairFoldsByReinsertion) where the
  // listed pairs are complete and the mesh does not turn back over much of its
  // area: that cloud is rejected below whatever the repair does, and its thousands
  // of pairs would cost seconds (a thin sheet of 1,800 points: 0.2 -> 5.5 s).
  // Returns false if the progress callback cancelled.
  auto repairFolds = [&] (meshless::Triangles& mesh_triangles,
                          const std::vector<Eigen::Vector3f>& mesh_normals,
                          const meshless::MeshReport& mesh, const char* stage,
                          meshless::FoldRepairResult& repair,
                          std::vector<char>* rewritten = nullptr) {
    repair = {};
    if (mesh.self_intersecting_pairs == 0 ||
        mesh.intersecting_pairs.size () != mesh.self_intersecting_pairs || !mesh.isManifold () ||
        !mesh.isOriented () ||
        areaAgainstNormals (mesh_triangles, mesh_normals) > max_area_against_normals)
      return true;
    const auto repair_start = std::chrono::steady_clock::now ();
    meshless::FoldRepairOptions repair_options;
    if (mesh_normals.size () == points.size ()) {
      repair_options.neighbours = neighbours;
      repair_options.normals = &mesh_normals;
    }
    repair_options.rewritten = rewritten;
    repair = meshless::repairFoldsByReinsertion (points, mesh_triangles, mesh.intersecting_pairs,
                                                 repair_options);
    return record ({stage, 1.0,
                    std::chrono::duration<double> (std::chrono::steady_clock::now () - repair_start)
                        .count (),
                    std::to_string (repair.pairs_before) + " -> " +
                        std::to_string (repair.pairs_after) + " intersecting pairs, " +
                        std::to_string (repair.regions_remeshed) + " discs re-meshed, " +
                        std::to_string (repair.swaps) + " swaps"});
  };

  // What optimizeAndCheck did to one triangulation; the report takes it over when
  // that triangulation becomes the result (adopt).
  struct Checked
  {
    meshless::EdgeSwapResult optimization;
    meshless::FoldRepairResult raw_repair, repair;
    meshless::MeshReport mesh;
  };
  auto adopt = [&] (Checked&& checked) {
    report_.optimization = std::move (checked.optimization);
    report_.raw_fold_repair = std::move (checked.raw_repair);
    report_.fold_repair = std::move (checked.repair);
    report_.mesh = std::move (checked.mesh);
  };

  // Optimization and the class's own check of its result before it reports
  // success; an empty string, or what is wrong.
  auto optimizeAndCheck = [&] (meshless::Triangles& mesh_triangles,
                               const std::vector<Eigen::Vector3f>& mesh_normals,
                               Checked& checked) -> std::string {
    meshless::EdgeSwapResult& optimization = checked.optimization;
    meshless::FoldRepairResult& raw_repair = checked.raw_repair;
    meshless::FoldRepairResult& repair = checked.repair;
    meshless::MeshReport& mesh = checked.mesh;
    meshless::MeshCheckOptions check;
    check.check_self_intersections = check_self_intersections_;
    check.max_listed_intersections = 65536; // for distantIntersectingPairs and the repair
    // The slots the repair and the swaps rewrite after a raw check that listed all
    // its pairs: the final check then tests only pairs with a triangle rewritten
    // since, or in one of those pairs (MeshCheckOptions::known_apart). They rewrite
    // a few percent of the triangles (armadillo_uniform_1m: 45,364 swaps on 2M).
    // (A copy of the raw triangles to compare with took 24 MB through the swaps,
    // whose peak it raised to 605 MB.)
    std::vector<char> rewritten;
    std::vector<std::pair<std::size_t, std::size_t>> raw_pairs;
    if (optimize_ && !report_.convex_hull) {
      // The folds of the raw triangulation first: re-meshed in discs they come out
      // as the surface runs, while the swaps' own removal of intersections can leave
      // triangles across a part thinner than the point spacing (webs). Measured
      // against the swaps alone: bunny_igl 20 -> 2 intersecting pairs, cow_igl 9 -> 4,
      // armadillo_noisy_100k 2 -> 0 (10.8 -> 4.3 s: no retry needed), fandisk's
      // largest distance to its reference 1.34e-2 -> 1.23e-2 of the diagonal, the
      // same as without optimization.
      // Where that check and repair leave no pair, the swaps need not count again.
      meshless::EdgeSwapOptions swap_options = swap_options_;
      swap_options.renumber_vertices = false; // the points follow a Z-order curve (above)
      if (sphere && check_self_intersections_) {
        const auto raw_start = std::chrono::steady_clock::now ();
        const meshless::MeshReport raw = meshless::checkMesh (points, mesh_triangles, check);
        if (raw.self_intersections_checked &&
            raw.intersecting_pairs.size () == raw.self_intersecting_pairs) {
          rewritten.assign (mesh_triangles.size (), 0);
          raw_pairs = raw.intersecting_pairs;
        }
        if (!record ({"check raw", 0.93,
                      std::chrono::duration<double> (std::chrono::steady_clock::now () - raw_start)
                          .count (),
                      std::to_string (raw.self_intersecting_pairs) + " intersecting pairs"}) ||
            !repairFolds (mesh_triangles, mesh_normals, raw, "repair raw", raw_repair,
                          rewritten.empty () ? nullptr : &rewritten))
          return "cancelled by the progress callback";
        // The repair ran only on a complete list (repairFolds) and counts exactly.
        const bool repaired = raw_repair.success && raw_repair.pairs_before > 0 &&
                              raw_repair.pairs_before == raw.self_intersecting_pairs &&
                              raw_repair.pairs_after == 0;
        swap_options.input_free_of_intersections =
            raw.self_intersections_checked && (raw.self_intersecting_pairs == 0 || repaired);
      }
      meshless::releaseFreedMemory (); // the checks' and the repair's arrays
      swap_options.rewritten = rewritten.empty () ? nullptr : &rewritten;
      const auto optimize_start = std::chrono::steady_clock::now ();
      optimization = meshless::optimizeBySwaps (points, mesh_triangles, swap_options);
      if (!optimization.success)
        return "the edge-swap optimization failed: " + optimization.message +
               " (setOptimize (false) skips it)";
      if (!record ({"optimize", 0.95,
                    std::chrono::duration<double> (std::chrono::steady_clock::now () - optimize_start)
                        .count (),
                    std::to_string (optimization.swaps) + " swaps"}))
        return "cancelled by the progress callback";
    }
    const auto check_start = std::chrono::steady_clock::now ();
    meshless::MeshCheckOptions final_check = check;
    if (!rewritten.empty ()) {
      std::vector<char>& known_apart = rewritten; // in place: known apart = not rewritten
      for (char& r : known_apart)
        r = !r;
      for (const auto& [s, t] : raw_pairs)
        known_apart[s] = known_apart[t] = 0;
      final_check.known_apart = &known_apart;
    }
    mesh = meshless::checkMesh (points, mesh_triangles, final_check);
    record ({"check", 1.0,
             std::chrono::duration<double> (std::chrono::steady_clock::now () - check_start).count (),
             ""});
    // Local folds the swaps could not open: re-meshed, then checked again (the pair
    // list must be complete for the repair to trust it).
    if (!repairFolds (mesh_triangles, mesh_normals, mesh, "repair", repair))
      return "cancelled by the progress callback";
    if (repair.regions_remeshed > 0)
      mesh = meshless::checkMesh (points, mesh_triangles, check);
    // Outward, judged after the repair (re-meshing the fan of a far outlier moves
    // much of the volume: a fuzzer finding). A closed, consistently oriented mesh
    // with a negative volume is inside out as a whole: the orientation vote of the
    // normals can be carried by one far outlier (an unreliable normal with a large
    // weight). Reversing every triangle
    // turns it; of the check's figures only the volume changes, to its negative.
    if (sphere && mesh.isSphereLike () && mesh.signed_volume < 0.0) {
      for (auto& t : mesh_triangles)
        std::swap (t[1], t[2]);
      mesh.signed_volume = -mesh.signed_volume;
    }
    const bool valid =
        sphere ? mesh.isSphereLike () && mesh_triangles.size () == 2 * n - 4 && mesh.signed_volume > 0.0
               : mesh.isManifold () && mesh.isOriented () && mesh.components == 1 &&
                     mesh.boundary_loops == 1 + report_.holes &&
                     mesh.euler_characteristic == 1 - static_cast<long> (report_.holes);
    if (!valid || mesh.unused_vertices != 0)
      return "the result failed its own check (a bug; please report it with the cloud): " +
             meshless::describe (mesh);
    return "";
  };
  Checked first;
  const std::string problem = optimizeAndCheck (triangles, normals, first);
  adopt (std::move (first));
  if (!problem.empty ())
    return fail (problem);

  // A closed genus-0 surface through a cloud with handles or a boundary has to
  // turn back over itself: it intersects itself, and large parts of it face against
  // the cloud's oriented normals (see meshless::areaFacingAgainstNormals) or it
  // passes through itself between parts far apart on the mesh, where a local fold
  // of the triangulation never reaches (see meshless::distantIntersectingPairs).
  auto turnsBackWith = [&] (const meshless::Triangles& mesh_triangles,
                            const std::vector<Eigen::Vector3f>& mesh_normals,
                            const meshless::MeshReport& mesh, double& against,
                            std::size_t& distant) {
    against = areaAgainstNormals (mesh_triangles, mesh_normals);
    distant = sphere ? meshless::distantIntersectingPairs (points.size (), mesh_triangles,
                                                           mesh.intersecting_pairs,
                                                           max_local_fold_hops)
                     : 0;
    return mesh.self_intersecting_pairs > 0 &&
           (against > max_area_against_normals || distant > 0);
  };
  auto turnsBack = [&] () {
    return turnsBackWith (triangles, normals, report_.mesh, report_.area_against_normals,
                          report_.distant_intersecting_pairs);
  };

  // Another run of the sphere pipeline with `options`, optimized, repaired and
  // checked; it replaces the result if it is valid, does not turn back and
  // intersects itself less. Returns the number of the attempt whose base mesh the
  // run used, or -1 if it found none.
  auto tryAnother = [&] (const meshless::SpherePipelineOptions& options, bool& kept,
                         meshless::SpherePipelineStats* stats = nullptr) {
    kept = false;
    meshless::SphereTriangulation other = meshless::triangulateSphere (points, *neighbours, options);
    if (stats)
      *stats = other.stats;
    if (!other.success)
      return -1;
    const int attempt = other.stats.base_attempt;
    Checked checked;
    double against = 0.0;
    std::size_t distant = 0;
    if (optimizeAndCheck (other.triangles, other.normals, checked).empty () &&
        checked.mesh.self_intersecting_pairs < report_.mesh.self_intersecting_pairs &&
        !turnsBackWith (other.triangles, other.normals, checked.mesh, against, distant)) {
      triangles = std::move (other.triangles);
      normals = std::move (other.normals);
      report_.stats = other.stats;
      if (neighbours != &nb.neighbours)
        report_.neighbours_k = k_ + 2;
      adopt (std::move (checked));
      kept = true;
    }
    return attempt;
  };

  // The retries after a first run with `options` (statistics `first`) while its
  // result intersects itself.
  auto retrySequence = [&] (meshless::SpherePipelineOptions options,
                            const meshless::SpherePipelineStats& first) {
    // Where the surface is thinner than the point spacing, kNN edges join its two
    // sides and the patches fold there. If the result intersects itself, try again
    // with those edges dropped (see meshless::buildSurfaceGraphs) and keep the result
    // with fewer intersecting pairs, if it does not turn back; a failed second attempt
    // changes nothing, and a cloud without such edges (counted by the first run) makes
    // none. Also when the first result turns back: folds across thin parts can turn
    // a genus-0 cloud's first mesh back over 8% of its area (measured: cow_igl's
    // hooves and horns, depending on the order of the points), and a cloud with a
    // handle or a boundary gets a second result that turns back too (rocker_arm,
    // fertility, face_igl: rejected all the same, face_igl 0.3 s later). A second
    // result that does not turn back is a sphere-like surface by the same test the
    // first one failed, so the further base meshes below may then run; a layout that
    // hid a handle behind a membrane would have to pass that test too.
    int last_attempt = first.base_attempt;
    if (report_.mesh.self_intersecting_pairs > 0 && first.thin_part_edges > 0) {
      meshless::SpherePipelineOptions thin = options;
      thin.separate_thin_sheets = true;
      bool kept = false;
      meshless::SpherePipelineStats stats;
      tryAnother (thin, kept, &stats);
      if (kept) {
        report_.thin_sheet_retry = true;
        options = thin;
        last_attempt = stats.base_attempt;
      }
    }

    // Other base meshes cut the surface elsewhere, and a fold left by one layout may
    // not form in another (measured: horse 5 -> 0 pairs with the next rotation).
    // Further attempts of the same deterministic sequence, after the one the result
    // came from; the result with the fewest pairs is kept. Not for a result that
    // turns back (a handle or a boundary): another layout may hide the handle
    // behind a membrane without intersecting itself (measured on rocker_arm), a
    // genus-0 surface, but not a faithful one.
    if (base_faces_.empty () && report_.mesh.self_intersecting_pairs > 0 && !turnsBack ()) {
      for (int retry = 0; retry < base_retries_ && report_.mesh.self_intersecting_pairs > 0;
           ++retry) {
        meshless::SpherePipelineOptions next = options;
        next.first_attempt = last_attempt + 1;
        ++report_.base_retries;
        bool kept = false;
        last_attempt = tryAnother (next, kept);
        report_.base_retry_kept |= kept;
        if (last_attempt < 0)
          break;
      }
    }
  };
  if (sphere)
    retrySequence (sphere_options, report_.stats);

  // Folds left after all of that: the same sequence once more on the k + 2
  // nearest neighbours (the first base mesh, the thin-part run, further base
  // meshes), kept where it leaves fewer pairs. Where a part is only a few points
  // across, k neighbours may leave a point's ring one-sided or spanning the part;
  // two more close it (measured: a 1:1:20 ellipsoid sample 6 -> 0 pairs, a 93%
  // subset of bunny_igl 4 -> 0). Costs up to as many runs again, only on clouds
  // that would otherwise keep their pairs.
  if (sphere && base_faces_.empty () && radius_ == 0.0 && base_retries_ > 0 &&
      report_.mesh.self_intersecting_pairs > 0 && !turnsBack () &&
      static_cast<std::size_t> (k_) + 2 < n) {
    const auto denser_start = std::chrono::steady_clock::now ();
    neighbourhood.k = k_ + 2;
    denser = meshless::searchNeighbourhoods (*tree_, cloud_indices, neighbourhood);
    if (denser.success && denser.num_empty == 0) {
      if (!record ({"neighbourhoods", 0.02,
                    std::chrono::duration<double> (std::chrono::steady_clock::now () - denser_start)
                        .count (),
                    std::to_string (n) + " points, k = " + std::to_string (k_ + 2)}))
        return fail ("cancelled by the progress callback");
      neighbours = &denser.neighbours;
      meshless::SpherePipelineStats stats;
      bool kept = false;
      if (tryAnother (first_options, kept, &stats) >= 0)
        retrySequence (first_options, stats);
    }
  }

  // A small cloud whose mesh still intersects itself (its neighbourhoods span
  // much of it): if every point lies on the convex hull, the hull is the closed
  // surface through them, free of intersections.
  if (sphere && !report_.convex_hull && report_.mesh.self_intersecting_pairs > 0 &&
      base_faces_.empty () && n <= max_hull_points) {
    meshless::Triangles hull = meshless::convexHullThroughAll (points, max_hull_points);
    Checked checked;
    report_.convex_hull = !hull.empty ();
    if (report_.convex_hull && optimizeAndCheck (hull, normals, checked).empty () &&
        checked.mesh.self_intersecting_pairs == 0) {
      triangles = std::move (hull);
      adopt (std::move (checked));
      record ({"hull", 1.0, 0.0, std::to_string (triangles.size ()) + " triangles"});
    }
    else
      report_.convex_hull = false;
  }
  if (sphere && turnsBack ())
    return fail ("the cloud does not look like the surface of one sphere-like object: a "
                 "closed mesh through it intersects itself (" +
                 std::to_string (report_.mesh.self_intersecting_pairs) + " pairs" +
                 (report_.distant_intersecting_pairs > 0
                      ? ", " + std::to_string (report_.distant_intersecting_pairs) +
                            " of them between parts of it far apart"
                      : std::string ()) +
                 ") and " +
                 std::to_string (static_cast<int> (100.0 * report_.area_against_normals + 0.5)) +
                 "% of its area faces against the cloud's normals (a handle, genus > 0; a "
                 "boundary: use setTopology (Topology::Disc); parts thinner than the point "
                 "spacing: sample them more densely; or far outliers: remove them)");
  if (report_.mesh.self_intersecting_pairs > 0 && !allow_self_intersections_)
    return fail (std::to_string (report_.mesh.self_intersecting_pairs) +
                 " pair(s) of triangles still intersect each other after the repair" +
                 (sphere ? " and the retries, in local folds" : "") +
                 " (parts thinner than the point spacing, or noise): the mesh is " +
                 (sphere ? "closed" : "manifold") +
                 " but not embedded (setAllowSelfIntersections (true) returns it anyway; "
                 "more neighbours or a denser sample may avoid the folds)");
  if (report_.mesh.self_intersecting_pairs > 0)
    PCL_WARN ("[pcl::%s::reconstruct] %zu pair(s) of triangles intersect in local folds "
              "(noisy or thin input); the mesh is %s and oriented all the same\n",
              getClassName ().c_str (), report_.mesh.self_intersecting_pairs,
              sphere ? "closed" : "manifold");

  polygons.resize (triangles.size ());
  for (std::size_t t = 0; t < triangles.size (); ++t) {
    auto& vertices = polygons[t].vertices;
    vertices.resize (3);
    for (int k = 0; k < 3; ++k)
      vertices[k] = static_cast<pcl::index_t> (cloud_indices[triangles[t][k]]);
  }
  report_.success = true;
  return true;
}

} // namespace pcl

#define PCL_INSTANTIATE_SphericalMeshlessReconstruction(T)                            \
  template class PCL_EXPORTS pcl::SphericalMeshlessReconstruction<T>;
