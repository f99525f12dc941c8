// What a gazebo_ros user reaches for (rostest: interfaces.test, wing_timeout_release.test):
// reference frames in set_state and apply_wrench, gazebo_msgs' request field names and
// "<creature>::<link>" link fields, flapsim/get_physics and set_physics, a
// paused node that answers `rostopic echo -n1` with use_sim_time, and the wing command
// timeout. The node starts paused; sim times are reached through flapsim/step.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Empty.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include "flapsim/ApplyWrench.h"
#include "flapsim/ClearWrenches.h"
#include "flapsim/DeleteCreature.h"
#include "flapsim/GetPhysics.h"
#include "flapsim/GetState.h"
#include "flapsim/SetPhysics.h"
#include "flapsim/SetState.h"
#include "flapsim/SpawnCreature.h"
#include "flapsim/Step.h"
#include "flapsim/types.h"
#include "node_calls.h"
#include "recorder.h"
#include "wait_for.h"

namespace {

using flapsim_test::callEmpty;
using flapsim_test::callService;
using flapsim_test::firstMessageOf;
using flapsim_test::getState;
using flapsim_test::Recorder;
using flapsim_test::step;
using flapsim_test::waitFor;
constexpr double kWait = 20.0;  // s (wall), upper bound of any wait
constexpr double kPlateMass = 0.01;

flapsim::SetState::Response setState(const flapsim::SetState::Request& req) {
  return callService<flapsim::SetState>("/flapsim/set_state", req);
}

flapsim::ApplyWrench::Response applyWrench(const flapsim::ApplyWrench::Request& req) {
  return callService<flapsim::ApplyWrench>("/flapsim/apply_wrench", req);
}

void clearWrenches() {
  EXPECT_TRUE(callService<flapsim::ClearWrenches>("/flapsim/clear_wrenches").success);
}

flapsim::GetPhysics::Response getPhysics() {
  const auto p = callService<flapsim::GetPhysics>("/flapsim/get_physics");
  EXPECT_TRUE(p.success) << p.status_message;
  return p;
}

flapsim::SetPhysics::Response setPhysics(const flapsim::SetPhysics::Request& req) {
  return callService<flapsim::SetPhysics>("/flapsim/set_physics", req);
}

flapsim::SetPhysics::Request asRequest(const flapsim::GetPhysics::Response& p) {
  flapsim::SetPhysics::Request r;
  r.step_size = p.step_size;
  r.real_time_factor = p.real_time_factor;
  r.publish_rate = p.publish_rate;
  r.gravity = p.gravity;
  r.air_density = p.air_density;
  r.drag_coefficient = p.drag_coefficient;
  r.wind = p.wind;
  return r;
}

geometry_msgs::Pose yawed(double x, double y, double z, double yaw) {
  geometry_msgs::Pose p;
  p.position.x = x;
  p.position.y = y;
  p.position.z = z;
  p.orientation.w = std::cos(yaw / 2);
  p.orientation.z = std::sin(yaw / 2);
  return p;
}

flapsim::Pose poseOf(const geometry_msgs::Pose& p) {
  return flapsim::Pose{
      flapsim::Vec3(p.position.x, p.position.y, p.position.z),
      flapsim::Quat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z)};
}

class Interfaces : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ros::service::waitForService("/flapsim/step", ros::Duration(60)));
    callEmpty("/flapsim/pause");
  }
  ros::NodeHandle nh_;
};

// set_state in another creature's link frame: the pose lands where that frame puts it, and
// get_state in the same frame reads back what was set. A frame that does not exist is refused
// by name and nothing changes.
TEST_F(Interfaces, SetStateInAnotherCreaturesLinkFrame) {
  flapsim::SetState::Request body;
  body.name = "fu";
  body.pose = yawed(3, 4, 5, 0.7);
  ASSERT_TRUE(setState(body).success);
  flapsim::SetState::Request r;
  r.name = "plate";
  r.reference_frame = "fu/unit0_body";
  r.pose = yawed(0.5, 0, 1, 0.2);
  r.twist.linear.x = 2.0;
  const auto set = setState(r);
  ASSERT_TRUE(set.success) << set.status_message;
  const auto world = getState("plate");
  const flapsim::Pose want = poseOf(getState("fu", "unit0_body").pose) * poseOf(r.pose);
  EXPECT_NEAR((poseOf(world.pose).position - want.position).norm(), 0.0, 1e-12);
  EXPECT_NEAR(poseOf(world.pose).orientation.angularDistance(want.orientation), 0.0, 1e-12);
  // 2 m/s along the body's x, which is yawed 0.7 rad (the body is at rest)
  EXPECT_NEAR(world.twist.linear.x, 2.0 * std::cos(0.7), 1e-12);
  EXPECT_NEAR(world.twist.linear.y, 2.0 * std::sin(0.7), 1e-12);
  const auto back = getState("plate", "", "fu::unit0_body");
  EXPECT_EQ(back.header.frame_id, "fu/unit0_body");
  EXPECT_NEAR(back.pose.position.x, 0.5, 1e-12);
  EXPECT_NEAR(back.pose.position.z, 1.0, 1e-12);
  EXPECT_NEAR(back.twist.linear.x, 2.0, 1e-12);

  for (const auto& [frame, cause] : std::vector<std::pair<std::string, std::string>>{
           {"fu/tail", "unknown reference_frame 'fu/tail'"},
           {"fu/", "unknown reference_frame 'fu/'"},    // no link: not fu's root
           {"fu::", "unknown reference_frame 'fu::'"},  // likewise
           {"ghost", "unknown reference_frame 'ghost'"}}) {
    r.reference_frame = frame;
    const auto refused = setState(r);
    EXPECT_FALSE(refused.success) << frame;
    EXPECT_NE(refused.status_message.find(cause), std::string::npos) << refused.status_message;
    const auto after = getState("plate");
    EXPECT_EQ(after.pose.position.z, world.pose.position.z) << frame;
  }
}

// set_state in a frame of the creature itself takes the frame where it is at the call, as
// Gazebo's set_model_state does: 1 m along its own x moves the creature 1 m along the x it had.
TEST_F(Interfaces, SetStateInItsOwnFrameMovesItFromWhereItIs) {
  flapsim::SetState::Request r;
  r.name = "plate";
  r.pose = yawed(1, 2, 50, 0.5);
  ASSERT_TRUE(setState(r).success);
  for (const std::string frame : {"plate", "plate/plate", "plate::plate"}) {
    const flapsim::Pose before = poseOf(getState("plate").pose);
    r.reference_frame = frame;
    r.pose = yawed(1, 0, 0, 0.1);
    const auto moved = setState(r);
    ASSERT_TRUE(moved.success) << frame << ": " << moved.status_message;
    const flapsim::Pose after = poseOf(getState("plate").pose);
    const flapsim::Pose want = before * poseOf(r.pose);
    EXPECT_NEAR((after.position - want.position).norm(), 0.0, 1e-12) << frame;
    EXPECT_NEAR(after.orientation.angularDistance(want.orientation), 0.0, 1e-12) << frame;
  }
}

// gazebo_msgs' field names (model_name, link_name, body_name, model_xml) name what the former
// ones (name, link, urdf_xml) do; either may be given, both set must agree (a refusal names
// both). A link field may be "<creature>::<link>", the creature then empty or the same.
TEST_F(Interfaces, GazeboFieldNamesAndCreatureLinkForms) {
  const auto old_names = getState("fu", "unit0_body");
  ASSERT_TRUE(old_names.success);
  flapsim::GetState::Request g;
  for (const auto& [model, link, old_link] :
       std::vector<std::array<std::string, 3>>{{"fu", "unit0_body", ""},
                                               {"", "fu::unit0_body", ""},
                                               {"fu", "fu::unit0_body", ""},
                                               {"", "", "fu::unit0_body"}}) {
    g.model_name = model;
    g.link_name = link;
    g.link = old_link;
    const auto s = callService<flapsim::GetState>("/flapsim/get_state", g);
    ASSERT_TRUE(s.success) << model << " " << link << " " << old_link << ": " << s.status_message;
    EXPECT_EQ(s.pose.position.z, old_names.pose.position.z);
    EXPECT_EQ(s.status_message, old_names.status_message);
  }
  for (const auto& [model, name, link, cause] : std::vector<std::array<std::string, 4>>{
           {"fu", "plate", "", "model_name 'fu' and name 'plate' differ (name is model_name's"},
           {"plate", "", "fu::unit0_body",
            "link_name 'fu::unit0_body' is a link of 'fu', not of model_name 'plate'"},
           {"", "", "fu::", "link_name 'fu::' names no link"}}) {
    g = flapsim::GetState::Request();
    g.model_name = model;
    g.name = name;
    g.link_name = link;
    const auto s = callService<flapsim::GetState>("/flapsim/get_state", g);
    EXPECT_FALSE(s.success);
    EXPECT_NE(s.status_message.find(cause), std::string::npos) << s.status_message;
  }
  flapsim::SetState::Request r;
  r.model_name = "plate";
  r.pose = yawed(7, 0, 40, 0);
  ASSERT_TRUE(setState(r).success);
  EXPECT_EQ(getState("plate").pose.position.x, 7.0);
  // A wrench on body_name "<creature>::<link>" (gazebo's form), cleared the same way.
  flapsim::ApplyWrench::Request w;
  w.body_name = "plate::plate";
  w.wrench.force.z = 1.0;
  const auto applied = applyWrench(w);
  ASSERT_TRUE(applied.success) << applied.status_message;
  EXPECT_NE(applied.status_message.find("wrench on 'plate' link 'plate'"), std::string::npos);
  // One that waits for its start_time (gazebo's): the reply says when it will act.
  w.start_time = ros::Time(1000, 0);
  const auto waiting = applyWrench(w);
  ASSERT_TRUE(waiting.success) << waiting.status_message;
  EXPECT_NE(waiting.status_message.find(" acts from t = 1000.000000000 s"), std::string::npos)
      << waiting.status_message;
  flapsim::ClearWrenches::Request c;
  c.body_name = "plate::plate";
  const auto cleared = callService<flapsim::ClearWrenches>("/flapsim/clear_wrenches", c);
  EXPECT_EQ(cleared.status_message, "cleared 2 wrench(es)");
  // Spawn and delete by model_name and model_xml.
  std::string urdf;
  ASSERT_TRUE(ros::param::get("/plate/robot_description", urdf));
  flapsim::SpawnCreature::Request sp;
  sp.model_name = "extra";
  sp.model_xml = urdf;
  sp.initial_pose = yawed(0, 9, 30, 0);
  sp.urdf_xml = urdf + " ";
  auto spawned = callService<flapsim::SpawnCreature>("/flapsim/spawn", sp);
  EXPECT_FALSE(spawned.success);
  EXPECT_EQ(spawned.status_message,
            "model_xml and urdf_xml differ (urdf_xml is model_xml's former name: give one)");
  sp.urdf_xml.clear();
  spawned = callService<flapsim::SpawnCreature>("/flapsim/spawn", sp);
  ASSERT_TRUE(spawned.success) << spawned.status_message;
  flapsim::DeleteCreature::Request d;
  d.model_name = "extra";
  const auto deleted = callService<flapsim::DeleteCreature>("/flapsim/delete", d);
  EXPECT_TRUE(deleted.success) << deleted.status_message;
}

// A push given in the plate's own frame with the point left at {} acts at the plate's origin
// (its centre of mass): it moves the plate along the plate's x (world y, the plate yawed 90
// degrees) by F dt / m in a step and turns it not at all. The same request in the world frame
// acts at the world origin, 10 m below: it also turns the plate (what issue 26 saw).
TEST_F(Interfaces, ApplyWrenchInTheLinksFrameActsAtItsOrigin) {
  clearWrenches();
  flapsim::SetState::Request still;
  still.name = "plate";
  still.pose = yawed(0, 0, 10, M_PI / 2);
  ASSERT_TRUE(setState(still).success);
  flapsim::ApplyWrench::Request w;
  w.name = "plate";
  w.reference_frame = "plate";
  w.wrench.force.x = 1.0;
  w.duration = ros::Duration(0.001);
  const auto applied = applyWrench(w);
  ASSERT_TRUE(applied.success) << applied.status_message;
  EXPECT_NE(applied.status_message.find("given in plate/plate"), std::string::npos);
  step(1);
  const auto s = getState("plate");
  EXPECT_NEAR(s.twist.linear.y, 1.0 * 0.001 / kPlateMass, 1e-12);
  EXPECT_NEAR(s.twist.linear.x, 0.0, 1e-12);
  EXPECT_LT(std::hypot(s.twist.angular.x, s.twist.angular.y, s.twist.angular.z), 1e-12);

  ASSERT_TRUE(setState(still).success);
  w.reference_frame = "";
  ASSERT_TRUE(applyWrench(w).success);
  step(1);
  const auto turned = getState("plate");
  EXPECT_GT(turned.twist.linear.x, 0.0);             // pushed along world x
  EXPECT_GT(std::abs(turned.twist.angular.y), 1.0);  // 10 m x 1 N about y, on 3e-5 kg m^2

  w.reference_frame = "plate/wing";
  const auto refused = applyWrench(w);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.status_message.find("unknown reference_frame 'plate/wing'"), std::string::npos)
      << refused.status_message;
  clearWrenches();
}

// get_physics reads what runs; set_physics changes gravity and the air at once (a plate in
// vacuum then falls at the new gravity exactly: v = g t), and the dynamic_reconfigure config
// follows. Another step size, or a bad value, is refused by name and nothing changes.
TEST_F(Interfaces, SetPhysicsChangesGravityAndTheAirAndTheConfigFollows) {
  const auto before = getPhysics();
  EXPECT_EQ(before.step_size, 0.001);
  EXPECT_TRUE(before.paused);
  EXPECT_EQ(before.gravity.z, -9.81);
  EXPECT_EQ(before.air_density, 1.204);
  EXPECT_EQ(before.publish_rate, 100.0);

  auto r = asRequest(before);
  r.step_size = 0.002;
  r.gravity.z = -1.62;
  auto refused = setPhysics(r);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.status_message.find("step_size 0.002 s: the step size cannot change"),
            std::string::npos)
      << refused.status_message;
  r = asRequest(before);
  r.air_density = std::nan("");
  refused = setPhysics(r);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.status_message.find("density"), std::string::npos) << refused.status_message;
  EXPECT_EQ(getPhysics().gravity.z, -9.81);
  EXPECT_EQ(getPhysics().air_density, 1.204);

  r = asRequest(before);
  r.gravity.z = -1.62;
  r.air_density = 0.0;
  const auto set = setPhysics(r);
  ASSERT_TRUE(set.success) << set.status_message;
  EXPECT_EQ(getPhysics().gravity.z, -1.62);
  EXPECT_EQ(getPhysics().air_density, 0.0);
  double gravity_z = 0.0;
  EXPECT_TRUE(ros::param::get("/flapsim/gravity_z", gravity_z));  // dynparam get shows it
  EXPECT_EQ(gravity_z, -1.62);

  flapsim::SetState::Request still;
  still.name = "plate";
  still.pose = yawed(0, 0, 20, 0);
  ASSERT_TRUE(setState(still).success);
  step(100);
  EXPECT_NEAR(getState("plate").twist.linear.z, -1.62 * 0.1, 1e-12);

  ASSERT_TRUE(setPhysics(asRequest(before)).success);
  EXPECT_EQ(getPhysics().gravity.z, -9.81);
}

// set_physics with `fields` changes only the fields named ({wind: {x: 1}} alone zeroed gravity
// and density); an unknown field is refused; reset restores the physics of the start (it kept
// the changed ones).
TEST_F(Interfaces, SetPhysicsChangesOnlyTheNamedFieldsAndResetRestoresTheStart) {
  const auto start = getPhysics();
  flapsim::SetPhysics::Request r;
  r.fields = {"wind"};
  r.wind.x = 1.0;
  ASSERT_TRUE(setPhysics(r).success);
  const auto windy = getPhysics();
  EXPECT_EQ(windy.wind.x, 1.0);
  EXPECT_EQ(windy.gravity.z, start.gravity.z);
  EXPECT_EQ(windy.air_density, start.air_density);
  EXPECT_EQ(windy.drag_coefficient, start.drag_coefficient);
  EXPECT_EQ(windy.publish_rate, start.publish_rate);
  EXPECT_EQ(windy.real_time_factor, start.real_time_factor);
  r.fields = {"wind", "gravitty"};
  const auto refused = setPhysics(r);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.status_message.find("fields: 'gravitty' is not one of"), std::string::npos)
      << refused.status_message;
  r.fields = {"gravity", "air_density"};
  r.gravity.z = -3.0;
  r.air_density = 2.0;
  ASSERT_TRUE(setPhysics(r).success);
  EXPECT_EQ(getPhysics().gravity.z, -3.0);
  EXPECT_EQ(getPhysics().wind.x, 1.0);  // kept
  std_srvs::Empty reset;
  ASSERT_TRUE(flapsim_test::call("/flapsim/reset", reset));
  const auto after = getPhysics();
  EXPECT_EQ(after.gravity.z, start.gravity.z);
  EXPECT_EQ(after.air_density, start.air_density);
  EXPECT_EQ(after.wind.x, start.wind.x);
  double gravity_z = 0.0;
  EXPECT_TRUE(ros::param::get("/flapsim/gravity_z", gravity_z));  // the config follows
  EXPECT_EQ(gravity_z, start.gravity.z);
}

// With use_sim_time (as every launch file sets it), `rostopic echo -n1` of /clock, of a
// creature's odom, imu, joint_states and power, answers while the node is paused, with the
// current sim time (power hung).
TEST_F(Interfaces, RostopicEchoAnswersWhilePaused) {
  bool sim_time = false;
  ASSERT_TRUE(ros::param::get("/use_sim_time", sim_time) && sim_time);
  const ros::Time t = step(7);  // not on a publication boundary (every 10 steps)
  const std::regex at_t("secs: +" + std::to_string(t.sec) + "\\s+nsecs: +" +
                        std::to_string(t.nsec) + "\\b");
  // Three times each: whether rospy's own /clock subscriber (which shares the connection)
  // takes the one message a new connection gets varies from run to run.
  for (int i = 0; i < 3; ++i) {
    for (const char* topic :
         {"/clock", "/plate/odom", "/plate/imu", "/fu/joint_states", "/fu/power"}) {
      const std::string out = firstMessageOf(topic);
      EXPECT_TRUE(std::regex_search(out, at_t)) << topic << " at " << t << ":\n" << out;
    }
  }
}

// ---- the wing command timeout: ~wing_command_timeout 0.05 s (50 steps) ----------------------

struct Wings {
  explicit Wings(ros::NodeHandle& nh) {
    js.start(nh, "/fu/joint_states");
    diagnostics.start(nh, "/diagnostics");
    EXPECT_TRUE(waitFor([&] { return js.connected(); }, kWait));
  }
  sensor_msgs::JointState::ConstPtr at(const ros::Time& t) { return js.at(t, kWait); }
  // The level of fu's last diagnostics status.
  int level() {
    int level = -1;
    for (const auto& m : diagnostics.msgs) {
      for (const auto& s : m->status) {
        if (s.hardware_id == "fu") level = s.level;
      }
    }
    return level;
  }
  Recorder<sensor_msgs::JointState> js;
  Recorder<diagnostic_msgs::DiagnosticArray> diagnostics;
};

flapsim::Step commandStep(std::uint32_t steps) {
  flapsim::Step s;
  s.request.steps = steps;
  s.request.creatures = {"fu"};
  s.request.wing_commands.resize(1);
  s.request.wing_commands[0].downstroke_rate = {40, 40};
  s.request.wing_commands[0].upstroke_rate = {10, 10};
  s.request.wing_commands[0].amplitude = {0.8, 0.8};
  return s;
}

// hold: up to step 49 after the last command the wings stroke (their motors driving them at
// the stroke's 10 or 60 rad/s); from step 50 the motors hold them: 20 steps later they stand still
// (below 1e-3 rad/s) where they were, and /diagnostics warns. A new command (here in a step
// request) starts them again, and its own timeout.
TEST_F(Interfaces, WingsAreHeldOnceTheCommandTimesOut) {
  Wings wings(nh_);
  callEmpty("/flapsim/reset");  // fu's wing_command parameter: commanded at t = 0
  auto stroking = wings.at(step(49));
  ASSERT_TRUE(stroking);
  EXPECT_GT(std::abs(stroking->velocity[0]), 5.0);
  step(1);
  const double held_at = wings.at(step(10))->position[0];
  const auto held = wings.at(step(20));
  ASSERT_TRUE(held);
  EXPECT_LT(std::abs(held->velocity[0]), 1e-3);
  EXPECT_LT(std::abs(held->velocity[1]), 1e-3);
  EXPECT_NEAR(held->position[0], held_at, 1e-3);
  EXPECT_TRUE(
      waitFor([&] { return wings.level() == diagnostic_msgs::DiagnosticStatus::WARN; }, kWait));

  flapsim::Step again = commandStep(10);
  ASSERT_TRUE(flapsim_test::call("/flapsim/step", again) && again.response.success);
  const auto moving = wings.at(step(39));  // 49 steps after the command
  ASSERT_TRUE(moving);
  EXPECT_GT(std::abs(moving->velocity[0]), 5.0);
  step(31);
  EXPECT_LT(std::abs(wings.at(step(1))->velocity[0]), 1e-3);
}

// flapsim/reset after a lapse: the world gives back the command that lapsed (fu's wing_command
// parameter) and starts its timeout again at 0, so the wings stroke from t = 0 as in the first
// run, to the bit, /diagnostics says OK again, and they are held again from step 50.
TEST_F(Interfaces, AResetAfterALapseFliesTheCommandAgainFromTimeZero) {
  Wings wings(nh_);
  callEmpty("/flapsim/reset");
  const auto first = wings.at(step(30));
  ASSERT_TRUE(first);
  ASSERT_TRUE(wings.at(step(40)));  // step 70: held since step 50
  EXPECT_TRUE(
      waitFor([&] { return wings.level() == diagnostic_msgs::DiagnosticStatus::WARN; }, kWait));
  callEmpty("/flapsim/reset");
  wings.js.clear();
  EXPECT_TRUE(
      waitFor([&] { return wings.level() == diagnostic_msgs::DiagnosticStatus::OK; }, kWait));
  const auto again = wings.at(step(30));
  ASSERT_TRUE(again);
  EXPECT_GT(std::abs(again->velocity[0]), 5.0);  // stroking
  EXPECT_EQ(again->position, first->position);
  EXPECT_EQ(again->velocity, first->velocity);
  EXPECT_EQ(again->effort, first->effort);
  step(20);
  const auto held = wings.at(step(20));
  ASSERT_TRUE(held);
  EXPECT_LT(std::abs(held->velocity[0]), 1e-3);
}

// release (wing_timeout_release.test): from step 50 the wing motors let go: the joints apply
// no torque at all, and the wings swing on freely.
TEST_F(Interfaces, WingsAreReleasedOnceTheCommandTimesOut) {
  Wings wings(nh_);
  callEmpty("/flapsim/reset");
  auto stroking = wings.at(step(49));
  ASSERT_TRUE(stroking);
  EXPECT_NE(stroking->effort[0], 0.0);
  const auto released = wings.at(step(1));
  ASSERT_TRUE(released);
  EXPECT_NE(released->effort[0], 0.0);  // the 50th step was still driven
  const auto free = wings.at(step(1));
  ASSERT_TRUE(free);
  EXPECT_EQ(free->effort[0], 0.0);
  EXPECT_EQ(free->effort[1], 0.0);
  EXPECT_GT(std::abs(free->velocity[0]), 1.0);  // not held: still swinging
  EXPECT_TRUE(
      waitFor([&] { return wings.level() == diagnostic_msgs::DiagnosticStatus::WARN; }, kWait));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_interfaces");
  return RUN_ALL_TESTS();
}
