#include "flapsim_ros/node_main.h"

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/topic_manager.h>
#include <rosgraph_msgs/Log.h>

#include <algorithm>
#include <exception>
#include <functional>

namespace flapsim_ros {

namespace {

// Whether a rosout node runs (it publishes /rosout_agg).
bool rosoutNodeRuns() {
  ros::master::V_TopicInfo topics;
  if (!ros::master::getTopics(topics)) return false;
  return std::any_of(topics.begin(), topics.end(),
                     [](const ros::master::TopicInfo& t) { return t.name == "/rosout_agg"; });
}

// Logs `text` as FATAL once someone listens on /rosout (the rosout node or any subscriber),
// then waits until the rosout node echoes it on /rosout_agg, or, without one, 0.3 s, so that
// it is sent to each listener before the process ends. Without a master it is only printed;
// every wait is bounded (2 s of wall time in all).
void logFatal(const std::string& text) {
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(2.0);
  ros::CallbackQueue queue;
  ros::Subscriber echo;
  bool seen = false;
  const bool master = ros::ok() && ros::master::check();
  if (master && rosoutNodeRuns()) {
    ros::NodeHandle nh;
    nh.setCallbackQueue(&queue);
    echo = nh.subscribe<rosgraph_msgs::Log>(
        "/rosout_agg", 10, [&](const rosgraph_msgs::Log::ConstPtr& m) {
          seen = seen || (m->level == rosgraph_msgs::Log::FATAL && m->msg == text);
        });
  }
  auto waitWhile = [&](const std::function<bool()>& pending, const ros::WallTime& end) {
    while (pending() && ros::WallTime::now() < end) queue.callAvailable(ros::WallDuration(0.01));
  };
  auto topics = ros::TopicManager::instance();
  if (master) waitWhile([&] { return topics->getNumSubscribers("/rosout") == 0; }, until);
  if (echo) waitWhile([&] { return echo.getNumPublishers() == 0; }, until);
  ROS_FATAL_STREAM(text);
  if (echo) {
    waitWhile([&] { return !seen; }, until);
  } else if (master) {
    waitWhile([] { return true; }, std::min(until, ros::WallTime::now() + ros::WallDuration(0.3)));
  }
}

}  // namespace

int runNode(const std::string& node, const std::function<int()>& body) {
  ros::NodeHandle keep;  // roscpp (and its logging) stays up until the cause is logged
  try {
    return body();
  } catch (const std::exception& e) {
    logFatal(node + ": " + e.what());
    return 1;
  }
}

}  // namespace flapsim_ros
