// flapsim_node's guards through its ROS interface (rostest: see node_reliability.test): the
// divergence watchdog's report, the step cap, spawn file roots and the warning limiter.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <unistd.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/ApplyWrench.h"
#include "flapsim/ClearWrenches.h"
#include "flapsim/DeleteCreature.h"
#include "flapsim/GetState.h"
#include "flapsim/SetState.h"
#include "flapsim/SpawnCreature.h"
#include "flapsim/Step.h"
#include "flapsim/WingCommand.h"
#include "flapsim_ros/urdf_source.h"
#include "recorder.h"
#include "service_call.h"
#include "wait_for.h"

namespace {

constexpr double kWait = 20.0;  // s (wall), upper bound of any wait

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool waitUntil(const std::function<bool()>& done, double timeout = kWait) {
  return flapsim_test::waitFor(done, timeout);
}

using flapsim_test::Recorder;

class NodeGuards : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nh_ = std::make_unique<ros::NodeHandle>();
    ASSERT_TRUE(ros::service::waitForService("/flapsim/step", ros::Duration(60)));
    rosout_.start(*nh_, "/rosout");
    diagnostics_.start(*nh_, "/diagnostics");
    odom_.start(*nh_, "/low/odom");
    high_odom_.start(*nh_, "/high/odom");
    wing_ = nh_->advertise<flapsim::WingCommand>("/low/wing_command", 1000);
    ASSERT_TRUE(waitUntil([] {
      return rosout_.connected() && diagnostics_.connected() && odom_.connected() &&
             high_odom_.connected() && wing_.getNumSubscribers() > 0;
    }));
  }
  static void TearDownTestSuite() {
    rosout_ = {};
    diagnostics_ = {};
    odom_ = {};
    high_odom_ = {};
    wing_.shutdown();
    nh_.reset();
  }
  static flapsim::Step step(std::uint32_t n) {
    flapsim::Step s;
    s.request.steps = n;
    EXPECT_TRUE(flapsim_test::call("/flapsim/step", s));
    return s;
  }
  // Messages /flapsim logged at `level` that contain `text`.
  static int logged(std::uint8_t level, const std::string& text) {
    return static_cast<int>(std::count_if(rosout_.msgs.begin(), rosout_.msgs.end(), [&](auto& m) {
      return m->name == "/flapsim" && m->level == level && m->msg.find(text) != std::string::npos;
    }));
  }
  static const nav_msgs::Odometry* odomAt(Recorder<nav_msgs::Odometry>& r, std::uint64_t ns) {
    const nav_msgs::Odometry* found = nullptr;
    waitUntil([&] {
      for (const auto& m : r.msgs) {
        if (m->header.stamp.toNSec() == ns) found = m.get();
      }
      return found != nullptr;
    });
    return found;
  }

  static std::unique_ptr<ros::NodeHandle> nh_;
  static Recorder<rosgraph_msgs::Log> rosout_;
  static Recorder<diagnostic_msgs::DiagnosticArray> diagnostics_;
  static Recorder<nav_msgs::Odometry> odom_, high_odom_;
  static ros::Publisher wing_;
};

std::unique_ptr<ros::NodeHandle> NodeGuards::nh_;
Recorder<rosgraph_msgs::Log> NodeGuards::rosout_;
Recorder<diagnostic_msgs::DiagnosticArray> NodeGuards::diagnostics_;
Recorder<nav_msgs::Odometry> NodeGuards::odom_, NodeGuards::high_odom_;
ros::Publisher NodeGuards::wing_;

// In vacuum 'high' falls from rest and passes 2 m/s at step 204 (9.81 x 0.204); 'low',
// thrown up at 1 m/s, passes it at step 306. Each is logged once, as an error naming it,
// the step and the quantity, and shown on /diagnostics; until then each moves freely.
TEST_F(NodeGuards, AFrozenCreatureIsReportedOnceAndTheOthersGoOn) {
  const flapsim::Step s = step(300);
  ASSERT_TRUE(s.response.success) << s.response.status_message;
  const std::string high =
      "creature 'high' diverged at step 204 (t = 0.204000000 s): link "
      "'plate' moves at 2.001 m/s (max_speed 2 m/s)";
  EXPECT_TRUE(waitUntil([&] { return logged(rosgraph_msgs::Log::ERROR, high) == 1; }));
  const nav_msgs::Odometry* h = odomAt(high_odom_, 300000000);
  const nav_msgs::Odometry* l = odomAt(odom_, 300000000);
  ASSERT_TRUE(h && l);
  EXPECT_NEAR(h->twist.twist.linear.z, -9.81 * 0.203, 1e-9);  // frozen at step 203
  EXPECT_NEAR(l->twist.twist.linear.z, 1.0 - 9.81 * 0.300, 1e-9);
  EXPECT_TRUE(waitUntil([] {
    const auto& d = diagnostics_.msgs;
    if (d.empty()) return false;
    bool high_error = false, low_ok = false;
    for (const auto& st : d.back()->status) {
      high_error |= st.name == "flapsim: high" && st.level == st.ERROR &&
                    st.message.find("diverged at step 204") != std::string::npos;
      low_ok |= st.name == "flapsim: low" && st.level == st.OK;
    }
    return high_error && low_ok;
  }));

  ASSERT_TRUE(step(100).response.success);
  EXPECT_TRUE(waitUntil([&] {
    return logged(rosgraph_msgs::Log::ERROR, "creature 'low' diverged at step 306") == 1;
  }));
  // No second report of 'high' in a wall second.
  EXPECT_FALSE(
      waitUntil([&] { return logged(rosgraph_msgs::Log::ERROR, "'high' diverged") > 1; }, 1.0));
}

// steps: 4294967295 held the node (pause, spawn, /clock, SIGINT) for hours.
TEST_F(NodeGuards, StepsOverTheCapAreRefusedByName) {
  const ros::Time before = step(0).response.sim_time;
  const flapsim::Step s = step(4294967295u);
  EXPECT_FALSE(s.response.success);
  EXPECT_EQ(s.response.status_message,
            "steps 4294967295 is over max_steps_per_call 1000 (parameter ~max_steps_per_call): "
            "no step taken");
  EXPECT_EQ(s.response.sim_time, before);
}

// The last command for a creature named twice used to win silently.
TEST_F(NodeGuards, ACreatureNamedTwiceInOneStepIsRefused) {
  flapsim::Step s;
  s.request.steps = 1;
  s.request.creatures = {"low", "low"};
  s.request.wing_commands.resize(2);
  ASSERT_TRUE(flapsim_test::call("/flapsim/step", s));
  EXPECT_FALSE(s.response.success);
  EXPECT_EQ(s.response.status_message,
            "wing commands refused, no step taken: creature 'low' is named twice");
}

// Missing files, directories, files outside the roots: one text, so that any node on the
// graph cannot probe the host's files; a file under a root spawns.
TEST_F(NodeGuards, RefusedSpawnFilesShareOneText) {
  const std::string urdf = std::string(FLAPSIM_SOURCE_DIR) + "/urdf";
  // A readable URDF outside the roots (the temporary directory).
  std::string outside = (std::filesystem::temp_directory_path() / "flapsim_XXXXXX").string();
  const int fd = ::mkstemp(&outside[0]);
  ASSERT_GE(fd, 0);
  ::close(fd);
  std::ofstream(outside) << readText(urdf + "/plate.urdf");
  std::vector<std::string> roots;  // the reply names them
  ASSERT_TRUE(ros::param::get("/flapsim/urdf_roots", roots));
  for (const std::string& path :
       {urdf + "/missing.urdf", urdf, outside, std::string("/dev/zero")}) {
    flapsim::SpawnCreature s;
    s.request.name = "probe";
    s.request.urdf_file = path;
    ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
    EXPECT_FALSE(s.response.success) << path;
    EXPECT_EQ(s.response.status_message, flapsim_ros::refusedUrdfFileMessage(path, roots, ""));
  }
  ::unlink(outside.c_str());
  flapsim::SpawnCreature ok;
  ok.request.name = "probe";
  ok.request.urdf_file = urdf + "/plate.urdf";
  ok.request.initial_pose.position.x = 20;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", ok));
  EXPECT_TRUE(ok.response.success) << ok.response.status_message;
}

// A new unknown joint name in each command was a new cause: one warning per message.
TEST_F(NodeGuards, DistinctBadCommandsAreOneWarning) {
  for (int i = 0; i < 100; ++i) {
    flapsim::WingCommand c;
    c.joint_names = {"j" + std::to_string(i)};
    c.downstroke_rate = {10};
    c.upstroke_rate = {10};
    c.amplitude = {0.5};
    wing_.publish(c);
  }
  const std::string text = "rejected wing command for 'low': creature 'low': no joint 'j";
  EXPECT_TRUE(waitUntil([&] { return logged(rosgraph_msgs::Log::WARN, text) == 1; }));
  EXPECT_FALSE(waitUntil([&] { return logged(rosgraph_msgs::Log::WARN, text) > 1; }, 1.0));
}

// Issue 27, case 7: 3,000 get_state calls with distinct unknown names wrote 3,000 warnings
// (the name was part of the cause); the same for set_state, apply_wrench, clear_wrenches.
TEST_F(NodeGuards, UnknownNamesAreOneWarningPerService) {
  for (int i = 0; i < 300; ++i) {
    const std::string name = "ghost" + std::to_string(i);
    flapsim::GetState g;
    g.request.name = name;
    flapsim::SetState st;
    st.request.name = name;
    st.request.pose.orientation.w = 1;
    flapsim::ApplyWrench a;
    a.request.name = name;
    flapsim::ClearWrenches c;
    c.request.name = name;
    ASSERT_TRUE(flapsim_test::call("/flapsim/get_state", g) &&
                flapsim_test::call("/flapsim/set_state", st) &&
                flapsim_test::call("/flapsim/apply_wrench", a) &&
                flapsim_test::call("/flapsim/clear_wrenches", c));
    ASSERT_FALSE(g.response.success || st.response.success || a.response.success ||
                 c.response.success);
  }
  for (const std::string service : {"get_state", "set_state", "apply_wrench", "clear_wrenches"}) {
    const std::string text = service + " refused";
    EXPECT_TRUE(waitUntil([&] { return logged(rosgraph_msgs::Log::WARN, text) >= 1; })) << text;
    EXPECT_EQ(logged(rosgraph_msgs::Log::WARN, text), 1) << text;
  }
}

// Issue 27, case 6: a 64 MiB urdf_xml was parsed (7 s, +133 MB, kept again for the latched
// robot_description); the 16 MiB limit was the urdf_file's only.
TEST_F(NodeGuards, AUrdfXmlOverTheFileLimitIsRefusedByName) {
  flapsim::SpawnCreature s;
  s.request.name = "huge";
  s.request.urdf_xml = "<robot name='huge'>" + std::string((16u << 20) - 18, ' ') + "</robot>";
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  EXPECT_FALSE(s.response.success);
  EXPECT_EQ(s.response.status_message,
            "spawn request 'huge': 16777225 bytes, over the limit of 16 MiB");
  flapsim::GetState g;
  g.request.name = "huge";
  ASSERT_TRUE(flapsim_test::call("/flapsim/get_state", g));
  EXPECT_FALSE(g.response.success);  // nothing was spawned
}

// A link of 1,000 boxes is refused by the limit on shapes per link (it froze the node for
// hours: the union volume cost n^4), an element urdfdom drops is refused naming the link, a
// link simulated from its <visual> says so in the reply; the world keeps its creatures.
TEST_F(NodeGuards, ShapeLimitsAndDroppedElementsAreRefusedByName) {
  const std::string inertial =
      R"(<inertial><mass value="0.1"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0")"
      R"( izz="1e-3"/></inertial>)";
  std::string pile = "<robot name='pile'><link name='heap'>" + inertial;
  for (int k = 0; k < 1000; ++k) {
    pile += "<collision><origin xyz='" + std::to_string(0.013 * (k % 37)) + " " +
            std::to_string(0.017 * (k % 23)) + " " + std::to_string(0.011 * (k % 19)) +
            "'/><geometry><box size='0.05 0.04 0.03'/></geometry></collision>";
  }
  pile += "</link></robot>";
  flapsim::SpawnCreature s;
  s.request.name = "pile";
  s.request.urdf_xml = pile;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  EXPECT_FALSE(s.response.success);
  EXPECT_EQ(s.response.status_message,
            "spawn request 'pile': link 'heap' has 1000 shapes (<collision> or <visual>), over the "
            "limit of 256 per link");
  s.request.name = "dropped";
  s.request.urdf_xml = "<robot name='d'><link name='wing'>" + inertial +
                       "<collision><geometry><box size='0.1 0.1 0.1'/></geometry></collision>"
                       "<collision><geometry><sphere/></geometry></collision></link></robot>";
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  EXPECT_FALSE(s.response.success);
  EXPECT_NE(s.response.status_message.find(
                "the URDF parser dropped an element it could not read: Sphere shape must have a "
                "radius attribute; Could not parse collision element for Link [wing]"),
            std::string::npos)
      << s.response.status_message;
  for (const char* name : {"pile", "dropped"}) {
    flapsim::GetState g;
    g.request.name = name;
    ASSERT_TRUE(flapsim_test::call("/flapsim/get_state", g));
    EXPECT_FALSE(g.response.success) << name;  // nothing was spawned
  }
  s.request.name = "seen";
  s.request.urdf_xml = "<robot name='v'><link name='shell'>" + inertial +
                       "<visual><geometry><box size='0.1 0.1 0.1'/></geometry></visual>"
                       "</link></robot>";
  s.request.initial_pose.position.x = 40;
  s.request.initial_pose.position.z = 5;
  s.request.initial_pose.orientation.w = 1;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s));
  EXPECT_TRUE(s.response.success);
  EXPECT_EQ(s.response.status_message,
            "spawned 'seen': 1 links, 0 wing joints; creature 'seen', link 'shell' has no "
            "<collision>: its <visual> shapes are simulated (contact and air)");
  flapsim::DeleteCreature d;
  d.request.name = "seen";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
  EXPECT_TRUE(d.response.success);
  flapsim::GetState g;
  g.request.name = "low";
  ASSERT_TRUE(flapsim_test::call("/flapsim/get_state", g));
  EXPECT_TRUE(g.response.success);
}

// A controller that falls behind (its command answers a state 0.5 s of sim time old, by its
// stamp) is named on /diagnostics and in the log; a timely command clears it (it was silent).
TEST_F(NodeGuards, ALaggingControllerIsNamedOnDiagnostics) {
  flapsim::SpawnCreature s;
  s.request.name = "lagger";
  s.request.urdf_file = std::string(FLAPSIM_SOURCE_DIR) + "/urdf/plate.urdf";
  s.request.initial_pose.position.x = 60;
  s.request.initial_pose.position.z = 0.0011;  // resting on the ground (max_speed is 2 m/s)
  s.request.initial_pose.orientation.w = 1;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", s) && s.response.success);
  ros::Publisher commands = nh_->advertise<flapsim::WingCommand>("/lagger/wing_command", 10);
  ASSERT_TRUE(waitUntil([&] { return commands.getNumSubscribers() > 0; }));
  const flapsim::Step stepped = step(1000);
  const ros::Time now(stepped.response.sim_time);
  // Whether lagger's latest status on /diagnostics says `text` (waited for).
  auto status = [&](const std::string& text) {
    return waitUntil([&] {
      std::string latest;
      for (const auto& a : diagnostics_.msgs) {
        for (const auto& st : a->status) {
          if (st.name == "flapsim: lagger") latest = st.message;
        }
      }
      return latest.find(text) != std::string::npos;
    });
  };
  flapsim::WingCommand late;  // a plate has no wings: the empty command is valid
  late.header.stamp = now - ros::Duration(0.5);
  commands.publish(late);
  EXPECT_TRUE(status("wing commands lag: the last answered a state 0.5"));
  EXPECT_TRUE(waitUntil([] {
    return logged(rosgraph_msgs::Log::WARN,
                  "creature 'lagger': its wing command answers a state 0.5") == 1;
  }));
  flapsim::WingCommand timely;
  timely.header.stamp = now;
  commands.publish(timely);
  EXPECT_TRUE(status("running"));
  flapsim::DeleteCreature d;
  d.request.name = "lagger";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", d));
}

// Smaller items of issue 27: set_state to z = -0.5 threw a creature to 4.2 m without a word;
// dynamic_reconfigure's clamps (density 1e9 -> 1e5) were logged by no one.
TEST_F(NodeGuards, ASetStateBelowTheGroundAndAClampedReconfigureAreSaid) {
  flapsim::SpawnCreature spawn;
  spawn.request.name = "sunk";
  spawn.request.urdf_file = std::string(FLAPSIM_SOURCE_DIR) + "/urdf/plate.urdf";
  spawn.request.initial_pose.position.x = -20;
  spawn.request.initial_pose.position.z = 1;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", spawn) && spawn.response.success);
  flapsim::SetState st;
  st.request.name = "sunk";
  st.request.pose.position.x = -20;
  st.request.pose.position.z = -0.5;
  st.request.pose.orientation.w = 1;
  ASSERT_TRUE(flapsim_test::call("/flapsim/set_state", st));
  EXPECT_TRUE(st.response.success);
  EXPECT_NE(st.response.status_message.find(
                "; its collision shapes reach 0.501 m below the ground (z = 0)"),
            std::string::npos)
      << st.response.status_message;
  st.request.pose.position.z = 0.5;  // above it: nothing to say
  ASSERT_TRUE(flapsim_test::call("/flapsim/set_state", st));
  EXPECT_EQ(st.response.status_message.find("below the ground"), std::string::npos);
  EXPECT_EQ(spawn.response.status_message.find("below the ground"), std::string::npos);
  flapsim::DeleteCreature del;
  del.request.name = "sunk";
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", del));
  // A spawn below the ground is done as asked and said, as set_state is (it was silent).
  spawn.request.initial_pose.position.z = -0.3;
  ASSERT_TRUE(flapsim_test::call("/flapsim/spawn", spawn));
  EXPECT_TRUE(spawn.response.success);
  EXPECT_NE(spawn.response.status_message.find(
                "; its collision shapes reach 0.301 m below the ground (z = 0)"),
            std::string::npos)
      << spawn.response.status_message;
  ASSERT_TRUE(flapsim_test::call("/flapsim/delete", del));

  dynamic_reconfigure::Reconfigure r;
  dynamic_reconfigure::DoubleParameter d;
  d.name = "density";
  d.value = 1e9;
  r.request.config.doubles.push_back(d);
  ASSERT_TRUE(flapsim_test::call("/flapsim/set_parameters", r));
  EXPECT_TRUE(waitUntil([&] {
    return logged(rosgraph_msgs::Log::WARN,
                  "reconfigure: density = 100000, the top of its range [0, 100000]") == 1;
  }));
}

// The node's resident memory (kB), found through the master and its getPid call.
long nodeRssKb() {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = "/flapsim";
  if (!ros::master::execute("lookupNode", args, result, payload, true)) return -1;
  std::string uri = payload;
  const std::string host_port = uri.substr(uri.find("//") + 2);
  const std::string host = host_port.substr(0, host_port.find(':'));
  const int port = std::stoi(host_port.substr(host_port.find(':') + 1));
  XmlRpc::XmlRpcClient client(host.c_str(), port, "/");
  XmlRpc::XmlRpcValue pid_args, pid_result;
  pid_args[0] = ros::this_node::getName();
  if (!client.execute("getPid", pid_args, pid_result)) return -1;
  const int pid = pid_result[2];
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

// roscpp's node handle kept a weak pointer to every publisher and subscriber it made: each
// spawn and delete of a creature held about 0.7 KB (3,000 cycles: +2.2 MB).
TEST_F(NodeGuards, SpawnDeleteChurnDoesNotGrowTheNode) {
  ros::ServiceClient spawn = nh_->serviceClient<flapsim::SpawnCreature>("/flapsim/spawn", true);
  ros::ServiceClient remove = nh_->serviceClient<flapsim::DeleteCreature>("/flapsim/delete", true);
  const std::string urdf =
      "<robot name='p'><link name='plate'><inertial><mass value='0.01'/>"
      "<inertia ixx='1e-5' iyy='1e-5' izz='2e-5' ixy='0' ixz='0' iyz='0'/>"
      "</inertial><collision><geometry><box size='0.2 0.2 0.002'/>"
      "</geometry></collision></link></robot>";
  long after_100 = -1;
  for (int i = 1; i <= 3000; ++i) {
    flapsim::SpawnCreature s;
    s.request.name = "churn";
    s.request.urdf_xml = urdf;
    s.request.initial_pose.position.z = 50;
    ASSERT_TRUE(spawn.call(s) && s.response.success) << i << ": " << s.response.status_message;
    flapsim::DeleteCreature d;
    d.request.name = "churn";
    ASSERT_TRUE(remove.call(d) && d.response.success) << i;
    if (i == 100) after_100 = nodeRssKb();
  }
  const long after_3000 = nodeRssKb();
  ASSERT_GT(after_100, 0);
  std::printf("flapsim_node RSS: %ld kB after 100 cycles, %ld kB after 3000\n", after_100,
              after_3000);
  EXPECT_LT(after_3000 - after_100, 200);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_reliability");
  return RUN_ALL_TESTS();
}
