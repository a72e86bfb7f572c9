/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "freed_memory.h"

#include <cstdlib> // defines __GLIBC__ where it is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pcl {
namespace meshless {

bool
releaseFreedMemory ()
{
#if defined(__GLIBC__)
  malloc_trim (0); // every arena, free pages inside the heaps too (glibc >= 2.8)
  return true;
#else
  return false;
#endif
}

} // namespace meshless
} // namespace pcl
