/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/patch_flips.h>
#include <pcl/surface/meshless/triangle_intersection.h> // orient2d

#include <Eigen/Geometry>

#include "common/constants.h"
#include "common/half_edges.h"
#include "common/swap_predicates.h" // decided as the edge swaps decide

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pcl {
namespace meshless {

std::size_t
flipFlatEdgesInPatch (const Points3& points,
                      const std::vector<pcl::index_t>& global_of,
                      const Points2& uv,
                      Triangles& triangles,
                      const PatchFlipOptions& options)
{
  const std::size_t m = uv.size ();
  if (triangles.empty () || global_of.size () != m)
    return 0;
  for (const Triangle& t : triangles)
    for (const pcl::index_t v : t)
      if (v < 0 || static_cast<std::size_t> (v) >= m)
        return 0; // outside the contract: left as it is
  // Twins of the half-edges, -1 on the boundary, in the compact form: the flips run
  // beside another patch's factorization, the peak of large clouds.
  const auto T = static_cast<std::int32_t> (triangles.size ());
  std::vector<std::int32_t> twin = halfEdgeTwins (triangles, m);
  const double cos_flat = std::cos (options.max_dihedral_deg * pi / 180.0);
  const double cos_fold = std::cos (std::clamp (options.max_fold_angle_deg, 0.0, 180.0) * pi / 180.0);
  const auto P = [&] (pcl::index_t local) -> const Eigen::Vector3d& { return points[global_of[local]]; };

  std::size_t flips = 0;
  std::size_t budget = options.flips_per_triangle * triangles.size ();
  // Every interior edge once in a sweep; after a flip, the four edges around the
  // new diagonal on a stack before the sweep goes on.
  std::vector<std::int32_t> work;
  std::int32_t sweep = 0;
  while (budget > 0) {
    std::int32_t h;
    if (!work.empty ()) {
      h = work.back ();
      work.pop_back ();
    }
    else {
      while (sweep < 3 * T && !(twin[sweep] > sweep))
        ++sweep;
      if (sweep == 3 * T)
        break;
      h = sweep++;
    }
    const std::int32_t g = twin[h];
    if (g < 0)
      continue;
    const std::int32_t t0 = h / 3, t1 = g / 3;
    const int j0 = h % 3, j1 = g % 3;
    // Triangles (a, b, c) and (b, a, d); the flip makes (c, a, d) and (d, b, c).
    const pcl::index_t a = triangles[t0][j0], b = triangles[t0][(j0 + 1) % 3];
    const pcl::index_t c = triangles[t0][(j0 + 2) % 3], d = triangles[t1][(j1 + 2) % 3];
    if (c == d)
      continue;
    const Eigen::Vector3d &pa = P (a), &pb = P (b), &pc = P (c), &pd = P (d);
    if (!oppositeAnglesExceedPi (pa, pb, pc, pd))
      continue;
    // Unit normals of the old triangles (zero if degenerate, which no flat quad has).
    const Eigen::Vector3d o0 = (pb - pa).cross (pc - pa).normalized ();
    const Eigen::Vector3d o1 = (pa - pb).cross (pd - pb).normalized ();
    if (o0.dot (o1) < cos_flat)
      continue;
    const Eigen::Vector3d n0 = (pa - pc).cross (pd - pc), n1 = (pb - pd).cross (pc - pd);
    if (nearlyDegenerateTriangle (n0, pc, pa, pd) || nearlyDegenerateTriangle (n1, pd, pb, pc) ||
        !normalsWithin (n0, n1, cos_flat))
      continue;
    const double old_cos = std::min (cos_fold, o0.dot (o1));
    if (!(normalsWithin (n0, o0, old_cos) || normalsWithin (n0, o1, old_cos)) ||
        !(normalsWithin (n1, o0, old_cos) || normalsWithin (n1, o1, old_cos)))
      continue;
    // Strictly convex in the plane: both new triangles turn as the old ones do.
    // Then c-d crosses a-b inside the quad, and no other edge of the embedding can
    // join c and d.
    const int turn = orient2d (uv[a], uv[b], uv[c]);
    if (turn == 0 || orient2d (uv[c], uv[a], uv[d]) != turn || orient2d (uv[d], uv[b], uv[c]) != turn)
      continue;

    const std::int32_t bc = twin[3 * t0 + (j0 + 1) % 3], ca = twin[3 * t0 + (j0 + 2) % 3];
    const std::int32_t ad = twin[3 * t1 + (j1 + 1) % 3], db = twin[3 * t1 + (j1 + 2) % 3];
    triangles[t0] = {c, a, d};
    triangles[t1] = {d, b, c};
    // New half-edges: 3 t0 + 0 c->a, + 1 a->d, + 2 d->c; 3 t1 + 0 d->b, + 1 b->c,
    // + 2 c->d.
    const std::int32_t links[6][2] = {{3 * t0, ca},     {3 * t0 + 1, ad}, {3 * t0 + 2, 3 * t1 + 2},
                                      {3 * t1, db},     {3 * t1 + 1, bc}, {3 * t1 + 2, 3 * t0 + 2}};
    for (const auto& link : links) {
      twin[link[0]] = link[1];
      if (link[1] >= 0)
        twin[link[1]] = link[0];
    }
    ++flips;
    --budget;
    for (const std::int32_t e : {3 * t0, 3 * t0 + 1, 3 * t1, 3 * t1 + 1})
      work.push_back (e);
  }
  return flips;
}

} // namespace meshless
} // namespace pcl
