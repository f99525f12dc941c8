// World::stepData: the named outputs of a creature's last step (flapsim/step_data.h), checked
// against physics they must obey: the momentum balance, the power meter, free fall, and the
// pressure law on a plate moving face-on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynamics/bullet_body.h"
#include "dynamics/bullet_scene.h"
#include "dynamics/momentum.h"
#include "flapsim/step_data.h"
#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

// The creature's momentum (its bodies': no added mass in these worlds) about its COM.
SystemMomentum momentumOf(const World& w, const std::string& name) {
  return systemMomentum(test::bodyMotions(*w.model(name), w.state(name)));
}

// Each link's COM in `state` (world frame).
std::vector<Vec3> comsOf(const CreatureModel& m, const CreatureState& state) {
  std::vector<Vec3> out;
  for (const BodyMotion& b : test::bodyMotions(m, state)) out.push_back(b.com);
  return out;
}

// Water without added mass (the momentum is the bodies' alone), the drag stiff enough at
// 1 ms to be implicit, and whole steps (no substeps at the turns), no ground.
WorldParams stiffWater() {
  WorldParams p = test::openSky();
  p.air.density = 1000.0;
  p.air.added_mass = false;
  p.turn_substep = 0.0;
  return p;
}

// In a step without contact, the sum over the links of the fluid and external wrenches, with
// gravity, is the change of the creature's momentum: linear, and angular about its COM (the
// wrenches' moments about the COMs of the step's start, whose StepData::com are those of the
// state before the step). A flapping unit in water whose drag is implicit, pushed off its COM.
TEST(StepData, FluidExternalAndGravityAreTheMomentumChange) {
  World w(stiffWater());
  auto model = loadUrdf("flap_unit.urdf");
  w.spawn("u", model, at(0, 0, 5), Twist{Vec3(0.3, 0.0, -0.4), Vec3(0.0, 0.5, 0.2)});
  w.setWingCommands("u", {}, {StrokeCommand{30, 10, 0.8}, StrokeCommand{30, 10, 0.8}});
  ExternalWrench push;
  push.force = Vec3(0.2, -0.1, 0.3);
  push.torque = Vec3(0.0, 0.01, 0.0);
  push.point = Vec3(0.05, 0.02, 5.0);
  push.duration = -1.0;
  w.applyWrench("u", push);
  const double dt = w.params().step_size;
  const double mass = model->totalMass();
  int implicit_steps = 0;
  for (int i = 0; i < 200; ++i) {
    const CreatureState before = w.state("u");
    const SystemMomentum p0 = momentumOf(w, "u");
    w.step();
    const StepData d = w.stepData("u");
    const SystemMomentum p1 = momentumOf(w, "u");
    ASSERT_EQ(d.step, dt);
    ASSERT_EQ(d.substeps, 1);
    ASSERT_FALSE(d.contact);
    const std::vector<Vec3> com = comsOf(*model, before);
    Vec3 force = mass * w.params().gravity, moment = Vec3::Zero();
    for (size_t k = 0; k < model->links.size(); ++k) {
      ASSERT_LT((d.com[k] - com[k]).norm(), 1e-12) << "link " << k << " step " << i;
      const Vec3 f = d.fluid_wrench[k].force + d.external_wrench[k].force;
      force += f;
      moment +=
          (d.com[k] - p0.com).cross(f) + d.fluid_wrench[k].torque + d.external_wrench[k].torque;
    }
    const Vec3 dp = p1.linear - p0.linear, dl = p1.angular - p0.angular;
    ASSERT_LT((dp - dt * force).norm(), 1e-9 * (1.0 + dp.norm())) << "step " << i;
    ASSERT_LT((dl - dt * moment).norm(), 1e-9 * (1.0 + dl.norm())) << "step " << i;
    // The implicit drag's share is in it: the explicit wrenches alone miss the change.
    Vec3 explicit_force = mass * w.params().gravity;
    for (const LinkAero& a : w.aeroForces("u")) explicit_force += a.wrench.force;
    for (const Wrench& e : d.external_wrench) explicit_force += e.force;
    if ((explicit_force - force).norm() > 1e-3 * force.norm()) ++implicit_steps;
  }
  EXPECT_GT(implicit_steps, 100);  // the water's drag was stiff in most steps
}

// The external wrench is the one applied, about the link's COM: its force, and its torque
// plus the moment of the force at its point.
TEST(StepData, ExternalWrenchIsTheAppliedOneAboutTheCom) {
  World w(test::vacuum());
  auto model = loadUrdf("plate.urdf");
  w.spawn("p", model, at(1, 2, 3));
  ExternalWrench push;
  push.force = Vec3(0.0, 0.0, 0.5);
  push.torque = Vec3(0.02, 0.0, 0.0);
  push.point = Vec3(1.1, 2.0, 3.0);  // 0.1 m along x from the COM
  w.applyWrench("p", push);
  w.step();
  const StepData d = w.stepData("p");
  EXPECT_EQ(d.external_wrench[0].force, push.force);
  const Vec3 torque = push.torque + Vec3(0.1, 0.0, 0.0).cross(push.force);
  EXPECT_LT((d.external_wrench[0].torque - torque).norm(), 1e-14);
  w.step();  // the wrench acted for one step
  EXPECT_EQ(w.stepData("p").external_wrench[0].force, Vec3::Zero());
}

// With the servo's impulse for a meter (MotorWorkMeter::kServoImpulse), each motor's power
// over a step is its servo's effort times the mean of its joint's velocities at the step's
// start and end (the power meter's trapezoid), as World::power gives it; the efforts are
// CreatureState's. A flap unit stroking in air, in whole steps.
TEST(StepData, WithTheServoMeterServoEffortTimesMeanJointVelocityIsThePower) {
  WorldParams p = test::openSky();
  p.turn_substep = 0.0;
  p.motor_work = MotorWorkMeter::kServoImpulse;
  World w(p);
  auto model = loadUrdf("flap_unit.urdf");
  w.spawn("u", model, at(0, 0, 5));
  w.setWingCommands("u", {}, {StrokeCommand{30, 10, 0.8}, StrokeCommand{30, 10, 0.8}});
  double largest = 0.0;
  for (int i = 0; i < 300; ++i) {
    const CreatureState before = w.state("u");
    w.step();
    const CreatureState after = w.state("u");
    const StepData d = w.stepData("u");
    const CreaturePower power = w.power("u");
    double total = 0.0;
    for (int j : model->wing_joints) {
      const double mean_velocity = 0.5 * (before.joint_velocities[j] + after.joint_velocities[j]);
      const double expected = d.servo_effort[j] * mean_velocity;
      ASSERT_NEAR(d.joint_power[j], expected, 1e-12 * (1.0 + std::abs(expected))) << i;
      ASSERT_EQ(d.joint_power[j], power.power[j]);
      ASSERT_EQ(d.servo_effort[j], after.joint_efforts[j]);
      total += d.joint_power[j];
      largest = std::max(largest, std::abs(d.joint_power[j]));
    }
    ASSERT_EQ(d.total_power, power.totalPower());
    ASSERT_NEAR(d.total_power, total, 1e-12 * (1.0 + std::abs(total)));
  }
  EXPECT_GT(largest, 0.1);  // W: the motors worked
}

// A plate in free fall in vacuum feels no fluid wrench, also right after it flew in air (the
// aero bodies' last wrenches are then an older step's), and falls at g.
TEST(StepData, FreeFallInVacuumHasNoFluidWrench) {
  World w(test::openSky());
  auto model = loadUrdf("plate.urdf");
  w.spawn("p", model, at(0, 0, 10), Twist{Vec3(0.0, 0.0, -3.0), Vec3::Zero()});
  w.step(5);
  ASSERT_GT(w.stepData("p").fluid_wrench[0].force.norm(), 0.01);
  AirParams vacuum = w.params().air;
  vacuum.enabled = false;
  w.setAirParams(vacuum);
  const SystemMomentum p0 = momentumOf(w, "p");
  w.step();
  const StepData d = w.stepData("p");
  EXPECT_EQ(d.fluid_wrench[0].force, Vec3::Zero());
  EXPECT_EQ(d.fluid_wrench[0].torque, Vec3::Zero());
  const Vec3 dv = (momentumOf(w, "p").linear - p0.linear) / model->totalMass();
  EXPECT_LT((dv - w.params().step_size * w.params().gravity).norm(), 1e-12);
}

// A level plate moving face-on, explicitly (drag far from stiff): the fluid force is along
// -v, 1/2 rho Cd A v^2 over its face, and has no moment about its COM.
TEST(StepData, FaceOnPlateFeelsThePressureLaw) {
  WorldParams p = test::openSky();
  p.gravity = Vec3::Zero();
  p.air.buoyancy = false;
  p.air.added_mass = false;
  World w(p);
  const Vec3 v(0.0, 0.0, -2.0);
  w.spawn("p", loadUrdf("plate.urdf"), at(0, 0, 10), Twist{v, Vec3::Zero()});
  w.step();
  const StepData d = w.stepData("p");
  const double area = 0.2 * 0.2;
  const double magnitude = 0.5 * p.air.density * p.air.drag_coefficient * area * v.squaredNorm();
  const Wrench& f = d.fluid_wrench[0];
  EXPECT_NEAR(f.force.norm(), magnitude, 1e-12 * magnitude);
  EXPECT_NEAR(f.force.normalized().dot(-v.normalized()), 1.0, 1e-12);
  EXPECT_LT(f.torque.norm(), 1e-12 * magnitude);
  EXPECT_FALSE(d.contact);
}

// A plate lying on the ground is in contact, and its step data says so.
TEST(StepData, PlateOnTheGroundIsInContact) {
  World w;
  w.spawn("p", loadUrdf("plate.urdf"), at(0, 0, 0.0011));
  w.step(50);
  EXPECT_TRUE(w.stepData("p").contact);
}

// No step data before the first step, after setState, and after a step the watchdog refused.
TEST(StepData, IsEmptyWithoutAStep) {
  WorldParams p = test::vacuum();
  p.max_speed = 0.05;  // m/s: gravity passes it within 6 ms
  World w(p);
  auto model = loadUrdf("plate.urdf");
  w.spawn("p", model, at(0, 0, 5));
  EXPECT_EQ(w.stepData("p").step, 0.0);
  EXPECT_EQ(w.stepData("p").fluid_wrench.size(), model->links.size());
  EXPECT_EQ(w.stepData("p").servo_effort.size(), model->joints.size());
  w.step();
  EXPECT_EQ(w.stepData("p").step, p.step_size);
  EXPECT_EQ(w.stepData("p").substeps, 1);
  StateRequest still;
  still.pose = at(0, 0, 5);
  w.setState("p", still);
  EXPECT_EQ(w.stepData("p").step, 0.0);
  EXPECT_EQ(w.stepData("p").substeps, 0);
  for (int i = 0; i < 20 && !w.divergence("p"); ++i) w.step();
  ASSERT_TRUE(w.divergence("p"));
  EXPECT_EQ(w.stepData("p").step, 0.0);
}

// A step in which a wing turns is taken in substeps, and its data says how many; its wrenches
// are the means over the step (each substep's weighted by its length), so that with gravity
// they are still the change of the linear momentum over the step. A flapping unit in water
// whose drag is implicit, pushed.
TEST(StepData, AStepInSubstepsGivesTheMeanWrenchesOverIt) {
  WorldParams p = stiffWater();
  p.turn_substep = 0.0003;  // s: a turning step in 4 pieces, two of them not equal
  World w(p);
  auto model = loadUrdf("flap_unit.urdf");
  w.spawn("u", model, at(0, 0, 5));
  w.setWingCommands("u", {}, {StrokeCommand{30, 10, 0.8}, StrokeCommand{30, 10, 0.8}});
  ExternalWrench push;
  push.force = Vec3(0.2, -0.1, 0.3);
  push.point = Vec3(0.05, 0.02, 5.0);
  push.duration = -1.0;
  w.applyWrench("u", push);
  int cut = 0;
  for (int i = 0; i < 300; ++i) {
    const SystemMomentum p0 = momentumOf(w, "u");
    w.step();
    const StepData d = w.stepData("u");
    if (d.substeps < 2) continue;
    ++cut;
    Vec3 force = model->totalMass() * p.gravity;
    for (size_t k = 0; k < model->links.size(); ++k) {
      force += d.fluid_wrench[k].force + d.external_wrench[k].force;
    }
    const Vec3 dp = momentumOf(w, "u").linear - p0.linear;
    ASSERT_LT((dp - p.step_size * force).norm(), 1e-9 * (1.0 + dp.norm())) << "step " << i;
  }
  EXPECT_GE(cut, 4);  // the turns of 300 ms of strokes
}

// Bullet's step in its three phases, with no stage between them, is stepSimulation(h, 0, h)
// to the bit: full steps (lean steps off) of a flap unit thrown onto the ground, bouncing
// and coming to rest on it.
TEST(StepOrder, PhasesWithNothingBetweenAreBulletsStep) {
  WorldParams p;
  p.lean_steps = false;
  auto model = loadUrdf("flap_unit.urdf");
  const Pose pose = at(0, 0, 0.3, Quat(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized())));
  const Twist twist{Vec3(0.5, 0.0, -1.0), Vec3(1.0, 2.0, 0.5)};
  BulletBody phased(*model, pose, twist, p), bullet(*model, pose, twist, p);
  const double h = p.step_size;
  int touching = 0;
  for (int i = 0; i < 600; ++i) {
    ServoWorld& w = phased.world();
    ASSERT_TRUE(w.beginStep(h));
    w.constrain();
    w.integrate();
    bullet.world().stepSimulation(h, 0, h);
    phased.framesAfterStep();  // for the ground check of the next step
    bullet.framesAfterStep();
    BodySnapshot a, b;
    a.take(phased.multiBody());
    b.take(bullet.multiBody());
    ASSERT_TRUE(a.position == b.position && a.orientation == b.orientation &&
                a.velocity == b.velocity && a.omega == b.omega && a.q == b.q && a.qdot == b.qdot)
        << "step " << i;
    ASSERT_EQ(phased.hasContacts(), bullet.hasContacts()) << "step " << i;
    if (phased.hasContacts()) ++touching;
  }
  EXPECT_GT(touching, 100);  // the steps with contact were compared too
}

// The phases run in their order only, and a step Bullet rounds to nothing moves nothing.
TEST(StepOrder, PhasesOutOfOrderAreRefused) {
  Scene scene{WorldParams()};
  ServoWorld& w = scene.world();
  EXPECT_THROW(w.constrain(), std::logic_error);
  EXPECT_THROW(w.integrate(), std::logic_error);
  EXPECT_TRUE(w.beginStep(0.001));
  EXPECT_THROW(w.beginStep(0.001), std::logic_error);
  EXPECT_THROW(w.integrate(), std::logic_error);
  w.constrain();
  EXPECT_THROW(w.constrain(), std::logic_error);
  w.integrate();
  EXPECT_FALSE(w.beginStep(0.0));
  w.constrain();
  w.integrate();
}

}  // namespace
}  // namespace flapsim
