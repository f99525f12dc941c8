// Scenarios do not step until their controllers have answered (issue 43, item 2).
//
// ~mode "wait" (controller_wait.test: flapsim_node with a creature `answered` whose controller
// is this test, and `orphan`, whose controller never starts): sim time holds at 0 while either
// waits, with /diagnostics saying so; this test's command releases `answered` only; after
// ~controller_wait_timeout the node names the missing controller and runs.
//
// ~mode "launch" (hover_start.test, afc_start.test: a scenario launched paused): once this test
// has the state at t = 0 it unpauses flapsim, as a user's launch would run; the controller's
// first command answers the state at t = 0, the wings move in the first publication period, and
// up to ~duration s of sim time <creature>/odom stays at or above ~min_height m and tilts at
// most ~max_tilt_deg degrees.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "flapsim/WingCommand.h"
#include "node_calls.h"
#include "recorder.h"

namespace {

using flapsim_test::callEmpty;
using flapsim_test::Recorder;
using flapsim_test::waitFor;

constexpr double kWait = 60.0;  // s (wall): the bound on every wait

std::string param(const std::string& key, const std::string& def) {
  std::string v = def;
  ros::param::get("~" + key, v);
  return v;
}

double param(const std::string& key, double def) {
  double v = def;
  ros::param::get("~" + key, v);
  return v;
}

// The status of `creature` in the last /diagnostics array ("" level -1 if none yet).
const diagnostic_msgs::DiagnosticStatus* statusOf(
    const Recorder<diagnostic_msgs::DiagnosticArray>& diag, const std::string& creature) {
  if (diag.msgs.empty()) return nullptr;
  for (const auto& s : diag.msgs.back()->status) {
    if (s.hardware_id == creature) return &s;
  }
  return nullptr;
}

bool has(const diagnostic_msgs::DiagnosticStatus* s, int level, const std::string& text) {
  return s && s->level == level && s->message.find(text) != std::string::npos;
}

TEST(ControllerStart, SimTimeHoldsUntilEachControllerAnswersOrTheWaitEnds) {
  if (param("mode", "") != "wait") GTEST_SKIP() << "controller_wait.test";
  using diagnostic_msgs::DiagnosticStatus;
  ros::NodeHandle nh;
  Recorder<diagnostic_msgs::DiagnosticArray> diag;
  diag.start(nh, "/diagnostics");
  Recorder<rosgraph_msgs::Clock> clock;
  clock.start(nh, "/clock");
  // Both wait, sim time at 0.
  ASSERT_TRUE(waitFor(
      [&] {
        return has(statusOf(diag, "answered"), DiagnosticStatus::WARN, "/controller_start") &&
               has(statusOf(diag, "orphan"), DiagnosticStatus::WARN, "/no_such_controller");
      },
      kWait));
  EXPECT_EQ(diag.msgs.back()->header.stamp, ros::Time(0));
  // This test answers for `answered` (a latched command, as the shipped controllers send).
  ros::Publisher pub = nh.advertise<flapsim::WingCommand>("/answered/wing_command", 1, true);
  flapsim::WingCommand cmd;
  cmd.downstroke_rate = {40.0, 40.0};
  cmd.upstroke_rate = {10.0, 10.0};
  cmd.amplitude = {0.8, 0.8};
  pub.publish(cmd);
  ASSERT_TRUE(waitFor(
      [&] { return has(statusOf(diag, "answered"), DiagnosticStatus::OK, "running"); }, kWait));
  EXPECT_TRUE(has(statusOf(diag, "orphan"), DiagnosticStatus::WARN, "waiting"));
  EXPECT_EQ(diag.msgs.back()->header.stamp, ros::Time(0)) << "ran before the orphan's wait ended";
  // The wait ends: the missing controller named, at t = 0, and the simulation runs.
  ASSERT_TRUE(waitFor(
      [&] {
        return has(statusOf(diag, "orphan"), DiagnosticStatus::ERROR,
                   "its controller /no_such_controller sent no wing command within");
      },
      kWait));
  EXPECT_EQ(diag.msgs.back()->header.stamp, ros::Time(0));
  std::printf("controller_wait: orphan: %s\n", statusOf(diag, "orphan")->message.c_str());
  ASSERT_TRUE(waitFor(
      [&] { return !clock.msgs.empty() && clock.msgs.back()->clock >= ros::Time(0.1); }, kWait));
}

// The flight from t = 0 to `end`: lowest height, largest tilt (deg), and samples.
struct Flight {
  double lowest = 1e9, tilt = 0.0;
  ros::Time lowest_at, tilt_at;
  int samples = 0;
};

Flight flightOf(const Recorder<nav_msgs::Odometry>& odom, const ros::Time& end) {
  Flight f;
  for (const auto& m : odom.msgs) {
    if (m->header.stamp > end) continue;
    ++f.samples;
    if (m->pose.pose.position.z < f.lowest) {
      f.lowest = m->pose.pose.position.z;
      f.lowest_at = m->header.stamp;
    }
    const auto& q = m->pose.pose.orientation;
    const double up = std::clamp(1.0 - 2.0 * (q.x * q.x + q.y * q.y), -1.0, 1.0);  // R(2,2)
    if (std::acos(up) * 180.0 / M_PI > f.tilt) {
      f.tilt = std::acos(up) * 180.0 / M_PI;
      f.tilt_at = m->header.stamp;
    }
  }
  return f;
}

// The largest wing joint speed (rad/s) in the first joint_states after t = 0.
double firstWingSpeed(const Recorder<sensor_msgs::JointState>& joints) {
  for (const auto& m : joints.msgs) {
    if (m->header.stamp.isZero()) continue;
    double fastest = 0.0;
    for (size_t j = 0; j < m->name.size() && j < m->velocity.size(); ++j) {
      if (m->name[j].find("wing") != std::string::npos) {
        fastest = std::max(fastest, std::abs(m->velocity[j]));
      }
    }
    return fastest;
  }
  return 0.0;
}

TEST(ControllerStart, TheControllerFliesTheScenarioFromTimeZero) {
  if (param("mode", "") != "launch") GTEST_SKIP() << "hover_start.test, afc_start.test";
  const std::string c = param("creature", "hover");
  const ros::Time end(param("duration", 5.0));
  ros::NodeHandle nh;
  Recorder<nav_msgs::Odometry> odom;
  std::vector<flapsim::WingCommand::ConstPtr> commands;
  Recorder<sensor_msgs::JointState> joints;
  odom.start(nh, "/" + c + "/odom", 100000);
  // How late the controller answers: the last sim time (/clock) this test has when a command
  // comes, less the stamp of the state it answers (to a publication period: 10 ms).
  ros::Time clock_now;
  double lag = 0.0;
  ros::Subscriber clock_sub = nh.subscribe<rosgraph_msgs::Clock>(
      "/clock", 1000, [&](const rosgraph_msgs::Clock::ConstPtr& m) { clock_now = m->clock; });
  ros::Subscriber command_sub = nh.subscribe<flapsim::WingCommand>(
      "/" + c + "/wing_command", 100000, [&](const flapsim::WingCommand::ConstPtr& m) {
        commands.push_back(m);
        lag = std::max(lag, (clock_now - m->header.stamp).toSec());
      });
  joints.start(nh, "/" + c + "/joint_states", 100000);
  ASSERT_TRUE(waitFor([&] { return !odom.msgs.empty() && !joints.msgs.empty(); }, kWait));
  ASSERT_EQ(odom.msgs.front()->header.stamp, ros::Time(0)) << "the launch must start paused";
  if (param("unpause", 1.0) != 0.0) callEmpty("/flapsim/unpause");
  ASSERT_TRUE(waitFor([&] { return !odom.msgs.empty() && odom.msgs.back()->header.stamp >= end; },
                      param("wall_timeout", 120.0)));
  const double first = commands.empty() ? -1.0 : commands.front()->header.stamp.toSec();
  const double speed = firstWingSpeed(joints);
  const Flight f = flightOf(odom, end);
  std::printf(
      "%s from t = 0 to %.1f s: first command stamped %.3f s, wing speed %.2f rad/s at the first "
      "publication after t = 0, lowest %.4f m (t = %.2f s), largest tilt %.2f deg (t = %.2f s; "
      "%d odometry samples), commands up to %.0f ms of sim time late\n",
      c.c_str(), end.toSec(), first, speed, f.lowest, f.lowest_at.toSec(), f.tilt,
      f.tilt_at.toSec(), f.samples, 1000.0 * lag);
  EXPECT_EQ(first, 0.0) << "the controller's first command (-1: none) answers a later state";
  EXPECT_GT(speed, param("min_wing_speed", 1.0));
  EXPECT_GE(f.samples, static_cast<int>(0.99 * end.toSec() * 100.0));  // 100 Hz, from t = 0
  EXPECT_GE(f.lowest, param("min_height", 2.9));
  EXPECT_LE(f.tilt, param("max_tilt_deg", 10.0));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "controller_start");
  return RUN_ALL_TESTS();
}
