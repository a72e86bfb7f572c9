/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

namespace pcl {
namespace meshless {

/** \brief The team size for a parallel region of a stage whose options ask for
  * `requested` threads: that many if positive, else all cores (OpenMP's default
  * team, omp_get_max_threads). Stages pass it in a num_threads clause, so the
  * library never changes OpenMP's global setting. 1 without OpenMP.
  *
  * Defined in the library, which is built with OpenMP, so that code built without
  * it (a test) gets the same answer. */
int
threadCount (int requested);

/** \brief The calling thread's index in its parallel team (0 outside one). */
int
threadIndex ();

} // namespace meshless
} // namespace pcl
