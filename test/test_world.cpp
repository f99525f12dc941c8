// The world: analytic motion, air in the loop, determinism, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "doc_figure.h"
#include "flapsim/make_creature.h"
#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::bitIdentical;
using test::flapOnHinge;
using test::kFlapHingeInertia;
using test::loadUrdf;
using test::openSky;
using test::vacuum;

constexpr double kG = 9.81;

TEST(World, FreeFallWithoutAirIsExact) {
  WorldParams p = openSky();
  p.air.enabled = false;
  World w(p);
  w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 100));
  const double dt = p.step_size;
  for (int k = 0; k < 4; ++k) {
    w.step(500);
    const double t = w.time();
    const Pose pose = w.rootPose("plate");
    const Twist tw = w.rootTwist("plate");
    // Semi-implicit Euler lags the exact parabola by at most g t dt.
    EXPECT_NEAR(pose.position.z(), 100.0 - 0.5 * kG * t * t, kG * t * dt) << t;
    EXPECT_NEAR(tw.linear.z(), -kG * t, 1e-9) << t;
    EXPECT_EQ(pose.position.x(), 0.0);
  }
  EXPECT_DOUBLE_EQ(w.time(), 2.0);
  EXPECT_EQ(w.stepCount(), 2000u);
}

TEST(World, FlatPlateReachesTerminalSpeed) {
  WorldParams p = openSky();
  p.air.buoyancy = false;
  World w(p);
  w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 100));
  w.step(3000);
  const double vt = std::sqrt(2 * 0.01 * kG / (p.air.density * p.air.drag_coefficient * 0.04));
  EXPECT_NEAR(-w.rootTwist("plate").linear.z(), vt, 0.02 * vt);
  EXPECT_NEAR(-w.rootTwist("plate").linear.z(), vt, 0.001 * vt);  // in fact much closer
}

TEST(World, TerminalSpeedScalesWithDragCoefficient) {
  double v[2];
  for (int i = 0; i < 2; ++i) {
    WorldParams p = openSky();
    p.air.buoyancy = false;
    p.air.drag_coefficient = i == 0 ? 1.15 : 2.0;
    World w(p);
    w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 100));
    w.step(3000);
    v[i] = -w.rootTwist("plate").linear.z();
  }
  EXPECT_NEAR(v[0] / v[1], std::sqrt(2.0 / 1.15), 1e-3);
}

// A drag coefficient changed in flight updates the surfaces in place (their cells are not
// rebuilt): the flight goes on as in a world that had it from the start, to the bit, and a
// link with its own <aero drag_coefficient> keeps that.
TEST(World, DragChangedInFlightActsAsIfSetFromTheStart) {
  std::string own = readUrdfFile(test::sourcePath("urdf/plate.urdf"));
  const Quat tilt(Eigen::AngleAxisd(0.3, Vec3::UnitX()));
  own.replace(own.find(R"(subdivisions="4 4")"), 18, R"(subdivisions="4 4" drag_coefficient="3")");
  const auto own_model = parseCreatureModel(own, "own.urdf");
  WorldParams p = openSky();
  p.air.drag_coefficient = 1.15;
  World changed(p);
  p.air.drag_coefficient = 2.0;
  World from_start(p);
  for (World* w : {&changed, &from_start}) {
    w->spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 100, tilt));
    w->spawn("own", own_model, at(1, 0, 100, tilt));
  }
  changed.setAirParams(p.air);
  for (int k = 0; k < 4; ++k) {
    changed.step(250);
    from_start.step(250);
    EXPECT_TRUE(bitIdentical(changed.state("plate"), from_start.state("plate"))) << k;
    EXPECT_TRUE(bitIdentical(changed.state("own"), from_start.state("own"))) << k;
  }
  // And the coefficient acted: a plate at 1.15 falls faster.
  World kept(openSky());
  kept.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 100, tilt));
  kept.step(1000);
  EXPECT_LT(kept.rootPose("plate").position.z(), changed.rootPose("plate").position.z() - 0.1);
}

TEST(World, LevelPlateFallsStraightDown) {
  World w(openSky());
  w.spawn("plate", loadUrdf("plate.urdf"), at(0.5, -0.25, 50));
  w.step(2000);
  const Pose pose = w.rootPose("plate");
  EXPECT_NEAR(pose.position.x(), 0.5, 1e-6);
  EXPECT_NEAR(pose.position.y(), -0.25, 1e-6);
  EXPECT_LT(pose.position.z(), 47.0);
}

// Without added mass (which slows the start: AddedMass.* in test_fluid.cpp).
TEST(World, BuoyancyLiftsAPlateInWater) {
  WorldParams p = openSky();
  p.air.density = 1000.0;
  p.air.added_mass = false;
  World w(p);
  w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 0));
  w.step(1);
  // At rest there is no drag: the first step accelerates at g (rho V / m - 1).
  const double volume = 0.2 * 0.2 * 0.002;
  const double a = kG * (1000.0 * volume / 0.01 - 1.0);
  EXPECT_NEAR(w.rootTwist("plate").linear.z(), a * p.step_size, 1e-9);
  w.step(999);
  EXPECT_GT(w.rootPose("plate").position.z(), 0.01);
}

// A plate denser than water sinks flat at sqrt(2 (m - rho V) g / (rho Cd A)).
TEST(World, DensePlateSinksAtTerminalSpeedInWater) {
  WorldParams p = openSky();
  p.air = waterParams();
  World w(p);
  auto steel = parseCreatureModel(R"(<robot name="steel"><link name="p">
    <inertial><mass value="0.5"/><inertia ixx="1.67e-3" ixy="0" ixz="0" iyy="1.67e-3" iyz="0" izz="3.33e-3"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.002"/></geometry></collision></link></robot>)");
  w.spawn("steel", steel, at(0, 0, 0));
  w.step(5000);  // its added mass (6.3 kg) makes the approach slow: tanh(t / 0.69 s)
  const double volume = 0.2 * 0.2 * 0.002;
  const double vt = std::sqrt(2 * (0.5 - 1000.0 * volume) * kG / (1000.0 * 1.15 * 0.04));
  test::printFigure("speed", -w.rootTwist("steel").linear.z());
  test::printFigure("expected", vt);
  EXPECT_NEAR(-w.rootTwist("steel").linear.z(), vt, 1e-3 * vt);
  EXPECT_NEAR(w.rootPose("steel").position.x(), 0.0, 1e-9);
}

TEST(World, PlateComesToRestOnTheGround) {
  World w;  // ground on by default
  w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 0.5));
  w.step(3000);
  EXPECT_NEAR(w.rootPose("plate").position.z(), 0.001, 2e-3);
  EXPECT_NEAR(w.rootTwist("plate").linear.norm(), 0.0, 1e-3);
}

// Collision detection is skipped while a creature is clear of the ground: a plate thrown
// down at 20 m/s flies freely, exactly, and is then caught and comes to rest.
TEST(World, FastFallIsCaughtByTheGround) {
  WorldParams p;
  p.air.enabled = false;
  World w(p);
  Twist down;
  down.linear = Vec3(0, 0, -20);
  w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 2), down);
  w.step(50);  // 1 m down, still in the air: free flight (semi-implicit Euler)
  EXPECT_NEAR(w.rootPose("plate").position.z(), 2.0 - 20 * 0.05 - 0.5 * kG * 0.05 * 0.051, 1e-9);
  w.step(950);
  EXPECT_GT(w.rootPose("plate").position.z(), -0.005);
  EXPECT_LT(w.rootPose("plate").position.z(), 0.01);
  EXPECT_LT(w.rootTwist("plate").linear.norm(), 0.05);
}

// The flap on a revolute hinge with `limit` and `dynamics` elements.
CreatureModelPtr hingedFlap(const std::string& axis, const std::string& limit,
                            const std::string& dynamics) {
  return flapOnHinge("revolute", axis, limit + dynamics);
}

// A horizontal flap on a hinge with an enormous URDF damping: it sinks under gravity slowly
// and smoothly, instead of the explicit damping torque making the step blow up.
TEST(World, HugeJointDampingStaysStable) {
  auto hinge = flapOnHinge("continuous", "1 0 0", R"(<dynamics damping="1000"/>)");
  World w(openSky());
  w.spawn("h", hinge, at(0, 0, 1));
  w.step(1000);
  const CreatureState s = w.state("h");
  EXPECT_TRUE(std::isfinite(s.joint_positions[0]));
  EXPECT_LT(s.joint_positions[0], 0.0);   // it did sink (tip down is negative about +x)
  EXPECT_GT(s.joint_positions[0], -0.5);  // but slowly: heavily damped
  EXPECT_LT(std::abs(s.joint_velocities[0]), 1.0);
}

// The values too stiff for an explicit step are named: on the flap's hinge (I = 1.34e-4 kg m^2
// about it), a 1 ms step keeps damping up to I / (4 dt) = 0.0335 N m s/rad and a spring up to
// I / (4 dt^2) = 33.5 N m/rad explicit; at 0.1 ms, ten and a hundred times more.
TEST(World, ImplicitJointValuesAreNamed) {
  auto stiff = flapOnHinge("continuous", "1 0 0", R"(<dynamics damping="0.1"/>)",
                           R"(<spring joint="hinge" stiffness="5000" reference="0"/>)");
  const std::vector<std::string> at1ms = implicitJointValues(*stiff, 0.001);
  ASSERT_EQ(at1ms.size(), 2u);
  EXPECT_EQ(at1ms[0],
            "joint 'hinge': damping 0.1 is more than an explicit step of 0.001 s keeps stable "
            "(0.0335): it acts implicitly, its motion faster than the step damped out");
  EXPECT_EQ(at1ms[1],
            "joint 'hinge': spring stiffness 5000 is more than an explicit step of 0.001 s keeps "
            "stable (33.5): it acts implicitly, its motion faster than the step damped out");
  const std::vector<std::string> at01ms = implicitJointValues(*stiff, 0.0001);
  ASSERT_EQ(at01ms.size(), 1u);  // the damping is within the explicit bound (0.335), not the spring
  EXPECT_NE(at01ms[0].find("spring stiffness 5000"), std::string::npos) << at01ms[0];
  EXPECT_NE(at01ms[0].find("(3350)"), std::string::npos) << at01ms[0];
  EXPECT_TRUE(
      implicitJointValues(*flapOnHinge("continuous", "1 0 0", R"(<dynamics damping="0.01"/>)",
                                       R"(<spring joint="hinge" stiffness="0.01"/>)"),
                          0.001)
          .empty());
}

// A spring 150 times stiffer than an explicit 1 ms step keeps stable (5000 N m/rad on the
// flap's hinge, about x, its COM 0.1 m out along y) holds the flap against gravity where
// statics put it, k q = m g d cos q: 1.962e-6 rad, to 1e-6 of it (measured 1.9e-12). An explicit
// spring would have been lowered to 33.5 N m/rad, sagging 150 times as far, and is unstable
// at its own stiffness.
TEST(World, AStiffSpringHoldsItsStaticDeflection) {
  const double k = 5000.0, weight_moment = 0.01 * 9.81 * 0.1;
  auto flap = flapOnHinge("continuous", "1 0 0", "",
                          R"(<spring joint="hinge" stiffness="5000" reference="0"/>)");
  World w(vacuum());  // in air, buoyancy would lift it by 0.24 %
  w.spawn("h", flap, at(0, 0, 1));
  w.step(500);
  const double q = w.state("h").joint_positions[0];
  EXPECT_NEAR(-q, weight_moment / k, 1e-6 * weight_moment / k);
  EXPECT_LT(std::abs(w.state("h").joint_velocities[0]), 1e-9);
}

// A <spring> of 0.01 N m/rad on the flap's hinge, released 0.1 rad from its reference in
// vacuum: it swings with the period 2 pi sqrt(I / k) = 0.7274 s of a torsion pendulum
// (measured between the first and the eleventh upward zero crossings, within 0.5%).
TEST(World, SpringJointSwingsAtItsNaturalPeriod) {
  auto flap = flapOnHinge("continuous", "0 0 1", "",
                          R"(<spring joint="hinge" stiffness="0.01" reference="0.1"/>)");
  WorldParams p = vacuum();
  p.step_size = 0.0001;
  World w(p);
  w.spawn("h", flap, at(0, 0, 1));
  std::vector<double> crossings;  // upward through the reference
  double last = w.state("h").joint_positions[0] - 0.1;
  for (int i = 0; i < 100000 && crossings.size() < 11; ++i) {
    w.step(1);
    const double q = w.state("h").joint_positions[0] - 0.1;
    if (last < 0.0 && q >= 0.0) crossings.push_back(w.time() - p.step_size * q / (q - last));
    last = q;
  }
  ASSERT_EQ(crossings.size(), 11u);
  const double period = (crossings.back() - crossings.front()) / 10.0;
  const double expected = 2.0 * M_PI * std::sqrt(kFlapHingeInertia / 0.01);
  test::printFigure("period", period);
  test::printFigure("expected", expected);
  EXPECT_NEAR(period, expected, 0.005 * expected);
}

// A weak motor accelerates at effort / inertia until it reaches its target, then holds it.
TEST(Servo, EffortLimitsTheMotor) {
  const double effort = 0.01;
  World w(vacuum());
  w.spawn(
      "h",
      hingedFlap("0 0 1", R"(<limit lower="-100" upper="100" effort="0.01" velocity="50"/>)", ""),
      at(0, 0, 1));
  w.setJointVelocityTarget("h", "hinge", 10.0);
  w.step(50);
  EXPECT_NEAR(w.state("h").joint_velocities[0], 0.05 * effort / kFlapHingeInertia, 1e-9);
  EXPECT_NEAR(w.state("h").joint_efforts[0], effort, 1e-12);  // pushing with all it has
  w.step(250);  // 0.3 s: past the 0.134 s the target takes
  EXPECT_NEAR(w.state("h").joint_velocities[0], 10.0, 1e-9);
  EXPECT_NEAR(w.state("h").joint_efforts[0], 0.0, 1e-9);  // a free spin needs no torque
}

// Coulomb friction holds the flap level while gravity's torque m g d is below it, and
// only slows it when above.
TEST(Servo, JointFrictionHoldsOrSlows) {
  const double gravity_torque = 0.01 * kG * 0.1;
  const std::string limit = R"(<limit lower="-3" upper="3" effort="1" velocity="50"/>)";
  World w(vacuum());
  w.spawn("held", hingedFlap("1 0 0", limit, R"(<dynamics friction="0.012"/>)"), at(0, 0, 1));
  w.spawn("slipping", hingedFlap("1 0 0", limit, R"(<dynamics friction="0.005"/>)"), at(1, 0, 1));
  w.step(10);
  EXPECT_NEAR(w.state("held").joint_velocities[0], 0.0, 1e-12);
  EXPECT_NEAR(w.state("held").joint_positions[0], 0.0, 1e-12);
  EXPECT_NEAR(w.state("held").joint_efforts[0], gravity_torque, 1e-9);  // holds the weight
  EXPECT_NEAR(w.state("slipping").joint_efforts[0], 0.005, 1e-12);      // slides at its friction
  // Tip down is negative about +x; the angle stays under 2e-3 rad, so cos ~ 1.
  const double expected = -(gravity_torque - 0.005) / kFlapHingeInertia * 0.01;
  EXPECT_NEAR(w.state("slipping").joint_velocities[0], expected, 1e-3 * std::abs(expected));
}

// Momentum conservation of a flapping creature: test_momentum.cpp.

TEST(World, PositiveWingAngleLiftsTheTip) {
  World w(openSky());
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 10));
  w.setJointVelocityTarget("u", "unit0_wing_left_joint", 2.0);
  w.setJointVelocityTarget("u", "unit0_wing_right_joint", 2.0);
  w.step(100);
  const auto s = w.state("u");
  auto m = w.model("u");
  EXPECT_NEAR(s.joint_positions[m->findJoint("unit0_wing_left_joint")], 0.2, 0.01);
  const Vec3 body = s.link_poses[0].position;
  for (const char* wing : {"unit0_wing_left", "unit0_wing_right"}) {
    const int l = m->findLink(wing);
    const Vec3 tip = s.link_poses[l].apply(Vec3(0, l == 1 ? 0.3 : -0.3, 0));
    EXPECT_GT(tip.z() - body.z(), 0.05) << wing;
  }
}

TEST(World, StrokeTracksCommandedRates) {
  World w(openSky());
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 10));
  w.setWingCommands("u", {}, {StrokeCommand{30, 10, 0.8}, StrokeCommand{30, 10, 0.8}});
  w.step(10);  // mid-downstroke (-0.8 is reached after ~27 ms)
  auto s = w.state("u");
  EXPECT_NEAR(s.joint_velocities[0], -30.0, 1e-6);
  EXPECT_NEAR(s.joint_velocities[1], -30.0, 1e-6);
  w.step(60);  // mid-upstroke
  s = w.state("u");
  EXPECT_NEAR(s.joint_velocities[0], 10.0, 1e-6);
  // Left and right stay mirror images.
  EXPECT_NEAR(s.joint_positions[0], s.joint_positions[1], 1e-12);
  EXPECT_EQ(w.wingCommand("u", "unit0_wing_right_joint").downstroke_rate, 30.0);
}

CreatureState runFlapUnit(World& w, int steps) {
  w.step(steps);
  return w.state("u");
}

World* makeFlapWorld(World* w) {
  w->spawn("u", loadUrdf("flap_unit.urdf"),
           at(0, 0, 2, Quat(Eigen::AngleAxisd(0.05, Vec3::UnitX()))));
  w->spawn("p", loadUrdf("plate.urdf"), at(1, 0, 3, Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()))));
  w->setWingCommands("u", {}, {StrokeCommand{35, 10, 0.7}, StrokeCommand{30, 12, 0.8}});
  return w;
}

TEST(Determinism, TwoRunsAndAResetAgreeBitForBit) {
  World a, b;
  makeFlapWorld(&a);
  makeFlapWorld(&b);
  const CreatureState sa = runFlapUnit(a, 3000);
  const CreatureState sb = runFlapUnit(b, 3000);
  EXPECT_TRUE(bitIdentical(sa, sb));
  a.reset();
  EXPECT_EQ(a.time(), 0.0);
  const CreatureState again = runFlapUnit(a, 3000);
  EXPECT_TRUE(bitIdentical(sa, again));
  EXPECT_EQ(a.state("p").link_poses[0].position, b.state("p").link_poses[0].position);
  // Not trivially equal: the unit did move.
  EXPECT_GT((sa.link_poses[0].position - Vec3(0, 0, 2)).norm(), 0.01);
}

TEST(Determinism, RemoveAndSpawnAgainUnderTheSameName) {
  World w(openSky());
  w.spawn("p", loadUrdf("plate.urdf"), at(0, 0, 5));
  w.step(100);
  w.remove("p");
  EXPECT_FALSE(w.has("p"));
  w.spawn("p", loadUrdf("plate.urdf"), at(0, 0, 5));
  EXPECT_EQ(w.rootPose("p").position.z(), 5.0);
  EXPECT_EQ(w.creatureNames(), std::vector<std::string>{"p"});
}

// Creatures flapping and landing on the ground (contacts in every world) on 1 to 3 threads.
TEST(Determinism, ThreadsAndNeighboursDoNotChangeATrajectory) {
  auto unit = loadUrdf("flap_unit.urdf");
  auto plate = loadUrdf("plate.urdf");
  auto run = [&](int threads, int creatures) {
    WorldParams p;
    p.threads = threads;
    World w(p);
    for (int i = 0; i < creatures; ++i) {
      const std::string name = "u" + std::to_string(i);
      w.spawn(name, i % 2 ? plate : unit,
              at(i, 0, 0.05, Quat(Eigen::AngleAxisd(0.3 * i + 0.1, Vec3::UnitX()))));
      if (i % 2 == 0) w.setWingCommands(name, {}, {{20.0 + i, 10, 0.8}, {21, 10, 0.8}});
    }
    w.step(3000);
    return w.state("u0");
  };
  const CreatureState alone = run(1, 1);
  // Started on the ground, too slow a stroke to fly off (w1 = 20): it hops in contact.
  EXPECT_LT(alone.link_poses[0].position.z(), 0.5);
  EXPECT_TRUE(bitIdentical(alone, run(1, 6)));  // neighbours do not perturb it
  for (int k = 0; k < 5; ++k) {
    EXPECT_TRUE(bitIdentical(alone, run(2, 6)));  // nor does stepping on two threads
    EXPECT_TRUE(bitIdentical(alone, run(3, 6)));
  }
}

// ---- bad input: an error naming the culprit, and a world that carries on untouched ----

template <typename F>
void expectRejected(F&& bad, const std::string& culprit) {
  World reference, w;
  makeFlapWorld(&reference);
  makeFlapWorld(&w);
  reference.step(200);
  w.step(200);
  try {
    bad(w);
    ADD_FAILURE() << "no error, expected one naming '" << culprit << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(culprit), std::string::npos) << e.what();
  }
  reference.step(300);
  w.step(300);
  EXPECT_TRUE(bitIdentical(reference.state("u"), w.state("u"))) << culprit;
  EXPECT_EQ(reference.creatureNames(), w.creatureNames());
}

TEST(BadInput, IsRejectedAndTheWorldKeepsItsState) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const StrokeCommand ok{30, 10, 0.8};
  expectRejected([&](World& w) { w.spawn("u", loadUrdf("plate.urdf"), at(0, 0, 1)); }, "'u'");
  expectRejected([&](World& w) { w.spawn("", loadUrdf("plate.urdf"), at(0, 0, 1)); }, "empty");
  expectRejected([&](World& w) { w.spawn("q", loadUrdf("plate.urdf"), at(nan, 0, 1)); }, "'q'");
  expectRejected([&](World& w) { w.remove("ghost"); }, "ghost");
  expectRejected([&](World& w) { w.setWingCommands("ghost", {}, {ok, ok}); }, "ghost");
  expectRejected([&](World& w) { w.setWingCommands("u", {"elbow"}, {ok}); }, "elbow");
  expectRejected([&](World& w) { w.setWingCommands("u", {}, {ok}); }, "1 commands for 2");
  expectRejected(
      [&](World& w) {
        w.setWingCommands("u", {"unit0_wing_left_joint", "unit0_wing_right_joint"},
                          {ok, StrokeCommand{nan, 1, 1}});
      },
      "unit0_wing_right_joint");
  expectRejected(
      [&](World& w) {
        w.setWingCommands("u", {}, {ok, StrokeCommand{30, -1, 1}});
      },
      "upstroke");
  // The wing joints range over +-1.4 rad: a 1.5 rad stroke would never turn.
  expectRejected(
      [&](World& w) {
        w.setWingCommands("u", {}, {ok, StrokeCommand{30, 10, 1.5}});
      },
      "unit0_wing_right_joint': amplitude 1.5 rad does not fit inside its limits [-1.4");
  expectRejected([&](World& w) { w.setJointVelocityTarget("u", "unit0_wing_left_joint", nan); },
                 "unit0_wing_left_joint");
  expectRejected([&](World& w) { w.setJointVelocityTarget("u", "tail", 1.0); }, "tail");
  expectRejected(
      [&](World& w) {
        AirParams air;
        air.density = -1;
        w.setAirParams(air);
      },
      "density");
  expectRejected([&](World& w) { w.step(-1); }, "step");
}

TEST(BadInput, InvalidWorldParamsAreNamed) {
  WorldParams p;
  p.step_size = 0.0;
  EXPECT_THROW({ World w(p); }, InputError);
  p = WorldParams();
  p.air.subdivisions_u = 0;
  try {
    World w(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("subdivisions"), std::string::npos);
  }
  for (double bad : {-0.001, 1e-300, 5e-8}) {  // 1e-300: 1e297 pieces a step
    p = WorldParams();
    p.turn_substep = bad;
    try {
      World w(p);
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("turn_substep must be 0 (off) or finite and >= 1e-7 s"),
                std::string::npos)
          << e.what();
    }
  }
}

// A plate without an <aero> override, so the world's grid applies.
const char* kPlainPlate = R"(<robot name="p"><link name="p">
  <inertial><mass value="0.01"/><inertia ixx="3e-5" ixy="0" ixz="0" iyy="3e-5" iyz="0" izz="6e-5"/></inertial>
  <collision><geometry><box size="0.2 0.2 0.002"/></geometry></collision></link></robot>)";

TEST(AirParams, FinerGridKeepsFlatDrag) {
  // The same plate with 1x1 and 8x8 cells: flat translation gives the same force.
  double v[2];
  for (int i = 0; i < 2; ++i) {
    WorldParams p = openSky();
    p.air.subdivisions_u = p.air.subdivisions_v = (i == 0 ? 1 : 8);
    World w(p);
    w.spawn("plate", parseCreatureModel(kPlainPlate), at(0, 0, 10));
    w.step(500);
    v[i] = w.rootTwist("plate").linear.z();
  }
  EXPECT_NEAR(v[0], v[1], 1e-9);
}

}  // namespace
}  // namespace flapsim
