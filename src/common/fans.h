/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <array>
#include <map>
#include <vector>

namespace pcl {
namespace meshless {

/** \brief Whether the faces around a vertex form one cycle: each face is given as
  * the pair (the corner after the vertex, the corner before it), and the cycle
  * follows a face's "before" corner to the face whose "after" corner it is. */
inline bool
isOneFan (const std::vector<std::array<int, 2>>& fan)
{
  if (fan.empty ())
    return false;
  std::map<int, int> next_of;
  for (const auto& [next, previous] : fan)
    if (!next_of.emplace (previous, next).second)
      return false;
  int current = fan[0][0];
  std::size_t steps = 0;
  do {
    const auto it = next_of.find (current);
    if (it == next_of.end ())
      return false;
    current = it->second;
    ++steps;
  } while (current != fan[0][0] && steps <= fan.size ());
  return steps == fan.size () && current == fan[0][0];
}

} // namespace meshless
} // namespace pcl
