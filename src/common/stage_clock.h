/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
#pragma once

#include <pcl/surface/meshless/sphere_pipeline.h> // ProgressCallback

#include <chrono>
#include <string>

namespace pcl {
namespace meshless {

/** \brief Times stages and reports them to a progress callback; remembers a
  * cancellation. Every stage of the library reports through it. */
class StageClock
{
public:
  explicit StageClock (const ProgressCallback& callback) : callback_ (callback) {}

  /** \brief Starts timing the next stage. */
  void
  restart ()
  {
    start_ = Clock::now ();
  }

  /** \brief Reports the stage timed since the last restart (or report), and starts
    * the next one. \return false if the callback cancelled, now or before. */
  bool
  done (const std::string& stage, double fraction, const std::string& detail = "")
  {
    const auto now = Clock::now ();
    const double seconds = std::chrono::duration<double> (now - start_).count ();
    start_ = now;
    if (callback_ && !callback_ ({stage, fraction, seconds, detail}))
      cancelled_ = true;
    return !cancelled_;
  }

  /** \brief Whether the callback has cancelled. */
  bool
  cancelled () const
  {
    return cancelled_;
  }

private:
  using Clock = std::chrono::steady_clock;
  const ProgressCallback& callback_;
  Clock::time_point start_ = Clock::now ();
  bool cancelled_ = false;
};

} // namespace meshless
} // namespace pcl
