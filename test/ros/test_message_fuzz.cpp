// A seeded fuzzer over the messages a user sends flapsim_node (WingCommand, Step, Spawn),
// through the adapters and a world, without a master: every message is either accepted and
// the world steps on with a finite state, or refused with an InputError naming its cause,
// leaving the world as it was. Same seed, same messages: a failure replays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "flapsim/world.h"
#include "flapsim_ros/conversions.h"
#include "flapsim_ros/params.h"

namespace {

using flapsim_ros::WingCommandRequest;

const double kNan = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
// Numbers a careless or hostile user sends; valid ones among them.
const double kNumbers[] = {kNan, kInf, -kInf, -1.0, 0.0, 1e300, -1e300, 1e-300, 1e5, 1e6,
                           0.3,  0.8,  1.39,  1.41, 10,  40,    200,    250,    1e4, 3.0};
// Joint names: the flap unit's wings, a non-wing, unknown and odd names.
const char* const kJoints[] = {"unit0_wing_left_joint",   "unit0_wing_right_joint",
                               "unit0_wing_left_joint",   "unit0_body",
                               "no_such_joint",           "",
                               "unit0_wing_left_joint\n", "../../etc"};
const char* const kNames[] = {"c", "d", "ghost", "", "c", "a b", "9x", "d"};

class Fuzzer {
 public:
  explicit Fuzzer(std::uint64_t seed) : rng_(seed) {}
  size_t pick(size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }
  double number() {
    if (pick(3) == 0) return std::uniform_real_distribution<double>(-50, 300)(rng_);
    return kNumbers[pick(std::size(kNumbers))];
  }
  std::vector<double> numbers(size_t n) {
    std::vector<double> v(n);
    for (double& x : v) x = number();
    return v;
  }

  // A valid command for the flap unit's two wings, then up to three mutations: a number
  // from the list, an array one longer or shorter, a joint name added.
  flapsim::WingCommand wingCommand() {
    const double rates[] = {10, 40, 200, 250}, amplitudes[] = {0.3, 0.8, 1.39};
    flapsim::WingCommand m;
    if (pick(2)) m.joint_names = {kJoints[0], kJoints[1]};
    for (int k = 0; k < 2; ++k) {
      m.downstroke_rate.push_back(rates[pick(4)]);
      m.upstroke_rate.push_back(rates[pick(4)]);
      m.amplitude.push_back(amplitudes[pick(3)]);
    }
    std::vector<double>* arrays[] = {&m.downstroke_rate, &m.upstroke_rate, &m.amplitude,
                                     &m.feather_angle};
    for (size_t i = 0, n = pick(4); i < n; ++i) {
      std::vector<double>& a = *arrays[pick(4)];
      switch (pick(3)) {
        case 0:
          if (!a.empty()) a[pick(a.size())] = kNumbers[pick(std::size(kNumbers))];
          break;
        case 1:
          if (pick(2) && !a.empty()) {
            a.pop_back();
          } else {
            a.push_back(number());
          }
          break;
        default:
          m.joint_names.push_back(kJoints[pick(std::size(kJoints))]);
          break;
      }
    }
    return m;
  }

  geometry_msgs::Pose pose() {
    geometry_msgs::Pose p;
    p.position.x = pick(2) ? number() : 0.0;
    p.position.z = pick(2) ? number() : 5.0;
    p.orientation.w = pick(2) ? number() : 0.0;
    p.orientation.x = pick(2) ? number() : 0.0;
    p.orientation.y = pick(4) ? 0.0 : number();
    p.orientation.z = pick(4) ? 0.0 : number();
    return p;
  }
  geometry_msgs::Twist twist() {
    geometry_msgs::Twist t;
    if (pick(2)) t.linear.x = number();
    if (pick(2)) t.linear.z = number();
    if (pick(3) == 0) t.angular.z = number();
    return t;
  }

 private:
  std::mt19937_64 rng_;
};

bool finite(const flapsim::CreatureState& s) {
  for (const auto& p : s.link_poses) {
    if (!p.position.allFinite() || !p.orientation.coeffs().allFinite()) return false;
  }
  for (const auto& t : s.link_twists) {
    if (!t.linear.allFinite() || !t.angular.allFinite()) return false;
  }
  return true;
}

flapsim::CreatureModelPtr flapUnit() {
  static const flapsim::CreatureModelPtr m =
      flapsim::loadCreatureModel(std::string(FLAPSIM_SOURCE_DIR) + "/urdf/flap_unit.urdf");
  return m;
}

// WingCommand messages as the topic callback handles them (fromMsg, then the world).
TEST(MessageFuzz, WingCommandsAreAcceptedOrRefusedByNameAndTheWorldStaysFinite) {
  flapsim::World w;
  w.spawn("c", flapUnit(), flapsim::Pose{flapsim::Vec3(0, 0, 5), flapsim::Quat::Identity()});
  Fuzzer f(15);
  int accepted = 0, refused = 0;
  flapsim::StrokeCommand in_force;  // of the left wing
  for (int i = 0; i < 3000 && !::testing::Test::HasFailure(); ++i) {
    const flapsim::WingCommand msg = f.wingCommand();
    try {
      const WingCommandRequest r = flapsim_ros::fromMsg(msg);
      w.setWingCommands("c", r.joints, r.strokes);
      ++accepted;
      in_force = w.wingCommand("c", "unit0_wing_left_joint");
    } catch (const flapsim::InputError& e) {
      ++refused;
      EXPECT_GT(std::string(e.what()).size(), 10u) << "message " << i;
    }
    // A refused command keeps the one in force.
    EXPECT_EQ(w.wingCommand("c", "unit0_wing_left_joint").downstroke_rate, in_force.downstroke_rate)
        << "message " << i;
    w.step(2);
    ASSERT_TRUE(finite(w.state("c"))) << "message " << i;
  }
  std::printf("wing command fuzz: %d accepted, %d refused\n", accepted, refused);
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, 0);
}

// flapsim/step wing command lists (stepCommands converts, the world checks all or nothing).
TEST(MessageFuzz, StepRequestsAreCheckedAllOrNothing) {
  flapsim::World w;
  for (const char* name : {"c", "d"}) w.spawn(name, flapUnit(), flapsim::Pose());
  const std::string wing = flapUnit()->joints[flapUnit()->wing_joints[0]].name;
  Fuzzer f(16);
  int accepted = 0, refused = 0;
  for (int i = 0; i < 3000 && !::testing::Test::HasFailure(); ++i) {
    std::vector<std::string> creatures;
    std::vector<flapsim::WingCommand> commands;
    const size_t n = f.pick(4);
    for (size_t k = 0; k < n; ++k) creatures.push_back(kNames[f.pick(std::size(kNames))]);
    for (size_t k = 0, m = f.pick(4) == 0 ? f.pick(4) : n; k < m; ++k) {
      commands.push_back(f.wingCommand());
    }
    const double before_c = w.wingCommand("c", wing).downstroke_rate;
    const double before_d = w.wingCommand("d", wing).downstroke_rate;
    try {
      const auto requests = flapsim_ros::stepCommands(creatures, commands);
      EXPECT_EQ(requests.size(), creatures.size());
      w.setWingCommands(requests);
      ++accepted;
    } catch (const flapsim::InputError& e) {
      ++refused;
      const std::string what = e.what();
      // Names the creature at fault, or says what does not match; commands nobody.
      EXPECT_TRUE(what.find("creature '") != std::string::npos ||
                  what.find("step request has") != std::string::npos)
          << "request " << i << ": " << what;
      EXPECT_EQ(w.wingCommand("c", wing).downstroke_rate, before_c) << "request " << i;
      EXPECT_EQ(w.wingCommand("d", wing).downstroke_rate, before_d) << "request " << i;
    }
  }
  std::printf("step request fuzz: %d accepted, %d refused\n", accepted, refused);
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, 0);
}

// flapsim/spawn poses, twists and names (fromMsg, validateCreatureName, then the world).
TEST(MessageFuzz, SpawnRequestsAreAcceptedOrRefusedByName) {
  flapsim::World w;
  Fuzzer f(17);
  int accepted = 0, refused = 0;
  for (int i = 0; i < 3000 && !::testing::Test::HasFailure(); ++i) {
    const std::string name = kNames[f.pick(std::size(kNames))];
    try {
      const std::string err = flapsim_ros::validateCreatureName(name);
      if (!err.empty()) throw flapsim::InputError(err);
      w.spawn(name, flapUnit(), flapsim_ros::fromMsg(f.pose()), flapsim_ros::fromMsg(f.twist()));
      ++accepted;
      w.step(3);
      ASSERT_TRUE(finite(w.state(name))) << "request " << i;
      w.remove(name);
    } catch (const flapsim::InputError& e) {
      ++refused;
      EXPECT_NE(std::string(e.what()).find("creature"), std::string::npos)
          << "request " << i << ": " << e.what();
    }
    ASSERT_TRUE(w.creatureNames().empty()) << "request " << i;
  }
  std::printf("spawn fuzz: %d accepted, %d refused\n", accepted, refused);
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, 0);
}

}  // namespace
