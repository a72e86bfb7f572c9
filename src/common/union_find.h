/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief Union-find over the elements 0 .. n - 1, with path halving.
  *
  * The smaller root becomes the root of a union, so a set's root is its smallest
  * member whatever the order of the unions: callers may use find() as a
  * deterministic label. boost::disjoint_sets does not fit: its union by rank picks
  * either root, and its storage takes a size_t parent and a rank per element where
  * this takes one Index (the mesh checks join every corner of a mesh).
  */
template <typename Index>
class DisjointSets
{
public:
  explicit DisjointSets (std::size_t n) : parent_ (n, Index{0})
  {
    std::iota (parent_.begin (), parent_.end (), Index{0});
  }

  /** \brief The root (smallest member) of x's set. */
  Index
  find (Index x)
  {
    while (parent_[x] != x)
      x = parent_[x] = parent_[parent_[x]];
    return x;
  }

  /** \brief Joins the sets of a and b.
    * \return false if they were one set already */
  bool
  join (Index a, Index b)
  {
    a = find (a);
    b = find (b);
    if (a == b)
      return false;
    parent_[std::max (a, b)] = std::min (a, b);
    return true;
  }

  /** \brief Whether x is the root of its set (each set has exactly one). */
  bool
  isRoot (Index x) const
  {
    return parent_[x] == x;
  }

  std::size_t
  size () const
  {
    return parent_.size ();
  }

private:
  std::vector<Index> parent_;
};

} // namespace meshless
} // namespace pcl
