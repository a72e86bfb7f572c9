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
  * the resident set holds both. Measured on armadillo_uniform_1m with two threads:
  * after the fold repair 204 MB in use but 528 MB resident; released after the
  * sphere pipeline and before the edge swaps, the swaps' peak 690 -> about 620 MB,
  * and no slower (three runs each, the same within the machine's noise).
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
