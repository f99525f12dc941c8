// Recording a topic in rostests: every message kept, in arrival order, and the one stamped
// at a given sim time waited for (with wait_for.h's wall-clock bound).
#pragma once

#include <ros/ros.h>

#include <string>
#include <vector>

#include "wait_for.h"

namespace flapsim_test {

template <class M>
class Recorder {
 public:
  void start(ros::NodeHandle& nh, const std::string& topic, unsigned queue = 10000) {
    sub_ = nh.subscribe<M>(topic, queue,
                           [this](const boost::shared_ptr<const M>& m) { msgs.push_back(m); });
  }
  bool connected() const { return sub_.getNumPublishers() > 0; }
  void clear() { msgs.clear(); }
  /// The last message stamped `t`, waited for up to `timeout` s (wall); null if none came.
  boost::shared_ptr<const M> at(const ros::Time& t, double timeout) {
    boost::shared_ptr<const M> found;
    waitFor(
        [&] {
          for (auto it = msgs.rbegin(); it != msgs.rend(); ++it) {
            if ((*it)->header.stamp == t) {
              found = *it;
              return true;
            }
          }
          return false;
        },
        timeout);
    return found;
  }

  std::vector<boost::shared_ptr<const M>> msgs;

 private:
  ros::Subscriber sub_;
};

}  // namespace flapsim_test
