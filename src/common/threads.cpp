/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#include "threads.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pcl {
namespace meshless {

int
threadCount (int requested)
{
#ifdef _OPENMP
  return requested > 0 ? requested : omp_get_max_threads ();
#else
  (void) requested;
  return 1;
#endif
}

int
threadIndex ()
{
#ifdef _OPENMP
  return omp_get_thread_num ();
#else
  return 0;
#endif
}

} // namespace meshless
} // namespace pcl
