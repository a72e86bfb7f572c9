/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/delaunay_2d.h>
#include <pcl/surface/meshless/patch_triangulation.h>

#include <algorithm>
#include <limits>

namespace pcl {
namespace meshless {

PatchTriangulation
triangulatePatch (const Points3& points,
                  const Weights& weights,
                  const Patch& patch,
                  const SolveOptions& options,
                  const PatchRingContext* rings,
                  const PatchFlipOptions& flips)
{
  PatchTriangulation result;
  const std::size_t loop_size = patch.loop.size ();
  const std::size_t m = patch.points.size ();
  if (loop_size < 3 || m < loop_size ||
      !std::equal (patch.loop.begin (), patch.loop.end (), patch.points.begin ())) {
    result.message = "a patch must list its loop (of at least three points) first";
    return result;
  }

  Parameterization map;
  {
    // The system goes before the triangulation starts: with the patches solved in
    // parallel, another patch's factorization may be running (the peak memory of
    // large clouds).
    const Points2 boundary_uv = circleBoundary (points, patch.loop);
    const MeshlessSystem system =
        buildMeshlessSystem (weights, patch.points, patch.loop, boundary_uv, rings);
    if (!system.success) {
      result.message = system.message;
      return result;
    }
    map = solveMeshlessSystem (system, patch.points, patch.loop, boundary_uv, options);
  }
  if (!map.success) {
    result.message = map.message;
    return result;
  }

  Delaunay2DResult delaunay = delaunay2D (map.uv);
  if (!delaunay.success) {
    result.message = "the Delaunay triangulation of the parameter points failed: " +
                     delaunay.message;
    return result;
  }
  if (delaunay.num_duplicates > 0) {
    result.message = std::to_string (delaunay.num_duplicates) +
                     " point(s) of a patch coincide with others in parameter space (the "
                     "map squeezes a thin part far inside the patch below double "
                     "precision, or the points are duplicates; another base mesh, or "
                     "more points across the part, may avoid it)";
    return result;
  }
  // The hull must be the loop, in order: local indices 0 .. loop_size-1 cyclically.
  bool hull_is_loop = delaunay.hull.size () == loop_size;
  if (hull_is_loop) {
    const auto start = static_cast<std::size_t> (delaunay.hull[0]);
    for (std::size_t k = 0; k < loop_size && hull_is_loop; ++k)
      hull_is_loop = static_cast<std::size_t> (delaunay.hull[k]) == (start + k) % loop_size;
  }
  if (!hull_is_loop) {
    result.message = "an interior point of a patch landed on its boundary in parameter "
                     "space, so the patch would not close up with its neighbours";
    return result;
  }
  const std::size_t expected = 2 * m - 2 - loop_size;
  if (delaunay.triangles.size () != expected) {
    result.message = "the patch triangulation has " + std::to_string (delaunay.triangles.size ()) +
                     " triangles instead of " + std::to_string (expected);
    return result;
  }

  if (flips.enabled)
    result.flips = flipFlatEdgesInPatch (points, patch.points, map.uv, delaunay.triangles, flips);

  result.smallest_edge = std::numeric_limits<double>::infinity ();
  for (Triangle& t : delaunay.triangles) {
    for (int k = 0; k < 3; ++k)
      result.smallest_edge =
          std::min (result.smallest_edge, (map.uv[t[k]] - map.uv[t[(k + 1) % 3]]).norm ());
    t = {patch.points[t[0]], patch.points[t[1]], patch.points[t[2]]}; // in place: one copy less
  }
  result.triangles = std::move (delaunay.triangles);
  result.uv = std::move (map.uv);
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
