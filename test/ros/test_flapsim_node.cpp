// flapsim_node through its ROS interface (rostest: see flapsim_node.test).
// The node starts paused; tests reach sim times through flapsim/step and wait
// for messages with that exact stamp (timeouts only bound the waits).
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/DeleteCreature.h"
#include "flapsim/SpawnCreature.h"
#include "flapsim/Step.h"
#include "flapsim/WingCommand.h"
#include "node_calls.h"
#include "recorder.h"

namespace {

constexpr std::uint64_t kStepNs = 1000000;  // step_size 0.001 s
constexpr double kWait = 20.0;              // s (wall), upper bound of any wait
const char* kLeft = "unit0_wing_left_joint";
const char* kRight = "unit0_wing_right_joint";

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string sourcePath(const std::string& relative) {
  return std::string(FLAPSIM_SOURCE_DIR) + "/" + relative;
}

/// Processes callbacks until `done()` or `timeout` seconds of wall time.
bool waitUntil(const std::function<bool()>& done, double timeout = kWait) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok()) {
    if (done()) return true;
    if (ros::WallTime::now() > deadline) return false;
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.01));
  }
  return false;
}

using flapsim_test::Recorder;

/// The last message of `r` stamped `t` (waits for it); null if none came.
template <class M>
boost::shared_ptr<const M> at(Recorder<M>& r, const ros::Time& t) {
  return r.at(t, kWait);
}

class Node : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nh_ = std::make_unique<ros::NodeHandle>();
    ASSERT_TRUE(ros::service::waitForService("/flapsim/step", ros::Duration(60)));
    for (const char* s : {"reset", "pause", "unpause", "spawn", "delete"}) {
      ASSERT_TRUE(ros::service::waitForService(std::string("/flapsim/") + s, ros::Duration(10)));
    }
    clock_.start(*nh_, "/clock");
    tf_.start(*nh_, "/tf");
    markers_.start(*nh_, "/flapsim/aero_markers");
    rosout_.start(*nh_, "/rosout");
    js_.start(*nh_, "/flap_unit/joint_states");
    odom_.start(*nh_, "/flap_unit/odom");
    plate_odom_.start(*nh_, "/plate/odom");
    wing_ = nh_->advertise<flapsim::WingCommand>("/flap_unit/wing_command", 10);
    ASSERT_TRUE(waitUntil([] {
      return clock_.connected() && tf_.connected() && markers_.connected() && js_.connected() &&
             odom_.connected() && plate_odom_.connected() && wing_.getNumSubscribers() > 0;
    })) << "flapsim's topics did not connect";
  }
  static void TearDownTestSuite() {
    clock_ = {};
    tf_ = {};
    markers_ = {};
    rosout_ = {};
    js_ = {};
    odom_ = {};
    plate_odom_ = {};
    wing_.shutdown();
    nh_.reset();
  }
  void SetUp() override { pause(); }

  static void pause() {
    std_srvs::Empty e;
    ASSERT_TRUE(flapsim_test::call("/flapsim/pause", e));
  }
  static void unpause() {
    std_srvs::Empty e;
    ASSERT_TRUE(flapsim_test::call("/flapsim/unpause", e));
  }
  /// Resets the world and forgets the messages seen so far: sim times repeat
  /// after a reset, so an old message could otherwise match a new stamp.
  static void reset() {
    std_srvs::Empty e;
    ASSERT_TRUE(flapsim_test::call("/flapsim/reset", e));
    clock_.clear();
    tf_.clear();
    markers_.clear();
    js_.clear();
    odom_.clear();
    plate_odom_.clear();
  }
  static flapsim::Step step(std::uint32_t n) {
    flapsim::Step s;
    s.request.steps = n;
    EXPECT_TRUE(flapsim_test::call("/flapsim/step", s));
    return s;
  }
  /// Steps n (must succeed) and returns the new sim time.
  static ros::Time stepOk(std::uint32_t n) {
    flapsim::Step s = step(n);
    EXPECT_TRUE(s.response.success) << s.response.status_message;
    return s.response.sim_time;
  }
  static flapsim::WingCommand command(std::vector<std::string> names, std::vector<double> w1,
                                      std::vector<double> w2, std::vector<double> amp) {
    flapsim::WingCommand c;
    c.joint_names = std::move(names);
    c.downstroke_rate = std::move(w1);
    c.upstroke_rate = std::move(w2);
    c.amplitude = std::move(amp);
    return c;
  }
  /// Publishes a stroke for both wings and steps until the joints move at
  /// -w1 or +w2 (so the command has arrived); false if they never do.
  static bool commandAndWait(double w1, double w2, double amp) {
    wing_.publish(command({}, {w1, w1}, {w2, w2}, {amp, amp}));
    for (int i = 0; i < 400; ++i) {
      auto js = at(js_, stepOk(5));
      if (!js) return false;
      bool ok = true;
      for (double v : js->velocity) {
        ok = ok && (std::abs(v + w1) < 0.5 || std::abs(v - w2) < 0.5);
      }
      if (ok) return true;
    }
    return false;
  }
  /// Joint velocities of the flap unit seen over `chunks` x 5 steps.
  static std::vector<double> sampleVelocities(int chunks) {
    std::vector<double> v;
    for (int i = 0; i < chunks; ++i) {
      auto js = at(js_, stepOk(5));
      if (!js) break;
      v.insert(v.end(), js->velocity.begin(), js->velocity.end());
    }
    return v;
  }
  static bool warned(const std::string& text) {
    return waitUntil([&] {
      for (const auto& m : rosout_.msgs) {
        if (m->name == "/flapsim" && m->level == rosgraph_msgs::Log::WARN &&
            m->msg.find(text) != std::string::npos) {
          return true;
        }
      }
      return false;
    });
  }
  static bool advertised(const std::string& topic) {
    ros::master::V_TopicInfo topics;
    ros::master::getTopics(topics);
    return std::any_of(topics.begin(), topics.end(),
                       [&](const auto& t) { return t.name == topic; });
  }

  static std::unique_ptr<ros::NodeHandle> nh_;
  static Recorder<rosgraph_msgs::Clock> clock_;
  static Recorder<tf2_msgs::TFMessage> tf_;
  static Recorder<visualization_msgs::MarkerArray> markers_;
  static Recorder<rosgraph_msgs::Log> rosout_;
  static Recorder<sensor_msgs::JointState> js_;
  static Recorder<nav_msgs::Odometry> odom_, plate_odom_;
  static ros::Publisher wing_;
};

std::unique_ptr<ros::NodeHandle> Node::nh_;
Recorder<rosgraph_msgs::Clock> Node::clock_;
Recorder<tf2_msgs::TFMessage> Node::tf_;
Recorder<visualization_msgs::MarkerArray> Node::markers_;
Recorder<rosgraph_msgs::Log> Node::rosout_;
Recorder<sensor_msgs::JointState> Node::js_;
Recorder<nav_msgs::Odometry> Node::odom_, Node::plate_odom_;
ros::Publisher Node::wing_;

bool hasClock(const Recorder<rosgraph_msgs::Clock>& r, const ros::Time& t) {
  return std::any_of(r.msgs.begin(), r.msgs.end(), [&](const auto& m) { return m->clock == t; });
}

const geometry_msgs::TransformStamped* findTf(const Recorder<tf2_msgs::TFMessage>& r,
                                              const std::string& child, const ros::Time& t) {
  for (auto it = r.msgs.rbegin(); it != r.msgs.rend(); ++it) {
    for (const auto& tr : (*it)->transforms) {
      if (tr.child_frame_id == child && tr.header.stamp == t) return &tr;
    }
  }
  return nullptr;
}

TEST_F(Node, TopicsCarryFramesJointNamesAndSimStamps) {
  reset();
  const ros::Time t = stepOk(20);
  EXPECT_EQ(t.toNSec(), 20 * kStepNs);
  EXPECT_TRUE(waitUntil([&] { return hasClock(clock_, t); })) << "no /clock at " << t;

  auto js = at(js_, t);
  ASSERT_TRUE(js);
  EXPECT_EQ(js->name, (std::vector<std::string>{kLeft, kRight}));
  EXPECT_EQ(js->position.size(), 2u);
  EXPECT_EQ(js->velocity.size(), 2u);

  auto odom = at(odom_, t);
  ASSERT_TRUE(odom);
  EXPECT_EQ(odom->header.frame_id, "world");
  EXPECT_EQ(odom->child_frame_id, "flap_unit/unit0_body");
  auto plate = at(plate_odom_, t);
  ASSERT_TRUE(plate);
  EXPECT_EQ(plate->child_frame_id, "plate/plate");

  // the tree of the URDF: the roots in the world, the wings on the body
  for (const auto& [parent, frame] : std::vector<std::pair<std::string, std::string>>{
           {"world", "flap_unit/unit0_body"},
           {"flap_unit/unit0_body", "flap_unit/unit0_wing_left"},
           {"flap_unit/unit0_body", "flap_unit/unit0_wing_right"},
           {"world", "plate/plate"}}) {
    const geometry_msgs::TransformStamped* tr = nullptr;
    EXPECT_TRUE(waitUntil([&] { return (tr = findTf(tf_, frame, t)) != nullptr; }))
        << "no tf for " << frame << " at " << t;
    if (tr) {
      EXPECT_EQ(tr->header.frame_id, parent);
    }
  }

  // markers: a DELETEALL, then arrows in the world frame at t, per link and per cell
  visualization_msgs::MarkerArray::ConstPtr markers;
  ASSERT_TRUE(waitUntil([&] {
    for (const auto& m : markers_.msgs) {
      if (!m->markers.empty() && m->markers[0].header.stamp == t) markers = m;
    }
    return markers != nullptr;
  }));
  EXPECT_EQ(markers->markers[0].action, visualization_msgs::Marker::DELETEALL);
  int plate_arrows = 0, cell_arrows = 0;
  for (const auto& m : markers->markers) {
    EXPECT_EQ(m.header.frame_id, "world");
    EXPECT_EQ(m.header.stamp, t);
    if (m.action == visualization_msgs::Marker::DELETEALL) continue;
    EXPECT_EQ(m.type, visualization_msgs::Marker::ARROW);
    plate_arrows += m.ns == "plate";
    cell_arrows += m.ns == "plate/cells";
  }
  EXPECT_EQ(plate_arrows, 1);
  EXPECT_GT(cell_arrows, 0);

  std::string description;
  ASSERT_TRUE(nh_->getParam("/flap_unit/robot_description", description));
  EXPECT_EQ(description, readFile(sourcePath("urdf/flap_unit.urdf")));
}

TEST_F(Node, OdomAgreesWithTfForTheRootLink) {
  reset();
  const ros::Time t1 = stepOk(30);
  for (auto* rec : {&odom_, &plate_odom_}) {
    auto odom = at(*rec, t1);
    ASSERT_TRUE(odom);
    const geometry_msgs::TransformStamped* tr = nullptr;
    ASSERT_TRUE(waitUntil([&] { return (tr = findTf(tf_, odom->child_frame_id, t1)) != nullptr; }));
    EXPECT_EQ(tr->transform.translation.x, odom->pose.pose.position.x);
    EXPECT_EQ(tr->transform.translation.y, odom->pose.pose.position.y);
    EXPECT_EQ(tr->transform.translation.z, odom->pose.pose.position.z);
    EXPECT_EQ(tr->transform.rotation.x, odom->pose.pose.orientation.x);
    EXPECT_EQ(tr->transform.rotation.y, odom->pose.pose.orientation.y);
    EXPECT_EQ(tr->transform.rotation.z, odom->pose.pose.orientation.z);
    EXPECT_EQ(tr->transform.rotation.w, odom->pose.pose.orientation.w);
  }
  // The twist is the root frame's velocity in that (child) frame: rotated to
  // the world it matches the displacement over one step.
  auto a = at(plate_odom_, t1);
  const ros::Time t2 = stepOk(1);
  auto b = at(plate_odom_, t2);
  ASSERT_TRUE(a && b);
  const auto& q = b->pose.pose.orientation;
  const auto& v = b->twist.twist.linear;
  // v_world = q * v_body * q^-1
  const double qv[3] = {q.x, q.y, q.z};
  const double vb[3] = {v.x, v.y, v.z};
  double t[3] = {2 * (qv[1] * vb[2] - qv[2] * vb[1]), 2 * (qv[2] * vb[0] - qv[0] * vb[2]),
                 2 * (qv[0] * vb[1] - qv[1] * vb[0])};
  const double vw[3] = {vb[0] + q.w * t[0] + (qv[1] * t[2] - qv[2] * t[1]),
                        vb[1] + q.w * t[1] + (qv[2] * t[0] - qv[0] * t[2]),
                        vb[2] + q.w * t[2] + (qv[0] * t[1] - qv[1] * t[0])};
  const double dt = 1e-3;
  const double fd[3] = {(b->pose.pose.position.x - a->pose.pose.position.x) / dt,
                        (b->pose.pose.position.y - a->pose.pose.position.y) / dt,
                        (b->pose.pose.position.z - a->pose.pose.position.z) / dt};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(vw[i], fd[i], 0.01) << "axis " << i;
  // and it is not trivially world-aligned: the plate is rolled, pitched and yawed
  EXPECT_GT(std::abs(vb[0] - vw[0]) + std::abs(vb[1] - vw[1]), 0.05);
}

TEST_F(Node, StepAdvancesSimTimeByExactlyNSteps) {
  const ros::Time t0 = stepOk(0);
  const ros::Time t1 = stepOk(7);
  EXPECT_EQ(t1.toNSec() - t0.toNSec(), 7 * kStepNs);
  const ros::Time t2 = stepOk(1234);
  EXPECT_EQ(t2.toNSec() - t1.toNSec(), 1234 * kStepNs);
  EXPECT_EQ(stepOk(0), t2);
  EXPECT_TRUE(waitUntil([&] { return hasClock(clock_, t2); }));
  auto js = at(js_, t2);
  EXPECT_TRUE(js) << "no joint_states at the stepped time";
}

TEST_F(Node, WingCommandDrivesTheJointsAtTheCommandedRates) {
  reset();
  ASSERT_TRUE(commandAndWait(30, 10, 0.8)) << "wing joints never moved at -30 or +10 rad/s";
  std::vector<double> v = sampleVelocities(60);  // 0.3 s: several strokes
  ASSERT_FALSE(v.empty());
  const int down =
      std::count_if(v.begin(), v.end(), [](double x) { return std::abs(x + 30) < 0.5; });
  const int up = std::count_if(v.begin(), v.end(), [](double x) { return std::abs(x - 10) < 0.5; });
  EXPECT_GT(down, 0);
  EXPECT_GT(up, 0);
  EXPECT_GT(down + up, static_cast<int>(v.size() * 3 / 4));  // mostly at a commanded rate
  EXPECT_GE(*std::min_element(v.begin(), v.end()), -31.0);
  EXPECT_LE(*std::max_element(v.begin(), v.end()), 11.0);
  auto js = at(js_, stepOk(0));
  ASSERT_TRUE(js);
  for (double q : js->position) EXPECT_LE(std::abs(q), 0.9);

  // named joints, in any order
  wing_.publish(command({kRight, kLeft}, {20, 20}, {5, 5}, {0.6, 0.6}));
  bool seen = false;
  for (int i = 0; i < 400 && !seen; ++i) {
    auto s = at(js_, stepOk(5));
    ASSERT_TRUE(s);
    seen = std::abs(s->velocity[0] + 20) < 0.5 || std::abs(s->velocity[0] - 5) < 0.5;
  }
  EXPECT_TRUE(seen) << "named-joint command never took effect";
}

TEST_F(Node, DeterministicAcrossResetAndStep) {
  ASSERT_TRUE(commandAndWait(30, 10, 0.8));
  auto run = [&](std::vector<std::uint32_t> chunks) {
    reset();
    ros::Time t;
    for (std::uint32_t n : chunks) t = stepOk(n);
    EXPECT_EQ(t.toNSec(), 500 * kStepNs);
    return std::make_pair(at(odom_, t), at(js_, t));
  };
  auto a = run({500});
  auto b = run({500});
  auto c = run({123, 250, 127});  // same steps, other chunks
  for (const auto* r : {&b, &c}) {
    ASSERT_TRUE(a.first && a.second && r->first && r->second);
    const auto& p = a.first->pose.pose;
    const auto& q = r->first->pose.pose;
    EXPECT_EQ(p.position.x, q.position.x);
    EXPECT_EQ(p.position.y, q.position.y);
    EXPECT_EQ(p.position.z, q.position.z);
    EXPECT_EQ(p.orientation.x, q.orientation.x);
    EXPECT_EQ(p.orientation.w, q.orientation.w);
    EXPECT_EQ(a.first->twist.twist.linear.z, r->first->twist.twist.linear.z);
    EXPECT_EQ(a.first->twist.twist.angular.x, r->first->twist.twist.angular.x);
    EXPECT_EQ(a.second->position, r->second->position);
    EXPECT_EQ(a.second->velocity, r->second->velocity);
  }
  // the run did something: it moved and flapped
  EXPECT_NE(a.first->pose.pose.position.z, 10.0);
  EXPECT_NE(a.second->position[0], 0.0);
}

TEST_F(Node, StepAppliesItsWingCommandsBeforeTheFirstStep) {
  // whatever was commanded before (here 20/5 via the topic), a step request
  // carrying a command flies exactly as the same request after a reset
  auto run = [&](std::uint32_t steps) {
    reset();
    flapsim::Step s;
    s.request.steps = steps;
    s.request.creatures = {"flap_unit"};
    s.request.wing_commands = {command({}, {30, 30}, {10, 10}, {0.8, 0.8})};
    EXPECT_TRUE(flapsim_test::call("/flapsim/step", s));
    EXPECT_TRUE(s.response.success) << s.response.status_message;
    return std::make_pair(at(odom_, s.response.sim_time), at(js_, s.response.sim_time));
  };
  auto a = run(400);
  ASSERT_TRUE(commandAndWait(20, 5, 0.6));
  auto b = run(400);
  ASSERT_TRUE(a.first && a.second && b.first && b.second);
  EXPECT_EQ(a.first->pose.pose.position.z, b.first->pose.pose.position.z);
  EXPECT_EQ(a.first->pose.pose.orientation.x, b.first->pose.pose.orientation.x);
  EXPECT_EQ(a.second->position, b.second->position);
  EXPECT_EQ(a.second->velocity, b.second->velocity);
  // and the command acts from the first step: 5 steps in, the wings swing down at 30
  reset();
  flapsim::Step s;
  s.request.steps = 5;
  s.request.creatures = {"flap_unit"};
  s.request.wing_commands = {command({}, {30, 30}, {10, 10}, {0.8, 0.8})};
  ASSERT_TRUE(flapsim_test::call("/flapsim/step", s));
  auto js = at(js_, s.response.sim_time);
  ASSERT_TRUE(js);
  EXPECT_NEAR(js->velocity[0], -30.0, 0.5);
  EXPECT_NEAR(js->velocity[1], -30.0, 0.5);

  // refused as a whole: no step taken, earlier creatures not commanded either
  const ros::Time t0 = s.response.sim_time;
  struct Case {
    std::vector<std::string> creatures;
    std::vector<flapsim::WingCommand> commands;
    std::string expect;
  };
  const auto good = command({}, {20, 20}, {5, 5}, {0.6, 0.6});
  const Case cases[] = {
      {{"flap_unit"}, {}, "1 creatures but 0 wing_commands"},
      {{"flap_unit", "ghost"}, {good, good}, "unknown creature 'ghost'"},
      {{"flap_unit", "plate"}, {good, good}, "creature 'plate': 2 commands for 0 wing joints"},
      {{"flap_unit"}, {command({}, {20, -1}, {5, 5}, {0.6, 0.6})}, "downstroke rate"},
      {{"flap_unit"},
       {command({}, {20, 20}, {5, 5}, {0.6, 1.5})},
       "creature 'flap_unit': joint 'unit0_wing_right_joint': amplitude 1.5 rad does not fit"},
  };
  for (const Case& c : cases) {
    flapsim::Step bad;
    bad.request.steps = 10;
    bad.request.creatures = c.creatures;
    bad.request.wing_commands = c.commands;
    ASSERT_TRUE(flapsim_test::call("/flapsim/step", bad));
    EXPECT_FALSE(bad.response.success) << c.expect;
    EXPECT_NE(bad.response.status_message.find(c.expect), std::string::npos)
        << "'" << bad.response.status_message << "' lacks '" << c.expect << "'";
    EXPECT_EQ(bad.response.sim_time, t0);
  }
  // still the 30/10 stroke
  std::vector<double> v = sampleVelocities(40);
  ASSERT_FALSE(v.empty());
  EXPECT_GE(*std::min_element(v.begin(), v.end()), -31.0);
  EXPECT_GT(std::count_if(v.begin(), v.end(), [](double x) { return std::abs(x + 30) < 0.5; }), 0);
  EXPECT_EQ(std::count_if(v.begin(), v.end(), [](double x) { return std::abs(x + 20) < 0.5; }), 0);
}

/// The first message on `topic` as a new subscriber in a process of its own sees it (this
/// process's subscription already exists, and a node connects to a topic once).
using flapsim_test::firstMessageOf;

TEST_F(Node, ALateSubscriberOfAPausedNodeGetsTheCurrentStepAtOnce) {
  reset();
  const ros::Time t = stepOk(7);  // between two publication boundaries (every 10 steps)
  ASSERT_EQ(t.toNSec(), 7 * kStepNs);
  // rviz or a recorder connecting now, with no further step: it gets t = 0.007 s
  const std::string clock = firstMessageOf("/clock");
  const std::regex at_t("secs: +0\\s+nsecs: +7000000\\b");
  EXPECT_TRUE(std::regex_search(clock, at_t)) << clock;
  const std::string tf = firstMessageOf("/tf");
  for (const char* frame : {"flap_unit/unit0_body", "plate/plate", "flapsim/view"}) {
    EXPECT_NE(tf.find(std::string("child_frame_id: \"") + frame + "\""), std::string::npos)
        << frame << " missing in\n"
        << tf;
  }
  EXPECT_TRUE(std::regex_search(tf, at_t)) << tf;
}

TEST_F(Node, CreatureMarkersAreLatchedAndFollowSpawnAndDelete) {
  // latest latched creature_markers: the creatures (namespaces) and markers per creature
  auto latest = [&](std::map<std::string, int>* per_creature) {
    Recorder<visualization_msgs::MarkerArray> r;
    r.start(*nh_, "/flapsim/creature_markers");
    if (!waitUntil([&] { return !r.msgs.empty(); })) return false;
    per_creature->clear();
    const auto& markers = r.msgs.back()->markers;
    EXPECT_EQ(markers.at(0).action, visualization_msgs::Marker::DELETEALL);
    for (const auto& m : markers) {
      if (m.action != visualization_msgs::Marker::ADD) continue;
      ++(*per_creature)[m.ns];
      EXPECT_EQ(m.header.frame_id.rfind(m.ns + "/", 0), 0u) << m.header.frame_id;
    }
    return true;
  };
  std::map<std::string, int> per_creature;
  ASSERT_TRUE(latest(&per_creature));
  EXPECT_EQ(per_creature, (std::map<std::string, int>{{"flap_unit", 3}, {"plate", 1}}));

  flapsim::SpawnCreature s;
  s.request.name = "shown";
  s.request.urdf_file = sourcePath("urdf/plate.urdf");
  s.request.initial_pose.position.z = 5.0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  ASSERT_TRUE(s.response.success) << s.response.status_message;
  ASSERT_TRUE(latest(&per_creature));
  EXPECT_EQ(per_creature,
            (std::map<std::string, int>{{"flap_unit", 3}, {"plate", 1}, {"shown", 1}}));

  flapsim::DeleteCreature d;
  d.request.name = "shown";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
  ASSERT_TRUE(d.response.success) << d.response.status_message;
  ASSERT_TRUE(latest(&per_creature));
  EXPECT_EQ(per_creature, (std::map<std::string, int>{{"flap_unit", 3}, {"plate", 1}}));
}

TEST_F(Node, SpawnDeleteAndSpawnAgainUnderTheSameName) {
  Recorder<nav_msgs::Odometry> extra;
  extra.start(*nh_, "/extra/odom");
  flapsim::SpawnCreature s;
  s.request.name = "extra";
  s.request.urdf_file = sourcePath("urdf/plate.urdf");
  s.request.initial_pose.position.z = 5.0;  // orientation all zero: identity
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  ASSERT_TRUE(s.response.success) << s.response.status_message;
  EXPECT_TRUE(advertised("/extra/odom"));
  EXPECT_TRUE(advertised("/extra/joint_states"));
  EXPECT_TRUE(nh_->hasParam("/extra/robot_description"));
  ASSERT_TRUE(waitUntil([&] { return extra.connected(); }));
  const ros::Time t1 = stepOk(10);
  auto o1 = at(extra, t1);
  ASSERT_TRUE(o1);
  EXPECT_EQ(o1->child_frame_id, "extra/plate");
  EXPECT_LT(o1->pose.pose.position.z, 5.0);
  EXPECT_GT(o1->pose.pose.position.z, 4.99);

  flapsim::DeleteCreature d;
  d.request.name = "extra";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
  ASSERT_TRUE(d.response.success) << d.response.status_message;
  EXPECT_FALSE(advertised("/extra/odom"));
  EXPECT_FALSE(advertised("/extra/joint_states"));
  EXPECT_FALSE(nh_->hasParam("/extra/robot_description"));
  EXPECT_TRUE(waitUntil([&] { return !extra.connected(); })) << "still connected after delete";
  const ros::Time t2 = stepOk(10);
  EXPECT_TRUE(at(odom_, t2));  // the others go on

  s.request.urdf_file.clear();
  s.request.urdf_xml = readFile(sourcePath("urdf/plate.urdf"));
  s.request.initial_pose.position.z = 6.0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  ASSERT_TRUE(s.response.success) << s.response.status_message;
  EXPECT_TRUE(advertised("/extra/odom"));
  ASSERT_TRUE(waitUntil([&] { return extra.connected(); }));
  const ros::Time t3 = stepOk(10);
  auto o3 = at(extra, t3);
  ASSERT_TRUE(o3);
  EXPECT_LT(o3->pose.pose.position.z, 6.0);
  EXPECT_GT(o3->pose.pose.position.z, 5.99);

  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
  EXPECT_TRUE(d.response.success);
}

// A hinge damped beyond what an explicit 1 ms step keeps stable (I / (4 dt) = 0.0335 N m s/rad
// for this flap): spawned, its damping acting implicitly, named in the reply and in a warning.
TEST_F(Node, SpawnNamesTheJointValuesThatActImplicitly) {
  flapsim::SpawnCreature s;
  s.request.name = "damped";
  s.request.urdf_xml = R"(<robot name="d"><link name="world"/>
    <link name="flap"><inertial><origin xyz="0 0.1 0"/><mass value="0.01"/>
      <inertia ixx="3.4e-5" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="3.4e-5"/></inertial>
      <collision><origin xyz="0 0.1 0"/><geometry><box size="0.05 0.2 0.002"/></geometry></collision></link>
    <joint name="hinge" type="continuous"><parent link="world"/><child link="flap"/>
      <axis xyz="1 0 0"/><dynamics damping="1000"/></joint></robot>)";
  s.request.initial_pose.position.z = 5.0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  ASSERT_TRUE(s.response.success) << s.response.status_message;
  const std::string line =
      "creature 'damped', joint 'hinge': damping 1000 is more than an explicit step of 0.001 s "
      "keeps stable (0.0335): it acts implicitly, its motion faster than the step damped out";
  EXPECT_NE(s.response.status_message.find(line), std::string::npos) << s.response.status_message;
  EXPECT_TRUE(warned(line));
  flapsim::DeleteCreature d;
  d.request.name = "damped";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
  EXPECT_TRUE(d.response.success) << d.response.status_message;
}

// A mesh that cannot be had (an unknown package) is refused by name: the link, the URI and
// why; nothing is spawned. Boxes, cylinders, spheres and meshes are all simulated: a spawn
// names none of them as ignored.
TEST_F(Node, SpawnRefusesAnUnreadableMeshByName) {
  flapsim::SpawnCreature s;
  s.request.name = "shapes";
  s.request.urdf_xml = R"(<robot name="s">
    <link name="body"><inertial><mass value="0.01"/>
      <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
      <collision><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision></link>
    <link name="shell"><inertial><mass value="0.01"/>
      <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
      <collision><geometry><mesh filename="package://x/shell.stl"/></geometry></collision></link>
    <joint name="j2" type="fixed"><parent link="body"/><child link="shell"/></joint></robot>)";
  s.request.initial_pose.position.z = 40.0;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  EXPECT_FALSE(s.response.success);
  for (const std::string part :
       {"link 'shell'", "mesh 'package://x/shell.stl'", "unknown package"}) {
    EXPECT_NE(s.response.status_message.find(part), std::string::npos)
        << part << " not in: " << s.response.status_message;
  }
  flapsim::DeleteCreature d;
  d.request.name = "shapes";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
  EXPECT_FALSE(d.response.success);  // it was never spawned
}

TEST_F(Node, BadWingCommandsWarnAndKeepTheLastValidCommand) {
  reset();
  ASSERT_TRUE(commandAndWait(30, 10, 0.8));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    flapsim::WingCommand msg;
    std::string warning;
  };
  const Case cases[] = {
      {command({"no_such_joint"}, {30}, {10}, {0.8}), "no joint 'no_such_joint'"},
      {command({}, {30, 30}, {10}, {0.8, 0.8}), "differ in length"},
      {command({kLeft, kRight}, {30}, {10}, {0.8}), "2 joint_names but 1 strokes"},
      {command({}, {30}, {10}, {0.8}), "1 commands for 2 wing joints"},
      {command({}, {nan, 30}, {10, 10}, {0.8, 0.8}), "downstroke rate must be finite"},
      {command({}, {30, 30}, {10, -1}, {0.8, 0.8}), "upstroke rate must be finite and >= 0"},
      {command({kLeft}, {30}, {10}, {-0.8}), "amplitude must be finite and >= 0"},
  };
  for (const Case& c : cases) {
    wing_.publish(c.msg);
    EXPECT_TRUE(warned(c.warning)) << "no warning containing: " << c.warning;
  }
  // still flapping at the last valid rates
  std::vector<double> v = sampleVelocities(60);
  ASSERT_FALSE(v.empty());
  EXPECT_GT(std::count_if(v.begin(), v.end(), [](double x) { return std::abs(x + 30) < 0.5; }), 0);
  EXPECT_GT(std::count_if(v.begin(), v.end(), [](double x) { return std::abs(x - 10) < 0.5; }), 0);
  EXPECT_GE(*std::min_element(v.begin(), v.end()), -31.0);
  EXPECT_LE(*std::max_element(v.begin(), v.end()), 11.0);
}

TEST_F(Node, BadServiceCallsFailAndLeaveTheWorldAlone) {
  const ros::Time t0 = stepOk(0);
  auto fu0 = at(odom_, t0);
  auto pl0 = at(plate_odom_, t0);
  ASSERT_TRUE(fu0 && pl0);

  struct SpawnCase {
    std::string name, xml, file, expect;
    double z;
  };
  const SpawnCase spawns[] = {
      {"plate", "", sourcePath("urdf/plate.urdf"), "'plate' is taken", 1.0},
      {"broken", "<robot name='b'><link name='a'>", "", "broken", 1.0},
      {"nofile", "", "/nonexistent/x.urdf", "/nonexistent/x.urdf", 1.0},
      {"a b", "", sourcePath("urdf/plate.urdf"), "'a b'", 1.0},
      {"nourdf", "", "", "exactly one of model_xml (urdf_xml) and urdf_file", 1.0},
      {"nanpose", "", sourcePath("urdf/plate.urdf"), "position must be finite",
       std::numeric_limits<double>::quiet_NaN()},
  };
  for (const SpawnCase& c : spawns) {
    flapsim::SpawnCreature s;
    s.request.name = c.name;
    s.request.urdf_xml = c.xml;
    s.request.urdf_file = c.file;
    s.request.initial_pose.position.z = c.z;
    ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s)) << c.name;
    EXPECT_FALSE(s.response.success) << c.name;
    EXPECT_NE(s.response.status_message.find(c.expect), std::string::npos)
        << c.name << ": '" << s.response.status_message << "' lacks '" << c.expect << "'";
  }
  EXPECT_TRUE(warned("spawn refused: creature name 'plate' is taken"));
  flapsim::DeleteCreature d;
  d.request.name = "ghost";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
  EXPECT_FALSE(d.response.success);
  EXPECT_NE(d.response.status_message.find("'ghost'"), std::string::npos)
      << d.response.status_message;

  // the world is as it was: same time, same creatures, same state
  odom_.clear();
  plate_odom_.clear();
  const ros::Time t1 = stepOk(0);
  EXPECT_EQ(t1, t0);
  auto fu1 = at(odom_, t1);
  auto pl1 = at(plate_odom_, t1);
  ASSERT_TRUE(fu1 && pl1);
  EXPECT_EQ(fu1->pose.pose.position.z, fu0->pose.pose.position.z);
  EXPECT_EQ(fu1->twist.twist.linear.z, fu0->twist.twist.linear.z);
  EXPECT_EQ(pl1->pose.pose.position.x, pl0->pose.pose.position.x);
  EXPECT_EQ(pl1->pose.pose.orientation.w, pl0->pose.pose.orientation.w);
  for (const char* gone : {"/broken/odom", "/nofile/odom", "/nanpose/odom", "/nourdf/odom"}) {
    EXPECT_FALSE(advertised(gone)) << gone;
  }

  // step while running
  unpause();
  EXPECT_TRUE(waitUntil([&] { return !clock_.msgs.empty() && clock_.msgs.back()->clock > t1; }));
  flapsim::Step s = step(10);
  EXPECT_FALSE(s.response.success);
  EXPECT_NE(s.response.status_message.find("pause"), std::string::npos)
      << s.response.status_message;
  EXPECT_TRUE(warned("step refused"));
  pause();
  EXPECT_TRUE(stepOk(1) > t1);  // alive, paused, stepping
}

TEST_F(Node, PauseStopsTheClock) {
  const ros::Time t0 = stepOk(0);
  clock_.clear();  // older messages may carry later times (before a reset)
  unpause();
  ASSERT_TRUE(waitUntil([&] { return !clock_.msgs.empty() && clock_.msgs.back()->clock > t0; }))
      << "/clock did not advance while running";
  pause();
  const ros::Time tp = stepOk(0);  // paused: no steps in between
  EXPECT_GE(tp, clock_.msgs.back()->clock);
  EXPECT_GT(tp, t0);
  // Wait a wall second for any clock past tp: none may come.
  const bool advanced = waitUntil(
      [&] {
        return std::any_of(clock_.msgs.begin(), clock_.msgs.end(),
                           [&](const auto& m) { return m->clock > tp; });
      },
      1.0);
  EXPECT_FALSE(advanced) << "/clock moved on after flapsim/pause";
  EXPECT_EQ(stepOk(3).toNSec(), tp.toNSec() + 3 * kStepNs);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_flapsim_node");
  return RUN_ALL_TESTS();
}
