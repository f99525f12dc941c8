// ExternalWrench::start_time (gazebo_msgs/ApplyBodyWrench's start_time): a wrench applied
// ahead acts from the first step that starts at or after its start time, as if it had been
// applied by a call made when the world got there; a start time already passed means the next
// step; its duration counts from its start; clearWrenches and reset drop it while it waits.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "dynamics/momentum.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::bitIdentical;
using test::loadUrdf;

constexpr double kStart = 0.25, kEnd = 0.5;  // s

// A torque on the left wing of a beating flap unit in open sky (no force: the point plays no
// part, so the wrench is the same to the bit whenever it is applied).
ExternalWrench wingTorque() {
  ExternalWrench w;
  w.link = "unit0_wing_left";
  w.torque = Vec3(0.002, -0.001, 0.003);
  w.duration = 0.1;
  return w;
}

WorldParams skyOfStep(double step_size) {
  WorldParams p = test::openSky();
  p.step_size = step_size;
  return p;
}

void spawnBeating(World& w) {
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 3));
  w.setWingCommands("u", {}, {{40, 10, 0.8}, {30, 12, 0.7}});
}

// No air, no gravity: a plate at rest stays at rest, its momentum exactly zero.
WorldParams stillVacuum() {
  WorldParams p = test::vacuum();
  p.gravity = Vec3::Zero();
  return p;
}

bool externalActs(const World& w) {
  for (const Wrench& e : w.stepData("u").external_wrench) {
    if (e.force != Vec3::Zero() || e.torque != Vec3::Zero()) return true;
  }
  return false;
}

// Steps one at a time to kEnd; the start of the first step an external wrench acted in.
double flyTo(World& w, double end) {
  double first = -1.0;
  while (w.time() < end - 1e-9) {
    const double start = w.time();
    w.step(1);
    if (first < 0.0 && externalActs(w)) first = start;
  }
  return first;
}

// Step 0.001 s: 0.25 s is step 250's start. Step 0.0003 s: 0.25 s falls inside step 834
// (0.2499-0.2502 s), so it acts from step 835's start, 834 x 0.0003 = 0.2502 s.
TEST(WrenchStart, AppliedAheadIsBitIdenticalToACallAtTheFirstStepAtOrAfterItsStart) {
  for (const double h : {0.001, 0.0003}) {
    const double want = h == 0.001 ? 250 * 0.001 : 834 * 0.0003;
    World ahead(skyOfStep(h));
    spawnBeating(ahead);
    ExternalWrench w = wingTorque();
    w.start_time = kStart;
    EXPECT_EQ(ahead.applyWrench("u", w), want) << h;
    EXPECT_EQ(ahead.wrenchCount("u"), 1) << h;
    EXPECT_EQ(flyTo(ahead, kEnd), want) << h;

    World called(skyOfStep(h));
    spawnBeating(called);
    flyTo(called, kStart);  // the first step start at or after 0.25 s
    EXPECT_EQ(called.time(), want) << h;
    EXPECT_EQ(called.applyWrench("u", wingTorque()), want) << h;
    EXPECT_EQ(flyTo(called, kEnd), want) << h;
    EXPECT_TRUE(bitIdentical(ahead.state("u"), called.state("u"))) << h;

    World none(skyOfStep(h));  // the wrench changed the flight
    spawnBeating(none);
    flyTo(none, kEnd);
    EXPECT_FALSE(bitIdentical(ahead.state("u"), none.state("u"))) << h;
  }
}

TEST(WrenchStart, AStartTimeAlreadyPassedActsFromTheNextStepAsNoStartTime) {
  auto run = [](double start_time) {
    World w(skyOfStep(0.001));
    spawnBeating(w);
    flyTo(w, 0.1);
    const double now = w.time();
    ExternalWrench x = wingTorque();
    x.start_time = start_time;
    EXPECT_EQ(w.applyWrench("u", x), now) << start_time;
    EXPECT_EQ(flyTo(w, 0.3), now) << start_time;
    return w.state("u");
  };
  const CreatureState now = run(0.0);
  EXPECT_TRUE(bitIdentical(run(0.05), now));
  EXPECT_TRUE(bitIdentical(run(-3.0), now));
}

SystemMomentum plateMomentum(const World& w, const CreatureModel& m) {
  return systemMomentum(test::bodyMotions(m, w.state("p")));
}

// A push of 0.3 N along x at plate "p"'s origin, starting at `start` s.
ExternalWrench pushOnPlate(const World& w, double start) {
  ExternalWrench push;
  push.force = Vec3(0.3, 0.0, 0.0);
  push.point = w.state("p").link_poses[0].position;
  push.start_time = start;
  return push;
}

// A push on a plate in vacuum: nothing while it waits, then its full impulse over its
// duration counted from its start (50 steps from 0.1 s, not from the call at 0).
TEST(WrenchStart, TheDurationCountsFromTheStart) {
  World w(stillVacuum());
  auto m = loadUrdf("plate.urdf");
  w.spawn("p", m, at(0, 0, 5));
  ExternalWrench push = pushOnPlate(w, 0.1);
  push.duration = 0.05;
  EXPECT_EQ(w.applyWrench("p", push), 100 * 0.001);
  w.step(100);
  EXPECT_EQ(plateMomentum(w, *m).linear.x(), 0.0);  // waited: nothing acted
  EXPECT_EQ(w.wrenchCount("p"), 1);
  w.step(49);
  EXPECT_EQ(w.wrenchCount("p"), 1);  // 49 of its 50 steps
  w.step(1);
  EXPECT_EQ(w.wrenchCount("p"), 0);
  EXPECT_NEAR(plateMomentum(w, *m).linear.x(), 0.3 * 0.05, 1e-15);
}

TEST(WrenchStart, ClearWrenchesAndResetDropAWaitingWrench) {
  World w(stillVacuum());
  auto m = loadUrdf("plate.urdf");
  w.spawn("p", m, at(0, 0, 5));
  const ExternalWrench push = pushOnPlate(w, 0.05);
  w.applyWrench("p", push);
  EXPECT_EQ(w.clearWrenches("p"), 1);
  w.applyWrench("p", push);
  w.reset();
  EXPECT_EQ(w.wrenchCount("p"), 0);
  w.step(200);
  EXPECT_EQ(plateMomentum(w, *m).linear.x(), 0.0);  // nothing acted
}

TEST(WrenchStart, ANonFiniteOrFarStartTimeIsRefusedByName) {
  World w(stillVacuum());
  w.spawn("p", loadUrdf("plate.urdf"), at(0, 0, 5));
  const double inf = std::numeric_limits<double>::infinity();
  for (const double t : {std::nan(""), inf, -inf, 2e9}) {
    ExternalWrench x;
    x.force = Vec3(1, 0, 0);
    x.start_time = t;
    try {
      w.applyWrench("p", x);
      ADD_FAILURE() << "start_time " << t << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                "creature 'p': wrench start_time must be finite and within +-1e9 s (s of sim "
                "time; 0: the next step)");
    }
    EXPECT_EQ(w.wrenchCount("p"), 0) << t;
  }
}

}  // namespace
}  // namespace flapsim
