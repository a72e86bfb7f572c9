/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "common/constants.h"
#include "common/half_edges.h"
#include "common/spacing.h"
#include "common/stage_clock.h"
#include "common/union_find.h"

#include <pcl/surface/meshless/delaunay_2d.h>
#include <pcl/surface/meshless/disc_pipeline.h>
#include <pcl/surface/meshless/mesh_checks.h>
#include <pcl/surface/meshless/neighbourhood_graph.h>
#include <pcl/surface/meshless/normal_orientation.h>
#include <pcl/surface/meshless/ordered_neighbourhoods.h>
#include <pcl/surface/meshless/patch_triangulation.h>
#include <pcl/surface/meshless/surface_graphs.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

namespace pcl {
namespace meshless {

namespace {

/** Winding number of polygon `loop` (parameter points) around p. */
int
windingNumber (const Points2& uv, const std::vector<pcl::index_t>& loop, const Eigen::Vector2d& p)
{
  int winding = 0;
  for (std::size_t k = 0; k < loop.size (); ++k) {
    const Eigen::Vector2d& a = uv[loop[k]];
    const Eigen::Vector2d& b = uv[loop[(k + 1) % loop.size ()]];
    const double side = (b.x () - a.x ()) * (p.y () - a.y ()) - (p.x () - a.x ()) * (b.y () - a.y ());
    if (a.y () <= p.y ()) {
      if (b.y () > p.y () && side > 0.0)
        ++winding;
    }
    else if (b.y () <= p.y () && side < 0.0)
      --winding;
  }
  return winding;
}

/** \brief The loop with the points it stepped over put back. On a lattice or a
  * pixel outline the boundary runs through nearly collinear points, and a ring can
  * reach past the nearer one to the next; left inside, such a point maps inside the
  * circle and its triangles fold over the loop edge or lie flat along it. So does a
  * point the walk passed by off the surface (samples in rows: a row's end beyond
  * the chord of its neighbours). A point of either end's ring that projects inside
  * an edge and lies within a tenth of its length of it, or off the surface's side
  * (on the edge's right, around the ends' normals) within a quarter, joins the loop there,
  * the nearest to the edge's start first; the two new edges are looked at again. */
std::vector<pcl::index_t>
withSteppedOverPoints (const Points3& points,
                       const std::vector<Eigen::Vector3f>& normals,
                       const CsrGraph& rings,
                       const std::vector<pcl::index_t>& loop,
                       std::vector<char>& taken)
{
  const double max_offset = 0.1;          // of the edge's length, either side
  const double max_outside_offset = 0.25; // of the edge's length, off the surface's side
  std::vector<pcl::index_t> result;
  result.reserve (loop.size ());
  std::vector<std::pair<pcl::index_t, pcl::index_t>> edges; // to look at, last first
  for (std::size_t k = 0; k < loop.size (); ++k) {
    edges.assign (1, {loop[k], loop[(k + 1) % loop.size ()]});
    while (!edges.empty ()) {
      const auto [a, b] = edges.back ();
      edges.pop_back ();
      const Eigen::Vector3d along = points[b] - points[a];
      const double length_squared = along.squaredNorm ();
      const Eigen::Vector3d inward = (normals[a] + normals[b]).cast<double> ().cross (along);
      pcl::index_t best = -1;
      double best_t = 1.0;
      for (const pcl::index_t end : {a, b})
        for (const pcl::index_t* d = rings.begin (end); d != rings.end (end); ++d) {
          if (taken[*d] || !(length_squared > 0.0))
            continue;
          const Eigen::Vector3d offset = points[*d] - points[a];
          const double t = offset.dot (along) / length_squared;
          const double limit = offset.dot (inward) < 0.0 ? max_outside_offset : max_offset;
          if (t > 0.0 && t < best_t &&
              (offset - t * along).squaredNorm () <= limit * limit * length_squared) {
            best = *d;
            best_t = t;
          }
        }
      if (best < 0) {
        result.push_back (a);
        continue;
      }
      taken[best] = 1;
      edges.push_back ({best, b});
      edges.push_back ({a, best});
    }
  }
  return result;
}

/** \brief The median length of a closed loop's edges. */
double
medianEdge (const Points3& points, const std::vector<pcl::index_t>& loop)
{
  std::vector<double> edges (loop.size ());
  for (std::size_t k = 0; k < loop.size (); ++k)
    edges[k] = (points[loop[(k + 1) % loop.size ()]] - points[loop[k]]).norm ();
  return median (edges);
}

/** \brief The median of `spacing` over a loop's points. */
double
medianSpacing (const std::vector<double>& spacing, const std::vector<pcl::index_t>& loop)
{
  std::vector<double> values (loop.size ());
  for (std::size_t k = 0; k < loop.size (); ++k)
    values[k] = spacing[loop[k]];
  return median (values);
}

/** \brief The length of a closed loop. */
double
loopLength (const Points3& points, const std::vector<pcl::index_t>& loop)
{
  double length = 0.0;
  for (std::size_t k = 0; k < loop.size (); ++k)
    length += (points[loop[(k + 1) % loop.size ()]] - points[loop[k]]).norm ();
  return length;
}

/** \brief The mean of a loop's points. */
Eigen::Vector3d
loopCentroid (const Points3& points, const std::vector<pcl::index_t>& loop)
{
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero ();
  for (const auto v : loop)
    centroid += points[v];
  return centroid / static_cast<double> (loop.size ());
}

/** \brief The least distance of a loop's points from their centroid. */
double
centroidClearance (const Points3& points, const std::vector<pcl::index_t>& loop)
{
  const Eigen::Vector3d centroid = loopCentroid (points, loop);
  double nearest = std::numeric_limits<double>::max ();
  for (const auto v : loop)
    nearest = std::min (nearest, (points[v] - centroid).norm ());
  return nearest;
}

/** \brief Twice a loop's area over its length: a circle's radius, and for a
  * ragged or off-centre hole still about its radius (the area is the vector
  * area's, the largest of the loop's projections). */
double
halfWidth (const Points3& points, const std::vector<pcl::index_t>& loop)
{
  Eigen::Vector3d vector_area = Eigen::Vector3d::Zero ();
  for (std::size_t k = 0; k < loop.size (); ++k)
    vector_area += 0.5 * (points[loop[k]] - points[loop[0]])
                             .cross (points[loop[(k + 1) % loop.size ()]] - points[loop[0]]);
  const double length = loopLength (points, loop);
  return length > 0.0 ? 2.0 * vector_area.norm () / length : 0.0;
}

/** \brief sampleSpacing of every point over its row of `neighbourhoods`. */
std::vector<double>
sampleSpacings (const Points3& points, const CsrGraph& neighbourhoods)
{
  std::vector<double> spacing (points.size (), 0.0), distances;
  for (std::size_t v = 0; v < points.size (); ++v) {
    const auto vi = static_cast<pcl::index_t> (v);
    spacing[v] = sampleSpacing (points, vi, neighbourhoods.begin (vi), neighbourhoods.end (vi),
                                distances);
  }
  return spacing;
}

/** \brief The points and weights with one more point per hole, at its rim's
  * centroid. A rim point's ring is open towards the hole (its weights then the
  * fallback's, over its unordered neighbourhood) or spans it with long edges (on
  * a concave rim), and the map folded rims next to rows, clusters or uneven
  * sampling. With the centre its ring surrounds it on the surface's side: mean
  * value weights over the ring closed by the centre (kept as they were where
  * those do not exist), the centre's own on the rim points evenly, so that each
  * hole is nearly a fan, which tends to keep the rim simple in the map (as Tutte's
  * theorem does for convex combinations over planar graphs). */
struct WithHoleCentres
{
  Points3 points;
  Weights weights;
};

WithHoleCentres
withHoleCentres (const Points3& points,
                 const Weights& weights,
                 const std::vector<Eigen::Vector3f>& normals,
                 const CsrGraph& rings,
                 const std::vector<std::vector<pcl::index_t>>& holes)
{
  const std::size_t n = points.size ();
  std::vector<pcl::index_t> centre_of (n, -1); // one each: the walks take their loops' points
  WithHoleCentres result;
  result.points = points;
  for (std::size_t h = 0; h < holes.size (); ++h) {
    for (const auto v : holes[h])
      centre_of[v] = static_cast<pcl::index_t> (n + h);
    result.points.push_back (loopCentroid (points, holes[h]));
  }
  CsrGraph& graph = result.weights.neighbours;
  std::vector<double>& values = result.weights.values;
  graph.offsets.assign (1, 0);
  std::vector<std::pair<double, pcl::index_t>> around;
  Points2 ring;
  std::vector<double> lambda;
  for (std::size_t v = 0; v < n; ++v) {
    const auto vi = static_cast<pcl::index_t> (v);
    bool closed = false;
    if (centre_of[v] >= 0) {
      // v's ring and the centre, counter-clockwise in v's tangent plane
      const Eigen::Vector3d normal = normals[v].cast<double> ().normalized ();
      const Eigen::Vector3d u = normal.unitOrthogonal (), w = normal.cross (u);
      around.clear ();
      auto add = [&] (pcl::index_t d) {
        const Eigen::Vector3d offset = result.points[d] - points[v];
        around.emplace_back (std::atan2 (offset.dot (w), offset.dot (u)), d);
      };
      for (const pcl::index_t* d = rings.begin (vi); d != rings.end (vi); ++d)
        add (*d);
      add (centre_of[v]);
      std::sort (around.begin (), around.end ());
      ring.clear ();
      for (const auto& [angle, d] : around) {
        const Eigen::Vector3d offset = result.points[d] - points[v];
        ring.emplace_back (offset.dot (u), offset.dot (w));
      }
      closed = meanValueWeights (ring, lambda);
      if (closed)
        for (std::size_t k = 0; k < around.size (); ++k) {
          graph.adjacency.push_back (around[k].second);
          values.push_back (lambda[k]);
        }
    }
    if (!closed)
      for (auto k = weights.neighbours.offsets[v]; k < weights.neighbours.offsets[v + 1]; ++k) {
        graph.adjacency.push_back (weights.neighbours.adjacency[k]);
        values.push_back (weights.values[k]);
      }
    graph.offsets.push_back (static_cast<pcl::index_t> (graph.adjacency.size ()));
  }
  for (const auto& rim : holes) {
    for (const auto v : rim) {
      graph.adjacency.push_back (v);
      values.push_back (1.0 / static_cast<double> (rim.size ()));
    }
    graph.offsets.push_back (static_cast<pcl::index_t> (graph.adjacency.size ()));
  }
  result.weights.success = true;
  return result;
}

/** Walks boundary loops along the mutual ring graph with the outer-face rule
  * (see findBoundaryLoops), and keeps which points the loops found so far hold. */
class BoundaryWalker
{
public:
  BoundaryWalker (const Points3& points,
                  const std::vector<Eigen::Vector3f>& normals,
                  const CsrGraph& rings,
                  const CsrGraph& mutual,
                  std::size_t min_loop,
                  bool cut_notches)
  : points_ (points)
  , normals_ (normals)
  , rings_ (rings)
  , mutual_ (mutual)
  , min_loop_ (min_loop)
  , cut_notches_ (cut_notches)
  , on_loop_ (points.size (), 0)
  , seen_in_walk_ (points.size (), -1)
  {}

  bool
  onLoop (pcl::index_t v) const
  {
    return on_loop_[v] != 0;
  }

  /** Marks a loop found by another walker as taken. */
  void
  take (const std::vector<pcl::index_t>& loop)
  {
    for (const auto v : loop)
      on_loop_[v] = 1;
  }

  /** The loop walked from `start` (empty if the walk does not close one of at
    * least min_loop points), its points then taken, with the points it steps over. */
  std::vector<pcl::index_t>
  loopFrom (pcl::index_t start)
  {
    std::vector<pcl::index_t> loop;
    if (!walk (start, loop) || loop.size () < min_loop_)
      return {};
    for (auto v : loop)
      on_loop_[v] = 1;
    return withSteppedOverPoints (points_, normals_, rings_, loop, on_loop_);
  }

private:
  /** v's walkable neighbours: its ring members that are mutual, in ring
    * (counter-clockwise) order. */
  void
  walkable (pcl::index_t v, std::vector<pcl::index_t>& out) const
  {
    out.clear ();
    for (const pcl::index_t* w = rings_.begin (v); w != rings_.end (v); ++w)
      if (std::binary_search (mutual_.begin (v), mutual_.end (v), *w))
        out.push_back (*w);
  }

  /** The neighbour of `current` that follows `previous` counter-clockwise, or -1. */
  pcl::index_t
  after (pcl::index_t current, pcl::index_t previous)
  {
    walkable (current, around_);
    const auto it = std::find (around_.begin (), around_.end (), previous);
    if (it == around_.end () || around_.size () < 2)
      return -1;
    return around_[(static_cast<std::size_t> (it - around_.begin ()) + 1) % around_.size ()];
  }

  /** The ring member of `start` at the end of its largest angular gap, or -1. */
  pcl::index_t
  firstStep (pcl::index_t start)
  {
    walkable (start, around_);
    if (around_.size () < 2)
      return -1;
    localCoordinates (points_, start, around_.data (), around_.data () + around_.size (),
                      normals_[start].cast<double> (), LocalPlane::ProjectOntoFit, local_);
    std::size_t gap_end = 0;
    double widest = -1.0;
    for (std::size_t j = 0; j < around_.size (); ++j) {
      const Eigen::Vector2d& a = local_[j];
      const Eigen::Vector2d& b = local_[(j + 1) % around_.size ()];
      double angle = std::atan2 (a.x () * b.y () - a.y () * b.x (), a.dot (b));
      if (angle <= 0.0)
        angle += two_pi;
      if (angle > widest) {
        widest = angle;
        gap_end = (j + 1) % around_.size ();
      }
    }
    return around_[gap_end];
  }

  /** Walks from `start` into `loop`. \return whether it closed. */
  bool
  walk (pcl::index_t start, std::vector<pcl::index_t>& loop)
  {
    ++walk_id_;
    pcl::index_t previous = start, current = firstStep (start);
    if (current < 0)
      return false;
    loop = {start};
    seen_in_walk_[start] = walk_id_;
    const std::size_t n = points_.size ();
    // Cutting off notches shortens the loop: the steps are bounded too.
    for (std::size_t steps = 0; loop.size () <= n && steps <= 2 * n; ++steps) {
      if (current == start)
        return true;
      if (on_loop_[current])
        return false; // another loop
      if (seen_in_walk_[current] == walk_id_) {
        if (!cut_notches_)
          return false; // a figure of eight: not a simple boundary
        switch (cutNotch (current, loop)) {
        case Notch::Kept:
          return false;
        case Notch::LoopClosed:
          return true;
        case Notch::Cut:
          break; // on from current, turning from the last point walked into it
        }
      }
      else {
        seen_in_walk_[current] = walk_id_;
        loop.push_back (current);
      }
      const pcl::index_t next = after (current, previous);
      if (next < 0)
        return false;
      previous = current;
      current = next;
    }
    return false;
  }

  enum class Notch { Kept, LoopClosed, Cut };

  /** The walk meets `current` again (a notch pinched to one point): of the two
    * loops through it, the longer one is the boundary and the shorter one's points
    * fall inside, if it is too short to be a loop. */
  Notch
  cutNotch (pcl::index_t current, std::vector<pcl::index_t>& loop)
  {
    const auto again = std::find (loop.begin (), loop.end (), current);
    const auto index = static_cast<std::size_t> (again - loop.begin ());
    if (std::min (loop.size () - index, index + 1) >= min_loop_)
      return Notch::Kept;
    if (loop.size () - index > index + 1) {
      loop.erase (loop.begin (), again);
      return Notch::LoopClosed;
    }
    for (auto k = index + 1; k < loop.size (); ++k)
      seen_in_walk_[loop[k]] = -1;
    loop.resize (index + 1);
    return Notch::Cut;
  }

  const Points3& points_;
  const std::vector<Eigen::Vector3f>& normals_;
  const CsrGraph& rings_;
  const CsrGraph& mutual_;
  const std::size_t min_loop_;
  const bool cut_notches_;
  std::vector<char> on_loop_;
  std::vector<int> seen_in_walk_;
  int walk_id_ = 0;
  std::vector<pcl::index_t> around_;
  Points2 local_;
};

/** \brief The triangles of `disc` whose parameter centroid lies outside every
  * hole's parameter polygon, into `kept`. \return whether they make a disc with
  * that many holes through every point, none of them touching a hole's centre
  * (an index past the points): a folded map can split a hole's rim into several
  * loops or keep a centre's triangles. */
bool
trianglesOutsideHoles (const Points3& points,
                       const PatchTriangulation& disc,
                       const Patch& patch,
                       const std::vector<std::vector<pcl::index_t>>& holes,
                       int num_threads,
                       Triangles& kept)
{
  const std::size_t n = points.size ();
  std::vector<pcl::index_t> local_of (n + holes.size (), -1);
  for (std::size_t i = 0; i < patch.points.size (); ++i)
    local_of[patch.points[i]] = static_cast<pcl::index_t> (i);
  std::vector<std::vector<pcl::index_t>> rims = holes;
  for (auto& rim : rims)
    for (auto& v : rim)
      v = local_of[v];
  kept.clear ();
  for (const Triangle& t : disc.triangles) {
    const Eigen::Vector2d centroid =
        (disc.uv[local_of[t[0]]] + disc.uv[local_of[t[1]]] + disc.uv[local_of[t[2]]]) / 3.0;
    const bool in_hole = std::any_of (rims.begin (), rims.end (), [&] (const auto& rim) {
      return windingNumber (disc.uv, rim, centroid) != 0;
    });
    if (in_hole)
      continue;
    if (std::any_of (t.begin (), t.end (),
                     [&] (pcl::index_t v) { return static_cast<std::size_t> (v) >= n; }))
      return false;
    kept.push_back (t);
  }
  MeshCheckOptions light;
  light.num_threads = num_threads;
  light.check_self_intersections = false;
  const MeshReport cut = checkMesh (points, kept, light);
  return cut.isDiscWithHoles (holes.size ()) && cut.unused_vertices == 0;
}

} // namespace

BoundaryLoops
findBoundaryLoops (const Points3& points,
                   const std::vector<Eigen::Vector3f>& normals,
                   const CsrGraph& rings,
                   const CsrGraph& mutual,
                   const std::vector<float>& largest_gap,
                   double min_gap,
                   std::size_t min_loop,
                   const std::vector<double>& spacing,
                   double min_rim_gap)
{
  BoundaryLoops result;
  const std::size_t n = points.size ();
  const double least_gap = std::min (min_gap, min_rim_gap);
  std::vector<pcl::index_t> candidates;
  for (std::size_t v = 0; v < n; ++v)
    if (largest_gap[v] >= least_gap)
      candidates.push_back (static_cast<pcl::index_t> (v));
  std::stable_sort (candidates.begin (), candidates.end (),
                    [&] (pcl::index_t a, pcl::index_t b) { return largest_gap[a] > largest_gap[b]; });
  const auto rims = std::find_if (candidates.begin (), candidates.end (),
                                  [&] (pcl::index_t v) { return largest_gap[v] < min_gap; });

  std::optional<BoundaryWalker> walker;
  auto walkFrom = [&] (pcl::index_t start) {
    if (walker->onLoop (start))
      return;
    std::vector<pcl::index_t> loop = walker->loopFrom (start);
    if (!loop.empty ())
      result.loops.push_back (std::move (loop));
  };
  // Walks stop where the outline passes a point twice; only where that leaves no
  // loop at all do they walk again and cut such notches off (a loop found the
  // first way is never traded for one found by cutting).
  for (const bool cut_notches : {false, true}) {
    if (cut_notches && !result.loops.empty ())
      break;
    walker.emplace (points, normals, rings, mutual, min_loop, cut_notches);
    std::for_each (candidates.begin (), rims, walkFrom);
  }
  auto longer = [&] (const std::vector<pcl::index_t>& a, const std::vector<pcl::index_t>& b) {
    return loopLength (points, a) > loopLength (points, b);
  };
  std::stable_sort (result.loops.begin (), result.loops.end (), longer);
  // Where the outer boundary is too ragged to walk, the longest loop found can be a
  // gap of the sample: as the outer loop it would fold the whole map. An outer loop
  // is a gap's if it is neither wide nor long (a boundary is some square root of
  // the point count long, a gap a few points).
  const double min_outline_width = 2.0; // loop edges
  if (!result.loops.empty () &&
      centroidClearance (points, result.loops.front ()) <
          min_outline_width * medianEdge (points, result.loops.front ()) &&
      static_cast<double> (result.loops.front ().size ()) < 0.5 * std::sqrt (static_cast<double> (n))) {
    result.message = "the outline is too ragged to follow: the longest loop found (" +
                     std::to_string (result.loops.front ().size ()) +
                     " points) is a gap of the sample, not its boundary (noise along the "
                     "outline: smooth the points first; or too few neighbours)";
    result.loops.clear ();
    return result;
  }
  // The rim of a round hole a few spacings wide is concave all round: none of its
  // gaps reaches min_gap. Its walks start once the outline is known (the smaller
  // gaps walked must not stand in for a missed outline), without cutting notches;
  // the longest loop stays the outline.
  if (!result.loops.empty () && rims != candidates.end ()) {
    walker.emplace (points, normals, rings, mutual, min_loop, false);
    for (const auto& loop : result.loops)
      walker->take (loop);
    std::for_each (rims, candidates.end (), walkFrom);
    std::stable_sort (result.loops.begin (), result.loops.end (), longer);
  }
  // An inner loop is a hole only if it is wider than the gaps of the sample itself:
  // jittered or noisy samples leave gaps a few points around, as wide as a scan's
  // small dropouts. Narrower loops are closed over (measured: doc/benchmarks.md). The
  // points' spacing is the yardstick where given; loop edges are coarser (the walk
  // steps over rim points, and dense clusters shorten a gap's edges).
  const bool spaced = spacing.size () == n;
  const double min_hole_half_width = spaced ? 2.05 : 1.5;
  auto narrow = [&] (const std::vector<pcl::index_t>& loop) {
    const double yardstick = spaced ? medianSpacing (spacing, loop) : medianEdge (points, loop);
    return !(yardstick > 0.0 && halfWidth (points, loop) >= min_hole_half_width * yardstick);
  };
  if (result.loops.size () > 1)
    result.loops.erase (std::remove_if (result.loops.begin () + 1, result.loops.end (), narrow),
                        result.loops.end ());
  result.success = !result.loops.empty ();
  if (!result.success)
    result.message = "no boundary loop found: the cloud looks closed (use the sphere "
                     "topology) or its boundary is too ragged for k neighbours";
  return result;
}

std::size_t
openMissedHoles (const Points3& points, const CsrGraph& neighbourhoods, Triangles& triangles,
                 double max_span)
{
  const std::size_t n = points.size ();
  const std::vector<double> spacing = sampleSpacings (points, neighbourhoods);
  auto spans = [&] (const Triangle& t) {
    for (int e = 0; e < 3; ++e) {
      const pcl::index_t a = t[e], b = t[(e + 1) % 3];
      const double local = std::max (spacing[a], spacing[b]);
      if (local > 0.0 && (points[a] - points[b]).norm () > max_span * local)
        return true;
    }
    return false;
  };
  std::vector<char> removed (triangles.size (), 0);
  bool any = false;
  for (std::size_t t = 0; t < triangles.size (); ++t)
    if (spans (triangles[t]))
      removed[t] = any = true;
  if (!any)
    return 0;
  // Regions: long triangles joined across their shared edges. One that reaches the
  // boundary is no hole (removed, it would only move the outline): it stays.
  const std::vector<std::int32_t> twins = halfEdgeTwins (triangles, n);
  DisjointSets<std::uint32_t> regions (triangles.size ());
  for (std::size_t h = 0; h < twins.size (); ++h)
    if (twins[h] >= 0 && removed[h / 3] && removed[static_cast<std::size_t> (twins[h]) / 3])
      regions.join (static_cast<std::uint32_t> (h / 3),
                    static_cast<std::uint32_t> (static_cast<std::size_t> (twins[h]) / 3));
  std::vector<char> on_outline (triangles.size (), 0);
  for (std::size_t h = 0; h < twins.size (); ++h)
    if (twins[h] < 0 && removed[h / 3])
      on_outline[regions.find (static_cast<std::uint32_t> (h / 3))] = 1;
  std::size_t num_regions = 0;
  Triangles kept;
  kept.reserve (triangles.size ());
  for (std::size_t t = 0; t < triangles.size (); ++t) {
    const std::uint32_t region = removed[t] ? regions.find (static_cast<std::uint32_t> (t)) : 0;
    if (!removed[t] || on_outline[region])
      kept.push_back (triangles[t]);
    else if (region == t)
      ++num_regions;
  }
  if (num_regions > 0)
    triangles = std::move (kept);
  return num_regions;
}

DiscTriangulation
triangulateDisc (const Points3& points,
                 const CsrGraph& neighbourhoods,
                 const DiscPipelineOptions& options)
{
  DiscTriangulation result;
  const std::size_t n = points.size ();
  StageClock clock (options.progress);
  if (n < 3) {
    result.message = "an open surface needs at least three points";
    return result;
  }
  SurfaceGraphOptions graphs;
  graphs.weights = options.weights;
  graphs.num_threads = options.num_threads;
  const SurfaceGraphs surface = buildSurfaceGraphs (points, neighbourhoods, graphs);
  result.graph_pieces = surface.pieces;
  if (!surface.success) {
    result.message = surface.message;
    return result;
  }
  const OrderedNeighbourhoods& ordered = surface.ordered;
  const Weights& weights = surface.weights;
  if (!clock.done ("rings and weights", 0.3, std::to_string (weights.num_fallbacks) + " fallbacks")) {
    result.message = "cancelled by the progress callback";
    return result;
  }

  const BoundaryLoops boundary =
      findBoundaryLoops (points, ordered.normals, ordered.rings, surface.mutual, ordered.largest_gap,
                         pi, 8, sampleSpacings (points, neighbourhoods));
  if (!boundary.success) {
    result.message = boundary.message;
    return result;
  }
  Patch patch;
  patch.loop = boundary.loops.front ();
  patch.points = patch.loop;
  std::vector<char> on_outer (n, 0);
  for (auto v : patch.loop)
    on_outer[v] = 1;
  for (std::size_t v = 0; v < n; ++v)
    if (!on_outer[v])
      patch.points.push_back (static_cast<pcl::index_t> (v));
  if (!clock.done ("boundary", 0.4,
               std::to_string (patch.loop.size ()) + " points on the outer loop, " +
                   std::to_string (boundary.loops.size () - 1) + " inner loop(s)")) {
    result.message = "cancelled by the progress callback";
    return result;
  }

  const std::vector<std::vector<pcl::index_t>> holes (boundary.loops.begin () + 1,
                                                      boundary.loops.end ());
  PatchTriangulation disc;
  Triangles kept;
  if (holes.empty ()) {
    disc = triangulatePatch (points, weights, patch, options.solve);
    kept = disc.triangles;
  }
  else {
    const WithHoleCentres filled =
        withHoleCentres (points, weights, ordered.normals, ordered.rings, holes);
    Patch with_centres = patch;
    for (std::size_t h = 0; h < holes.size (); ++h)
      with_centres.points.push_back (static_cast<pcl::index_t> (n + h));
    disc = triangulatePatch (filled.points, filled.weights, with_centres, options.solve);
    // A bent or C-shaped hole's centroid can lie off the hole: then the map
    // without centres.
    if (!disc.success ||
        !trianglesOutsideHoles (points, disc, with_centres, holes, options.num_threads, kept)) {
      disc = triangulatePatch (points, weights, patch, options.solve);
      if (disc.success &&
          !trianglesOutsideHoles (points, disc, patch, holes, options.num_threads, kept)) {
        result.message = std::to_string (holes.size ()) +
                         " inner boundary loop(s) (holes) could not be cut out cleanly; "
                         "the parameterization folds around them";
        return result;
      }
    }
  }
  if (!disc.success) {
    result.message = disc.message;
    return result;
  }
  result.holes = holes.size ();
  result.triangles = std::move (kept);
  result.normals = ordered.normals;
  result.outer_loop = patch.loop;
  clock.done ("triangulation", 1.0, std::to_string (result.triangles.size ()) + " triangles");
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
