// flock.launch (see flock.test, started paused): `count` creatures afc<i> with
// odometry, `count` ann_controller nodes /afc<i>/ann_controller, and every
// controller commands its own creature: its first command is what the
// network gives for that creature's attitude (the flock starts with
// alternating roll, so neighbours' attitudes, and commands, differ).
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "flapsim/Step.h"
#include "flapsim/WingCommand.h"
#include "flapsim/evolve.h"
#include "service_call.h"
#include "wait_for.h"

namespace {

using flapsim_test::waitFor;

// What the test hears of each creature i: its odometry and every attitude on it, the stamp of
// the last, and its controller's first command.
struct Heard {
  std::map<int, nav_msgs::Odometry> odom;
  std::map<int, std::vector<flapsim::Quat>> attitudes;  // every published one
  std::map<int, double> latest;                         // the last odom stamp of each
  std::map<int, flapsim::WingCommand> command;
  std::vector<ros::Subscriber> subs;
};

void subscribe(ros::NodeHandle& nh, int count, Heard& h) {
  for (int i = 0; i < count; ++i) {
    const std::string ns = "/afc" + std::to_string(i);
    h.subs.push_back(nh.subscribe<nav_msgs::Odometry>(
        ns + "/odom", 100, [&h, i](const nav_msgs::Odometry::ConstPtr& m) {
          h.odom[i] = *m;
          const auto& q = m->pose.pose.orientation;
          h.attitudes[i].emplace_back(q.w, q.x, q.y, q.z);
          h.latest[i] = m->header.stamp.toSec();
        }));
    h.subs.push_back(nh.subscribe<flapsim::WingCommand>(
        ns + "/wing_command", 100, [&h, i](const flapsim::WingCommand::ConstPtr& m) {
          if (!h.command.count(i)) h.command[i] = *m;
        }));
  }
}

// One ann_controller per creature, /afc<i>/ann_controller, and none more.
void expectOneControllerEach(int count) {
  std::vector<std::string> nodes;
  ASSERT_TRUE(ros::master::getNodes(nodes));
  const std::set<std::string> all(nodes.begin(), nodes.end());
  int controllers = 0;
  for (const auto& n : all) controllers += n.find("/ann_controller") != std::string::npos;
  EXPECT_EQ(controllers, count);
  for (int i = 0; i < count; ++i) {
    EXPECT_TRUE(all.count("/afc" + std::to_string(i) + "/ann_controller")) << i;
  }
  EXPECT_FALSE(all.count("/afc" + std::to_string(count) + "/ann_controller"));
}

// Publish t = 0, then step one control period at a time until every
// controller has commanded (their timers run on sim time).
void stepUntilEveryControllerCommanded(int count, Heard& h) {
  ASSERT_TRUE(ros::service::waitForService("/flapsim/step", ros::Duration(60.0)));
  flapsim::Step step;
  step.request.steps = 0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/step", step));
  ASSERT_TRUE(waitFor([&] { return static_cast<int>(h.odom.size()) == count; }, 30.0));
  for (int k = 0; k < 200 && static_cast<int>(h.command.size()) < count; ++k) {
    step.request.steps = 20;
    ASSERT_TRUE(flapsim_test::call("/flapsim/step", step));
    waitFor([&] { return static_cast<int>(h.command.size()) == count; }, 0.2);
  }
  ASSERT_EQ(static_cast<int>(h.command.size()), count) << "not every controller commanded";
}

// Every controller's first command is what the network gives for its own creature's attitude,
// and for no other's.
void expectEachCommandsItsOwn(const flapsim::FlapUnitController& net, int count, Heard& h) {
  for (int i = 0; i < count; ++i) {
    const flapsim::WingCommand& c = h.command[i];
    ASSERT_EQ(c.joint_names.size(), 2u);
    EXPECT_EQ(c.joint_names[0], "unit0_wing_left_joint");
    ASSERT_EQ(c.downstroke_rate.size(), 2u);
    // Which creature's attitude gives this command? Its own, and no other's.
    for (int j = 0; j < count; ++j) {
      bool match = false;
      for (const flapsim::Quat& q : h.attitudes[j]) {
        const flapsim::WingPairCommand w = net.command(q);
        match = match || (std::abs(w.left.downstroke_rate - c.downstroke_rate[0]) < 1e-9 &&
                          std::abs(w.right.downstroke_rate - c.downstroke_rate[1]) < 1e-9);
      }
      EXPECT_EQ(match, i == j) << "command of controller " << i << " vs attitude of creature " << j;
    }
  }
}

TEST(Flock, KCreaturesAndKControllersEachFlyingItsOwn) {
  ros::NodeHandle nh, pnh("~");
  int count = 0;
  ASSERT_TRUE(pnh.getParam("count", count));
  ASSERT_GE(count, 2);

  std::string weights;
  ASSERT_TRUE(pnh.getParam("weights", weights));
  const flapsim::ControllerSpec spec = flapsim::loadControllerYaml(weights);
  const flapsim::FlapUnitController net(spec.params, spec.weights);

  Heard h;
  subscribe(nh, count, h);
  // Every odom topic has the simulator, every wing_command topic a controller.
  ASSERT_TRUE(waitFor(
      [&] {
        for (const auto& s : h.subs) {
          if (s.getNumPublishers() != 1) return false;
        }
        return true;
      },
      60.0));
  ASSERT_NO_FATAL_FAILURE(expectOneControllerEach(count));

  ASSERT_NO_FATAL_FAILURE(stepUntilEveryControllerCommanded(count, h));
  // Every creature's odometry up to the last command's time has arrived (a command can come
  // in before the odometry of the state it was computed from).
  double last_command = 0.0;
  for (const auto& [i, c] : h.command) {
    last_command = std::max(last_command, c.header.stamp.toSec());
  }
  ASSERT_TRUE(waitFor(
      [&] {
        for (int i = 0; i < count; ++i) {
          if (!h.latest.count(i) || h.latest[i] < last_command) return false;
        }
        return true;
      },
      30.0))
      << "no odometry up to t = " << last_command;
  ASSERT_NO_FATAL_FAILURE(expectEachCommandsItsOwn(net, count, h));
  // And the creatures are distinct bodies at their spaced poses.
  EXPECT_NE(h.odom[0].pose.pose.position.x, h.odom[1].pose.pose.position.x);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_flock");
  return RUN_ALL_TESTS();
}
