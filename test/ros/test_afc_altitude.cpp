// afc.launch with altitude:=A holds it through ROS: the controller flies by the IMU (it
// subscribes to <creature>/imu, the topic `~imu_topic`), and on `~odom_topic`, from `~settle`
// s of sim time to `~duration`, the root stays within `~band` m of A and its up-component above
// `~min_up`. With `~torque` (N m) a roll torque about the world's x axis (the root's at its
// start heading) acts from `~torque_time` for `~torque_duration` s of sim time
// (flapsim/apply_wrench with start_time). Run with lockstep:=true: the flight is the same on
// every run.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "flapsim/ApplyWrench.h"
#include "service_call.h"
#include "wait_for.h"

namespace {

// The nodes that subscribe to `topic`, as the master knows them (empty if it cannot be asked).
std::vector<std::string> subscribersOf(const std::string& topic) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  std::vector<std::string> nodes;
  if (!ros::master::execute("getSystemState", args, result, payload, false)) return nodes;
  for (int i = 0; i < payload[1].size(); ++i) {
    if (static_cast<std::string>(payload[1][i][0]) != topic) continue;
    for (int k = 0; k < payload[1][i][1].size(); ++k) nodes.push_back(payload[1][i][1][k]);
  }
  return nodes;
}

TEST(AfcAltitude, FliesByTheImuAndHoldsTheAltitudeUprightAfterSettling) {
  ros::NodeHandle nh, pnh("~");
  double altitude = 0.0, settle = 10.0, duration = 60.0, band = 0.5, min_up = 0.9;
  double wall_timeout = 300.0;
  std::string odom = "/afc/odom", imu = "/afc/imu", controller = "/afc/ann_controller";
  ASSERT_TRUE(pnh.getParam("altitude", altitude)) << "~altitude is not set";
  pnh.getParam("settle", settle);
  pnh.getParam("duration", duration);
  pnh.getParam("band", band);
  pnh.getParam("min_up", min_up);
  pnh.getParam("wall_timeout", wall_timeout);
  pnh.getParam("odom_topic", odom);
  pnh.getParam("imu_topic", imu);
  pnh.getParam("controller", controller);
  double torque = 0.0, torque_time = 0.0, torque_duration = 0.5;
  std::string creature = "afc";
  pnh.getParam("torque", torque);
  pnh.getParam("torque_time", torque_time);
  pnh.getParam("torque_duration", torque_duration);
  pnh.getParam("creature", creature);

  bool seen = false;
  double last_t = 0.0, lowest_up = 1.0, low = 1e9, high = -1e9, sq = 0.0;
  int settled = 0;
  ros::Subscriber sub =
      nh.subscribe<nav_msgs::Odometry>(odom, 1000, [&](const nav_msgs::Odometry::ConstPtr& m) {
        last_t = m->header.stamp.toSec();
        seen = true;
        if (last_t < settle || last_t > duration) return;
        const auto& q = m->pose.pose.orientation;
        const double z = m->pose.pose.position.z;
        lowest_up = std::min(lowest_up, 1.0 - 2.0 * (q.x * q.x + q.y * q.y));
        low = std::min(low, z);
        high = std::max(high, z);
        sq += (z - altitude) * (z - altitude);
        ++settled;
      });
  bool pushed = torque == 0.0;
  flapsim_test::waitFor(
      [&] {
        if (!pushed && seen) {
          // Sent at the first odometry, to act from torque_time exactly (start_time): about the
          // world's x axis, the creature's roll axis at its start heading. Sent when the clock
          // passed torque_time, it acted from whichever step the call met, and flights in
          // lockstep parted between runs.
          flapsim::ApplyWrench a;
          a.request.name = creature;
          a.request.wrench.torque.x = torque;
          a.request.duration = ros::Duration(torque_duration);
          a.request.start_time = ros::Time(torque_time);
          pushed = flapsim_test::call("/flapsim/apply_wrench", a) && a.response.success;
          EXPECT_TRUE(pushed) << a.response.status_message;
          EXPECT_NEAR(a.response.start_time.toSec(), torque_time, 1e-6);
          std::printf("roll torque %.3f N m from t = %.3f s for %.2f s\n", torque,
                      a.response.start_time.toSec(), torque_duration);
          pushed = true;
        }
        return last_t >= duration;
      },
      wall_timeout);
  ASSERT_GE(last_t, duration) << "the flight did not reach t = " << duration << " s on " << odom;
  const std::vector<std::string> readers = subscribersOf(imu);
  EXPECT_NE(std::find(readers.begin(), readers.end(), controller), readers.end())
      << controller << " does not subscribe to " << imu;
  ASSERT_GT(settled, 0);
  std::printf("%d samples from t = %.1f s: z %.3f to %.3f m (rms error %.3f m), lowest up %.4f\n",
              settled, settle, low, high, std::sqrt(sq / settled), lowest_up);
  EXPECT_GE(low, altitude - band);
  EXPECT_LE(high, altitude + band);
  EXPECT_GT(lowest_up, min_up);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_afc_altitude");
  return RUN_ALL_TESTS();
}
