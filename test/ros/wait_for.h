// Waiting in rostests: spin the global queue until a condition holds or a wall-clock
// timeout passes (a bound on the wait, never a measurement).
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <functional>

namespace flapsim_test {

inline bool waitFor(const std::function<bool()>& done, double timeout) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && !done() && ros::WallTime::now() < deadline) {
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.01));
  }
  return done();
}

}  // namespace flapsim_test
