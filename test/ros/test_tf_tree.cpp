// The simulator's transforms (tf_tree.test, tf_repeats_*.test): a tree that follows each
// URDF (world -> root on /tf, parent -> child per movable joint on /tf, per fixed joint on
// /tf_static), tf2 lookups between any two links that agree with flapsim/get_state, and no
// frame twice at one stamp: tf2 listeners (ours, joining at any moment, and every node's on
// /rosout) never report TF_REPEATED_DATA.
#include <console_bridge/console.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <rosgraph_msgs/Log.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "flapsim/GetState.h"
#include "flapsim/SetState.h"
#include "flapsim/SpawnCreature.h"
#include "flapsim/Step.h"
#include "flapsim/creature_model.h"
#include "node_calls.h"
#include "recorder.h"
#include "wait_for.h"

namespace {

using flapsim_test::callEmpty;
using flapsim_test::getState;
using flapsim_test::Recorder;
using flapsim_test::step;
using flapsim_test::waitFor;
constexpr double kWait = 30.0;  // s (wall), upper bound of a wait

// tf2 reports a repeated stamp through console_bridge: counted here, whichever listener.
class RepeatCounter : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel, const char*, int) override {
    if (text.find("TF_REPEATED_DATA") == std::string::npos) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (first_.empty()) first_ = text;
    ++count_;
  }
  int count() const { return count_; }
  std::string first() {
    std::lock_guard<std::mutex> lock(mutex_);
    return first_;
  }

 private:
  std::atomic<int> count_{0};
  std::mutex mutex_;
  std::string first_;
};
RepeatCounter repeats;

// Other nodes' tf2 warnings reach /rosout through rosconsole_bridge.
struct RosoutRepeats {
  void start(ros::NodeHandle& nh) {
    sub = nh.subscribe<rosgraph_msgs::Log>("/rosout", 1000, [this](const auto& m) {
      if (m->msg.find("TF_REPEATED_DATA") != std::string::npos)
        lines.push_back(m->name + ": " + m->msg);
    });
  }
  ros::Subscriber sub;
  std::vector<std::string> lines;
};

std::string sourcePath(const std::string& relative) {
  return std::string(FLAPSIM_SOURCE_DIR) + "/" + relative;
}

flapsim::Pose poseOf(const geometry_msgs::Transform& t) {
  return flapsim::Pose{flapsim::Vec3(t.translation.x, t.translation.y, t.translation.z),
                       flapsim::Quat(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z)};
}
flapsim::Pose poseOf(const geometry_msgs::Pose& p) {
  return flapsim::Pose{
      flapsim::Vec3(p.position.x, p.position.y, p.position.z),
      flapsim::Quat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z)};
}
// Position and rotation angle between two poses.
std::pair<double, double> difference(const flapsim::Pose& a, const flapsim::Pose& b) {
  return {(a.position - b.position).norm(), a.orientation.angularDistance(b.orientation)};
}

flapsim::Step stepRequest(std::uint32_t n) {
  flapsim::Step s;
  s.request.steps = n;
  return s;
}

// ---- tf_tree.test: a paused flapsim with afc (urdf/afc_4.urdf: 11 revolute joints),
// copter (urdf/bamboo_copter.urdf: 2 fixed joints) and cad (test/ros/cad_unit.urdf: massless
// base_link and imu_link lumped into the body, full inertia tensors) ---------------------

class Tree : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ros::service::waitForService("/flapsim/step", ros::Duration(60)));
    callEmpty("/flapsim/pause");
  }
  ros::NodeHandle nh_;
};

using Edges = std::set<std::pair<std::string, std::string>>;

Edges edgesOf(const std::vector<geometry_msgs::TransformStamped>& transforms) {
  Edges e;
  for (const auto& t : transforms) e.insert({t.header.frame_id, t.child_frame_id});
  return e;
}

TEST_F(Tree, MovingJointsAreOnTfAndFixedJointsOnTfStatic) {
  Recorder<tf2_msgs::TFMessage> tf, tf_static;
  tf.start(nh_, "/tf");
  tf_static.start(nh_, "/tf_static");
  ASSERT_TRUE(waitFor([&] { return tf.connected() && !tf_static.msgs.empty(); }, kWait));
  const ros::Time t = step(10);
  Edges moving;
  ASSERT_TRUE(waitFor(
      [&] {
        moving.clear();
        for (const auto& m : tf.msgs) {
          for (const auto& tr : m->transforms) {
            if (tr.header.stamp == t) moving.insert({tr.header.frame_id, tr.child_frame_id});
          }
        }
        return moving.size() >= 17;
      },
      kWait));
  Edges want_moving = {{"world", "afc/unit0_body"},   {"world", "copter/pole"},
                       {"world", "flapsim/view"},     {"world", "flapsim/camera"},
                       {"world", "cad/body"},         {"cad/body", "cad/wing_left"},
                       {"cad/body", "cad/wing_right"}};
  // cad's massless base_link and imu_link, lumped into its body, hang from it.
  Edges want_static = {{"cad/body", "cad/base_link"}, {"cad/body", "cad/imu_link"}};
  const auto afc = flapsim::loadCreatureModel(sourcePath("urdf/afc_4.urdf"));
  for (const auto& j : afc->joints) {
    want_moving.insert(
        {"afc/" + afc->links[j.parent_link].name, "afc/" + afc->links[j.child_link].name});
  }
  const auto copter = flapsim::loadCreatureModel(sourcePath("urdf/bamboo_copter.urdf"));
  for (const auto& j : copter->joints) {
    want_static.insert({"copter/" + copter->links[j.parent_link].name,
                        "copter/" + copter->links[j.child_link].name});
  }
  EXPECT_EQ(want_moving.size(), 7u + 11u);
  EXPECT_EQ(moving, want_moving);
  EXPECT_EQ(edgesOf(tf_static.msgs.back()->transforms), want_static);
  // A fixed joint's transform is its URDF origin.
  for (const auto& tr : tf_static.msgs.back()->transforms) {
    if (tr.child_frame_id != "copter/blade_left") continue;
    const flapsim::Pose origin = copter->joints.at(copter->findJoint("blade_left_joint")).origin;
    const auto [dp, da] = difference(poseOf(tr.transform), origin);
    EXPECT_EQ(dp, 0.0);
    EXPECT_LT(da, 1e-12);
  }
}

// tf2 between any two links (through the tree, the static joints included) gives what
// flapsim/get_state gives for one link in the other's frame, and both what the two world
// poses give. 1e-9 m and 1e-9 rad: rounding over a chain of a dozen transforms is about
// 1e-15; a wrong joint would be off by the link lengths (cm) or the joint angles.
TEST_F(Tree, AnyTwoLinksLookUpAsGetStateGivesThem) {
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer, nh_);
  // connected (it has the paused step) before the step it is to see
  ASSERT_TRUE(
      waitFor([&] { return buffer.canTransform("world", "afc/unit0_body", ros::Time(0)); }, kWait));
  flapsim::Step s = stepRequest(137);
  s.request.creatures = {"afc"};
  s.request.wing_commands.resize(1);
  for (int i = 0; i < 8; ++i) {  // 4 pairs of wings stroking, the chain bending
    s.request.wing_commands[0].downstroke_rate.push_back(40 + i);
    s.request.wing_commands[0].upstroke_rate.push_back(10);
    s.request.wing_commands[0].amplitude.push_back(0.6);
  }
  ASSERT_TRUE(flapsim_test::call("/flapsim/step", s) && s.response.success)
      << s.response.status_message;
  const ros::Time t = s.response.sim_time;
  const std::vector<std::pair<std::string, std::string>> links = {
      {"afc", "unit0_body"},       {"afc", "unit3_wing_left"}, {"afc", "unit2_body"},
      {"afc", "unit1_wing_right"}, {"copter", "blade_left"},   {"copter", "pole"},
      {"cad", "base_link"},        {"cad", "imu_link"},        {"cad", "wing_left"}};
  for (const auto& [ca, la] : links) {
    for (const auto& [cb, lb] : links) {
      const std::string a = ca + "/" + la, b = cb + "/" + lb;
      ASSERT_TRUE(waitFor([&] { return buffer.canTransform(a, b, t); }, kWait)) << a << " " << b;
      const flapsim::Pose looked_up = poseOf(buffer.lookupTransform(a, b, t).transform);
      const flapsim::Pose from_world =
          poseOf(getState(ca, la).pose).inverse() * poseOf(getState(cb, lb).pose);
      const flapsim::GetState::Response relative = getState(cb, lb, a);
      EXPECT_EQ(relative.header.frame_id, a);
      const auto [dp, da] = difference(looked_up, from_world);
      EXPECT_LT(dp, 1e-9) << a << " -> " << b;
      EXPECT_LT(da, 1e-9) << a << " -> " << b;
      const auto [rp, ra] = difference(poseOf(relative.pose), from_world);
      EXPECT_LT(rp, 1e-12) << a << " -> " << b;
      EXPECT_LT(ra, 1e-12) << a << " -> " << b;
    }
  }
}

// Everything that republished a step before: flapsim/step of 0 steps, set_state and spawn
// while paused, a pause between publications, listeners joining while paused and while
// running as fast as it goes.
// One tf2 listener at a time: each join drops the last one and subscribes anew. (roscpp gives
// every subscriber of a topic in one process one connection: only a listener that is alone in
// its process joins with a connection of its own, which the node sees as a new subscriber.)
class Joining {
 public:
  explicit Joining(ros::NodeHandle& nh) : nh_(nh) { join(); }
  void join() {
    listener_.reset();
    buffer_ = std::make_unique<tf2_ros::Buffer>();
    listener_ = std::make_unique<tf2_ros::TransformListener>(*buffer_, nh_);
    ++joins_;
  }
  bool has(const std::string& frame, const ros::Time& t) {
    return waitFor([&] { return buffer_->canTransform("world", frame, t); }, kWait);
  }
  int joins() const { return joins_; }

 private:
  ros::NodeHandle& nh_;
  std::unique_ptr<tf2_ros::Buffer> buffer_;
  std::unique_ptr<tf2_ros::TransformListener> listener_;
  int joins_ = 0;
};

TEST_F(Tree, NoListenerGetsAFrameTwiceAtOneStamp) {
  RosoutRepeats rosout;
  rosout.start(nh_);
  const int before = repeats.count();
  Joining listener(nh_);
  ASSERT_TRUE(listener.has("afc/unit0_body", ros::Time(0)));
  step(3);
  step(0);
  listener.join();
  flapsim::SetState set;
  set.request.name = "copter";
  set.request.pose.position.z = 4.0;
  set.request.pose.orientation.w = 1.0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/set_state", set) && set.response.success);
  flapsim::SpawnCreature spawn;
  spawn.request.name = "plate_tf";
  spawn.request.urdf_file = sourcePath("urdf/plate.urdf");
  spawn.request.initial_pose.position.z = 2.0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", spawn) && spawn.response.success);
  listener.join();
  step(0);
  step(7);
  // running as fast as it goes: a listener joins every 30 ms of wall time, 60 times
  callEmpty("/flapsim/unpause");
  for (int i = 0; i < 60; ++i) {
    waitFor([] { return false; }, 0.03);
    listener.join();
  }
  callEmpty("/flapsim/pause");
  const ros::Time paused_at = step(0);
  listener.join();  // gets the step it is paused at, at once
  EXPECT_TRUE(listener.has("plate_tf/plate", paused_at));
  EXPECT_TRUE(listener.has("plate_tf/plate", step(1)));  // and the next
  EXPECT_EQ(repeats.count() - before, 0) << repeats.first();
  EXPECT_TRUE(rosout.lines.empty()) << rosout.lines.front();
}

// ---- tf_repeats_*.test: a scenario (flock.launch count:=4, afc.launch) running at rtf 0 ---

// A tf2 listener joins `~listeners` times, every 20 ms of wall time (as rviz and controllers
// do), while the scenario runs to `~duration` s of sim time; none of them, nor any node on
// /rosout (the controllers' tf2 listeners), sees a repeated stamp.
TEST(Scenario, NoListenerGetsAFrameTwiceAtOneStamp) {
  ros::NodeHandle nh, pnh("~");
  double duration = 3.0;
  int count = 50;
  pnh.getParam("duration", duration);
  pnh.getParam("listeners", count);
  RosoutRepeats rosout;
  rosout.start(nh);
  Recorder<rosgraph_msgs::Clock> clock;
  clock.start(nh, "/clock");
  ASSERT_TRUE(waitFor([&] { return !clock.msgs.empty(); }, 120.0)) << "no /clock";
  Joining listener(nh);
  ASSERT_TRUE(waitFor(
      [&] {
        if (listener.joins() < count) {
          waitFor([] { return false; }, 0.02);
          listener.join();
        }
        return listener.joins() == count && clock.msgs.back()->clock.toSec() >= duration;
      },
      300.0))
      << "sim time did not reach " << duration << " s";
  std::printf("%d listeners joined by t = %.2f s of sim time\n", count,
              clock.msgs.back()->clock.toSec());
  EXPECT_EQ(repeats.count(), 0) << repeats.first();
  EXPECT_TRUE(rosout.lines.empty()) << rosout.lines.front();
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_tf_tree");
  ros::NodeHandle nh;  // before the handler: rosconsole_bridge registers its own at start-up
  console_bridge::useOutputHandler(&repeats);
  return RUN_ALL_TESTS();
}
