/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "region_merging.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

namespace pcl {
namespace meshless {

namespace {

/** D's faces while regions merge: a face is dead once merged into another; every
  * merge tried is undone where it would break D. */
class RegionMerger
{
public:
  explicit RegionMerger (const GrownBaseMesh& grown)
  : faces_ (grown.mesh.faces)
  , alive_ (faces_.size (), 1)
  , stuck_ (faces_.size (), 0)
  , size_ (faces_.size (), 0)
  , merged_into_ (faces_.size ())
  , around_ (grown.mesh.vertices.size ())
  {
    for (std::size_t f = 0; f < faces_.size (); ++f)
      for (const int c : faces_[f])
        around_[c].push_back (static_cast<int> (f));
    for (const int f : grown.region_of)
      if (f >= 0 && static_cast<std::size_t> (f) < size_.size ())
        ++size_[f];
    std::iota (merged_into_.begin (), merged_into_.end (), 0);
  }

  /** Merges while a face below min_points can. \return the number of merges. */
  std::size_t
  run (std::size_t min_points)
  {
    std::size_t merges = 0;
    for (int f = smallestOpen (min_points); f >= 0; f = smallestOpen (min_points)) {
      std::vector<int> neighbours = edgeNeighbours (f);
      std::sort (neighbours.begin (), neighbours.end (), [&] (int a, int b) {
        return size_[a] < size_[b] || (size_[a] == size_[b] && a < b);
      });
      bool merged = false;
      for (const int g : neighbours)
        if ((merged = tryMerge (f, g)))
          break;
      if (merged)
        ++merges;
      else
        stuck_[f] = 1;
    }
    return merges;
  }

  /** D after the merges into `grown`, its regions renumbered as its faces. */
  void
  write (GrownBaseMesh& grown) const
  {
    std::vector<int> face_index (faces_.size (), -1);
    std::vector<int> corner_index (grown.mesh.vertices.size (), -1);
    BaseMesh mesh;
    std::vector<pcl::index_t> seeds;
    for (std::size_t f = 0; f < faces_.size (); ++f) {
      if (!alive_[f])
        continue;
      face_index[f] = static_cast<int> (mesh.faces.size ());
      std::vector<int> face;
      for (const int c : faces_[f]) {
        if (corner_index[c] < 0) {
          corner_index[c] = static_cast<int> (mesh.vertices.size ());
          mesh.vertices.push_back (grown.mesh.vertices[c]);
        }
        face.push_back (corner_index[c]);
      }
      mesh.faces.push_back (std::move (face));
      seeds.push_back (grown.seeds[f]);
    }
    std::vector<int> new_index (faces_.size ());
    for (std::size_t f = 0; f < faces_.size (); ++f)
      new_index[f] = face_index[root (static_cast<int> (f))];
    for (int& r : grown.region_of)
      if (r >= 0)
        r = new_index[r];
    mesh.point_faces = grown.region_of;
    grown.mesh = std::move (mesh);
    grown.seeds = std::move (seeds);
  }

private:
  int
  root (int f) const
  {
    while (merged_into_[f] != f)
      f = merged_into_[f];
    return f;
  }

  /** The smallest face below min_points that may still merge, or -1. */
  int
  smallestOpen (std::size_t min_points) const
  {
    int best = -1;
    for (std::size_t f = 0; f < faces_.size (); ++f)
      if (alive_[f] && !stuck_[f] && size_[f] < min_points &&
          (best < 0 || size_[f] < size_[best]))
        best = static_cast<int> (f);
    return best;
  }

  static int
  position (const std::vector<int>& face, int corner)
  {
    const auto it = std::find (face.begin (), face.end (), corner);
    return it == face.end () ? -1 : static_cast<int> (it - face.begin ());
  }

  /** The face that holds the directed edge b -> a (across a -> b), or -1. */
  int
  across (int a, int b) const
  {
    for (const int g : around_[b]) {
      const std::vector<int>& face = faces_[g];
      if (face[(position (face, b) + 1) % face.size ()] == a)
        return g;
    }
    return -1;
  }

  /** The faces across f's edges, each once. */
  std::vector<int>
  edgeNeighbours (int f) const
  {
    std::vector<int> neighbours;
    const std::vector<int>& face = faces_[f];
    for (std::size_t k = 0; k < face.size (); ++k) {
      const int g = across (face[k], face[(k + 1) % face.size ()]);
      if (g >= 0 && g != f &&
          std::find (neighbours.begin (), neighbours.end (), g) == neighbours.end ())
        neighbours.push_back (g);
    }
    return neighbours;
  }

  /** Whether some live face has the edge a - b in either direction. */
  bool
  hasEdge (int a, int b) const
  {
    for (const int f : around_[a]) {
      const std::vector<int>& face = faces_[f];
      const std::size_t m = face.size ();
      const int pos = position (face, a);
      if (face[(pos + 1) % m] == b || face[(pos + m - 1) % m] == b)
        return true;
    }
    return false;
  }

  /** Keeps face f as it was before the merge being tried (once per merge). */
  void
  save (int f)
  {
    for (const auto& saved : saved_faces_)
      if (saved.first == f)
        return;
    saved_faces_.emplace_back (f, faces_[f]);
  }

  /** Removes a corner that only two faces hold (it no longer joins three paths):
    * its two edges become one. \return false if that edge exists already or a face
    * would keep fewer than three corners. */
  bool
  dropCorner (int corner)
  {
    const std::vector<int> around = around_[corner];
    if (around.size () != 2)
      return around.size () > 2;
    const std::vector<int>& first = faces_[around[0]];
    const std::size_t m = first.size ();
    const int pos = position (first, corner);
    const int before = first[(pos + m - 1) % m], after = first[(pos + 1) % m];
    if (before == after || hasEdge (before, after))
      return false;
    for (const int f : around) {
      if (faces_[f].size () <= 3)
        return false;
      save (f);
      faces_[f].erase (faces_[f].begin () + position (faces_[f], corner));
    }
    around_[corner].clear ();
    return true;
  }

  /** Merges face g into face f across their one shared edge. \return false (and
    * nothing changed) where D would stop being a closed polygon mesh whose faces
    * are discs. */
  bool
  tryMerge (int f, int g)
  {
    const std::vector<int>& F = faces_[f];
    const std::vector<int>& G = faces_[g];
    std::vector<int> shared;
    for (const int c : F)
      if (position (G, c) >= 0)
        shared.push_back (c);
    if (shared.size () != 2)
      return false; // another shared arc or corner: the union would not be a disc
    const std::size_t m = F.size (), gm = G.size ();
    int iu = -1;
    for (std::size_t i = 0; i < m; ++i)
      if (position (shared, F[i]) >= 0 && position (shared, F[(i + 1) % m]) >= 0)
        iu = static_cast<int> (i);
    if (iu < 0)
      return false;
    const int u = F[iu], v = F[(iu + 1) % m];
    const int jv = position (G, v);
    if (G[(jv + 1) % gm] != u)
      return false;
    std::vector<int> merged;
    for (std::size_t k = 0; k < m; ++k)
      merged.push_back (F[(iu + 1 + k) % m]); // v ... u around F
    for (std::size_t k = 2; k < gm; ++k)
      merged.push_back (G[(jv + k) % gm]); // after u up to before v around G
    saved_faces_.clear ();
    saved_around_.clear ();
    for (const int c : G)
      saved_around_.emplace_back (c, around_[c]);
    save (f);
    save (g);
    for (const int c : G) {
      std::vector<int>& around = around_[c];
      around.erase (std::remove (around.begin (), around.end (), g), around.end ());
      if (std::find (around.begin (), around.end (), f) == around.end ())
        around.push_back (f);
    }
    faces_[f] = std::move (merged);
    alive_[g] = 0;
    if (!dropCorner (u) || !dropCorner (v)) {
      for (auto& saved : saved_faces_)
        faces_[saved.first] = std::move (saved.second);
      for (auto& saved : saved_around_)
        around_[saved.first] = std::move (saved.second);
      alive_[g] = 1;
      return false;
    }
    size_[f] += size_[g];
    merged_into_[g] = f;
    return true;
  }

  std::vector<std::vector<int>> faces_;
  std::vector<char> alive_, stuck_;
  std::vector<std::size_t> size_;
  std::vector<int> merged_into_;
  /** Per corner, the live faces that hold it. */
  std::vector<std::vector<int>> around_;
  /** What the merge being tried changed, to undo it. */
  std::vector<std::pair<int, std::vector<int>>> saved_faces_, saved_around_;
};

} // namespace

std::size_t
mergeSmallRegions (GrownBaseMesh& grown, std::size_t min_points)
{
  if (!grown.success || grown.mesh.faces.size () != grown.seeds.size ())
    return 0;
  RegionMerger merger (grown);
  const std::size_t merges = merger.run (min_points);
  if (merges == 0)
    return 0;
  GrownBaseMesh coarse = grown;
  merger.write (coarse);
  std::string problem;
  if (closedBaseMeshGenus (coarse.mesh, coarse.region_of.size (), problem) != grown.genus)
    return 0; // a merge the local checks missed: keep the fine D
  grown = std::move (coarse);
  return merges;
}

} // namespace meshless
} // namespace pcl
