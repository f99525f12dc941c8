// Driving creatures through flapsim_node (rostest: see drive.test): get_state, set_state,
// apply_wrench, clear_wrenches, <creature>/imu and creature_states, each with its bad input.
// The node starts paused; sim times are reached through flapsim/step and messages are waited
// for by their exact stamp (timeouts only bound the waits).
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "../doc_figure.h"
#include "flapsim/ApplyWrench.h"
#include "flapsim/ClearWrenches.h"
#include "flapsim/CreatureStates.h"
#include "flapsim/GetState.h"
#include "flapsim/SetState.h"
#include "flapsim/Step.h"
#include "recorder.h"
#include "service_call.h"
#include "wait_for.h"

namespace {

constexpr double kWait = 20.0;  // s (wall), upper bound of any wait
constexpr double kG = 9.81;
constexpr double kRho = 1.204, kCd = 1.15;
// plate.urdf: 0.2 m x 0.2 m x 2 mm, 10 g
constexpr double kPlateMass = 0.01, kPlateArea = 0.04, kPlateVolume = 0.2 * 0.2 * 0.002;

using flapsim_test::Recorder;

// Sets doubles through dynamic_reconfigure; returns the config the node runs after it.
dynamic_reconfigure::Config reconfigure(const std::vector<std::pair<std::string, double>>& values) {
  dynamic_reconfigure::Reconfigure r;
  for (const auto& [name, value] : values) {
    dynamic_reconfigure::DoubleParameter d;
    d.name = name;
    d.value = value;
    r.request.config.doubles.push_back(d);
  }
  EXPECT_TRUE(flapsim_test::call("/flapsim/set_parameters", r));
  return r.response.config;
}

double configValue(const dynamic_reconfigure::Config& c, const std::string& name) {
  for (const auto& d : c.doubles) {
    if (d.name == name) return d.value;
  }
  return std::nan("");
}

ros::Time step(std::uint32_t steps) {
  flapsim::Step s;
  s.request.steps = steps;
  EXPECT_TRUE(flapsim_test::call("/flapsim/step", s));
  EXPECT_TRUE(s.response.success) << s.response.status_message;
  return s.response.sim_time;
}

flapsim::GetState::Response getState(const std::string& name, const std::string& link = "") {
  flapsim::GetState g;
  g.request.name = name;
  g.request.link = link;
  EXPECT_TRUE(flapsim_test::call("/flapsim/get_state", g));
  return g.response;
}

geometry_msgs::Pose pose(double x, double y, double z, double qw = 1, double qx = 0, double qy = 0,
                         double qz = 0) {
  geometry_msgs::Pose p;
  p.position.x = x;
  p.position.y = y;
  p.position.z = z;
  p.orientation.w = qw;
  p.orientation.x = qx;
  p.orientation.y = qy;
  p.orientation.z = qz;
  return p;
}

flapsim::SetState::Response setState(flapsim::SetState::Request req) {
  flapsim::SetState s;
  s.request = req;
  EXPECT_TRUE(flapsim_test::call("/flapsim/set_state", s));
  return s.response;
}

flapsim::ApplyWrench::Response applyWrench(flapsim::ApplyWrench::Request req) {
  flapsim::ApplyWrench a;
  a.request = req;
  EXPECT_TRUE(flapsim_test::call("/flapsim/apply_wrench", a));
  return a.response;
}

flapsim::ClearWrenches::Response clearWrenches(const std::string& name,
                                               const std::string& link = "") {
  flapsim::ClearWrenches c;
  c.request.name = name;
  c.request.link = link;
  EXPECT_TRUE(flapsim_test::call("/flapsim/clear_wrenches", c));
  return c.response;
}

// Upward, at the plate's centre, until cleared: its weight less its buoyancy.
flapsim::ApplyWrench::Request hoverWrench(const std::string& name, const geometry_msgs::Point& at) {
  flapsim::ApplyWrench::Request w;
  w.name = name;
  w.reference_point = at;
  w.wrench.force.z = kPlateMass * kG - kRho * kPlateVolume * kG;
  w.duration = ros::Duration(-1.0);
  return w;
}

bool samePose(const geometry_msgs::Pose& a, const geometry_msgs::Pose& b) {
  return a.position.x == b.position.x && a.position.y == b.position.y &&
         a.position.z == b.position.z && a.orientation.x == b.orientation.x &&
         a.orientation.y == b.orientation.y && a.orientation.z == b.orientation.z &&
         a.orientation.w == b.orientation.w;
}

bool sameTwist(const geometry_msgs::Twist& a, const geometry_msgs::Twist& b) {
  return a.linear.x == b.linear.x && a.linear.y == b.linear.y && a.linear.z == b.linear.z &&
         a.angular.x == b.angular.x && a.angular.y == b.angular.y && a.angular.z == b.angular.z;
}

bool sameState(const flapsim::GetState::Response& a, const flapsim::GetState::Response& b) {
  return samePose(a.pose, b.pose) && sameTwist(a.twist, b.twist) &&
         a.joint_positions == b.joint_positions && a.joint_velocities == b.joint_velocities;
}

class Drive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nh_ = std::make_unique<ros::NodeHandle>();
    for (const char* s : {"step", "get_state", "set_state", "apply_wrench", "clear_wrenches"}) {
      ASSERT_TRUE(ros::service::waitForService(std::string("/flapsim/") + s, ros::Duration(60)));
    }
    imu_.start(*nh_, "/rest/imu");
    fall_imu_.start(*nh_, "/hover/imu");
    states_.start(*nh_, "/flapsim/creature_states");
    ASSERT_TRUE(flapsim_test::waitFor(
        [] { return imu_.connected() && fall_imu_.connected() && states_.connected(); }, kWait))
        << "flapsim's topics did not connect";
  }
  static void TearDownTestSuite() {
    imu_ = {};
    fall_imu_ = {};
    states_ = {};
    nh_.reset();
  }
  static std::unique_ptr<ros::NodeHandle> nh_;
  static Recorder<sensor_msgs::Imu> imu_, fall_imu_;
  static Recorder<flapsim::CreatureStates> states_;
};

std::unique_ptr<ros::NodeHandle> Drive::nh_;
Recorder<sensor_msgs::Imu> Drive::imu_, Drive::fall_imu_;
Recorder<flapsim::CreatureStates> Drive::states_;

// Before any step: the spawn pose, at rest, and the flap unit's two wing joints at zero.
TEST_F(Drive, GetStateReadsTheSpawnPose) {
  const auto s = getState("drag");
  ASSERT_TRUE(s.success) << s.status_message;
  EXPECT_EQ(s.header.frame_id, "world");
  EXPECT_TRUE(samePose(s.pose, pose(10, 0, 10)));
  EXPECT_TRUE(sameTwist(s.twist, geometry_msgs::Twist()));
  const auto u = getState("flap_unit", "unit0_wing_left");
  ASSERT_TRUE(u.success) << u.status_message;
  EXPECT_EQ(u.joint_names.size(), 2u);
  EXPECT_EQ(u.joint_positions, std::vector<double>(2, 0.0));
  EXPECT_NEAR(u.pose.position.x, 30.0, 0.2);  // a wing, beside the body
}

// A vertical plate set moving 5 m/s sideways, held up against gravity by a wrench of its
// weight less buoyancy, slows as m dv/dt = -rho Cd A v^2 / 2 says and does not sink.
TEST_F(Drive, SetStateThenStepFollowsTheDragLaw) {
  ASSERT_TRUE(applyWrench(hoverWrench("drag", pose(10, 0, 10).position)).success);
  flapsim::SetState::Request r;
  r.name = "drag";
  r.pose = pose(10, 0, 10, std::sqrt(0.5), std::sqrt(0.5));  // 90 deg about x: faces along y
  r.twist.linear.y = 5.0;
  const auto set = setState(r);
  ASSERT_TRUE(set.success) << set.status_message;
  const double t0 = getState("drag").header.stamp.toSec();
  const double k = 0.5 * kRho * kCd * kPlateArea;
  for (int i = 0; i < 4; ++i) {
    const double t = step(50).toSec() - t0;
    const auto s = getState("drag");
    const double law = 5.0 / (1.0 + k * 5.0 * t / kPlateMass);
    EXPECT_NEAR(s.twist.linear.y, law, 0.01 * law) << t;
    EXPECT_LT(std::abs(s.twist.linear.z), 1e-6) << t;
  }
  EXPECT_LT(getState("drag").twist.linear.y, 2.0);  // it did slow down
  const auto cleared = clearWrenches("drag");
  EXPECT_TRUE(cleared.success);
  EXPECT_NE(cleared.status_message.find("cleared 1 "), std::string::npos) << cleared.status_message;
}

// A plate at rest with a wrench of its weight less buoyancy hovers: vz stays below 1e-6 m/s
// for a second; without it, it falls.
TEST_F(Drive, ApplyWrenchOfTheWeightMakesAPlateHover) {
  flapsim::SetState::Request r;
  r.name = "hover";
  r.pose = pose(0, 0, 10);
  ASSERT_TRUE(setState(r).success);
  ASSERT_TRUE(applyWrench(hoverWrench("hover", r.pose.position)).success);
  for (int i = 0; i < 10; ++i) {
    step(100);
    const auto s = getState("hover");
    EXPECT_LT(std::abs(s.twist.linear.z), 1e-6);
    EXPECT_NEAR(s.pose.position.z, 10.0, 1e-6);
  }
  ASSERT_TRUE(clearWrenches("hover", "plate").success);
  step(100);
  EXPECT_LT(getState("hover").twist.linear.z, -0.5);
}

// A plate resting on the ground: its accelerometer reads +g up and its gyros zero. Set at
// rest in the air, after one step it reads only the buoyancy (what is not gravity).
TEST_F(Drive, ImuReadsGravityAtRestAndOnlyBuoyancyInFall) {
  const ros::Time t = step(500);
  const auto m = imu_.at(t, kWait);
  ASSERT_TRUE(m) << "no IMU message stamped " << t;
  EXPECT_EQ(m->header.frame_id, "rest/plate");
  EXPECT_NEAR(m->linear_acceleration.z, kG, 1e-3);
  EXPECT_NEAR(m->linear_acceleration.x, 0.0, 1e-3);
  EXPECT_NEAR(m->linear_acceleration.y, 0.0, 1e-3);
  EXPECT_LT(std::abs(m->angular_velocity.x) + std::abs(m->angular_velocity.y) +
                std::abs(m->angular_velocity.z),
            1e-6);
  EXPECT_NEAR(m->orientation.w, 1.0, 1e-6);

  clearWrenches("hover");
  flapsim::SetState::Request r;
  r.name = "hover";
  r.pose = pose(0, 0, 20);
  ASSERT_TRUE(setState(r).success);
  const ros::Time t1 = step(1);
  const auto f = fall_imu_.at(t1, kWait);
  ASSERT_TRUE(f) << "no IMU message stamped " << t1;
  EXPECT_NEAR(f->linear_acceleration.z, kRho * kPlateVolume * kG / kPlateMass, 1e-9);
  EXPECT_NEAR(std::hypot(f->linear_acceleration.x, f->linear_acceleration.y), 0.0, 1e-12);
}

// One message with every creature's root, in spawn order, equal to what get_state reads.
TEST_F(Drive, CreatureStatesListsEveryRoot) {
  const ros::Time t = step(10);
  const auto m = states_.at(t, kWait);
  ASSERT_TRUE(m) << "no creature_states stamped " << t;
  ASSERT_EQ(m->name, (std::vector<std::string>{"hover", "drag", "rest", "flap_unit"}));
  ASSERT_EQ(m->pose.size(), 4u);
  ASSERT_EQ(m->twist.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const auto s = getState(m->name[i]);
    EXPECT_TRUE(samePose(m->pose[i], s.pose)) << m->name[i];
    EXPECT_TRUE(sameTwist(m->twist[i], s.twist)) << m->name[i];
  }
}

// Lockstep: state set (joints too), wrench applied, N steps: the same to the bit, twice.
TEST_F(Drive, SetStateWrenchAndStepAreBitReproducible) {
  auto run = [] {
    flapsim::SetState::Request r;
    r.name = "flap_unit";
    r.pose = pose(30, 0, 5, std::cos(0.2), std::sin(0.2));
    r.twist.linear.x = 1.0;
    r.twist.angular.z = 0.5;
    r.joint_names = {"unit0_wing_left_joint", "unit0_wing_right_joint"};
    r.joint_positions = {0.3, -0.2};
    r.joint_velocities = {1.0, -2.0};
    const auto set = setState(r);
    EXPECT_TRUE(set.success) << set.status_message;
    const auto s = getState("flap_unit");
    EXPECT_NEAR(s.joint_positions[0], 0.3, 1e-15);
    EXPECT_NEAR(s.joint_velocities[1], -2.0, 1e-15);
    flapsim::ApplyWrench::Request w;
    w.name = "flap_unit";
    w.link = "unit0_wing_left";
    w.reference_point = getState("flap_unit", "unit0_wing_left").pose.position;
    w.wrench.force.y = 0.5;
    w.wrench.torque.z = 0.01;
    w.duration = ros::Duration(0.05);
    EXPECT_TRUE(applyWrench(w).success);
    step(200);
    return getState("flap_unit", "unit0_wing_right");
  };
  const auto a = run();
  step(33);
  const auto b = run();
  EXPECT_TRUE(sameState(a, b));
  EXPECT_GT(std::abs(a.pose.position.y), 1e-3);  // the push moved it
}

// Every bad request is refused with its cause named, and the creature keeps its state.
TEST_F(Drive, BadRequestsAreRefusedWithTheirCause) {
  const auto before = getState("flap_unit");
  auto expectRefused = [&](bool success, const std::string& message, const std::string& cause) {
    EXPECT_FALSE(success) << cause;
    EXPECT_NE(message.find(cause), std::string::npos) << message;
    EXPECT_TRUE(sameState(before, getState("flap_unit"))) << cause;
  };
  auto g = getState("ghost");
  expectRefused(g.success, g.status_message, "ghost");
  g = getState("flap_unit", "tail");
  expectRefused(g.success, g.status_message, "tail");

  flapsim::SetState::Request good;
  good.name = "flap_unit";
  good.pose = pose(30, 0, 3);
  auto r = good;
  r.name = "ghost";
  auto s = setState(r);
  expectRefused(s.success, s.status_message, "ghost");
  r = good;
  r.link = "tail";
  s = setState(r);
  expectRefused(s.success, s.status_message, "tail");
  r = good;
  r.pose.position.z = std::nan("");
  s = setState(r);
  expectRefused(s.success, s.status_message, "position");
  r = good;
  r.twist.linear.x = 1e4;
  s = setState(r);
  expectRefused(s.success, s.status_message, "linear twist");
  r = good;
  r.joint_names = {"unit0_wing_left_joint", "nope"};
  r.joint_positions = {0.1, 0.2};
  s = setState(r);
  expectRefused(s.success, s.status_message, "nope");
  r = good;
  r.joint_names = {"unit0_wing_left_joint"};
  r.joint_positions = {0.1, 0.2};
  s = setState(r);
  expectRefused(s.success, s.status_message, "joint_positions");
  r = good;
  r.joint_names = {"unit0_wing_left_joint"};
  r.joint_positions = {10.0};
  s = setState(r);
  expectRefused(s.success, s.status_message, "limits");

  flapsim::ApplyWrench::Request w;
  w.name = "flap_unit";
  w.wrench.force.x = 1.0;
  w.duration = ros::Duration(0.01);
  auto x = w;
  x.name = "ghost";
  auto a = applyWrench(x);
  expectRefused(a.success, a.status_message, "ghost");
  x = w;
  x.link = "tail";
  a = applyWrench(x);
  expectRefused(a.success, a.status_message, "tail");
  x = w;
  x.wrench.force.y = std::nan("");
  a = applyWrench(x);
  expectRefused(a.success, a.status_message, "force");
  auto c = clearWrenches("ghost");
  expectRefused(c.success, c.status_message, "ghost");
  c = clearWrenches("flap_unit", "tail");
  expectRefused(c.success, c.status_message, "tail");
  // and none of the refused wrenches was kept
  EXPECT_EQ(clearWrenches("flap_unit").status_message, "cleared 0 wrench(es)");
}

// A wind set through dynamic_reconfigure acts within one step: a hanging plate (held against
// gravity by a wrench, faces along x) in still air gains nothing in a step; after the wind
// turns to 5 m/s along x it gains (F dt + rho V U) / m in the next one: the drag
// F = rho Cd A v^2 / 2, and the push of the air's pressure gradient as it accelerates to U
// within the step (the Froude-Krylov force, rho V dU/dt: 0.048 of the 0.117 m/s). A change
// that would make the air non-finite is refused and the config put back.
TEST_F(Drive, ReconfiguredWindActsWithinOneStep) {
  flapsim::SetState::Request r;
  r.name = "drag";
  r.pose = pose(10, 0, 10, std::sqrt(0.5), 0, std::sqrt(0.5));  // 90 deg about y: faces along x
  ASSERT_TRUE(setState(r).success);
  clearWrenches("drag");
  ASSERT_TRUE(applyWrench(hoverWrench("drag", r.pose.position)).success);
  step(1);
  const double v0 = getState("drag").twist.linear.x;
  EXPECT_EQ(v0, 0.0);
  const dynamic_reconfigure::Config c = reconfigure({{"wind_x", 5.0}});
  EXPECT_EQ(configValue(c, "wind_x"), 5.0);
  EXPECT_EQ(configValue(c, "density"), kRho);  // the rest as it was
  step(1);
  const double force = 0.5 * kRho * kCd * kPlateArea * 25.0;
  const double push = kRho * kPlateVolume * 5.0;
  flapsim::test::printFigure("speed", getState("drag").twist.linear.x);
  flapsim::test::printFigure("expected", (force * 0.001 + push) / kPlateMass);
  EXPECT_NEAR(getState("drag").twist.linear.x, (force * 0.001 + push) / kPlateMass, 1e-9);

  const dynamic_reconfigure::Config refused = reconfigure({{"wind_y", std::nan("")}});
  EXPECT_EQ(configValue(refused, "wind_y"), 0.0);
  EXPECT_EQ(configValue(refused, "wind_x"), 5.0);
  EXPECT_EQ(configValue(reconfigure({{"wind_x", 0.0}}), "wind_x"), 0.0);
  clearWrenches("drag");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_drive");
  return RUN_ALL_TESTS();
}
