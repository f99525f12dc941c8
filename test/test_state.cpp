// Driving a creature from outside: World::setState (teleport, give it a velocity),
// World::applyWrench (a push or a gust, counted in the momentum balance) and the root's
// acceleration an IMU reads.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dynamics/momentum.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::bitIdentical;
using test::loadUrdf;

constexpr double kG = 9.81;

WorldParams vacuum() {
  WorldParams p;
  p.ground = false;
  p.gravity = Vec3::Zero();
  p.air.enabled = false;
  return p;
}

SystemMomentum momentumOf(const CreatureModel& m, const CreatureState& s) {
  return systemMomentum(test::bodyMotions(m, s));
}

Quat tilt(double angle, const Vec3& axis) {
  return Quat(Eigen::AngleAxisd(angle, axis.normalized()));
}

// The flap unit's state with both wings at given angles and rates (its joints in URDF order).
StateRequest unitRequest(const CreatureModel& m, const std::string& link, const Pose& pose,
                         const Twist& twist) {
  StateRequest r;
  r.link = link;
  r.pose = pose;
  r.twist = twist;
  r.joint_positions.assign(m.joints.size(), 0.0);
  r.joint_velocities.assign(m.joints.size(), 0.0);
  for (size_t i = 0; i < m.wing_joints.size(); ++i) {
    r.joint_positions[m.wing_joints[i]] = i % 2 == 0 ? 0.3 : -0.2;
    r.joint_velocities[m.wing_joints[i]] = i % 2 == 0 ? 2.0 : -1.5;
  }
  return r;
}

// The root's pose and twist, and the joints, read back as they were set (to rounding), from
// a creature that was somewhere else doing something else.
TEST(SetState, RootPoseTwistAndJointsReadBackAsSet) {
  World w(vacuum());
  auto m = loadUrdf("flap_unit.urdf");
  w.spawn("u", m, at(1, 2, 3, tilt(0.7, Vec3(1, 1, 0))), Twist{Vec3(3, 0, 1), Vec3(0, 2, 0)});
  w.step(37);
  const Pose pose = at(-4, 5, 6, tilt(1.1, Vec3(0, 1, 2)));
  const Twist twist{Vec3(0.5, -1, 2), Vec3(0.3, 0.2, -0.1)};
  w.setState("u", unitRequest(*m, "", pose, twist));
  const CreatureState s = w.state("u");
  EXPECT_LT((s.link_poses[0].position - pose.position).norm(), 1e-12);
  EXPECT_LT(s.link_poses[0].orientation.angularDistance(pose.orientation), 1e-12);
  EXPECT_LT((s.link_twists[0].linear - twist.linear).norm(), 1e-12);
  EXPECT_LT((s.link_twists[0].angular - twist.angular).norm(), 1e-12);
  for (size_t j = 0; j < m->joints.size(); ++j) {
    EXPECT_NEAR(s.joint_positions[j], unitRequest(*m, "", pose, twist).joint_positions[j], 1e-15);
    EXPECT_NEAR(s.joint_velocities[j], unitRequest(*m, "", pose, twist).joint_velocities[j], 1e-15);
  }
}

// The same for one wing: that link lands where asked, moving as asked, and the body follows
// through the hinge (the joint angle holds).
TEST(SetState, WingLinkPoseAndTwistReadBackAsSet) {
  World w(vacuum());
  auto m = loadUrdf("flap_unit.urdf");
  w.spawn("u", m, at(0, 0, 5));
  const int wing = m->findLink("unit0_wing_left");
  ASSERT_GT(wing, 0);
  const Pose pose = at(2, -1, 7, tilt(-0.4, Vec3(1, 0, 3)));
  const Twist twist{Vec3(-1, 0.5, 0.25), Vec3(0.1, -0.6, 0.4)};
  const StateRequest r = unitRequest(*m, "unit0_wing_left", pose, twist);
  w.setState("u", r);
  const CreatureState s = w.state("u");
  EXPECT_LT((s.link_poses[wing].position - pose.position).norm(), 1e-12);
  EXPECT_LT(s.link_poses[wing].orientation.angularDistance(pose.orientation), 1e-12);
  EXPECT_LT((s.link_twists[wing].linear - twist.linear).norm(), 1e-12);
  EXPECT_LT((s.link_twists[wing].angular - twist.angular).norm(), 1e-12);
  const int j = m->links[wing].parent_joint;
  EXPECT_NEAR(s.joint_positions[j], r.joint_positions[j], 1e-15);
  EXPECT_NEAR(s.joint_velocities[j], r.joint_velocities[j], 1e-15);
}

// Without joint values the joints keep theirs; only the root moves.
TEST(SetState, JointsKeepTheirStateWhenNotGiven) {
  World w(vacuum());
  auto m = loadUrdf("flap_unit.urdf");
  w.spawn("u", m, at(0, 0, 5));
  w.setWingCommands("u", {}, {{40, 10, 0.8}, {40, 10, 0.8}});
  w.step(20);
  const CreatureState before = w.state("u");
  StateRequest r;
  r.pose = at(10, 0, 5);
  w.setState("u", r);
  const CreatureState after = w.state("u");
  EXPECT_EQ(after.joint_positions, before.joint_positions);
  EXPECT_EQ(after.joint_velocities, before.joint_velocities);
  EXPECT_LT((after.link_poses[0].position - Vec3(10, 0, 5)).norm(), 1e-12);
  EXPECT_LT(after.link_twists[0].linear.norm() + after.link_twists[0].angular.norm(), 1e-12);
}

// Set, step N: the same result to the bit whatever came before, in this world or another,
// and whether the creature lay on the ground (its contacts and servo history are dropped).
TEST(SetState, SetThenStepIsBitReproducible) {
  auto m = loadUrdf("flap_unit.urdf");
  const StateRequest r =
      unitRequest(*m, "unit0_wing_right", at(0.3, 0.1, 4, tilt(0.2, Vec3(1, 0, 0))),
                  Twist{Vec3(1, 0, 0.5), Vec3(0, 0.3, 0)});
  auto run = [&](int before) {
    World w;  // with ground
    w.spawn("u", m, at(0, 0, 2), Twist{Vec3(0, 2, 0), Vec3::Zero()});
    w.step(before);
    w.setState("u", r);
    w.step(300);
    const CreatureState first = w.state("u");
    w.step(before + 11);
    w.setState("u", r);
    w.step(300);
    EXPECT_TRUE(bitIdentical(first, w.state("u"))) << before;
    return first;
  };
  const CreatureState a = run(0), b = run(123), c = run(2000);  // c: after landing
  EXPECT_TRUE(bitIdentical(a, b));
  EXPECT_TRUE(bitIdentical(a, c));
  // and the state did evolve: it fell and moved on
  EXPECT_LT(a.link_poses[0].position.z(), 4.0);
}

// A plate set face-on at 5 m/s (no gravity, no added mass) slows as m dv/dt = -k v^2 says:
// v(t) = v0 / (1 + k v0 t / m), k = rho Cd A / 2; to first order in the step.
TEST(SetState, PlateSetMovingSlowsAsTheDragLawSays) {
  std::vector<double> errors;
  for (double dt : {0.001, 0.0005, 0.00025}) {
    WorldParams p = test::openSky();
    p.step_size = dt;
    p.gravity = Vec3::Zero();
    p.air.added_mass = false;
    p.air.buoyancy = false;
    World w(p);
    auto m = loadUrdf("plate.urdf");
    w.spawn("plate", m, at(0, 0, 0));
    StateRequest r;
    r.pose = at(0, 0, 10);
    r.twist.linear = Vec3(0, 0, -5);
    w.setState("plate", r);
    const double k = 0.5 * p.air.density * p.air.drag_coefficient * 0.2 * 0.2;
    const double mass = 0.01;
    double worst = 0.0;
    for (int i = 1; i <= 4; ++i) {
      w.step(static_cast<int>(std::lround(0.05 / dt)));
      const double v = 5.0 / (1.0 + k * 5.0 * w.time() / mass);
      worst = std::max(worst, std::abs(-w.rootTwist("plate").linear.z() - v) / v);
    }
    EXPECT_LT(-w.rootTwist("plate").linear.z(), 1.4);  // it did slow down, to a quarter
    errors.push_back(worst);
  }
  EXPECT_LT(errors[0], 0.01);  // 1 ms: within 1%
  // first order: halving the step about halves the error
  EXPECT_LT(errors[1], 0.6 * errors[0]);
  EXPECT_LT(errors[2], 0.6 * errors[1]);
  EXPECT_LT(errors[2], 0.002);
}

// Every bad request is refused with an error naming its cause, and the world keeps its state.
TEST(SetState, BadRequestsAreNamedAndChangeNothing) {
  World w(vacuum());
  auto m = loadUrdf("flap_unit.urdf");
  w.spawn("u", m, at(0, 0, 5), Twist{Vec3(1, 0, 0), Vec3::Zero()});
  w.step(5);
  const CreatureState before = w.state("u");
  const StateRequest good = unitRequest(*m, "", at(0, 0, 1), Twist());
  auto expectRefused = [&](const std::string& creature, const StateRequest& r,
                           const std::string& named) {
    try {
      w.setState(creature, r);
      ADD_FAILURE() << "accepted; expected an error naming " << named;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    }
    EXPECT_TRUE(bitIdentical(before, w.state("u"))) << named;
  };
  expectRefused("nobody", good, "nobody");
  StateRequest r = good;
  r.link = "tail";
  expectRefused("u", r, "tail");
  r = good;
  r.pose.position.x() = NAN;
  expectRefused("u", r, "position");
  r = good;
  r.pose.orientation = Quat(0, 0, 0, 0);
  expectRefused("u", r, "quaternion");
  r = good;
  r.twist.linear = Vec3(2000, 0, 0);
  expectRefused("u", r, "linear twist");
  r = good;
  r.twist.angular.z() = INFINITY;
  expectRefused("u", r, "angular twist");
  r = good;
  r.joint_positions.pop_back();
  expectRefused("u", r, "joint_positions");
  r = good;
  r.joint_velocities[m->wing_joints[0]] = NAN;
  expectRefused("u", r, m->joints[m->wing_joints[0]].name);
  r = good;
  r.joint_positions[m->wing_joints[1]] = 10.0;  // beyond the hinge's limits
  expectRefused("u", r, "limits");
  // A spin that throws a wing tip past max_speed: refused by the speed check after the fact.
  r = good;
  r.twist.angular = Vec3(0, 0, 9e4);
  expectRefused("u", r, "max_speed");
}

// A push of known impulse changes the creature's linear momentum by exactly that impulse, and
// a pure torque its angular momentum by torque x time, in vacuum; the wrench then ends.
TEST(Wrench, PushChangesMomentumByItsImpulse) {
  World w(vacuum());
  auto m = loadUrdf("flap_unit.urdf");
  w.spawn("u", m, at(0, 0, 5, tilt(0.3, Vec3(1, 2, 0))));
  w.setWingCommands("u", {}, {{40, 10, 0.8}, {30, 12, 0.7}});  // internal forces too
  const SystemMomentum start = momentumOf(*m, w.state("u"));
  const int wing = m->findLink("unit0_wing_left");
  ExternalWrench push;
  push.link = "unit0_wing_left";
  push.force = Vec3(0.2, -0.1, 0.5);
  push.point = w.state("u").link_poses[wing].position;  // off the wing's COM: it also turns
  push.duration = 0.05;
  w.applyWrench("u", push);
  EXPECT_EQ(w.wrenchCount("u"), 1);
  w.step(50);
  EXPECT_EQ(w.wrenchCount("u"), 0);  // 0.05 s is 50 steps: it ended
  const Vec3 impulse = push.force * 0.05;
  const SystemMomentum after = momentumOf(*m, w.state("u"));
  EXPECT_LT((after.linear - start.linear - impulse).norm(), 1e-12 * impulse.norm() + 1e-15);
  w.step(100);  // and nothing more is added
  EXPECT_LT((momentumOf(*m, w.state("u")).linear - impulse).norm(), 1e-12 * impulse.norm());
}

// As gazebo_msgs/ApplyBodyWrench: a duration of 0 (its default) or a tenth of a step acts for
// exactly one step (it was refused as "shorter than half a step"): the impulse of one step.
TEST(Wrench, ADurationShorterThanAStepActsForOneStep) {
  for (const double duration : {0.0, 1e-4}) {
    World w(vacuum());
    auto m = loadUrdf("plate.urdf");
    w.spawn("p", m, at(0, 0, 5));
    ExternalWrench push;
    push.force = Vec3(0.3, 0.0, 0.0);
    push.point = w.state("p").link_poses[0].position;
    push.duration = duration;
    w.applyWrench("p", push);
    w.step(10);
    EXPECT_EQ(w.wrenchCount("p"), 0) << duration;
    const double impulse = 0.3 * w.params().step_size;
    EXPECT_NEAR(momentumOf(*m, w.state("p")).linear.x(), impulse, 1e-15) << duration;
  }
}

// A pure torque on a tumbling plate changes its angular momentum by torque x time.
TEST(Wrench, TorqueChangesAngularMomentumByItsImpulse) {
  World w(vacuum());
  auto m = loadUrdf("plate.urdf");
  w.spawn("p", m, at(0, 0, 5, tilt(0.3, Vec3(1, 2, 0))), Twist{Vec3::Zero(), Vec3(1, -2, 3)});
  const SystemMomentum before = momentumOf(*m, w.state("p"));
  ExternalWrench twist;
  twist.torque = Vec3(0.001, 0.002, -0.003);
  twist.point = w.rootPose("p").position;
  twist.duration = 0.1;
  w.applyWrench("p", twist);
  w.step(100);
  const SystemMomentum after = momentumOf(*m, w.state("p"));
  EXPECT_LT((after.angular - before.angular - twist.torque * 0.1).norm(),
            1e-9 * twist.torque.norm() * 0.1);
  EXPECT_LT(after.linear.norm(), 1e-15);
}

// An upward force equal to a plate's weight less its buoyancy, at its centre, holds it still
// in air: the drag never starts.
TEST(Wrench, WeightLessBuoyancyMakesAPlateHover) {
  WorldParams p = test::openSky();
  World w(p);
  auto m = loadUrdf("plate.urdf");
  w.spawn("plate", m, at(0, 0, 10));
  const double buoyancy = p.air.density * 0.2 * 0.2 * 0.002 * kG;
  ExternalWrench lift;
  lift.force = Vec3(0, 0, 0.01 * kG - buoyancy);
  lift.point = Vec3(0, 0, 10);
  lift.duration = -1.0;
  w.applyWrench("plate", lift);
  for (int i = 0; i < 10; ++i) {
    w.step(100);
    EXPECT_LT(std::abs(w.rootTwist("plate").linear.z()), 1e-6) << w.time();
  }
  EXPECT_EQ(w.wrenchCount("plate"), 1);  // until cleared
  EXPECT_EQ(w.clearWrenches("plate"), 1);
  w.step(100);
  EXPECT_LT(w.rootTwist("plate").linear.z(), -0.5);  // and then it falls
}

// Two worlds given the same state and wrench agree to the bit N steps on.
TEST(Wrench, StateAndWrenchThenStepIsBitReproducible) {
  auto m = loadUrdf("flap_unit.urdf");
  auto run = [&](int before) {
    World w(test::openSky());
    w.spawn("u", m, at(0, 0, 3));
    w.step(before);
    w.setState("u", unitRequest(*m, "", at(0, 0, 6), Twist()));
    ExternalWrench gust;
    gust.link = "unit0_wing_right";
    gust.force = Vec3(0.3, 0, 0.1);
    gust.point = w.state("u").link_poses[m->findLink("unit0_wing_right")].position;
    gust.duration = 0.1;
    w.applyWrench("u", gust);
    w.step(250);
    return w.state("u");
  };
  EXPECT_TRUE(bitIdentical(run(0), run(77)));
}

TEST(Wrench, BadWrenchesAreNamedAndChangeNothing) {
  World w(vacuum());
  auto m = loadUrdf("flap_unit.urdf");
  w.spawn("u", m, at(0, 0, 5));
  ExternalWrench good;
  good.force = Vec3(1, 0, 0);
  good.duration = 0.01;
  auto expectRefused = [&](const std::string& creature, const ExternalWrench& x,
                           const std::string& named) {
    try {
      w.applyWrench(creature, x);
      ADD_FAILURE() << "accepted; expected an error naming " << named;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    }
    EXPECT_EQ(w.wrenchCount("u"), 0) << named;
  };
  expectRefused("nobody", good, "nobody");
  ExternalWrench x = good;
  x.link = "tail";
  expectRefused("u", x, "tail");
  x = good;
  x.force.y() = NAN;
  expectRefused("u", x, "force");
  x = good;
  x.torque = Vec3(0, 0, 2e6);
  expectRefused("u", x, "torque");
  x = good;
  x.point.z() = INFINITY;
  expectRefused("u", x, "point");
  x = good;
  x = good;
  x.duration = NAN;
  expectRefused("u", x, "duration");
  EXPECT_THROW(w.clearWrenches("nobody"), InputError);
  EXPECT_THROW(w.clearWrenches("u", "tail"), InputError);
  x = good;
  x.duration = 2e9;  // beyond kMaxWrenchDuration
  expectRefused("u", x, "at most 1e9 s");
}

// Issue 27: the wrench table had no limit (90 bytes each, the step slower with each).
TEST(Wrench, AtMostKMaxWrenchesActOnACreature) {
  World w(vacuum());
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 5));
  ExternalWrench until_cleared;
  until_cleared.force = Vec3(0, 0, 1e-3);
  until_cleared.duration = -1.0;
  for (int i = 0; i < kMaxWrenches; ++i) w.applyWrench("u", until_cleared);
  try {
    w.applyWrench("u", until_cleared);
    ADD_FAILURE() << "wrench " << kMaxWrenches + 1 << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "creature 'u' has 1000 wrenches acting, the limit: clear some first");
  }
  EXPECT_EQ(w.wrenchCount("u"), kMaxWrenches);
  EXPECT_EQ(w.clearWrenches("u"), kMaxWrenches);
  w.applyWrench("u", until_cleared);  // room again
  EXPECT_EQ(w.wrenchCount("u"), 1);
}

// What an accelerometer needs: the root accelerates at g in free fall and not at all at rest
// on the ground.
TEST(RootAcceleration, IsGravityInFreeFallAndZeroAtRest) {
  WorldParams p;
  p.air.enabled = false;
  World w(p);
  auto m = loadUrdf("plate.urdf");
  w.spawn("falling", m, at(0, 0, 50));
  w.spawn("resting", m, at(3, 0, 0.001));
  EXPECT_EQ(w.rootAcceleration("falling"), Vec3::Zero());  // no step yet
  w.step(2000);
  EXPECT_LT((w.rootAcceleration("falling") - p.gravity).norm(), 1e-9);
  EXPECT_LT(w.rootAcceleration("resting").norm(), 1e-3);
  EXPECT_LT(std::abs(w.rootPose("resting").position.z() - 0.001), 1e-3);
}

}  // namespace
}  // namespace flapsim
