// A creature flown through ROS flies: from `~odom_topic`, until the sim time reaches
// `~duration`, its root's up-component never falls below 0.5 (no flip) and it ends more
// than `~min_climb` above its first sample. For afc.launch with lockstep:=true, where the
// controller drives the paused simulator: the flight is the same on every run.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include <algorithm>
#include <string>

#include "wait_for.h"

namespace {

TEST(AfcFlight, StaysUprightAndClimbsUntilTheDuration) {
  ros::NodeHandle nh, pnh("~");
  std::string topic = "/afc/odom";
  double duration = 20.0, min_climb = 1.0, wall_timeout = 300.0;
  pnh.getParam("odom_topic", topic);
  pnh.getParam("duration", duration);
  pnh.getParam("min_climb", min_climb);
  pnh.getParam("wall_timeout", wall_timeout);
  bool have_first = false;
  double first_z = 0.0, last_z = 0.0, last_t = 0.0, lowest_up = 1.0;
  int samples = 0;
  ros::Subscriber sub =
      nh.subscribe<nav_msgs::Odometry>(topic, 1000, [&](const nav_msgs::Odometry::ConstPtr& m) {
        const auto& q = m->pose.pose.orientation;
        const double up = 1.0 - 2.0 * (q.x * q.x + q.y * q.y);  // world z of the body z axis
        if (!have_first) first_z = m->pose.pose.position.z;
        have_first = true;
        lowest_up = std::min(lowest_up, up);
        last_z = m->pose.pose.position.z;
        last_t = m->header.stamp.toSec();
        ++samples;
      });
  flapsim_test::waitFor([&] { return last_t >= duration; }, wall_timeout);
  ASSERT_GE(last_t, duration) << "the flight did not reach t = " << duration << " s on " << topic;
  std::printf("%s: %d samples to t = %.3f s, z %.3f -> %.3f m, lowest up %.4f\n", topic.c_str(),
              samples, last_t, first_z, last_z, lowest_up);
  EXPECT_GT(lowest_up, 0.5);
  EXPECT_GT(last_z, first_z + min_climb);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_afc_flight");
  return RUN_ALL_TESTS();
}
