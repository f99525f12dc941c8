// A launch file starts and its creatures do what the scenario says. The
// launch file is included paused; this test connects, has the t = 0 state
// published (flapsim/step 0), steps `~duration` of sim time, checks each
// creature's displacement against `~checks` (a list, required, of {topic, min_dz, max_dz,
// min_dx, max_dx, min_abs_dx, min_dxy, max_dxy}, the bounds optional), and checks that unpausing
// runs the sim.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "flapsim/Step.h"
#include "service_call.h"
#include "wait_for.h"

namespace {

using flapsim_test::waitFor;

double member(XmlRpc::XmlRpcValue& v, const std::string& key, double def) {
  if (!v.hasMember(key)) return def;
  XmlRpc::XmlRpcValue& x = v[key];
  return x.getType() == XmlRpc::XmlRpcValue::TypeInt ? static_cast<int>(x) : static_cast<double>(x);
}

// Each creature's displacement from `first` to `at_end` (by odom topic) within the bounds of
// ~checks.
void expectDisplacements(ros::NodeHandle& pnh, std::map<std::string, nav_msgs::Odometry>& first,
                         std::map<std::string, nav_msgs::Odometry>& at_end) {
  XmlRpc::XmlRpcValue checks;
  ASSERT_TRUE(pnh.getParam("checks", checks)) << "~checks is missing: a scenario must say what "
                                                 "its creatures do";
  ASSERT_EQ(checks.getType(), XmlRpc::XmlRpcValue::TypeArray) << "~checks must be a list";
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < checks.size(); ++i) {
    const std::string t = checks[i]["topic"];
    ASSERT_TRUE(at_end.count(t)) << t << " is not in odom_topics";
    const auto& p0 = first[t].pose.pose.position;
    const auto& p1 = at_end[t].pose.pose.position;
    const double dz = p1.z - p0.z;
    const double dx = p1.x - p0.x;
    const double dxy = std::hypot(p1.x - p0.x, p1.y - p0.y);
    testing::Test::RecordProperty(t + "_dx", std::to_string(dx));
    testing::Test::RecordProperty(t + "_dz", std::to_string(dz));
    testing::Test::RecordProperty(t + "_dxy", std::to_string(dxy));
    EXPECT_GE(dz, member(checks[i], "min_dz", -inf)) << t;
    EXPECT_LE(dz, member(checks[i], "max_dz", inf)) << t;
    EXPECT_GE(dx, member(checks[i], "min_dx", -inf)) << t;
    EXPECT_LE(dx, member(checks[i], "max_dx", inf)) << t;
    EXPECT_GE(std::abs(dx), member(checks[i], "min_abs_dx", -inf)) << t;
    EXPECT_GE(dxy, member(checks[i], "min_dxy", -inf)) << t;
    EXPECT_LE(dxy, member(checks[i], "max_dxy", inf)) << t;
  }
}

TEST(LaunchSmoke, CreaturesMoveAsTheScenarioSays) {
  ros::NodeHandle nh, pnh("~");
  std::vector<std::string> topics;
  ASSERT_TRUE(pnh.getParam("odom_topics", topics));
  double duration = 1.0;
  pnh.getParam("duration", duration);

  std::map<std::string, nav_msgs::Odometry> first, last;
  std::vector<ros::Subscriber> subs;
  for (const std::string& t : topics) {
    subs.push_back(
        nh.subscribe<nav_msgs::Odometry>(t, 1000, [&, t](const nav_msgs::Odometry::ConstPtr& m) {
          if (!first.count(t)) first[t] = *m;
          last[t] = *m;
        }));
  }
  ASSERT_TRUE(ros::service::waitForService("/flapsim/step", ros::Duration(60)));
  ASSERT_TRUE(waitFor(
      [&] {
        for (const auto& s : subs) {
          if (s.getNumPublishers() == 0) return false;
        }
        return true;
      },
      30.0))
      << "odom topics did not connect";

  // t = 0: the spawn poses
  flapsim::Step step;
  step.request.steps = 0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/step", step));
  ASSERT_TRUE(step.response.success) << step.response.status_message << " (launch it paused)";
  EXPECT_EQ(step.response.sim_time, ros::Time(0));
  ASSERT_TRUE(waitFor([&] { return first.size() == topics.size(); }, 10.0));
  for (const auto& kv : first) EXPECT_EQ(kv.second.header.stamp, ros::Time(0)) << kv.first;

  // `duration` of sim time in one step request: exact, whatever the machine's speed
  double step_size = 0.001;
  nh.getParam("/flapsim/step_size", step_size);
  step.request.steps = static_cast<std::uint32_t>(std::llround(duration / step_size));
  ASSERT_TRUE(flapsim_test::call("/flapsim/step", step));
  ASSERT_TRUE(step.response.success) << step.response.status_message;
  const ros::Time end = step.response.sim_time;
  EXPECT_NEAR(end.toSec(), duration, 1e-9);
  ASSERT_TRUE(waitFor(
      [&] {
        for (const std::string& t : topics) {
          if (!last.count(t) || last[t].header.stamp != end) return false;
        }
        return true;
      },
      30.0))
      << "no odom at " << end;
  std::map<std::string, nav_msgs::Odometry> at_end = last;

  // and it runs by itself when unpaused
  std_srvs::Empty e;
  ASSERT_TRUE(flapsim_test::call("/flapsim/unpause", e));
  EXPECT_TRUE(waitFor([&] { return last[topics[0]].header.stamp > end; }, 30.0))
      << "no progress after flapsim/unpause";
  flapsim_test::call("/flapsim/pause", e);

  ASSERT_NO_FATAL_FAILURE(expectDisplacements(pnh, first, at_end));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_launch_smoke");
  return RUN_ALL_TESTS();
}
