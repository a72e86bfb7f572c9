/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include <pcl/surface/meshless/delaunay_2d.h>
#include <pcl/surface/meshless/fold_repair.h>
#include <pcl/surface/meshless/parameterization.h>
#include <pcl/surface/meshless/triangle_intersection.h>

#include "common/threads.h"
#include "common/uniform_grid.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace pcl {
namespace meshless {

namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

double
cross2 (const Vec2& a, const Vec2& b, const Vec2& c)
{
  return (b - a).x () * (c - a).y () - (b - a).y () * (c - a).x ();
}

/** Whether the segments pq and rs cross or touch (collinear ones count as meeting);
  * exact (orient2d). */
bool
segmentsMeet (const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s)
{
  return orient2d (p, q, r) * orient2d (p, q, s) <= 0 && orient2d (r, s, p) * orient2d (r, s, q) <= 0;
}

/** Broad phase: a uniform grid of triangle bounding boxes. Slots that change are
  * entered again in their new cells; a query tests candidates' current boxes, so
  * stale entries cost a box test and nothing else. */
class TriangleGrid
{
public:
  /** Only the blocks of block x block x block cells within `reach` cells of the
    * seeds are kept: the repair acts near the folds, and a query leaving those
    * blocks is refused (candidates() false). A kept block has a table of its cells,
    * and a cell's list is made when a triangle enters it: every cell within reach
    * made up front in a hash map costs time and memory, and lookups in it slow the
    * queries. */
  TriangleGrid (const Points3& points,
                const Triangles& triangles,
                double cell,
                const std::vector<pcl::index_t>& seeds,
                int reach,
                int threads)
  : points_ (points), triangles_ (triangles),
    frame_ (Vec3::Zero (), cell, -limit, limit - 1), visits_ (triangles.size ())
  {
    const Vec3 r = Vec3::Constant (reach * cell);
    for (const pcl::index_t v : seeds)
      forEachCell (blocksOf (rangeOf (points[v] - r, points[v] + r)), [&] (const Cell& b) {
        if (blocks_.emplace (keyOf (b), static_cast<std::int32_t> (block_origins_.size ())).second)
          block_origins_.push_back (b);
      });
    cell_of_.assign (block_origins_.size () * cells_per_block, -1);
    // The triangles there when the repair starts go into one array, cell after
    // cell, in slot order: their cells found on all threads (lookups only), then
    // counted and filled in. Growing a list per cell, one triangle after the other,
    // took a reallocation every few entries.
    std::vector<std::uint32_t> entry_start;
    std::vector<std::uint32_t> entries = initialEntries (entry_start, threads);
    std::vector<std::uint32_t> count_of;
    for (const std::uint32_t entry : entries) {
      std::int32_t& id = cell_of_[entry];
      if (id < 0) {
        id = static_cast<std::int32_t> (cell_coordinates_.size ());
        cell_coordinates_.push_back (cellOfEntry (entry));
        count_of.push_back (0);
      }
      ++count_of[id];
    }
    initial_start_.assign (count_of.size () + 1, 0);
    for (std::size_t id = 0; id < count_of.size (); ++id)
      initial_start_[id + 1] = initial_start_[id] + count_of[id];
    initial_slots_.resize (initial_start_.back ());
    std::vector<std::uint32_t> fill (initial_start_.begin (), initial_start_.end () - 1);
    for (std::size_t t = 0; t + 1 < entry_start.size (); ++t)
      for (std::uint32_t k = entry_start[t]; k < entry_start[t + 1]; ++k)
        initial_slots_[fill[cell_of_[entries[k]]]++] = static_cast<std::int32_t> (t);
    cells_.resize (cell_coordinates_.size ());
  }

  /** Enters slot t (whose triangle changed) in the kept cells its box covers. */
  void
  insert (std::int32_t t)
  {
    Vec3 lo, hi;
    box (triangles_[t], lo, hi);
    const auto range = rangeOf (lo, hi);
    if (!reachesKeptBlock (range))
      return;
    forCells (range, [&] (const Cell& c) {
      const std::ptrdiff_t entry = tableEntry (c);
      if (entry < 0)
        return;
      std::int32_t& id = cell_of_[entry];
      if (id < 0) {
        id = static_cast<std::int32_t> (cells_.size ());
        cells_.emplace_back ();
        cell_coordinates_.push_back (c);
        initial_start_.push_back (initial_start_.back ()); // no initial slots
      }
      // Once per cell: swaps tried and undone enter the same slot again and again.
      const auto first = initial_slots_.begin () + initial_start_[id];
      const auto last = initial_slots_.begin () + initial_start_[id + 1];
      std::vector<std::int32_t>& slots = cells_[id];
      if (!std::binary_search (first, last, t) && std::find (slots.begin (), slots.end (), t) == slots.end ())
        slots.push_back (t);
    });
  }

  /** Slots whose current box overlaps triangle `tri`'s box (each once); false if
    * the box reaches outside the kept blocks. */
  bool
  candidates (const Triangle& tri, std::vector<std::int32_t>& out) const
  {
    out.clear ();
    // Each slot once: a stamp per slot instead of sorting (the sort took a quarter
    // of the queries' time).
    visits_.startQuery ();
    Vec3 lo, hi;
    box (tri, lo, hi);
    const auto range = rangeOf (lo, hi);
    const auto scanOne = [&] (std::int32_t t) {
      if (!visits_.firstVisit (t))
        return;
      Vec3 tlo, thi;
      box (triangles_[t], tlo, thi);
      if ((tlo.array () <= hi.array ()).all () && (lo.array () <= thi.array ()).all ())
        out.push_back (t);
    };
    // A cell's slots: those there when the repair started, then those entered since.
    const auto scanCell = [&] (std::int32_t id) {
      for (std::uint32_t k = initial_start_[id]; k < initial_start_[id + 1]; ++k)
        scanOne (initial_slots_[k]);
      for (const std::int32_t t : cells_[id])
        scanOne (t);
    };
    // A box over more cells than are made (a far outlier's triangle, a long sliver)
    // is answered from the made cells inside it: walking all its cells can take
    // minutes.
    if (range.count () > static_cast<double> (cells_.size ())) {
      for (std::size_t id = 0; id < cells_.size (); ++id)
        if (range.contains (cell_coordinates_[id]))
          scanCell (static_cast<std::int32_t> (id));
      return leavesNoBlock (range);
    }
    bool inside = true;
    const Range blocks = blocksOf (range);
    if (blocks.lo == blocks.hi) {
      // The common case: one block, looked up once.
      const auto it = blocks_.find (keyOf (blocks.lo));
      if (it == blocks_.end ())
        return false;
      const std::int32_t* table = cell_of_.data () + it->second * cells_per_block;
      forEachCell (range, [&] (const Cell& c) {
        const std::int32_t id = table[local (c)];
        if (id >= 0)
          scanCell (id);
      });
      return true;
    }
    forEachCell (range, [&] (const Cell& c) {
      const std::ptrdiff_t entry = tableEntry (c);
      if (entry < 0)
        inside = false;
      else if (cell_of_[entry] >= 0)
        scanCell (cell_of_[entry]);
    });
    return inside;
  }

  /** The bounding box of triangle t. */
  void
  box (const Triangle& t, Vec3& lo, Vec3& hi) const
  {
    lo = points_[t[0]].cwiseMin (points_[t[1]]).cwiseMin (points_[t[2]]);
    hi = points_[t[0]].cwiseMax (points_[t[1]]).cwiseMax (points_[t[2]]);
  }

private:
  using Cell = GridCell;
  using Range = CellRange;

  /** Cells per block along each axis. */
  static constexpr std::int64_t block = 8;
  static constexpr std::size_t cells_per_block = block * block * block;
  /** Cell coordinates are clamped to [-limit, limit - 1]: the conversion is defined,
    * the loops end and keys stay unique; the mapping is monotone, so boxes that
    * overlap still share a cell. */
  static constexpr std::int64_t limit = std::int64_t{1} << 20;

  /** Whether a range of cells touches a kept block. */
  bool
  reachesKeptBlock (const Range& range) const
  {
    // Nearly every triangle lies in one block: most of the mesh is out of reach.
    bool any = false;
    forBlocks (range, [&] (const Cell& b) { any = any || blocks_.count (keyOf (b)) > 0; });
    return any;
  }

  /** The table entries of the kept cells each triangle's box covers, triangle
    * after triangle: those of slot t are entries[start[t] .. start[t + 1]). Found
    * on all threads (the tables are only read). */
  std::vector<std::uint32_t>
  initialEntries (std::vector<std::uint32_t>& start, int threads) const
  {
    const auto m = static_cast<std::ptrdiff_t> (triangles_.size ());
    // Per triangle: -1 out of reach, -2 over several blocks (its cells looked up
    // one by one), else the table of the one kept block it lies in.
    std::vector<std::int32_t> table_of (triangles_.size ());
    start.assign (triangles_.size () + 1, 0);
    const auto forEntries = [&] (std::ptrdiff_t t, auto&& visit) {
      const std::int32_t table = table_of[t];
      if (table == -1)
        return;
      Vec3 lo, hi;
      box (triangles_[t], lo, hi);
      forCells (rangeOf (lo, hi), [&] (const Cell& c) {
        const std::ptrdiff_t entry =
            table >= 0 ? static_cast<std::ptrdiff_t> (table) * static_cast<std::ptrdiff_t> (cells_per_block) +
                             static_cast<std::ptrdiff_t> (local (c))
                       : tableEntry (c);
        if (entry >= 0)
          visit (static_cast<std::uint32_t> (entry));
      });
    };
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::ptrdiff_t t = 0; t < m; ++t) {
      Vec3 lo, hi;
      box (triangles_[t], lo, hi);
      const Range range = rangeOf (lo, hi);
      const Range blocks = blocksOf (range);
      if (blocks.lo == blocks.hi) {
        // Nearly every triangle lies in one block: most of the mesh is out of reach.
        const auto it = blocks_.find (keyOf (blocks.lo));
        table_of[t] = it == blocks_.end () ? -1 : it->second;
      }
      else
        table_of[t] = reachesKeptBlock (range) ? -2 : -1;
      std::uint32_t count = 0;
      forEntries (t, [&] (std::uint32_t) { ++count; });
      start[t + 1] = count;
    }
    for (std::size_t t = 0; t < triangles_.size (); ++t)
      start[t + 1] += start[t];
    std::vector<std::uint32_t> entries (start.back ());
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::ptrdiff_t t = 0; t < m; ++t) {
      std::uint32_t k = start[t];
      forEntries (t, [&] (std::uint32_t entry) { entries[k++] = entry; });
    }
    return entries;
  }

  /** The cell of a table entry. */
  Cell
  cellOfEntry (std::uint32_t entry) const
  {
    const Cell& b = block_origins_[entry / cells_per_block];
    const std::uint32_t in = entry % cells_per_block;
    return {b[0] * block + in / (block * block), b[1] * block + (in / block) % block,
            b[2] * block + in % block};
  }

  Range
  rangeOf (const Vec3& lo, const Vec3& hi) const
  {
    return frame_.cellsOf (lo, hi);
  }

  static std::int64_t
  down (std::int64_t x)
  {
    // Floor division by the block size, a power of two (no branch, no division).
    static_assert (block == 8, "down() and local() shift by 3 bits");
    return static_cast<std::int64_t> (static_cast<std::uint64_t> (x + (limit << 1)) >> 3) -
           ((limit << 1) >> 3);
  }

  /** The blocks a range of cells touches (floor division). */
  static Range
  blocksOf (const Range& cells)
  {
    Range blocks;
    for (int k = 0; k < 3; ++k) {
      blocks.lo[k] = down (cells.lo[k]);
      blocks.hi[k] = down (cells.hi[k]);
    }
    return blocks;
  }

  /** A cell's place in its block's table. */
  static std::size_t
  local (const Cell& c)
  {
    const auto in = [] (std::int64_t x) { return static_cast<std::size_t> (x & (block - 1)); };
    return (in (c[0]) * block + in (c[1])) * block + in (c[2]);
  }

  /** Where cell c's id is in the tables (the id is -1 while no triangle entered
    * it); -1 if its block is not kept. */
  std::ptrdiff_t
  tableEntry (const Cell& c) const
  {
    const auto it = blocks_.find (keyOf ({down (c[0]), down (c[1]), down (c[2])}));
    if (it == blocks_.end ())
      return -1;
    return static_cast<std::ptrdiff_t> (it->second * cells_per_block + local (c));
  }

  /** Whether every block the range touches is kept. */
  bool
  leavesNoBlock (const Range& range) const
  {
    const Range blocks = blocksOf (range);
    if (blocks.count () > static_cast<double> (blocks_.size ()))
      return false;
    bool inside = true;
    forEachCell (blocks, [&] (const Cell& b) { inside = inside && blocks_.count (keyOf (b)) > 0; });
    return inside;
  }

  static std::uint64_t
  keyOf (const Cell& c)
  {
    const auto bits = [] (std::int64_t x) { return static_cast<std::uint64_t> (x) & 0x1fffff; };
    return (bits (c[0]) << 42) | (bits (c[1]) << 21) | bits (c[2]);
  }

  /** The cells of a range that insert() walks: a range over more cells than the
    * kept blocks hold is walked through the kept blocks instead. */
  template <typename Visit>
  void
  forCells (const Range& range, Visit visit) const
  {
    if (range.count () <= static_cast<double> (cell_of_.size ())) {
      forEachCell (range, visit);
      return;
    }
    for (const Cell& b : block_origins_) {
      Range cells;
      for (int k = 0; k < 3; ++k) {
        cells.lo[k] = std::max (range.lo[k], b[k] * block);
        cells.hi[k] = std::min (range.hi[k], b[k] * block + block - 1);
      }
      if (cells.lo[0] <= cells.hi[0] && cells.lo[1] <= cells.hi[1] &&
          cells.lo[2] <= cells.hi[2])
        forEachCell (cells, visit);
    }
  }

  /** The blocks a range of cells touches, or only the kept ones among them if
    * they are more than the kept ones. */
  template <typename Visit>
  void
  forBlocks (const Range& range, Visit visit) const
  {
    const Range blocks = blocksOf (range);
    if (blocks.count () <= static_cast<double> (blocks_.size ()))
      forEachCell (blocks, visit);
    else
      for (const Cell& b : block_origins_)
        if (blocks.contains (b))
          visit (b);
  }

  const Points3& points_;
  const Triangles& triangles_;
  GridFrame frame_;
  std::unordered_map<std::uint64_t, std::int32_t> blocks_; // kept block -> its table
  std::vector<Cell> block_origins_;                        // block coordinates per table
  std::vector<std::int32_t> cell_of_;                      // the tables: cell ids or -1
  std::vector<std::vector<std::int32_t>> cells_;           // slots per made cell
  std::vector<Cell> cell_coordinates_;                     // per made cell
  /** The slots in each made cell when the repair started: cell id's are
    * initial_slots_[initial_start_[id] .. initial_start_[id + 1]), ascending; those
    * entered later are in cells_[id]. */
  std::vector<std::uint32_t> initial_start_;
  std::vector<std::int32_t> initial_slots_;
  mutable VisitStamps visits_;
};

class FoldRepair
{
public:
  FoldRepair (const Points3& points,
              Triangles& triangles,
              double cell,
              const std::vector<pcl::index_t>& seeds,
              const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
              const FoldRepairOptions& options)
  : points_ (points)
  , triangles_ (triangles)
  , neighbours_ (options.neighbours)
  , normals_ (options.normals)
  , grid_ (points, triangles, cell, seeds, 8, threadCount (options.num_threads))
  , pairs_of_ (triangles.size (), 0)
  , rewritten_ (options.rewritten && options.rewritten->size () == triangles.size () ? options.rewritten
                                                                                      : nullptr)
  {
    for (const auto& [s, t] : pairs) {
      ++pairs_of_[s];
      ++pairs_of_[t];
    }
    // Stars as compressed rows; the few that re-meshing changes live in changed_.
    star_offsets_.assign (points.size () + 1, 0);
    for (const Triangle& t : triangles)
      for (const pcl::index_t v : t)
        ++star_offsets_[v + 1];
    for (std::size_t v = 0; v < points.size (); ++v)
      star_offsets_[v + 1] += star_offsets_[v];
    star_slots_.resize (star_offsets_.back ());
    std::vector<std::size_t> fill (star_offsets_.begin (), star_offsets_.end () - 1);
    for (std::size_t t = 0; t < triangles.size (); ++t)
      for (const pcl::index_t v : triangles[t])
        star_slots_[fill[v]++] = static_cast<std::int32_t> (t);
  }

  /** Slots of the triangles through v. */
  std::vector<std::int32_t>
  star (pcl::index_t v) const
  {
    const auto it = changed_.find (v);
    if (it != changed_.end ())
      return it->second;
    return {star_slots_.begin () + static_cast<std::ptrdiff_t> (star_offsets_[v]),
            star_slots_.begin () + static_cast<std::ptrdiff_t> (star_offsets_[v + 1])};
  }

  /** Re-meshes the disc formed by the triangles through the vertices `inner`
    * (closed as closedDiscRegion does; taken out and put back in the plane of the
    * disc's boundary, or in a map) if that lowers the number of intersecting pairs;
    * returns the decrease (0 if left alone). */
  std::size_t
  tryRemesh (std::vector<pcl::index_t> inner, std::size_t max_triangles)
  {
    const std::vector<std::int32_t> slots = closedDiscRegion (
        triangles_, [this] (pcl::index_t v) { return star (v); }, inner, max_triangles);
    // Nothing to gain where no triangle of the disc is in a pair (the other
    // vertices of a fold once one disc has opened it, and the larger discs around
    // them: most discs tried); the exact count below would find none.
    if (slots.empty () ||
        std::all_of (slots.begin (), slots.end (), [this] (std::int32_t t) { return pairs_of_[t] == 0; }))
      return 0;
    const auto inRegion = [&] (std::int32_t t) {
      return std::binary_search (slots.begin (), slots.end (), t);
    };
    // Interior: every triangle through it in the region (so the inner vertices and
    // any vertex the region happens to surround).
    std::vector<pcl::index_t> interior;
    std::set<pcl::index_t> region_vertices;
    for (const std::int32_t t : slots)
      region_vertices.insert (triangles_[t].begin (), triangles_[t].end ());
    for (const pcl::index_t x : region_vertices)
    {
      const auto around = star (x);
      if (std::all_of (around.begin (), around.end (), inRegion))
        interior.push_back (x);
    }
    // The boundary: directed edges of the region whose reverse is not in it.
    std::map<std::pair<pcl::index_t, pcl::index_t>, int> directed;
    for (const std::int32_t t : slots)
      for (int k = 0; k < 3; ++k)
        ++directed[{triangles_[t][k], triangles_[t][(k + 1) % 3]}];
    std::unordered_map<pcl::index_t, pcl::index_t> next;
    for (const auto& [edge, uses] : directed)
      if (!directed.count ({edge.second, edge.first}))
        if (!next.emplace (edge.first, edge.second).second)
          return 0; // the boundary touches itself
    if (next.empty ())
      return 0;
    std::vector<pcl::index_t> loop{next.begin ()->first};
    while (loop.size () <= next.size ()) {
      const auto found = next.find (loop.back ());
      if (found == next.end ())
        return 0; // the boundary does not close
      const pcl::index_t after = found->second;
      if (after == loop.front ())
        break;
      loop.push_back (after);
    }
    const std::size_t m = loop.size ();
    if (m != next.size () || m < 3 || slots.size () != 2 * interior.size () + m - 2)
      return 0; // not a disc

    // Two ways to re-mesh the disc: in the plane of its boundary, or, where the
    // disc does not project simply (it folds over a thin part), in a map of it
    // built from the points' own neighbourhoods on their side of the surface.

    // Admissible: as many triangles, none degenerate, no edge between boundary
    // vertices that the mesh has outside the region.
    std::set<pcl::index_t> boundary (loop.begin (), loop.end ());
    const auto admissible = [&] (const Triangles& fresh) {
      if (fresh.size () != slots.size ())
        return false;
      for (const Triangle& t : fresh) {
        if (projectionAxis (points_, t) < 0)
          return false;
        for (int k = 0; k < 3; ++k) {
          const pcl::index_t a = t[k], b = t[(k + 1) % 3];
          if (boundary.count (a) && boundary.count (b) && !directed.count ({a, b}) &&
              !directed.count ({b, a}) && hasEdgeOutside (a, b, inRegion))
            return false;
        }
      }
      return true;
    };

    // Nothing to gain where the disc's triangles intersect nothing (the other
    // vertices of a fold once one disc has opened it: most of the tries) or where
    // their pairs cannot be counted; no re-meshing is built.
    PairList old_pairs, new_pairs, candidate_pairs;
    const std::size_t before = pairsOf (slots, nullptr, &old_pairs);
    if (before == 0 || before == unknown)
      return 0;
    // The map only where the plane did not remove every pair.
    std::size_t after = before;
    Triangles fresh;
    for (int way = 0; way < 2 && after > 0; ++way) {
      Triangles candidate =
          way == 0 ? planarDisc (loop, interior) : mappedDisc (loop, interior, slots.size ());
      if (candidate.empty () || !admissible (candidate))
        continue;
      const std::size_t pairs = pairsOf (slots, &candidate, &candidate_pairs);
      if (pairs < after) {
        after = pairs;
        fresh = std::move (candidate);
        new_pairs.swap (candidate_pairs);
      }
    }
    if (fresh.empty ())
      return 0;

    replace (slots, fresh, &old_pairs, &new_pairs);
    return before - after;
  }

  /** Swaps the searches may still try (trySwaps stops trying once none are left),
    * and whether a swap was refused for want of them. */
  void
  setSwapBudget (std::size_t swaps)
  {
    swaps_left_ = swaps;
    swap_refused_ = false;
  }
  std::size_t
  swapsLeft () const
  {
    return swaps_left_;
  }
  bool
  swapRefused () const
  {
    return swap_refused_;
  }

  /** Swaps of the edges through v, up to `depth` in a row, that lower the number of
    * intersecting pairs: where a thin part's two sides come closer than the point
    * spacing, a triangle across the part can often be turned away by a swap where
    * no disc around v projects simply. A swap is tried only if it creates no edge
    * twice, no degenerate triangle, and no triangle facing against its vertices'
    * normals (or against its partner's); each further swap next to the last.
    * Returns the decrease (0 if nothing changed). */
  std::size_t
  trySwaps (pcl::index_t v, int depth)
  {
    const long gain = swapSearch (edgesThrough (v), depth, 0, 0);
    return gain > 0 ? static_cast<std::size_t> (gain) : 0;
  }

  /** The disc re-meshed in the plane of its boundary (Newell's normal): the
    * boundary polygon, if simple there, ear-clipped (best smallest angle first),
    * the inner vertices inserted into the triangles they fall in (strictly), Lawson
    * flips towards the Delaunay triangulation in that plane. Empty if a step fails. */
  Triangles
  planarDisc (const std::vector<pcl::index_t>& loop, const std::vector<pcl::index_t>& interior) const
  {
    const std::size_t m = loop.size ();
    // Plane of the boundary (Newell), projection.
    Vec3 normal = Vec3::Zero ();
    for (std::size_t i = 0; i < m; ++i)
      normal += points_[loop[i]].cross (points_[loop[(i + 1) % m]]);
    if (!(normal.norm () > 0.0))
      return Triangles ();
    normal.normalize ();
    const Vec3 u = normal.unitOrthogonal (), w = normal.cross (u);
    // Positions in the plane, by vertex index (every vertex read below is on the
    // loop or inside): a flat array kept between discs instead of a hash map, which
    // the loops below queried millions of times on the 1M cloud.
    std::vector<Vec2>& at = plane_positions_;
    if (at.size () != points_.size ())
      at.resize (points_.size ());
    for (const auto* part : {&loop, &interior})
      for (const pcl::index_t x : *part)
        at[x] = Vec2 (points_[x].dot (u), points_[x].dot (w));
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t j = i + 2; j < m; ++j)
        if (!(i == 0 && j == m - 1) &&
            segmentsMeet (at[loop[i]], at[loop[(i + 1) % m]], at[loop[j]], at[loop[(j + 1) % m]]))
          return Triangles ();

    // Ear clipping of the boundary polygon, best ears first.
    std::vector<pcl::index_t> remaining = loop;
    Triangles fresh;
    while (remaining.size () > 3) {
      const std::size_t r = remaining.size ();
      double best_quality = -1.0;
      std::size_t best = r;
      for (std::size_t k = 0; k < r; ++k) {
        const pcl::index_t a = remaining[(k + r - 1) % r], b = remaining[k], c = remaining[(k + 1) % r];
        const double area = cross2 (at[a], at[b], at[c]);
        if (!(area > 0.0))
          continue;
        bool empty = true;
        for (const pcl::index_t x : remaining)
          if (x != a && x != b && x != c && cross2 (at[a], at[b], at[x]) >= 0.0 &&
              cross2 (at[b], at[c], at[x]) >= 0.0 && cross2 (at[c], at[a], at[x]) >= 0.0) {
            empty = false;
            break;
          }
        if (!empty)
          continue;
        const double longest = std::max ({(at[a] - at[b]).squaredNorm (), (at[b] - at[c]).squaredNorm (),
                                          (at[c] - at[a]).squaredNorm ()});
        if (area / longest > best_quality) {
          best_quality = area / longest;
          best = k;
        }
      }
      if (best == r)
        return Triangles ();
      fresh.push_back ({remaining[(best + r - 1) % r], remaining[best], remaining[(best + 1) % r]});
      remaining.erase (remaining.begin () + static_cast<std::ptrdiff_t> (best));
    }
    if (!(cross2 (at[remaining[0]], at[remaining[1]], at[remaining[2]]) > 0.0))
      return Triangles ();
    fresh.push_back ({remaining[0], remaining[1], remaining[2]});

    // Interior vertices put back, each into the triangle it falls in (strictly).
    for (const pcl::index_t x : interior) {
      std::size_t host = fresh.size ();
      for (std::size_t i = 0; i < fresh.size () && host == fresh.size (); ++i) {
        const Vec2 &a = at[fresh[i][0]], &b = at[fresh[i][1]], &c = at[fresh[i][2]];
        const double scale = 1e-12 * ((a - b).squaredNorm () + (b - c).squaredNorm ());
        if (cross2 (a, b, at[x]) > scale && cross2 (b, c, at[x]) > scale && cross2 (c, a, at[x]) > scale)
          host = i;
      }
      if (host == fresh.size ())
        return Triangles ();
      const Triangle t = fresh[host];
      fresh[host] = {t[0], t[1], x};
      fresh.push_back ({t[1], t[2], x});
      fresh.push_back ({t[2], t[0], x});
    }
    // Lawson flips towards the Delaunay triangulation in the plane (interior edges
    // of the region only), bounded.
    for (std::size_t sweep = 0, flips = 1; sweep < 4 * fresh.size () && flips > 0; ++sweep) {
      flips = 0;
      for (std::size_t i = 0; i < fresh.size (); ++i)
        for (int k = 0; k < 3; ++k) {
          const pcl::index_t a = fresh[i][k], b = fresh[i][(k + 1) % 3], c = fresh[i][(k + 2) % 3];
          for (std::size_t j = 0; j < fresh.size (); ++j) {
            if (j == i)
              continue;
            int l = 0;
            while (l < 3 && !(fresh[j][l] == b && fresh[j][(l + 1) % 3] == a))
              ++l;
            if (l == 3)
              continue;
            const pcl::index_t d = fresh[j][(l + 2) % 3];
            // Flip ab to cd when d lies inside abc's circumcircle and acd, cbd... stay
            // counter-clockwise.
            const Vec2 &pa = at[a], &pb = at[b], &pc = at[c], &pd = at[d];
            if (!(cross2 (pa, pd, pc) > 0.0 && cross2 (pd, pb, pc) > 0.0))
              break;
            const Eigen::Matrix3d incircle =
                (Eigen::Matrix3d () << pa.x () - pd.x (), pa.y () - pd.y (), (pa - pd).squaredNorm (),
                 pb.x () - pd.x (), pb.y () - pd.y (), (pb - pd).squaredNorm (),
                 pc.x () - pd.x (), pc.y () - pd.y (), (pc - pd).squaredNorm ())
                    .finished ();
            if (!(incircle.determinant () > 1e-12 * std::pow ((pa - pb).squaredNorm (), 2)))
              break;
            bool exists = false; // cd already an edge of the new triangles
            for (const Triangle& t : fresh)
              for (int e = 0; e < 3; ++e)
                exists = exists || (t[e] == c && t[(e + 1) % 3] == d) || (t[e] == d && t[(e + 1) % 3] == c);
            if (exists)
              break;
            fresh[i] = {a, d, c};
            fresh[j] = {d, b, c};
            ++flips;
            break;
          }
        }
    }
    return fresh;
  }

  /** The disc re-meshed in a map: its loop on the unit circle (chord length), each
    * inner vertex at the weighted mean (inverse distance) of its cloud neighbours in
    * the disc whose oriented normals agree with its own, the points triangulated
    * (exact Delaunay). Empty if there is no such context, a vertex has no such
    * neighbour, the map is singular or its hull is not the loop. */
  Triangles
  mappedDisc (const std::vector<pcl::index_t>& loop,
              const std::vector<pcl::index_t>& interior,
              std::size_t triangles) const
  {
    if (!neighbours_ || !normals_ || interior.empty () ||
        neighbours_->size () != points_.size () || normals_->size () != points_.size ())
      return {};
    const std::size_t m = loop.size (), ni = interior.size ();
    std::unordered_map<pcl::index_t, std::size_t> local;
    for (std::size_t i = 0; i < m; ++i)
      local[loop[i]] = i;
    for (std::size_t i = 0; i < ni; ++i)
      local[interior[i]] = m + i;
    const Points2 circle = circleBoundary (points_, loop);
    // Sparse (a few neighbours per row): closed discs on thin parts reach a few
    // hundred unknowns, whose dense LU Eigen spread over OpenMP threads that mostly
    // waited.
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero (ni, 2);
    for (std::size_t i = 0; i < ni; ++i) {
      const pcl::index_t x = interior[i];
      std::vector<std::pair<std::size_t, double>> support;
      double total = 0.0;
      for (const pcl::index_t* y = neighbours_->begin (x); y != neighbours_->end (x); ++y) {
        const auto it = local.find (*y);
        if (*y == x || it == local.end () || (*normals_)[x].dot ((*normals_)[*y]) <= 0.0f)
          continue;
        const double w = 1.0 / std::max ((points_[*y] - points_[x]).norm (), 1e-300);
        support.emplace_back (it->second, w);
        total += w;
      }
      if (support.empty ())
        return {};
      entries.emplace_back (static_cast<int> (i), static_cast<int> (i), 1.0);
      for (const auto& [j, w] : support) {
        if (j < m)
          rhs.row (i) += (w / total) * circle[j].transpose ();
        else
          entries.emplace_back (static_cast<int> (i), static_cast<int> (j - m), -w / total);
      }
    }
    Eigen::SparseMatrix<double> system (static_cast<Eigen::Index> (ni), static_cast<Eigen::Index> (ni));
    system.setFromTriplets (entries.begin (), entries.end ());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute (system);
    if (lu.info () != Eigen::Success)
      return {};
    const Eigen::MatrixX2d solution = lu.solve (rhs);
    if (!solution.allFinite () ||
        (system * solution - rhs).norm () > 1e-9 * std::max (1.0, rhs.norm ()))
      return {};
    Points2 uv (m + ni);
    for (std::size_t i = 0; i < m; ++i)
      uv[i] = circle[i];
    for (std::size_t i = 0; i < ni; ++i)
      uv[m + i] = solution.row (i).transpose ();
    const Delaunay2DResult delaunay = delaunay2D (uv);
    if (!delaunay.success || delaunay.num_duplicates > 0 || delaunay.hull.size () != m ||
        delaunay.triangles.size () != triangles)
      return {};
    const auto start = static_cast<std::size_t> (delaunay.hull[0]);
    for (std::size_t k = 0; k < m; ++k)
      if (static_cast<std::size_t> (delaunay.hull[k]) != (start + k) % m)
        return {};
    std::vector<pcl::index_t> global (loop);
    global.insert (global.end (), interior.begin (), interior.end ());
    Triangles result;
    for (const Triangle& t : delaunay.triangles)
      result.push_back ({global[t[0]], global[t[1]], global[t[2]]});
    return result;
  }

  /** The neighbours of v. */
  std::vector<pcl::index_t>
  neighbours (pcl::index_t v) const
  {
    std::vector<pcl::index_t> result;
    for (const std::int32_t t : star (v))
      for (const pcl::index_t x : triangles_[t])
        if (x != v)
          result.push_back (x);
    std::sort (result.begin (), result.end ());
    result.erase (std::unique (result.begin (), result.end ()), result.end ());
    return result;
  }

  /** Vertices whose star a re-meshing or a swap has changed. */
  std::vector<pcl::index_t>
  changedVertices () const
  {
    std::vector<pcl::index_t> result;
    for (const auto& entry : changed_)
      result.push_back (entry.first);
    return result;
  }

  /** Whether the triangle in slot t intersects some other one. */
  bool
  intersectsSomething (std::int32_t t)
  {
    if (!grid_.candidates (triangles_[t], scratch_))
      return true; // out of reach: as if it did
    for (const std::int32_t o : scratch_)
      if (o != t && trianglesIntersect (points_, triangles_[t], triangles_[o]))
        return true;
    return false;
  }

private:
  /** Intersecting pairs (slot, other slot) found by pairsOf. */
  using PairList = std::vector<std::pair<std::int32_t, std::int32_t>>;

  /** One edge swap: the two slots and what they held before and hold after, and
    * the pairs of each (when apply could count them). */
  struct Swap
  {
    std::vector<std::int32_t> slots;
    Triangles before, after;
    PairList pairs_before, pairs_after;
    bool counted = false;
  };
  static constexpr long unknown_gain = std::numeric_limits<long>::min ();
  std::size_t swaps_left_ = std::numeric_limits<std::size_t>::max ();
  bool swap_refused_ = false;

  /** Puts `fresh` into `slots` (same order), keeping the stars, the grid and the
    * per-slot pair counts: the pairs the slots' triangles were in (`gone`) and
    * those the fresh ones are in (`come`), as pairsOf found them. Without them
    * (pairsOf could not count) the fresh triangles and every triangle whose box
    * overlaps theirs count as in pairs for good. */
  void
  replace (const std::vector<std::int32_t>& slots, const Triangles& fresh,
           const PairList* gone, const PairList* come)
  {
    const auto inSlots = [&] (std::int32_t t) {
      return std::find (slots.begin (), slots.end (), t) != slots.end ();
    };
    std::set<pcl::index_t> touched;
    for (const std::int32_t t : slots)
      touched.insert (triangles_[t].begin (), triangles_[t].end ());
    for (const Triangle& t : fresh)
      touched.insert (t.begin (), t.end ());
    for (const pcl::index_t x : touched) {
      std::vector<std::int32_t> kept = star (x);
      kept.erase (std::remove_if (kept.begin (), kept.end (), inSlots), kept.end ());
      changed_[x] = std::move (kept);
    }
    for (std::size_t i = 0; i < slots.size (); ++i) {
      triangles_[slots[i]] = fresh[i];
      if (rewritten_)
        (*rewritten_)[slots[i]] = 1;
      for (const pcl::index_t x : fresh[i])
        changed_[x].push_back (slots[i]);
      grid_.insert (slots[i]);
    }
    if (gone && come) {
      const auto add = [this] (std::int32_t t, int step) {
        if (pairs_of_[t] != uncounted)
          pairs_of_[t] = static_cast<std::uint32_t> (static_cast<long> (pairs_of_[t]) + step);
      };
      for (const auto& [a, b] : *gone) {
        add (a, -1);
        add (b, -1);
      }
      for (const auto& [a, b] : *come) {
        add (a, 1);
        add (b, 1);
      }
      return;
    }
    for (const std::int32_t t : slots) {
      pairs_of_[t] = uncounted;
      // The candidates of a box reaching past the kept blocks are those inside
      // them: all a later disc (inside them) can meet.
      grid_.candidates (triangles_[t], scratch_);
      for (const std::int32_t o : scratch_)
        pairs_of_[o] = uncounted;
    }
  }

  /** The edges through v, each as (v, other), in a fixed order. */
  std::vector<std::pair<pcl::index_t, pcl::index_t>>
  edgesThrough (pcl::index_t v) const
  {
    std::vector<std::pair<pcl::index_t, pcl::index_t>> edges;
    for (const pcl::index_t x : neighbours (v))
      edges.emplace_back (std::min (v, x), std::max (v, x));
    return edges;
  }

  /** The swap of edge ab, if admissible. */
  bool
  swapFor (pcl::index_t a, pcl::index_t b, Swap& swap) const
  {
    std::vector<std::int32_t> both;
    for (const std::int32_t t : star (a))
      if (std::find (triangles_[t].begin (), triangles_[t].end (), b) != triangles_[t].end ())
        both.push_back (t);
    if (both.size () != 2)
      return false;
    // t1 holds a -> b, t2 holds b -> a; c and d their third vertices.
    std::int32_t t1 = both[0], t2 = both[1];
    const auto third = [&] (std::int32_t t, pcl::index_t from, pcl::index_t to, pcl::index_t& other) {
      for (int k = 0; k < 3; ++k)
        if (triangles_[t][k] == from && triangles_[t][(k + 1) % 3] == to) {
          other = triangles_[t][(k + 2) % 3];
          return true;
        }
      return false;
    };
    pcl::index_t c = -1, d = -1;
    if (!third (t1, a, b, c))
      std::swap (t1, t2);
    if (!third (t1, a, b, c) || !third (t2, b, a, d) || c == d)
      return false;
    for (const std::int32_t t : star (c))
      if (std::find (triangles_[t].begin (), triangles_[t].end (), d) != triangles_[t].end ())
        return false; // cd is an edge already
    const Triangle n1{a, d, c}, n2{b, c, d};
    if (projectionAxis (points_, n1) < 0 || projectionAxis (points_, n2) < 0)
      return false;
    const Vec3 f1 = (points_[n1[1]] - points_[n1[0]]).cross (points_[n1[2]] - points_[n1[0]]);
    const Vec3 f2 = (points_[n2[1]] - points_[n2[0]]).cross (points_[n2[2]] - points_[n2[0]]);
    if (f1.normalized ().dot (f2.normalized ()) < -0.3)
      return false; // a sharp fold between the two new triangles
    // Against the mesh's own vertex normals (area-weighted, as the mesh is now):
    // where the part is thinner than the point spacing the cloud's normals are
    // least reliable.
    for (const auto* t : {&n1, &n2}) {
      Vec3 sum = Vec3::Zero ();
      for (const pcl::index_t x : *t)
        for (const std::int32_t o : star (x))
          sum += (points_[triangles_[o][1]] - points_[triangles_[o][0]])
                     .cross (points_[triangles_[o][2]] - points_[triangles_[o][0]]);
      const Vec3 face = t == &n1 ? f1 : f2;
      if (!(face.dot (sum) > 0.0))
        return false;
    }
    swap.slots = {t1, t2};
    swap.before = {triangles_[t1], triangles_[t2]};
    swap.after = {n1, n2};
    return true;
  }

  /** Depth first: each edge of `edges` swapped in turn on top of the `made` swaps
    * made so far (which gained `so_far`); kept, with the total gain returned, as
    * soon as that is positive, otherwise undone after trying up to `depth - 1` more
    * swaps next to it: the second of a run on any edge through the first's four
    * vertices, each later one on an outer edge of the two triangles the one before
    * made. Stops trying once the swap budget is spent. */
  long
  swapSearch (const std::vector<std::pair<pcl::index_t, pcl::index_t>>& edges, int depth, long so_far, int made)
  {
    for (const auto& [a, b] : edges) {
      Swap swap;
      if (!swapFor (a, b, swap))
        continue;
      if (swaps_left_ == 0) {
        swap_refused_ = true;
        break;
      }
      --swaps_left_;
      const long gain = apply (swap);
      if (gain != unknown_gain) {
        if (so_far + gain > 0)
          return so_far + gain;
        if (depth > 1) {
          std::vector<std::pair<pcl::index_t, pcl::index_t>> near;
          if (made == 0) {
            for (const std::int32_t t : swap.slots)
              for (const pcl::index_t x : triangles_[t])
                for (const auto& edge : edgesThrough (x))
                  near.push_back (edge);
          }
          else {
            // Later in a run only the outer edges of the two triangles just made:
            // a run continues where it changed the mesh, and the search's width
            // no longer multiplies at every step.
            for (const std::int32_t t : swap.slots)
              for (int i = 0; i < 3; ++i) {
                const pcl::index_t x = triangles_[t][i], y = triangles_[t][(i + 1) % 3];
                near.emplace_back (std::min (x, y), std::max (x, y));
              }
          }
          std::sort (near.begin (), near.end ());
          near.erase (std::unique (near.begin (), near.end ()), near.end ());
          // Not the new diagonal: swapping it back only undoes this swap.
          const pcl::index_t c = swap.after[0][1], d = swap.after[0][2];
          near.erase (std::remove (near.begin (), near.end (),
                                   std::make_pair (std::min (c, d), std::max (c, d))),
                      near.end ());
          const long total = swapSearch (near, depth - 1, so_far + gain, made + 1);
          if (total > 0)
            return total;
        }
      }
      undo (swap);
    }
    return 0;
  }

  /** Makes the swap; returns the decrease in intersecting pairs (negative if they
    * grow; unknown_gain if the grid cannot tell). */
  long
  apply (Swap& swap)
  {
    const std::size_t before = pairsOf (swap.slots, nullptr, &swap.pairs_before);
    const std::size_t after = pairsOf (swap.slots, &swap.after, &swap.pairs_after);
    swap.counted = before != unknown && after != unknown;
    replace (swap.slots, swap.after, swap.counted ? &swap.pairs_before : nullptr,
             swap.counted ? &swap.pairs_after : nullptr);
    if (!swap.counted)
      return unknown_gain;
    return static_cast<long> (before) - static_cast<long> (after);
  }

  void
  undo (const Swap& swap)
  {
    replace (swap.slots, swap.before, swap.counted ? &swap.pairs_after : nullptr,
             swap.counted ? &swap.pairs_before : nullptr);
  }

  template <typename InRegion>
  bool
  hasEdgeOutside (pcl::index_t a, pcl::index_t b, InRegion in_region) const
  {
    for (const std::int32_t t : star (a))
      if (!in_region (t))
        for (const pcl::index_t x : triangles_[t])
          if (x == b)
            return true;
    return false;
  }

  static constexpr std::size_t unknown = std::numeric_limits<std::size_t>::max ();

  /** Intersecting pairs that involve the star in `slots`: as it is (replacement
    * null), or with its triangles replaced (same order as the slots); `unknown` if
    * a triangle reaches outside the grid's kept blocks. */
  std::size_t
  pairsOf (const std::vector<std::int32_t>& slots, const Triangles* replacement,
           PairList* found = nullptr)
  {
    if (found)
      found->clear ();
    const auto current = [&] (std::size_t i) -> const Triangle& {
      return replacement ? (*replacement)[i] : triangles_[slots[i]];
    };
    // Triangles that meet have overlapping boxes: the exact test only for those
    // (a disc of two rings has thousands of pairs, nearly all apart).
    box_lo_.resize (slots.size ());
    box_hi_.resize (slots.size ());
    for (std::size_t i = 0; i < slots.size (); ++i)
      grid_.box (current (i), box_lo_[i], box_hi_[i]);
    // A disc's slots come sorted, a swap's two are few.
    const bool sorted = std::is_sorted (slots.begin (), slots.end ());
    const auto inSlots = [&] (std::int32_t o) {
      return sorted ? std::binary_search (slots.begin (), slots.end (), o)
                    : std::find (slots.begin (), slots.end (), o) != slots.end ();
    };
    std::size_t count = 0;
    for (std::size_t i = 0; i < slots.size (); ++i) {
      // Within the star, each pair once.
      for (std::size_t j = i + 1; j < slots.size (); ++j)
        if ((box_lo_[i].array () <= box_hi_[j].array ()).all () &&
            (box_lo_[j].array () <= box_hi_[i].array ()).all () &&
            trianglesIntersect (points_, current (i), current (j))) {
          ++count;
          if (found)
            found->emplace_back (slots[i], slots[j]);
        }
      // Against the rest of the mesh (the star's slots hold the old triangles in
      // the grid; they are skipped here).
      if (!grid_.candidates (current (i), scratch_))
        return unknown;
      for (const std::int32_t o : scratch_)
        if (!inSlots (o) && trianglesIntersect (points_, current (i), triangles_[o])) {
          ++count;
          if (found)
            found->emplace_back (slots[i], o);
        }
    }
    return count;
  }

  const Points3& points_;
  Triangles& triangles_;
  const CsrGraph* neighbours_ = nullptr;
  const std::vector<Eigen::Vector3f>* normals_ = nullptr;
  std::vector<std::size_t> star_offsets_;
  std::vector<std::int32_t> star_slots_;
  std::unordered_map<pcl::index_t, std::vector<std::int32_t>> changed_;
  TriangleGrid grid_;
  std::vector<std::int32_t> scratch_;
  std::vector<Vec3> box_lo_, box_hi_; // pairsOf's
  /** Per slot: the intersecting pairs its triangle is in, or `uncounted`. */
  std::vector<std::uint32_t> pairs_of_;
  /** FoldRepairOptions::rewritten, if it fits. */
  std::vector<char>* rewritten_ = nullptr;
  static constexpr std::uint32_t uncounted = std::numeric_limits<std::uint32_t>::max ();
  mutable std::vector<Vec2> plane_positions_; // planarDisc's, sized on first use
};

} // namespace

std::vector<std::int32_t>
closedDiscRegion (const Triangles& triangles,
                  const std::function<std::vector<std::int32_t> (pcl::index_t)>& star,
                  std::vector<pcl::index_t>& inner,
                  std::size_t max_triangles)
{
  std::vector<std::int32_t> slots;
  std::vector<std::pair<pcl::index_t, pcl::index_t>> directed, next;
  std::size_t last_size = 0;
  for (int growth = 0; growth < 16; ++growth) {
    std::sort (inner.begin (), inner.end ());
    inner.erase (std::unique (inner.begin (), inner.end ()), inner.end ());
    if (growth > 0 && inner.size () == last_size)
      return {}; // nothing new to take in (a boundary of the mesh itself, or non-manifold)
    last_size = inner.size ();
    slots.clear ();
    for (const pcl::index_t v : inner) {
      const auto around = star (v);
      slots.insert (slots.end (), around.begin (), around.end ());
    }
    std::sort (slots.begin (), slots.end ());
    slots.erase (std::unique (slots.begin (), slots.end ()), slots.end ());
    if (slots.size () > max_triangles || slots.size () < 4)
      return {};
    // Sorted arrays rather than a set and a map: a repair tries thousands of
    // regions, most of which it then leaves alone.
    directed.clear ();
    for (const std::int32_t t : slots)
      for (int k = 0; k < 3; ++k)
        directed.emplace_back (triangles[t][k], triangles[t][(k + 1) % 3]);
    std::sort (directed.begin (), directed.end ());
    directed.erase (std::unique (directed.begin (), directed.end ()), directed.end ());
    // The boundary: directed edges whose reverse is not in the region, by start.
    next.clear ();
    for (const auto& [a, b] : directed)
      if (!std::binary_search (directed.begin (), directed.end (), std::make_pair (b, a)))
        next.emplace_back (a, b);
    if (next.empty ())
      return {}; // the whole (closed) mesh
    std::vector<pcl::index_t> pinched;
    for (std::size_t i = 0; i + 1 < next.size (); ++i)
      if (next[i].first == next[i + 1].first && (pinched.empty () || pinched.back () != next[i].first))
        pinched.push_back (next[i].first);
    if (!pinched.empty ()) {
      inner.insert (inner.end (), pinched.begin (), pinched.end ());
      continue;
    }
    // The loops of the boundary; all but the longest are holes. Each boundary
    // vertex starts one edge now (none is pinched).
    std::vector<std::vector<pcl::index_t>> loops;
    std::vector<char> seen (next.size (), 0);
    const auto position = [&] (pcl::index_t x) -> std::ptrdiff_t {
      const auto it = std::lower_bound (next.begin (), next.end (), std::make_pair (x, pcl::index_t {0}),
                                        [] (const auto& e, const auto& key) { return e.first < key.first; });
      return it != next.end () && it->first == x ? it - next.begin () : -1;
    };
    for (std::size_t start = 0; start < next.size (); ++start) {
      if (seen[start])
        continue;
      loops.emplace_back ();
      std::ptrdiff_t at = static_cast<std::ptrdiff_t> (start);
      while (at >= 0 && !seen[at]) {
        seen[at] = 1;
        loops.back ().push_back (next[at].first);
        at = position (next[at].second);
      }
      if (at < 0)
        return {}; // the boundary does not close
      if (at != static_cast<std::ptrdiff_t> (start))
        return {}; // a tail into a loop: not an oriented manifold here
    }
    if (loops.size () == 1)
      return slots;
    // Loops of equal length: the one through the smallest vertex index is kept
    // (deterministic; around a limb the other side may then exceed max_triangles).
    std::stable_sort (loops.begin (), loops.end (),
                      [] (const auto& a, const auto& b) { return a.size () > b.size (); });
    for (std::size_t l = 1; l < loops.size (); ++l)
      inner.insert (inner.end (), loops[l].begin (), loops[l].end ());
  }
  return {};
}

FoldRepairResult
repairFoldsByReinsertion (const Points3& points,
                          Triangles& triangles,
                          const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                          const FoldRepairOptions& options)
{
  FoldRepairResult result;
  result.pairs_before = result.pairs_after = pairs.size ();
  if (pairs.empty ()) {
    result.success = true;
    return result;
  }
  for (const auto& [s, t] : pairs)
    if (s >= triangles.size () || t >= triangles.size ()) {
      result.message = "an intersecting pair names a triangle out of range";
      return result;
    }
  for (const Triangle& t : triangles)
    for (const pcl::index_t v : t)
      if (v < 0 || static_cast<std::size_t> (v) >= points.size ()) {
        result.message = "a triangle names a vertex out of range";
        return result;
      }
  if (!(options.max_pairs_per_triangle >= 0.0)) {
    result.message = "max_pairs_per_triangle must be a number >= 0";
    return result;
  }
  // A tangle: its cost grows with the crossings, and no local step lowers them.
  if (static_cast<double> (pairs.size ()) >
      options.max_pairs_per_triangle * static_cast<double> (triangles.size ())) {
    result.tangle = true;
    result.success = true;
    return result;
  }
  // Grid cells of about two mean edge lengths.
  double total = 0.0;
  for (const Triangle& t : triangles)
    total += (points[t[0]] - points[t[1]]).norm ();
  const double cell = triangles.empty () ? 1.0 : std::max (2.0 * total / triangles.size (), 1e-300);

  try {
    std::set<pcl::index_t> candidates;
    for (const auto& [s, t] : pairs)
      for (const std::size_t slot : {s, t})
        for (const pcl::index_t v : triangles[slot])
          candidates.insert (v);
    // The grid keeps the blocks within 8 cells (16 mean edge lengths) of the folds:
    // room for discs of two rings and the rounds after. A closed disc reaching past
    // them is not re-meshed (its pairs cannot be counted).
    FoldRepair repair (points, triangles, cell,
                       std::vector<pcl::index_t> (candidates.begin (), candidates.end ()), pairs, options);
    // Vertices of the triangles that still intersect, looked for where the repair
    // began or changed something.
    const std::set<pcl::index_t> folds = candidates;
    auto stillIntersecting = [&] () {
      std::set<pcl::index_t> around = folds;
      for (const pcl::index_t x : repair.changedVertices ())
        around.insert (x);
      std::set<pcl::index_t> left;
      for (const pcl::index_t x : around)
        for (const std::int32_t t : repair.star (x))
          if (repair.intersectsSomething (t))
            left.insert (triangles[t].begin (), triangles[t].end ());
      return left;
    };
    // Rounds of `step` on the vertices in `todo`: a vertex whose step lowered the
    // count hands on the vertices of the triangles around it still intersecting.
    auto rounds = [&] (std::set<pcl::index_t> todo, auto step, std::size_t& done) {
      for (int round = 0; round < options.max_rounds && !todo.empty (); ++round) {
        std::set<pcl::index_t> again;
        for (const pcl::index_t v : todo) {
          const std::size_t gain = step (v);
          if (gain == 0)
            continue;
          result.pairs_after -= gain;
          ++done;
          for (const std::int32_t t : repair.star (v))
            if (repair.intersectsSomething (t))
              for (const pcl::index_t x : triangles[t])
                again.insert (x);
        }
        todo.swap (again);
      }
    };
    // The vertex alone, then with its ring, then with two rings: folds that reach
    // past the vertex's own star need the larger discs.
    auto disc = [&] (pcl::index_t v) {
      std::vector<pcl::index_t> region{v};
      std::size_t gain = 0;
      for (int rings = 0; rings <= 2 && gain == 0; ++rings) {
        if (rings > 0) {
          const std::vector<pcl::index_t> inner = region;
          for (const pcl::index_t x : inner) {
            const auto around = repair.neighbours (x);
            region.insert (region.end (), around.begin (), around.end ());
          }
        }
        gain = repair.tryRemesh (region, options.max_region_triangles);
      }
      return gain;
    };
    auto swaps = [&] (pcl::index_t v) { return repair.trySwaps (v, options.max_swaps_in_a_row); };
    // Discs first, then swaps where pairs are left (interleaved, a swap can take
    // a disc's chance away); and again, as each opens folds for the other.
    for (int pass = 0; pass < options.max_passes && result.pairs_after > 0; ++pass) {
      const std::size_t at_start = result.pairs_after;
      rounds (pass == 0 ? candidates : stillIntersecting (), disc, result.regions_remeshed);
      if (options.swaps && result.pairs_after > 0)
        rounds (stillIntersecting (), swaps, result.swaps);
      if (result.pairs_after == at_start)
        break; // the next pass would start from the same triangles
    }
    repair.setSwapBudget (options.max_swaps_tried_in_longer_runs);
    for (int in_a_row = options.max_swaps_in_a_row + 1;
         options.swaps && options.max_swaps_tried_in_longer_runs > 0 &&
         in_a_row <= options.max_swaps_in_a_row_when_few &&
         result.pairs_after > 0 && result.pairs_after <= options.max_pairs_for_longer_runs &&
         !repair.swapRefused ();
         ++in_a_row) {
      const auto run = [&] (pcl::index_t v) { return repair.trySwaps (v, in_a_row); };
      rounds (stillIntersecting (), run, result.swaps);
    }
    result.longer_run_swaps_tried = options.max_swaps_tried_in_longer_runs - repair.swapsLeft ();
    result.longer_runs_cut_short = repair.swapRefused ();
  }
  catch (const std::bad_alloc&) {
    result.message = "out of memory";
    return result;
  }
  catch (const std::exception& e) {
    result.message = std::string ("unexpected error: ") + e.what ();
    return result;
  }
  result.success = true;
  return result;
}

} // namespace meshless
} // namespace pcl
