// Creatures flown through ROS fly: on each of `~odom_topics` (or the one `~odom_topic`),
// until the sim time reaches `~duration`, the root's up-component never falls below 0.5 (no
// flip) and the creature ends more than `~min_climb` above `~start_z`, the height the launch
// file spawned its root at (t = 0; the first sample this node receives may come later). For
// afc.launch and flock.launch with lockstep:=true, where a controller drives the paused
// simulator: the flight is the same on every run.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include <algorithm>
#include <string>
#include <vector>

#include "wait_for.h"

namespace {

struct Flight {
  bool have_first = false;
  double first_z = 0.0, first_t = 0.0, last_z = 0.0, last_t = 0.0, lowest_up = 1.0;
  int samples = 0;

  void add(const nav_msgs::Odometry& m) {
    const auto& q = m.pose.pose.orientation;
    const double up = 1.0 - 2.0 * (q.x * q.x + q.y * q.y);  // world z of the body z axis
    if (!have_first) {
      first_z = m.pose.pose.position.z;
      first_t = m.header.stamp.toSec();
    }
    have_first = true;
    lowest_up = std::min(lowest_up, up);
    last_z = m.pose.pose.position.z;
    last_t = m.header.stamp.toSec();
    ++samples;
  }
};

TEST(AfcFlight, StaysUprightAndClimbsUntilTheDuration) {
  ros::NodeHandle nh, pnh("~");
  std::string topic = "/afc/odom";
  std::vector<std::string> topics;
  double duration = 20.0, min_climb = 1.0, wall_timeout = 300.0, start_z = 0.0;
  ASSERT_TRUE(pnh.getParam("start_z", start_z)) << "~start_z (the spawn height) is not set";
  pnh.getParam("odom_topic", topic);
  if (!pnh.getParam("odom_topics", topics)) topics = {topic};
  pnh.getParam("duration", duration);
  pnh.getParam("min_climb", min_climb);
  pnh.getParam("wall_timeout", wall_timeout);
  // ~lockstep_param: a controller's lockstep parameter that must be true (a launch's default).
  std::string lockstep_param;
  if (pnh.getParam("lockstep_param", lockstep_param)) {
    bool lockstep = false;
    EXPECT_TRUE(ros::param::get(lockstep_param, lockstep) && lockstep) << lockstep_param;
  }
  std::vector<Flight> flights(topics.size());
  std::vector<ros::Subscriber> subs;
  for (size_t i = 0; i < topics.size(); ++i) {
    subs.push_back(nh.subscribe<nav_msgs::Odometry>(
        topics[i], 1000,
        [&flights, i](const nav_msgs::Odometry::ConstPtr& m) { flights[i].add(*m); }));
  }
  flapsim_test::waitFor(
      [&] {
        return std::all_of(flights.begin(), flights.end(),
                           [&](const Flight& f) { return f.last_t >= duration; });
      },
      wall_timeout);
  for (size_t i = 0; i < topics.size(); ++i) {
    const Flight& f = flights[i];
    ASSERT_GE(f.last_t, duration) << "the flight did not reach t = " << duration << " s on "
                                  << topics[i];
    std::printf(
        "%s: %d samples from t = %.3f s (z %.3f) to t = %.3f s, z %.3f -> %.3f m, "
        "lowest up %.4f\n",
        topics[i].c_str(), f.samples, f.first_t, f.first_z, f.last_t, start_z, f.last_z,
        f.lowest_up);
    EXPECT_GT(f.lowest_up, 0.5) << topics[i];
    EXPECT_GT(f.last_z, start_z + min_climb) << topics[i];
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_afc_flight");
  return RUN_ALL_TESTS();
}
