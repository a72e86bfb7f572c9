/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

/** \file
  * Freed memory given back to the operating system between stages.
  *
  * glibc's allocator keeps what a program frees for its next allocations, and
  * arrays of up to 32 MB come from that pool once a large one has been freed (its
  * mmap threshold rises). The stages free hundreds of MB of such arrays on a
  * million points in a scattered heap, and the next stages allocate theirs anew:
  * the resident set holds both. Released between stages, the peak of a large cloud
  * drops by about a tenth, and no time is lost (doc/benchmarks.md). The heap is the
  * host application's: the class releases only when asked (setReleaseFreedMemory).
  */
namespace pcl {
namespace meshless {

/** \brief Returns the allocator's free memory to the operating system where the C
  * library can (glibc: malloc_trim); does nothing elsewhere.
  * \return whether the C library offers it. */
bool
releaseFreedMemory ();

} // namespace meshless
} // namespace pcl
